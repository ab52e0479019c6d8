"""Between Dr.Jit's lanes and omnee's numpy batches.

The omnee core draws and evaluates in numpy arrays with one row per
connection. These helpers take the lanes of a Dr.Jit array where a mask is
set, hand them to omnee as rows (``float32`` for the once-more vertex, as a
renderer's precision; ``float64`` for the distances along rays), and put the
results back into full-width Dr.Jit arrays (zero on the other lanes).
"""

from __future__ import annotations

from typing import Any, Iterator, List, Sequence, Tuple

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
        # Component by component: numpy reads an evaluated mi.Float in
        # place, while a 3-vector would be packed by a kernel with the row
        # count compiled in (a new kernel for every batch size).
        if dr.size_v(g) == 3:
            out.append(np.stack([np.asarray(g[i], dtype=dtype) for i in range(3)], axis=1))
        else:
            out.append(np.asarray(g, dtype=dtype))
    return out


def _jit(kind: Any, values: Any, dtype: Any) -> Any:
    """A Dr.Jit array of the 1-D ``values``, copied to a 64-byte aligned
    numpy buffer first. Dr.Jit maps numpy memory rather than copying it and
    compiles the pointer's alignment into the kernels that read it (and a
    2-D array's row length as a literal): from aligned 1-D buffers the
    kernels are the same for every batch size and allocation, so a new
    seed or image does not compile them again."""
    values = np.asarray(values, dtype=dtype).ravel()
    pad = 64 // values.itemsize
    buffer = np.empty(values.size + pad, dtype=dtype)
    start = (-buffer.ctypes.data % 64) // values.itemsize
    aligned = buffer[start:start + values.size]
    aligned[...] = values
    return kind(aligned)


def _put(width: int, index: Any, value: Any) -> Any:
    out = dr.zeros(type(value), width)
    dr.scatter(out, value, index)
    return out


def floats(width: int, index: Any, values: Any) -> Any:
    """``values`` (``(k,)``) at lanes ``index`` of a zero ``mi.Float`` of
    ``width``."""
    return _put(width, index, _jit(mi.Float, values, np.float32))


def points(width: int, index: Any, values: Any) -> Any:
    """``values`` (``(k, 3)``) at lanes ``index`` of a zero ``mi.Point3f``."""
    v = np.asarray(values, dtype=np.float32)
    return _put(width, index, mi.Point3f(*(_jit(mi.Float, v[:, i], np.float32) for i in range(3))))


def mask(width: int, index: Any, values: Any) -> Any:
    """``values`` (bool ``(k,)``) at lanes ``index`` of a false ``mi.Bool``."""
    return _put(width, index, _jit(mi.Bool, values, bool))


def connectable(x0: Any, x2: Any) -> Any:
    """Lanes whose end points the core accepts: finite and distinct (it
    refuses ``x0 == x2``)."""
    return dr.all(dr.isfinite(x0)) & dr.all(dr.isfinite(x2)) & dr.any(x0 != x2)


def _refused_row(error: ValueError) -> int:
    """The row a ValueError of the core names (``row N: …``), or −1."""
    text = str(error)
    if text.startswith("row "):
        head = text[4:].split(":", 1)[0]
        if head.isdigit():
            return int(head)
    return -1


def _rows_accepted(call: Any, arrays: Sequence[np.ndarray]) -> Tuple[np.ndarray, Any]:
    """``call(*arrays)`` on the rows the core accepts: a row it refuses
    (which the lanes' own checks should have left out; rounding can differ
    at a hair's breadth) is dropped and the call made again. Returns the
    rows kept and the call's result on them."""
    keep = np.arange(len(arrays[0]))
    for _ in range(16):
        try:
            return keep, call(*[a[keep] for a in arrays])
        except ValueError as error:
            row = _refused_row(error)
            if row < 0:
                raise
            keep = np.delete(keep, row)
    raise RuntimeError("the omnee core refused more rows than expected")


def _kept(index: Any, kept: np.ndarray) -> Any:
    """The lanes of ``index`` whose rows :func:`_rows_accepted` kept."""
    if len(kept) == dr.width(index):
        return index
    return dr.gather(mi.UInt32, index, _jit(mi.UInt32, kept, np.uint32))


