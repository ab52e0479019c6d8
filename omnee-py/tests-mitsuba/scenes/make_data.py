"""Writes the test scenes' data: ``data/sky.exr``, a small environment map
(a blue gradient with a warm sun), and ``data/density.vol``, a 24³ grid of
a smooth cloud for the heterogeneous medium. Deterministic; run from any
folder with a Mitsuba variant installed: ``python make_data.py``."""

import os

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
HERE = os.path.dirname(os.path.abspath(__file__))


def sky(width: int = 64, height: int = 32) -> np.ndarray:
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    theta, phi = np.meshgrid(v * np.pi, u * 2 * np.pi, indexing="ij")
    up = np.cos(theta)
    image = np.empty((height, width, 3), np.float32)
    image[..., 0] = 0.25 + 0.35 * np.clip(up, 0, 1)
    image[..., 1] = 0.30 + 0.45 * np.clip(up, 0, 1)
    image[..., 2] = 0.40 + 0.80 * np.clip(up, 0, 1)
    # A sun 35 degrees above the horizon.
    elevation, azimuth = np.radians(35.0), 0.6
    sun = np.array([np.cos(elevation) * np.cos(azimuth), np.sin(elevation), np.cos(elevation) * np.sin(azimuth)])
    d = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta), np.sin(theta) * np.sin(phi)], -1)
    glow = np.exp((d @ sun - 1.0) * 60.0)
    image += (glow[..., None] * np.array([40.0, 32.0, 22.0])).astype(np.float32)
    return image


def cloud(n: int = 24) -> np.ndarray:
    x = (np.arange(n) + 0.5) / n * 2 - 1
    z, y, xx = np.meshgrid(x, x, x, indexing="ij")
    r2 = xx**2 + (1.4 * y) ** 2 + z**2
    density = np.exp(-2.5 * r2) * (1.0 + 0.4 * np.sin(5 * xx) * np.cos(4 * z) * np.sin(3 * y + 1))
    return np.clip(density, 0.0, None).astype(np.float32)[..., None]


if __name__ == "__main__":
    os.makedirs(os.path.join(HERE, "data"), exist_ok=True)
    mi.Bitmap(sky()).write(os.path.join(HERE, "data", "sky.exr"))
    mi.VolumeGrid(cloud()).write(os.path.join(HERE, "data", "density.vol"))
