"""The light-side point ``x0`` of the once-more strategies: drawn on the
scene's finite emitters, its density, the light it sends towards ``x1``, and
the density with which Mitsuba's own next event estimation would have picked
it.

Densities of ``x0`` are in the area measure on a surface emitter, and the
probability of picking the emitter alone for a delta-position one (point,
spot): every strategy that reaches a delta light carries the same delta,
so MIS compares what is left.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import drjit as dr
import mitsuba as mi


class LightPoint(NamedTuple):
    """A point ``x0`` on an emitter."""

    p: Any
    """The position (``mi.Point3f``)."""
    n: Any
    """The surface normal (zero for a delta position)."""
    uv: Any
    """The surface parameterisation (``mi.Point2f``)."""
    emitter: Any
    """``mi.EmitterPtr``."""
    delta: Any
    """Whether ``x0`` is a delta position (``mi.Bool``)."""
    pdf: Any
    """Its density under :func:`sample` (``mi.Float``): the emitter's
    probability times the area density on a surface emitter."""


def _has(flags: Any, flag: Any) -> Any:
    return (mi.UInt32(flags) & mi.UInt32(int(flag))) != 0


def is_delta(emitter: Any) -> Any:
    """Per lane: the emitter has a delta position."""
    return _has(emitter.flags(), mi.EmitterFlags.DeltaPosition)


def is_finite(emitter: Any) -> Any:
    """Per lane: the emitter has a position to connect to (delta or a
    surface), and is no environment."""
    flags = emitter.flags()
    finite = _has(flags, mi.EmitterFlags.DeltaPosition) | _has(flags, mi.EmitterFlags.Surface)
    return (emitter != None) & finite & ~_has(flags, mi.EmitterFlags.Infinite)  # noqa: E711


def light_pmf(info: Any, emitter: Any, active: Any) -> Any:
    """The probability with which :func:`sample` picks ``emitter`` (0 for
    emitters it never picks)."""
    total = sum(info.light_weights)
    active = mi.Bool(active) & is_finite(emitter)
    return dr.select(active, emitter.sampling_weight() / total, 0.0)


def nee_pmf(info: Any, emitter: Any, active: Any) -> Any:
    """The probability with which Mitsuba's next event estimation picks
    ``emitter`` (``Scene::pdf_emitter``: sampling weight over the sum)."""
    active = mi.Bool(active) & (emitter != None)  # noqa: E711
    return dr.select(active, emitter.sampling_weight() / info.all_weights, 0.0)


def sample(info: Any, u_emitter: Any, u_position: Any, time: Any, active: Any) -> LightPoint:
    """``x0``: an emitter with probability proportional to its sampling
    weight among the finite ones, then its position (the emitter's own for
    a delta light; uniform in area on a surface emitter's shape, whose
    ``pdf_position`` gives the density)."""
    active = mi.Bool(active)
    index = info.light_distribution.sample(u_emitter, active)
    emitter = dr.gather(mi.EmitterPtr, info.lights_ptr, index, active)
    delta = active & is_delta(emitter)
    surface = active & ~delta
    ps_delta, _ = emitter.sample_position(time, u_position, delta)
    shape = emitter.get_shape()
    ps_area = shape.sample_position(time, u_position, surface)
    area_pdf = shape.pdf_position(ps_area, surface)
    p = dr.select(delta, ps_delta.p, ps_area.p)
    n = dr.select(delta, mi.Normal3f(0.0), ps_area.n)
    uv = dr.select(delta, ps_delta.uv, ps_area.uv)
    pmf = light_pmf(info, emitter, active)
    pdf = dr.select(delta, pmf, pmf * area_pdf)
    ok = active & (pdf > 0.0)
    return LightPoint(p, n, uv, emitter, delta, dr.select(ok, pdf, 0.0))


def density(info: Any, emitter: Any, ps: Any, active: Any) -> Any:
    """The density of :func:`sample` at a position ``ps`` found otherwise
    (next event estimation's ``DirectionSample3f``, an emitter hit)."""
    active = mi.Bool(active) & is_finite(emitter)
    delta = active & is_delta(emitter)
    pmf = light_pmf(info, emitter, active)
    area = emitter.get_shape().pdf_position(ps, active & ~delta)
    return dr.select(delta, pmf, pmf * area)


class Emission(NamedTuple):
    """What ``x0`` sends towards ``x1``."""

    value: Any
    """``Le |cos θ0|`` of a surface emitter, the intensity (with a spot's
    falloff) of a delta light: the emitted light without the ``1/d10²``
    (``mi.Spectrum``)."""
    ds: Any
    """The ``mi.DirectionSample3f`` from ``x1`` to ``x0``."""
    g0: Any
    """``|cos θ0|/d10²`` (surface) or ``1/d10²`` (delta): from ``x0``'s
    density per area to the solid angle at ``x1``, and the geometry factor."""


def emission(x1: Any, x0: LightPoint, active: Any) -> Emission:
    """The light ``x0`` sends to the interaction ``x1`` (its ``p``, ``time``,
    ``wavelengths``). A delta light is asked by its own ``sample_direction``
    from ``x1``, which ignores its sample and connects to its position (and
    sets what its ``eval`` reads: a spot's falloff, a projector's texture
    coordinates); a surface emitter by ``eval_direction`` at the point
    :func:`sample` chose."""
    active = mi.Bool(active)
    delta = active & x0.delta
    surface = active & ~x0.delta
    d = x0.p - x1.p
    dist = dr.norm(d)
    d = d / dist
    ds = mi.DirectionSample3f(
        x0.p, x0.n, x0.uv, x1.time, mi.Float(0.0), x0.delta, d, dist, x0.emitter
    )
    value = mi.Spectrum(x0.emitter.eval_direction(x1, ds, surface))
    ds_delta, value_delta = x0.emitter.sample_direction(x1, mi.Point2f(0.5), delta)
    ds[delta] = ds_delta
    cos0 = dr.abs(dr.dot(ds.d, ds.n))
    inv_d2 = dr.rcp(dr.square(ds.dist))
    value = dr.select(delta, mi.Spectrum(value_delta) * dr.square(ds.dist), value * cos0)
    g0 = dr.select(delta, inv_d2, cos0 * inv_d2)
    ok = active & (ds.dist > 0.0) & dr.isfinite(ds.dist)
    return Emission(dr.select(ok, value, 0.0), ds, dr.select(ok, g0, 0.0))