def _by_group(groups: Sequence[Any], group: Any, active: Any, call: Any, *arrays: Any) -> Iterator[Tuple[Any, Any]]:
    """For each group with active lanes: the lanes the core accepted and
    ``call(phase, *rows)``, the core's result on their rows with the
    group's phase function."""
    for g, grp in enumerate(groups):
        index = lanes(active & (group == g))
        if dr.width(index) == 0:
            continue
        kept, result = _rows_accepted(lambda *r: call(grp.phase, *r), rows(index, *arrays))
        yield _kept(index, kept), result


def omnee_draw(groups: Sequence[Any], group: Any, x0: Any, x2: Any, u: Any, active: Any) -> Tuple[Any, Any, Any]:
    """OMNEE's vertex ``x1`` for every active lane, drawn by the core's
    batch over connections (float32) with its group's phase function:
    ``(x1, pdf, valid)``, the vertex and its volume density."""
    width = dr.width(active)
    x1 = dr.zeros(mi.Point3f, width)
    pdf = dr.zeros(mi.Float, width)
    valid = dr.zeros(mi.Bool, width)
    active = mi.Bool(active) & connectable(x0, x2)
    draw = lambda phase, a, b, uu: omnee.Omnee(x0=a, x2=b, phase=phase).sample(uu)  # noqa: E731
    for index, s in _by_group(groups, group, active, draw, x0, x2, u):
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
    density = lambda phase, a, b, c: omnee.Omnee(x0=a, x2=b, phase=phase).pdf(c)  # noqa: E731
    for index, values in _by_group(groups, group, active, density, x0, x2, x1):
        pdf += floats(width, index, values)
    return pdf


def segment_ok(x0: Any, origin: Any, direction: Any, t_min: Any, t_max: Any) -> Any:
    """Lanes whose segments the core accepts, with a margin: finite,
    ``0 ≤ t_min < t_max``, and ``x0`` off the ray's line by more than 10⁻⁴
    of its distance, or clearly before or past the segment. Equiangular
    sampling does not run on the others (and so has no density there: every
    strategy's weight sees the same rule)."""
    to_light = x0 - origin
    d = dr.normalize(direction)
    scale = dr.norm(to_light)
    off = dr.norm(dr.cross(to_light, d)) > 1e-4 * scale
    foot = dr.dot(to_light, d)
    margin = 1e-4 * scale
    return (dr.all(dr.isfinite(x0)) & dr.all(dr.isfinite(origin)) & dr.all(dr.isfinite(direction))
            & (t_min >= 0.0) & dr.isfinite(t_min) & (t_max > t_min) & (scale > 0.0)
            & (off | (foot < t_min - margin) | (foot > t_max + margin)))


def equiangular_draw(x0: Any, origin: Any, direction: Any, t_max: Any, u: Any, active: Any) -> Tuple[Any, Any, Any]:
    """The core's equiangular distance along each active lane's ray
    ``origin + t direction``, ``t ∈ [0, t_max]`` (∞ allowed), towards ``x0``
    (in float64: the rows' checks then see the lanes' values exactly):
    ``(t, pdf, valid)``, the distance and its density per metre."""
    width = dr.width(active)
    t = dr.zeros(mi.Float, width)
    pdf = dr.zeros(mi.Float, width)
    index = lanes(mi.Bool(active) & segment_ok(x0, origin, direction, 0.0, t_max))
    if dr.width(index) == 0:
        return t, pdf, dr.zeros(mi.Bool, width)
    kept, s = _rows_accepted(lambda a, o, d, hi, uu: omnee.EquiangularSegment(a, o, d, 0.0, hi).sample(uu),
                             rows(index, x0, origin, direction, mi.Float(t_max), u, dtype=np.float64))
    index = _kept(index, kept)
    return floats(width, index, s.t), floats(width, index, s.pdf), mask(width, index, s.valid)


def equiangular_pdf(x0: Any, origin: Any, direction: Any, t_min: Any, t_max: Any, t: Any, active: Any) -> Any:
    """The density per metre of the equiangular distance ``t`` on the
    segments ``[t_min, t_max]`` of the rays, towards ``x0``; 0 elsewhere."""
    width = dr.width(active)
    index = lanes(mi.Bool(active) & segment_ok(x0, origin, direction, t_min, t_max))
    if dr.width(index) == 0:
        return dr.zeros(mi.Float, width)
    kept, values = _rows_accepted(
        lambda a, o, d, lo, hi, tt: omnee.EquiangularSegment(a, o, d, lo, hi).pdf(tt),
        rows(index, x0, origin, direction, mi.Float(t_min), mi.Float(t_max), mi.Float(t), dtype=np.float64))
    return floats(width, _kept(index, kept), values)
