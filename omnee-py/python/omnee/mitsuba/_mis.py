"""The densities of the four strategies that reach a light from a medium
vertex, in one measure, and their power-heuristic weights.

A path ``… x2 → x1 → x0`` with ``x1`` in a medium and ``x0`` on a finite
emitter has the density, over ``x1`` (volume) and ``x0`` (area; a delta
light's probability alone), of

- **a**, volpath's free flight then next event estimation:
  ``q_a = q_ff · p_nee(x0 | x1)``;
- **b**, volpath's free flight then a phase-sampled direction that hits the
  emitter: ``q_b = q_ff · p_phase(ω10) |cos θ0| / d10²`` (0 for a delta light);
- **c**, OMNEE at ``x2``: ``q_c = p(x0) · p_omnee(x1 | x0, x2)``;
- **d**, equiangular sampling on the ray's medium segment:
  ``q_d = p(x0) · p_ω(ω21) · e^{−τ_entry} · p_eq(t) / d21²``;

with ``q_ff = p_ω(ω21) · m(x1) e^{−τ} / d21²`` the free-flight density of
``x1`` along the direction ``ω21`` that ``x2`` drew with density ``p_ω``
(``m(x1)`` the mean extinction at ``x1``, ``τ`` the optical-depth proxy of
:mod:`._transport`, ``τ_entry`` its value where the ray entered ``x1``'s
medium segment). Like volpath, the densities leave out Russian roulette and
the transmittance of the last edge (estimated, not sampled, by next event
estimation). Every strategy evaluates all four for its own path from the
same path quantities, so the weights ``w_s = q_s² / Σ q²`` sum to one.
"""

from __future__ import annotations

from typing import Any, Iterable, Tuple

import drjit as dr
import mitsuba as mi

# Densities are clamped here before squaring (f32 squares overflow at 1.8e19).
_LARGE = 1e18


STRATEGIES = ("volpath", "omnee", "equiangular")
"""What the ``mis`` parameter may name besides ``power``: all the weight on
one strategy wherever it can make the path (``volpath``: a and b together,
by the power heuristic), the power heuristic over the others elsewhere."""


def weights(mode: str, q_a: Any, q_b: Any, q_c: Any, q_d: Any) -> Tuple[Any, Any, Any, Any]:
    """The weights ``(w_a, w_b, w_c, w_d)`` of the four strategies for a
    path with densities ``q``: the power heuristic (``mode == "power"``), or
    all on the strategy ``mode`` names where its density is positive (the
    power heuristic among the others elsewhere)."""
    qs = (q_a, q_b, q_c, q_d)

    def power(i: int, among: Iterable[int]) -> Any:
        return power_weight(qs[i], *[qs[j] for j in among if j != i])

    if mode == "power":
        return tuple(power(i, range(4)) for i in range(4))
    own = {"volpath": (0, 1), "omnee": (2,), "equiangular": (3,)}[mode]
    rest = tuple(i for i in range(4) if i not in own)
    chosen = mi.Float(0.0)
    for i in own:
        chosen += mi.Float(qs[i])
    chosen = chosen > 0.0
    return tuple(
        dr.select(chosen, power(i, own), 0.0) if i in own else dr.select(chosen, 0.0, power(i, rest))
        for i in range(4)
    )


def power_weight(own: Any, *others: Any) -> Any:
    """The power heuristic ``own² / (own² + Σ others²)``, computed with every
    density relative to the largest (0 where the result is not finite)."""
    own = dr.minimum(mi.Float(own), _LARGE)
    clamped = [dr.minimum(mi.Float(q), _LARGE) for q in others]
    largest = own
    for q in clamped:
        largest = dr.maximum(largest, q)
    scale = dr.select(largest > 0.0, dr.rcp(largest), 0.0)
    r = own * scale
    total = dr.square(r)
    for q in clamped:
        total += dr.square(q * scale)
    w = r * r / total
    return dr.select(dr.isfinite(w) & (total > 0.0), w, 0.0)


def free_flight(pdf_dir: Any, m1: Any, tau: Any, t21: Any) -> Any:
    """``q_ff = p_ω · m(x1) e^{−τ} / d21²``."""
    return pdf_dir * m1 * dr.exp(-tau) / dr.square(t21)
