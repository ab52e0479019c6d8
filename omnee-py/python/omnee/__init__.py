"""omnee: once-more scattered next event estimation (OMNEE) over numpy arrays.

Between a light-side point ``x0`` and a receiver-side point ``x2``, OMNEE places
one scattering vertex ``x1`` angle first: the deflection θ from the phase
function, then ``x1`` on the circumcircle arc of constant θ through ``x0`` and
``x2``. Its estimator of the once-scattered transfer is ``f_c · θ/(s sin θ)``
(Hanika, Weidlich, Droske, EGSR 2022).

The API follows Mitsuba 3's warp functions (``square_to_X``,
``square_to_X_pdf``, ``X_to_square``): plain uniform numbers in, points,
densities and weights out, vectorised over arrays:

>>> import numpy as np, omnee
>>> phase = omnee.Phase("hg:0.9")
>>> t = omnee.Omnee(x0=[0, 0, 1], x2=[0, 0, 0], phase=phase)
>>> s = t.sample(np.random.default_rng(1).random((4, 3)))
>>> s.x1.shape, s.pdf.shape, bool(s.valid.all())
((4, 3), (4,), True)
>>> u = t.invert(s.x1).u            # back to the uniform numbers

One connection per row: ``x0`` and ``x2`` (and ``normal``) of shape
``(N, 3)`` (or ``(3,)``, shared by all rows); ``u`` of shape ``(N, 3)`` draws
one vertex per row, bit for bit what ``Omnee(x0[i], x2[i], phase)`` draws from
``u[i]``:

>>> rng = np.random.default_rng(2)
>>> x2 = rng.random((1000, 3)) + [0, 0, 2]       # 1000 shading points
>>> rows = omnee.Omnee(x0=[0, 0, 0], x2=x2, phase=phase)
>>> s = rows.sample(rng.random((1000, 3)))
>>> s.x1.shape, rows.rows
((1000, 3), 1000)

``out=`` takes the output arrays to fill (C-contiguous, the result's dtype
and shapes). Precision follows the input: float32 arrays are computed in
f32 (the renderer's precision) and answered in float32; float64, integer
and bool arrays, Python numbers and lists in f64. C-contiguous float32 and
float64 arrays are read in place (per-row end points too, at every call:
a technique sees later writes to them), and the GIL is released while the
Rust core samples (on all cores for long arrays). Bad parameters raise
``ValueError`` naming the field and its allowed range (uniform numbers
outside [0, 1], deflections outside [0, π], NaN included); arrays of a wrong
shape ``ValueError``, of a wrong dtype ``TypeError``. Techniques and phase
functions compare by value and pickle, so they travel to worker processes.

Beyond one vertex, ``Bridge`` draws bridges of ``k`` scattering vertices
between ``x0`` and ``x2`` (three uniform numbers per vertex), and
``estimate(..., vertices=K)`` (or ``vertices="auto"``) estimates the transfer
of K scattering vertices, with ``isotropic_transfer`` its exact value for
isotropic scattering:

>>> b = omnee.Bridge(x0=[0, 0, 1], x2=[0, 0, 0], phase="iso")
>>> s = b.sample(np.random.default_rng(3).random((4, 2, 3)))   # 4 bridges, k = 2
>>> s.vertices.shape, s.pdf.shape
((4, 2, 3), (4,))
>>> e = omnee.estimate(x0=[0, 0, 1], x2=[0, 0, 0], sigma_s=0.5, sigma_t=0.55, vertices=2)
>>> abs(e.mean - e.reference) < 4.5 * e.stderr
True

A reference that spends its evaluation budget raises ``NotConvergedError``
(a ``RuntimeError``), never runs on.
"""

from typing import NamedTuple, Optional

import numpy as np

from ._omnee import (
    Bridge,
    Distance,
    Equiangular,
    EquiangularSegment,
    Mis,
    NotConvergedError,
    Omnee,
    Phase,
    Technique,
    VertexCount,
    __version__,
    estimate,
    isotropic_transfer,
)

__all__ = [
    "Phase",
    "Technique",
    "Omnee",
    "Equiangular",
    "Distance",
    "Mis",
    "EquiangularSegment",
    "estimate",
    "Bridge",
    "VertexCount",
    "isotropic_transfer",
    "NotConvergedError",
    "BridgeSamples",
    "Samples",
    "Inversion",
    "DistanceSamples",
    "Estimate",
    "__version__",
]


