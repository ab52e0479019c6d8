"""Between Dr.Jit's lanes and omnee's numpy batches.

The omnee core draws and evaluates in numpy arrays with one row per
connection. These helpers take the lanes of a Dr.Jit array where a mask is
set, hand them to omnee as rows (``float32`` for the once-more vertex, as a
renderer's precision; ``float64`` for the distances along rays), and put the
results back into full-width Dr.Jit arrays (zero on the other lanes).
"""

from __future__ import annotations

from typing import Any, List, Sequence, Tuple

import drjit as dr
import mitsuba as mi
import numpy as np

import omnee


def lanes(mask: Any) -> Any:
    """The indices of the lanes where ``mask`` is set (``mi.UInt32``)."""
    return dr.compress(mi.Bool(mask))


def rows(index: Any, *arrays: Any, dtype: Any = np.float32) -> List[np.ndarray]:
    """The lanes ``index`` of Dr.Jit arrays as numpy rows, gathered in one
    kernel: ``(k, 3)`` for a 3-vector, ``(k,)`` for a scalar."""
    gathered = [dr.gather(type(x), x, index) for x in arrays]
    dr.eval(gathered)
    out = []
    for g in gathered:
        values = np.asarray(g, dtype=dtype)
        out.append(np.ascontiguousarray(values.T) if values.ndim == 2 else values)
    return out


def _put(width: int, index: Any, values: np.ndarray, kind: Any) -> Any:
    out = dr.zeros(kind, width)
    dr.scatter(out, kind(values), index)
    return out


def floats(width: int, index: Any, values: Any) -> Any:
    """``values`` (``(k,)``) at lanes ``index`` of a zero ``mi.Float`` of
    ``width``."""
    return _put(width, index, np.ascontiguousarray(values, dtype=np.float32), mi.Float)


def points(width: int, index: Any, values: Any) -> Any:
    """``values`` (``(k, 3)``) at lanes ``index`` of a zero ``mi.Point3f``."""
    return _put(width, index, np.ascontiguousarray(np.asarray(values, dtype=np.float32).T), mi.Point3f)


def mask(width: int, index: Any, values: Any) -> Any:
    """``values`` (bool ``(k,)``) at lanes ``index`` of a false ``mi.Bool``."""
    return _put(width, index, np.ascontiguousarray(values, dtype=bool), mi.Bool)


def connectable(x0: Any, x2: Any) -> Any:
    """Lanes whose end points the core accepts: finite and distinct (it
    refuses ``x0 == x2``)."""
    return dr.all(dr.isfinite(x0)) & dr.all(dr.isfinite(x2)) & dr.any(x0 != x2)


def omnee_draw(groups: Sequence[Any], group: Any, x0: Any, x2: Any, u: Any, active: Any) -> Tuple[Any, Any, Any]:
    """OMNEE's vertex ``x1`` for every active lane, drawn by the core's
    batch over connections (float32) with its group's phase function:
    ``(x1, pdf, valid)``, the vertex and its volume density."""
    width = dr.width(active)
    x1 = dr.zeros(mi.Point3f, width)
    pdf = dr.zeros(mi.Float, width)
    valid = dr.zeros(mi.Bool, width)
    active = mi.Bool(active) & connectable(x0, x2)
    for g, grp in enumerate(groups):
        index = lanes(active & (group == g))
        if dr.width(index) == 0:
            continue
        a, b, uu = rows(index, x0, x2, u)
        s = omnee.Omnee(x0=a, x2=b, phase=grp.phase).sample(uu)
        x1 += points(width, index, s.x1)
        pdf += floats(width, index, s.pdf)
        valid |= mask(width, index, s.valid)
    return x1, pdf, valid


def omnee_pdf(groups: Sequence[Any], group: Any, x0: Any, x2: Any, x1: Any, active: Any) -> Any:
    """The density with which OMNEE at ``x2`` (with its group's phase
    function) draws ``x1`` for the light point ``x0``; 0 on other lanes."""
    width = dr.width(active)
    pdf = dr.zeros(mi.Float, width)
    active = mi.Bool(active) & connectable(x0, x2)
    for g, grp in enumerate(groups):
        index = lanes(active & (group == g))
        if dr.width(index) == 0:
            continue
        a, b, c = rows(index, x0, x2, x1)
        pdf += floats(width, index, omnee.Omnee(x0=a, x2=b, phase=grp.phase).pdf(c))
    return pdf


def segment_ok(x0: Any, origin: Any, direction: Any, t_min: Any, t_max: Any) -> Any:
    """Lanes whose segments the core accepts: finite, ``0 ≤ t_min < t_max``,
    and ``x0`` not on the segment itself (off the line by more than 10⁻⁵
    of its distance, far beyond rounding, or past either end)."""
    to_light = x0 - origin
    d = dr.normalize(direction)
    off = dr.norm(dr.cross(to_light, d)) > 1e-5 * dr.norm(to_light)
    foot = dr.dot(to_light, d)
    return (dr.all(dr.isfinite(x0)) & dr.all(dr.isfinite(origin)) & dr.all(dr.isfinite(direction))
            & (t_min >= 0.0) & dr.isfinite(t_min) & (t_max > t_min)
            & (off | (foot < t_min) | (foot > t_max)))


def equiangular_draw(x0: Any, origin: Any, direction: Any, t_max: Any, u: Any, active: Any) -> Tuple[Any, Any, Any]:
    """The core's equiangular distance along each active lane's ray
    ``origin + t direction``, ``t ∈ [0, t_max]`` (∞ allowed), towards ``x0``:
    ``(t, pdf, valid)``, the distance and its density per metre."""
    width = dr.width(active)
    t = dr.zeros(mi.Float, width)
    pdf = dr.zeros(mi.Float, width)
    index = lanes(mi.Bool(active) & segment_ok(x0, origin, direction, 0.0, t_max))
    if dr.width(index) == 0:
        return t, pdf, dr.zeros(mi.Bool, width)
    a, o, d, hi, uu = rows(index, x0, origin, direction, mi.Float(t_max), u)
    s = omnee.EquiangularSegment(a, o, d, 0.0, hi).sample(uu)
    return floats(width, index, s.t), floats(width, index, s.pdf), mask(width, index, s.valid)


def equiangular_pdf(x0: Any, origin: Any, direction: Any, t_min: Any, t_max: Any, t: Any, active: Any) -> Any:
    """The density per metre of the equiangular distance ``t`` on the
    segments ``[t_min, t_max]`` of the rays, towards ``x0``; 0 elsewhere."""
    width = dr.width(active)
    index = lanes(mi.Bool(active) & segment_ok(x0, origin, direction, t_min, t_max))
    if dr.width(index) == 0:
        return dr.zeros(mi.Float, width)
    a, o, d, lo, hi, tt = rows(index, x0, origin, direction, mi.Float(t_min), mi.Float(t_max), mi.Float(t))
    return floats(width, index, omnee.EquiangularSegment(a, o, d, lo, hi).pdf(tt))
