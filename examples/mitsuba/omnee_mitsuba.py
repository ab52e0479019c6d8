"""OMNEE in a Mitsuba 3 scene: the once-more scattered light (and the direct
light) at the surface points that Mitsuba's camera rays hit, with one batch
of once-more vertices for all pixels at once.

For every camera sample, wavefront style (one array of rows per step):

1. Mitsuba: the camera ray and its first surface hit `x2` (with its BSDF);
2. the direct light at `x2` from a point light `x0`: one shadow ray and the
   BSDF (Mitsuba), the transmittance in closed form;
3. omnee: the once-more vertex `x1` between `x0` and `x2` for every row in
   one call, `omnee.Omnee(x0, x2, phase).sample(u)`, with its weight
   `θ/(s sin θ)`;
4. Mitsuba: the shadow rays `x1 → x0` and `x2 → x1` and the BSDF at `x2`
   towards `x1`; the transmittance of both edges in closed form. The
   estimate is `f_c · weight` with
   `f_c = I · V(x0, x1) T(x0, x1) · σs(x1) · T(x1, x2) V(x1, x2) · f(x2) cos θ2`
   (docs/math.md §1.1; Mitsuba's `bsdf.eval` includes the cosine).

The medium is homogeneous inside an axis-aligned box (`Fog`), so the
transmittance of a segment is `exp(−σt ℓ)` with `ℓ` its length inside the
box. Everything but the omnee call is Dr.Jit arithmetic on Mitsuba arrays,
so it needs an array variant (`llvm_ad_rgb`, `cuda_ad_rgb`); numpy carries
the rows into omnee and back.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import drjit as dr
import mitsuba as mi
import numpy as np
import omnee


@dataclass(frozen=True)
class Fog:
    """What the OMNEE side knows of the medium: its box, its coefficients
    and its phase function (an omnee phase spec)."""

    lo: np.ndarray
    hi: np.ndarray
    sigma_s: float
    sigma_t: float
    phase: str


def rows(v) -> np.ndarray:
    """A Mitsuba array of N 3-vectors as a C-contiguous float32 numpy array
    of shape (N, 3), the rows omnee reads in place."""
    return np.ascontiguousarray(np.asarray(v, dtype=np.float32).T)


def length_in_box(box: mi.BoundingBox3f, a: mi.Point3f, b: mi.Point3f) -> mi.Float:
    """ℓ: the length of each segment `a → b` inside the box, from the
    box's entry and exit distances along the line (the slab method)."""
    d = b - a
    dist = dr.norm(d)
    _, t_in, t_out = box.ray_intersect(mi.Ray3f(a, d / dr.maximum(dist, 1e-30)))
    return dr.maximum(dr.minimum(t_out, dist) - dr.maximum(t_in, 0.0), 0.0)