class Samples(NamedTuple):
    """What ``Technique.sample(u)`` returns, one entry per draw.

    For ``u`` of shape ``(..., 3)``: ``x1`` has shape ``(..., 3)`` and the
    others ``(...)``. ``Mis`` draws two vertices (OMNEE's and, now and then,
    the companion's) from ``u`` of shape ``(..., 6)``: ``x1`` then has shape
    ``(..., 2, 3)`` and the others ``(..., 2)``; the estimate of a draw is the
    sum over both of ``f_c(x1) · weight``.

    Where ``valid`` is False (the numbers give no vertex: θ ≥ θmax, outside
    the medium, on an end point, or no companion drawn) ``x1``, ``pdf`` and
    ``weight`` are 0, so ``sum(f_c(x1) * weight)`` stays unbiased.
    """

    x1: np.ndarray
    """The scattering vertex."""
    pdf: np.ndarray
    """Its density in the volume measure (m⁻³), finite (saturating at the dtype's max)."""
    weight: np.ndarray
    """The estimator ``k(x1)/pdf(x1)`` without ``f_c``, with the kernel
    ``k = p(θ)/(d1² d2²)``, in its closed form (m⁻¹), finite and ≥ 0."""
    valid: np.ndarray
    """Whether the numbers gave a vertex (bool)."""


class BridgeSamples(NamedTuple):
    """What ``Bridge.sample(u)`` returns for ``u`` of shape ``(..., k, 3)``:
    ``vertices`` of shape ``(..., k, 3)``, the others ``(...)``. Where
    ``valid`` is False (the numbers give no path) everything is 0. One
    estimate of ``I_k`` is ``sigma_s**k * exp(-sigma_t * length) * weight``."""

    vertices: np.ndarray
    """The inner vertices x_1 ... x_k."""
    pdf: np.ndarray
    """The density in the product of volume measures (m^-3k), finite (saturating)."""
    weight: np.ndarray
    """The kernel ``prod p(theta_i) / prod d_j^2`` over ``pdf``,
    ``D^(k+1)/(s^3 k!)`` for exactly sampled phase functions; finite, >= 0."""
    length: np.ndarray
    """The path's length ``D = d_1 + ... + d_(k+1)``."""
    valid: np.ndarray
    """Whether the numbers gave a path (bool)."""


class Inversion(NamedTuple):
    """What ``Technique.invert(x1)`` returns: ``u`` of shape ``(..., 3)`` with
    ``sample(u).x1 == x1``, and ``valid`` of shape ``(...)``, False (and ``u``
    0) where ``x1`` has no preimage (θ ≥ θmax, outside the medium, a mixture
    phase function whose sampler is not invertible)."""

    u: np.ndarray
    """The uniform numbers."""
    valid: np.ndarray
    """Whether ``x1`` has a preimage (bool)."""


class DistanceSamples(NamedTuple):
    """What ``EquiangularSegment.sample(u)`` returns, each of ``u``'s shape."""

    t: np.ndarray
    """The distance along the ray (m); 0 where ``valid`` is False."""
    pdf: np.ndarray
    """Its density per metre, finite (saturating at the dtype's max); 0 where
    ``valid`` is False."""
    valid: np.ndarray
    """Whether ``u`` gave a finite distance (False only for ``u = 1`` on an
    infinite segment)."""


class Estimate(NamedTuple):
    """What ``estimate(...)`` returns: the fields of ``omnee estimate --json``."""

    mean: float
    """The estimate of the integral I."""
    stderr: float
    """Its standard error, ``sqrt(sample variance / samples)``."""
    reference: Optional[float]
    """I by f64 adaptive quadrature (None with ``reference=False``); with
    ``vertices`` other than 1, the isotropic closed form of ``I_K`` (or of
    the sum over K for ``"auto"``)."""
    technique: str
    """The technique used (what ``auto`` resolved to)."""
    auto_reason: Optional[str]
    """For ``technique="auto"``: why it picked what it did."""
    samples: int
    """The number of draws."""
    accepted: int
    """Draws whose technique's own vertex contributed (θ < θmax, inside the medium)."""
    mean_cosine: float
    """The phase function's g."""
    tau: float
    """The optical thickness ``sigma_t · |x2 − x0|``."""
    seconds: float
    """Wall time of the sampling and the quadrature."""
