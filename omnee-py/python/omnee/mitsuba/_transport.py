"""Transmittance between two points of a Mitsuba scene, through null
interfaces, from Mitsuba's medium API; and the optical-depth proxy of the
MIS densities.

:func:`walk` follows a shadow ray from its origin to ``ray.maxt`` as
volpath's next event estimation does: across surfaces whose BSDF lets light
through unchanged (``null``; ``eval_null_transmission``), switching media at
each, with the closed form ``exp(−σt ℓ)`` in homogeneous media and ratio
tracking (each tentative collision against the majorant ``σ̄`` multiplies by
``σn/σ̄``) in heterogeneous ones. Any other surface blocks it.

On the way it adds up the optical-depth proxy ``τ = Σ m ℓ`` over the
segments it crosses, with ``m`` the mean over the spectrum's channels of the
medium's majorant (σt itself in a homogeneous medium): a deterministic
function of the path, so that every strategy evaluates the same free-flight
density for the same vertex (docs/mitsuba.md).
"""

from __future__ import annotations

from typing import Any, Optional, Tuple

import drjit as dr
import mitsuba as mi


def medium_interaction(medium: Any, p: Any, wi: Any, wavelengths: Any, time: Any, active: Any) -> Any:
    """A ``mi.MediumInteraction3f`` at ``p`` in ``medium`` (incoming
    direction ``wi`` pointing back towards the previous vertex), with the
    medium's coefficients at ``p``: ``sigma_s``, ``sigma_n``, ``sigma_t``."""
    n = dr.width(p)
    mei = dr.zeros(mi.MediumInteraction3f, n)
    mei.p = mi.Point3f(p)
    mei.wi = mi.Vector3f(wi)
    mei.sh_frame = mi.Frame3f(mei.wi)
    mei.time = mi.Float(time)
    mei.wavelengths = wavelengths
    mei.medium = medium
    mei.t = mi.Float(0.0)
    mei.mint = mi.Float(0.0)
    # A medium exists only inside its bounding box, where its free flights
    # are sampled (a grid's lookup would clamp to its edge outside it).
    inside = mi.Bool(active) & contains(medium, p)
    sigma_s, sigma_n, sigma_t = medium.get_scattering_coefficients(mei, inside)
    mei.sigma_s = dr.select(inside, sigma_s, 0.0)
    mei.sigma_n = dr.select(inside, sigma_n, 0.0)
    mei.sigma_t = dr.select(inside, sigma_t, 0.0)
    mei.combined_extinction = medium.get_majorant(mei, active)
    return mei


def contains(medium: Any, p: Any) -> Any:
    """Whether ``p`` lies in the bounding box of ``medium``: a ray from
    ``p`` enters the box at or before its origin and leaves it at or after
    (a homogeneous medium, unbounded, answers [0, ∞) everywhere)."""
    # A direction along no axis: the slab test of an axis the ray is
    # parallel to divides by zero.
    ray = mi.Ray3f(mi.Point3f(p), mi.Vector3f(0.48, 0.6, 0.64))
    hit, mint, maxt = medium.intersect_aabb(ray)
    return hit & (mint <= 0.0) & (maxt >= 0.0)


def medium_interaction_at(p: Any, wavelengths: Any) -> Any:
    """A bare ``mi.MediumInteraction3f`` at ``p``: what a medium's
    ``get_majorant`` reads."""
    mei = dr.zeros(mi.MediumInteraction3f, dr.width(p))
    mei.p = mi.Point3f(p)
    mei.wavelengths = wavelengths
    return mei


def mean_channels(spec: Any) -> Any:
    """The mean over the spectrum's channels, per lane. (Not ``dr.mean(…,
    axis=0)``, which compiles the array's width into its kernel as a literal:
    a new kernel for every wavefront size.)"""
    s = mi.UnpolarizedSpectrum(spec)
    n = dr.size_v(s)
    total = s[0]
    for i in range(1, n):
        total = total + s[i]
    return total * (1.0 / n)


def extinction_rate(medium: Any, p: Any, wavelengths: Any, active: Any) -> Any:
    """``m``, the proxy's extinction rate of ``medium`` (per metre): the mean
    over channels of its majorant at ``p`` (σt in a homogeneous medium), 0
    outside any medium."""
    active = mi.Bool(active) & (medium != None)  # noqa: E711 (Dr.Jit pointer test)
    majorant = medium.get_majorant(medium_interaction_at(p, wavelengths), active)
    return dr.select(active, mean_channels(majorant), 0.0)


