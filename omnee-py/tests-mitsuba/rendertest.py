"""Mitsuba 3's render test, as its ``src/render/tests/test_renders.py``
states it, for any integrator on any scene of its test form.

A test scene is ``test_<name>_<integrator>.xml`` whose integrator is
``<default name="integrator" .../>`` wrapped in ``moment``; its references
are ``refs/test_<name>_ref_<mode>.exr`` and ``..._var.exr`` (the mean and
the per-sample variance of an image rendered with many samples). The test
renders 2·10⁶ samples over the image (``2e6 // pixels`` per pixel, seed 0),
compares every pixel and channel of the mean, in XYZ, with the reference by
a z-test against the reference's variance (clamped below at 10⁻⁴), and
accepts the image when at least 99.75 % of the pixels' p-values are above
the Šidák-corrected level ``1 − (1 − 0.01)^(1/pixels)``.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from typing import Tuple

import numpy as np

SAMPLE_BUDGET = 2_000_000
SIGNIFICANCE = 0.01
PIXEL_FRACTION = 0.9975
COLOR_MODES = ("mono", "rgb", "spectral_polarized", "spectral")


@dataclass
class Outcome:
    """One render test."""

    accepted: bool
    """Whether the image passes."""
    fraction: float
    """The fraction of pixels (channels averaged) whose p-value is above the level."""
    min_p: float
    """The smallest p-value."""
    level: float
    """The Šidák-corrected level."""
    spp: int
    """Samples per pixel."""
    seconds: float
    """Wall time of the render."""
    image: np.ndarray
    """The rendered mean, XYZ."""
    reference: np.ndarray
    """The reference mean, XYZ."""
    variance_ratio: np.ndarray
    """Per pixel and channel, the image's per-sample variance over the
    reference's (where both are above 10⁻⁸): above 1 where the integrator
    is noisier than the reference's."""


def reference_files(scene_file: str, variant: str) -> Tuple[str, str]:
    """The reference and variance images of ``scene_file`` for ``variant``'s
    colour mode."""
    mode = next(m for m in COLOR_MODES if m in variant)
    folder, name = os.path.split(scene_file)
    stem = os.path.splitext(name)[0].rsplit("_", 1)[0]
    ref = os.path.join(folder, "refs", f"{stem}_ref_{mode}.exr")
    return ref, ref.replace(".exr", "_var.exr")


def scene_integrator(scene_file: str) -> str:
    """The integrator a test scene names in its file name (``…_volpath.xml``)."""
    return os.path.splitext(os.path.basename(scene_file))[0].rsplit("_", 1)[-1]


def _xyz(path: str) -> np.ndarray:
    import mitsuba as mi

    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.XYZ, mi.Struct.Type.Float32, False)
    return np.array(bitmap, copy=True)


def _moments(bitmap) -> Tuple[np.ndarray, np.ndarray]:
    """The mean and the per-sample variance of a film that a ``moment``
    integrator wrote (the layers ``NAME`` and ``m2_NAME`` besides the image
    itself, ``NAME`` the nested integrator's name), XYZ."""
    layers = bitmap.split()
    if len(layers) < 3:
        raise RuntimeError("the scene's integrator is not wrapped in a moment integrator")

    def array(layer) -> np.ndarray:
        out = np.array(layer, copy=True).astype(np.float64)
        return out[..., np.newaxis] if out.ndim == 2 else out

    mean, m2 = moment_layers(layers)
    mean, m2 = array(mean), array(m2)
    return mean, np.maximum(m2 - mean * mean, 0.0)


def moment_layers(layers):
    """The mean and second-moment bitmaps among ``Bitmap.split()``'s
    ``(name, bitmap)`` pairs: ``NAME`` and ``m2_NAME`` (by name: the split
    orders them by name, which puts ``m2_nested`` before ``nested``)."""
    named = dict(layers)
    for name in named:
        if name.startswith("m2_") and name[3:] in named:
            return named[name[3:]], named[name]
    raise RuntimeError(f"no moment layers among {list(named)}")


def p_values(mean: np.ndarray, spp: int, reference: np.ndarray, variance: np.ndarray) -> np.ndarray:
    """Two-sided p-values of ``|mean − reference| √(spp / variance)`` under
    the standard normal, the variance clamped below at 10⁻⁴."""
    variance = np.maximum(variance, 1e-4)
    z = np.abs(mean - reference) * np.sqrt(spp / variance)
    return np.vectorize(math.erfc)(z / math.sqrt(2.0))


def run(scene_file: str, integrator: str, variant: str, seed: int = 0, **parameters) -> Outcome:
    """Renders ``scene_file`` with ``integrator`` (the scene's ``$integrator``)
    as Mitsuba's render test does, in the current variant, and tests it."""
    import time

    import mitsuba as mi

    ref_file, var_file = reference_files(scene_file, variant)
    reference, variance = _xyz(ref_file), _xyz(var_file)
    pixels = reference.shape[0] * reference.shape[1]
    spp = SAMPLE_BUDGET // pixels
    scene = mi.load_file(scene_file, spp=spp, integrator=integrator, **parameters)
    start = time.time()
    scene.integrator().render(scene, seed=seed, spp=spp, develop=True)
    seconds = time.time() - start
    image, image_variance = _moments(scene.sensors()[0].film().bitmap(raw=False))
    p = p_values(image, spp, reference, variance)
    both = (variance > 1e-8) & (image_variance > 1e-8)
    ratio = np.where(both, image_variance / np.where(both, variance, 1.0), np.nan)
    level = 1.0 - (1.0 - SIGNIFICANCE) ** (1.0 / pixels)
    passed = np.count_nonzero(p > level) / p.shape[-1]
    return Outcome(
        accepted=passed >= PIXEL_FRACTION * pixels,
        fraction=passed / pixels,
        min_p=float(p.min()),
        level=level,
        spp=spp,
        seconds=seconds,
        image=image,
        reference=reference,
        variance_ratio=ratio,
    )


def scenes(folder: str, pattern: str = r"^test_.*\.xml$"):
    """The test scenes in ``folder`` whose references exist for ``rgb``."""
    found = []
    for name in sorted(os.listdir(folder)):
        if re.match(pattern, name):
            path = os.path.join(folder, name)
            if all(os.path.exists(f) for f in reference_files(path, "rgb")):
                found.append(path)
    return found
