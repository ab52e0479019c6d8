"""Mitsuba's phase functions as omnee phase functions.

The omnee core draws the deflection θ of the once-more vertex from a phase
function of its own; this module builds it from the scene's. Mitsuba's ``hg``
and omnee's ``hg`` are the same function of the deflection θ (Mitsuba
evaluates ``1 + g² + 2g ωi·ωo`` with ``ωi`` pointing back along the incoming
ray, so ``ωi·ωo = −cos θ``); ``blendphase`` ``(1 − w)·p0 + w·p1`` of two
Henyey–Greenstein lobes (``isotropic`` is ``hg`` with g = 0) is omnee's
two-term ``tthg:g0,g1,(1 − w)``; ``tabphase``, linear in ``cos θ`` between
values on a regular grid of ``cos θ ∈ [−1, 1]``, becomes an omnee table
constant per solid angle on bins that split each grid interval in
``TABLE_REFINE`` parts, valued at their midpoints in ``cos θ``.

Whatever omnee draws with, the integrator evaluates the scene's own phase
function at ``x1`` and divides by omnee's density: an approximation in the
mapping (the table's bins) costs variance, never bias.
"""

from __future__ import annotations

import math
from typing import Any, List, Optional, Tuple

import numpy as np

import omnee

TABLE_REFINE = 8
"""Bins of the omnee table per interval of Mitsuba's ``tabphase`` grid."""


class Unsupported(Exception):
    """A phase function omnee has no kind for; the message says which."""


def _children(obj: Any) -> List[Tuple[str, Any]]:
    """The named child objects (phase functions, volumes) Mitsuba's
    ``traverse`` reports for ``obj``."""
    import mitsuba as mi

    found: List[Tuple[str, Any]] = []

    class Collect(mi.TraversalCallback):  # type: ignore[misc]
        def put(self, name: str, value: Any, flags: Any) -> None:
            found.append((name, value))

    obj.traverse(Collect())
    return found


def _scalar(values: Any) -> float:
    """The one number of a Mitsuba scalar parameter (a width-1 array)."""
    a = np.asarray(values, dtype=np.float64).ravel()
    if a.size != 1:
        raise Unsupported(f"expected one number, got {a.size}")
    return float(a[0])


def _constant_weight(volume: Any) -> float:
    """The value of a constant ``blendphase`` weight volume."""
    if volume.class_name() != "ConstVolume":
        raise Unsupported(f"blendphase with a spatially varying weight ({volume.class_name()})")
    import mitsuba as mi

    params = mi.traverse(volume)
    keys = [k for k in params.keys() if k.endswith("value")]
    if len(keys) != 1:
        raise Unsupported("blendphase weight: not one constant value")
    return _scalar(params[keys[0]])


def _hg_g(phase: Any) -> Optional[float]:
    """g of a Henyey–Greenstein lobe (``hg``, or ``isotropic`` as g = 0),
    else None."""
    name = phase.class_name()
    if name == "IsotropicPhaseFunction":
        return 0.0
    if name == "HGPhaseFunction":
        import mitsuba as mi

        return _scalar(mi.traverse(phase)["g"])
    return None


def table_bins(values: np.ndarray, refine: int = TABLE_REFINE) -> Tuple[np.ndarray, np.ndarray]:
    """omnee table bins for Mitsuba's ``tabphase`` ``values``: the phase
    function's values at ``cos θ = −1 + 2i/(n − 1)``, linear in between.
    Returns the bin edges in θ (from 0 to π) and the bins' values, each the
    linear interpolant at its midpoint in ``cos θ``."""
    values = np.asarray(values, dtype=np.float64)
    n = values.size
    if n < 2:
        raise Unsupported("tabphase with fewer than two values")
    # Edges in cos θ from 1 (θ = 0) down to −1 (θ = π).
    cos_edges = np.linspace(1.0, -1.0, (n - 1) * refine + 1)
    mid = 0.5 * (cos_edges[:-1] + cos_edges[1:])
    grid = np.linspace(-1.0, 1.0, n)
    bins = np.interp(mid, grid, values)
    theta = np.arccos(np.clip(cos_edges, -1.0, 1.0))
    theta[0], theta[-1] = 0.0, math.pi
    return theta, bins


def omnee_phase(phase: Any) -> omnee.Phase:
    """The omnee phase function of Mitsuba's ``phase``; raises
    :class:`Unsupported` naming the kind omnee lacks."""
    name = phase.class_name()
    g = _hg_g(phase)
    if g is not None:
        return omnee.Phase("iso" if g == 0.0 else f"hg:{g!r}")
    if name == "RayleighPhaseFunction":
        return omnee.Phase("rayleigh")
    if name == "TabulatedPhaseFunction":
        import mitsuba as mi

        theta, bins = table_bins(np.asarray(mi.traverse(phase)["values"], dtype=np.float64))
        return omnee.Phase.table(theta, bins)
    if name == "BlendPhaseFunction":
        children = dict(_children(phase))
        lobes = [children.get("phase_0"), children.get("phase_1")]
        gs = [None if p is None else _hg_g(p) for p in lobes]
        if None in gs:
            kinds = ", ".join("?" if p is None else p.class_name() for p in lobes)
            raise Unsupported(f"blendphase of {kinds} (omnee blends two Henyey-Greenstein lobes)")
        w = _constant_weight(children["weight"])
        return omnee.Phase(f"tthg:{gs[0]!r},{gs[1]!r},{1.0 - w!r}")
    raise Unsupported(name)