class OnceMoreRenderer:
    """The OMNEE side: direct and once-more scattered light from a point
    light through a homogeneous fog, at the first surface hit of every
    camera ray; Mitsuba traces every ray, omnee places the vertices `x1`.

    `scene`: a Mitsuba scene (array variant) holding the opaque shapes and
    the camera but no medium (`scene.mitsuba_dict(with_fog=False)`): its
    `ray_test` is the visibility `V`; `light`, `intensity`: the point light
    `x0` and its intensity I (W/sr); `fog`: the medium's box, coefficients
    and phase function.
    """

    def __init__(self, scene: mi.Scene, light, intensity: float, fog: Fog):
        self.scene = scene
        self.sensor = scene.sensors()[0]
        self.width, self.height = (int(v) for v in self.sensor.film().size())
        self.x0_rows = np.asarray(light, dtype=np.float32)
        self.x0 = mi.Point3f(*(float(c) for c in light))
        self.intensity = float(intensity)
        self.fog = fog
        self.box = mi.BoundingBox3f(mi.Point3f(*map(float, fog.lo)), mi.Point3f(*map(float, fog.hi)))
        self.phase = omnee.Phase(fog.phase)

    def transmittance(self, a: mi.Point3f, b: mi.Point3f) -> mi.Float:
        """T(a, b) = exp(−σt ℓ)."""
        return dr.exp(-self.fog.sigma_t * length_in_box(self.box, a, b))

    def visible(self, a: mi.Point3f, b: mi.Point3f, active: mi.Bool) -> mi.Bool:
        """V(a, b) between two points on no surface (the light, a fog
        vertex): a shadow ray from `a` that stops just short of `b`."""
        d = b - a
        dist = dr.norm(d)
        ray = mi.Ray3f(a, d / dr.maximum(dist, 1e-30), (1.0 - 1e-4) * dist)
        return ~self.scene.ray_test(ray, active)

    def visible_from_surface(self, si: mi.SurfaceInteraction3f, p: mi.Point3f, active: mi.Bool) -> mi.Bool:
        """V(x2, p) from the surface hit: `spawn_ray_to` offsets the ray's
        ends against self-intersection."""
        return ~self.scene.ray_test(si.spawn_ray_to(p), active)

    def bsdf_cos(self, si: mi.SurfaceInteraction3f, p: mi.Point3f, active: mi.Bool) -> mi.Float:
        """`f(x2, ωi, ωo) cos θo` towards `p` from the hit (the first colour
        channel: the scene is grey)."""
        wo = si.to_local(dr.normalize(p - si.p))
        return si.bsdf().eval(mi.BSDFContext(), si, wo, active)[0]

    def render_pass(self, spp: int, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
        """One pass of `spp` camera samples per pixel: the images (height,
        width) of the direct and the once-more light, each pixel the mean of
        its samples (a box filter, as Mitsuba's `hdrfilm` with `box`); the
        pixel's radiance is their sum."""
        w, h = self.width, self.height
        pixel = np.repeat(np.arange(w * h, dtype=np.uint32), spp)
        n = pixel.size
        # 1. Camera rays through jittered positions in each pixel, and their hits.
        film = (np.stack([pixel % w, pixel // w]) + rng.random((2, n))) / np.array([[w], [h]])
        rays, _ = self.sensor.sample_ray(0.0, 0.5, mi.Point2f(film.astype(np.float32)), mi.Point2f(0.5))
        si = self.scene.ray_intersect(rays)
        # Evaluate the hits once: Dr.Jit is lazy, and every later kernel
        # that reads `si` would otherwise trace the camera rays again.
        dr.eval(si)
        hit = si.is_valid()
        x2 = si.p

        # 2. Direct light: I · V(x0, x2) T(x0, x2) · f cos θ2 / |x0 − x2|².
        direct = dr.select(
            hit & self.visible_from_surface(si, self.x0, hit),
            self.intensity
            * self.transmittance(self.x0, x2)
            * self.bsdf_cos(si, self.x0, hit)
            / dr.maximum(dr.squared_norm(self.x0 - x2), 1e-12),
            0.0,
        )

        # 3. omnee: one once-more vertex x1 per row, all rows in one call.
        #    Rows whose camera ray hit nothing get a dummy x2 and are dropped.
        x2_rows = rows(dr.select(hit, x2, self.x0 + 1.0))
        u = rng.random((n, 3), dtype=np.float32)  # float32: omnee samples in f32
        s = omnee.Omnee(x0=self.x0_rows, x2=x2_rows, phase=self.phase).sample(u)
        x1 = mi.Point3f(np.ascontiguousarray(s.x1.T))
        weight = mi.Float(s.weight)

        # 4. f_c · weight; σs(x1) = 0 outside the fog.
        live = hit & mi.Bool(s.valid) & self.box.contains(x1)
        live &= self.visible(x1, self.x0, live) & self.visible_from_surface(si, x1, live)
        f_c = (
            self.intensity
            * self.fog.sigma_s
            * self.transmittance(self.x0, x1)
            * self.transmittance(x1, x2)
            * self.bsdf_cos(si, x1, live)
        )
        once_more = dr.select(live, f_c * weight, 0.0)

        def image(values) -> np.ndarray:
            sums = np.bincount(pixel, weights=np.asarray(values, dtype=np.float64), minlength=w * h)
            return (sums / spp).reshape(h, w)

        return image(direct), image(once_more)