def walk(scene: Any, u: Any, ray: Any, medium: Any, channel: Any, active: Any,
         length: Optional[Any] = None) -> Tuple[Any, Any, Any]:
    """Follows ``ray`` (unit direction) from its origin to ``ray.maxt`` on
    the lanes of ``active``; with ``length``, surfaces count up to
    ``ray.maxt`` (a shadow ray stops short of the surface it aims at) and the
    media up to ``length`` (the full distance to a point ``x1`` or ``x0``:
    Mitsuba's ``spawn_ray_to`` shortens ``maxt`` by 10⁻³, which would bias
    the transmittance by ``e^{10⁻³ σt d}``).

    Returns ``(tr, tau, medium)``: the transmittance estimate per channel
    (0 where a surface blocks the way, and on the other lanes), the proxy
    optical depth ``τ`` of the way, and the medium at its end (``None``
    outside media). The active lanes are gathered first (a wavefront's
    shadow rays are a fraction of its lanes) and walked in one symbolic
    loop; ratio tracking draws from a PCG32 stream per lane seeded by the
    uniform number ``u``."""
    width = dr.width(active)
    index = dr.compress(mi.Bool(active))
    k = dr.width(index)
    tr = dr.zeros(mi.Spectrum, width)
    tau = dr.zeros(mi.Float, width)
    end = dr.zeros(mi.MediumPtr, width)
    if k == 0:
        return tr, tau, end

    def take(x: Any) -> Any:
        return dr.gather(type(x), x, index)

    seed = take(mi.UInt32(mi.Float(u) * 4294967040.0))
    full = take(mi.Float(ray.maxt if length is None else length) + dr.zeros(mi.Float, width))
    ray = mi.Ray3f(take(ray.o), take(ray.d), take(ray.maxt), take(ray.time), take(ray.wavelengths))
    channel = take(mi.UInt32(channel) + dr.zeros(mi.UInt32, width))
    tr_k, tau_k, end_k = _walk(scene, mi.PCG32(k, mi.UInt64(seed)), ray, full,
                               take(mi.MediumPtr(medium)), channel)
    dr.scatter(tr, tr_k, index)
    dr.scatter(tau, tau_k, index)
    dr.scatter(end, end_k, index)
    return tr, tau, end


def _walk(scene: Any, rng: Any, ray: Any, length: Any, medium: Any, channel: Any) -> Tuple[Any, Any, Any]:
    """:func:`walk` on lanes that are all active, with the masked updates
    of volpath's shadow rays (no branches: one straight loop body)."""
    n = dr.width(ray.o)
    ray = mi.Ray3f(ray)
    cutoff = mi.Float(ray.maxt)
    max_dist = mi.Float(length)
    state = (
        dr.full(mi.Bool, True, n),  # active
        ray,
        mi.MediumPtr(medium),
        dr.zeros(mi.Float, n),  # total distance
        dr.full(mi.Spectrum, 1.0, n),  # tr
        dr.zeros(mi.Float, n),  # tau
        dr.full(mi.Bool, True, n),  # needs an intersection
        dr.zeros(mi.SurfaceInteraction3f, n),
        rng,
    )

    def body(active: Any, ray: Any, medium: Any, total: Any, tr: Any, tau: Any, needs: Any, si: Any,
             rng: Any) -> Tuple[Any, ...]:
        remaining = max_dist - total
        ray.maxt = cutoff - total
        active &= remaining > 0.0
        needs &= active
        # Position, normals and the shape: all a crossing needs (nothing
        # past the cutoff: no surface counts there).
        query = needs & (ray.maxt > 0.0)
        si[query] = scene.ray_intersect(ray, mi.RayFlags.Minimal, False, query)
        si.t[needs & (~query | ~si.is_valid())] = dr.inf
        needs = mi.Bool(False)

        in_medium = active & (medium != None)  # noqa: E711
        segment_end = dr.minimum(remaining, si.t)
        mei = dr.zeros(mi.MediumInteraction3f)
        mei.p = ray.o
        mei.wavelengths = ray.wavelengths
        majorant = mi.Spectrum(medium.get_majorant(mei, in_medium))
        rate = mean_channels(majorant)

        # Homogeneous media: straight to the segment's end, in closed form.
        homogeneous = in_medium & medium.is_homogeneous()
        tr[homogeneous] *= dr.exp(-majorant * segment_end)

        # Heterogeneous media: one tentative collision of ratio tracking.
        tracking = in_medium & ~homogeneous
        collision = medium.sample_interaction(ray, rng.next_float32(), channel, tracking)
        collided = tracking & collision.is_valid() & (collision.t < segment_end)
        tr[collided] *= mi.Spectrum(collision.sigma_n) / mi.Spectrum(collision.combined_extinction)
        ray.o[collided] = collision.p
        si.t[collided] = si.t - collision.t
        total[collided] += collision.t
        tau[collided] += rate * collision.t

        # Everything else reached its segment's end: a surface or the target.
        ended = active & ~collided
        tau[ended] += dr.select(in_medium, rate, 0.0) * segment_end
        total[ended] += segment_end
        crossing = ended & si.is_valid() & (si.t <= remaining)
        bsdf = si.bsdf(ray)
        tr[crossing] *= bsdf.eval_null_transmission(si, crossing)
        ray[crossing] = si.spawn_ray(ray.d)
        needs |= crossing
        medium[crossing & si.is_medium_transition()] = si.target_medium(ray.d)
        active &= (collided | crossing) & dr.any(tr != 0.0)
        return active, ray, medium, total, tr, tau, needs, si, rng

    out = dr.while_loop(state, lambda active, *_: active, body, label="omnee walk")
    _, _, medium, _, tr, tau, _, _, _ = out
    return tr, tau, medium
