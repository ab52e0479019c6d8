"""Type stubs of the native module omnee._omnee (re-exported by ``omnee``).

Array arguments follow one dtype rule: float32 arrays are computed in f32 and
answered in float32; float64, integer and bool arrays, Python numbers and
sequences in f64 (float64). Any other dtype raises TypeError. A C-contiguous
float32 or float64 array is read in place (no copy) while the GIL is
released: do not write to it from another thread during the call. A 0-d
result is returned as a numpy scalar.
"""

from typing import Any, Dict, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt
from typing_extensions import disjoint_base

from . import BridgeSamples, DistanceSamples, Estimate, Inversion, Samples

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
    "__version__",
]

_ArrayLike = npt.ArrayLike
_FloatArray = npt.NDArray[np.floating[Any]]
_BoolArray = npt.NDArray[np.bool_]
_Point = Union[Sequence[float], _FloatArray]
"""A point ``(3,)``; for the techniques' ``x0``, ``x2``, ``normal`` also
``(N, 3)``, one point per row."""
_PhaseLike = Union["Phase", str]

__version__: str

@final
class Phase:
    """A phase function p(θ) of the deflection θ ∈ [0, π] between the incoming
    and the outgoing propagation direction (θ = 0: straight on), normalised
    over the sphere: ``2π ∫₀^π p(θ) sin θ dθ = 1``.

    ``spec``: ``iso``; ``hg:G`` Henyey–Greenstein,
    ``p = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2})``, g ∈ (−1, 1);
    ``tthg:G1,G2,W`` ``W·HG(G1) + (1 − W)·HG(G2)``; ``ff:B,N`` Fournier–Forand
    with backscatter fraction B ∈ (0, 0.5) and refractive index
    N ∈ [1.001, 1.5]; ``draine:G,ALPHA`` ``HG(G)·(1 + α cos²θ)``, normalised;
    ``mie:DIAMETER_UM`` the approximate Mie fit (Jendersie & d'Eon 2023),
    diameter ∈ (0, 50] µm; ``rayleigh`` ``p = 3/(16π) (1 + cos²θ)``;
    ``table:FILE.csv`` lines ``angle_deg,value``.

    Compared and hashed by value (the kind and its parameters). Raises
    ValueError naming the parameter and its allowed range; the methods raise
    ValueError for θ outside [0, π] or u outside [0, 1], NaN included.
    """

    def __new__(cls, spec: str) -> Phase: ...
    @staticmethod
    def table(theta: _ArrayLike, values: _ArrayLike) -> Phase:
        """A measured phase function from arrays (as Mitsuba's ``tabphase``
        holds one): ``theta``, the ``n + 1`` bin edges in radians, strictly
        increasing from 0 to π, and ``values``, the ``n`` bin values (≥ 0, not
        all 0), the density constant per solid angle within each bin:
        ``p(θ) = v_i / (2π Σ_j v_j (cos θ_j − cos θ_{j+1}))`` on bin ``i``. Its
        ``spec`` is ``table``. Raises ValueError naming ``theta`` or
        ``values`` for tables of the wrong shape."""
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...
    @property
    def spec(self) -> str:
        """The spec string."""
    def eval(self, theta: _ArrayLike) -> Any:
        """p(θ) per steradian, elementwise, θ ∈ [0, π]."""
    def sample(self, u: _ArrayLike) -> Any:
        """θ = P⁻¹(u), the deflection drawn from u ∈ [0, 1]; its
        solid-angle density is ``pdf(θ)``."""
    def pdf(self, theta: _ArrayLike) -> Any:
        """The solid-angle density of ``sample`` at θ; equals ``eval(θ)``."""
    def cdf(self, theta: _ArrayLike) -> Any:
        """``P(Θ ≤ θ) = 2π ∫₀^θ p(θ') sin θ' dθ'``."""
    def invert(self, theta: _ArrayLike) -> Any:
        """The u with ``sample(u) = θ`` (``cdf(θ)`` for inverse-CDF samplers).
        Raises ValueError for the mixtures (tthg, mie), which pick a lobe with u."""
    def mean_cosine(self) -> float:
        """``g = ⟨cos θ⟩ = 2π ∫₀^π p(θ) cos θ sin θ dθ``."""
    def backscatter_fraction(self) -> float:
        """``B = P(Θ > π/2)``."""
    def __eq__(self, other: object, /) -> bool: ...
    def __hash__(self) -> int: ...

@disjoint_base
class Technique:
    """A technique placing the scattering vertex ``x1`` of the once-more
    scattered connection ``x0 → x1 → x2``, restricted to deflections
    θ < θmax; every technique estimates the integral of the kernel
    ``k(x1) = p(θ)/(d1² d2²)`` times the factors ``f_c`` it does not sample.

    One connection (``x0``, ``x2`` of shape ``(3,)``), or one per row
    (``x0``, ``x2``, ``normal`` of shape ``(N, 3)``, or ``(3,)`` for a point
    shared by every row): then the first axis of ``u`` and ``x1`` is the
    row, ``(N, ..., 3)``. Techniques compare and hash by value and pickle
    (they travel to worker processes).

    The base class of Omnee, Equiangular, Distance and Mis; not constructed
    directly.
    """

    @property
    def x0(self) -> Union[Tuple[float, float, float], _FloatArray]:
        """The light-side end point(s)."""
    @property
    def x2(self) -> Union[Tuple[float, float, float], _FloatArray]:
        """The receiver-side end point(s)."""
    @property
    def theta_max(self) -> float:
        """The restriction θ < θmax, θmax ∈ (0, π]."""
    @property
    def phase(self) -> Phase:
        """The phase function at ``x1``."""
    @property
    def dimension(self) -> int:
        """Uniform numbers per draw: 3, or 6 for Mis."""
    @property
    def rows(self) -> Optional[int]:
        """The number of connections given per row, or None for one."""
    def sample(
        self,
        u: _ArrayLike,
        out: Optional[Tuple[_FloatArray, _FloatArray, _FloatArray, _BoolArray]] = None,
    ) -> Samples:
        """``x1`` from uniform numbers ``u`` in [0, 1] of shape ``(..., 3)``
        (``(..., 6)`` for Mis): ``Samples(x1, pdf, weight, valid)``, with
        ``weight = k(x1)/pdf(x1)`` in closed form; written into the four
        arrays of ``out`` (C-contiguous, the result's dtype and shapes) if
        given."""
    def pdf(self, x1: _ArrayLike, out: Optional[_FloatArray] = None) -> Any:
        """The volume density (m⁻³) of ``sample`` at points of shape
        ``(..., 3)``; 0 where it never samples. For Mis the combined density
        the vertices come with."""
    def __eq__(self, other: object, /) -> bool: ...
    def __hash__(self) -> int: ...
    def __getnewargs_ex__(self) -> Tuple[Tuple[Any, ...], Dict[str, Any]]: ...

@final
class Omnee(Technique):
    """OMNEE: θ = P⁻¹(u0) from the phase function, ``β = u1 θ``,
    ``φ = 2π u2`` on the circumcircle arc through x0 and x2;
    ``pdf(x1) = p(θ) (sin θ/θ) s / (d1² d2²)``, ``weight = θ/(s sin θ)``
    with ``s = |x2 − x0|``."""

    def __new__(
        cls, x0: _Point, x2: _Point, phase: _PhaseLike, theta_max: float = 3.141592653589793
    ) -> Omnee: ...
    def invert(
        self, x1: _ArrayLike, out: Optional[Tuple[_FloatArray, _BoolArray]] = None
    ) -> Inversion:
        """The uniform numbers ``sample`` maps to ``x1`` (shape ``(..., 3)``):
        ``Inversion(u, valid)``."""

@final
class Equiangular(Technique):
    """Equiangular sampling (Kulla & Fajardo 2012): a direction ω from x2
    (uniform on the sphere, or cosine-weighted about ``normal``) from
    ``(u0, u1)``, then the distance along it with density ∝ 1/d1² on the
    medium segment (all of space, or the ``slab`` (z_min, z_max)):
    ``pdf(x1) = pdf_ω(ω) c / (d1² d2²)``, ``weight = p(θ)/(pdf_ω(ω) c)``."""

    def __new__(
        cls,
        x0: _Point,
        x2: _Point,
        phase: _PhaseLike,
        theta_max: float = 3.141592653589793,
        normal: Optional[_Point] = None,
        slab: Optional[Tuple[float, float]] = None,
    ) -> Equiangular: ...
    def invert(
        self, x1: _ArrayLike, out: Optional[Tuple[_FloatArray, _BoolArray]] = None
    ) -> Inversion:
        """The uniform numbers ``sample`` maps to ``x1`` (shape ``(..., 3)``):
        ``Inversion(u, valid)``."""

@final
class Distance(Technique):
    """Distance sampling: a direction ω as for Equiangular, then the
    exponential free-flight distance with coefficient ``sigma_t`` on the
    medium segment [t_a, t_b]: ``pdf(t) = σ e^{−σ (t − t_a)} / (1 − e^{−σL})``,
    ``pdf(x1) = pdf_ω(ω) pdf(t) / t²``; ``sigma_t`` ∈ (0, ∞) without a slab,
    [0, ∞) with one."""

    def __new__(
        cls,
        x0: _Point,
        x2: _Point,
        phase: _PhaseLike,
        sigma_t: float,
        theta_max: float = 3.141592653589793,
        normal: Optional[_Point] = None,
        slab: Optional[Tuple[float, float]] = None,
    ) -> Distance: ...
    def invert(
        self, x1: _ArrayLike, out: Optional[Tuple[_FloatArray, _BoolArray]] = None
    ) -> Inversion:
        """The uniform numbers ``sample`` maps to ``x1`` (shape ``(..., 3)``):
        ``Inversion(u, valid)``."""

@final
class Mis(Technique):
    """MIS as the CLI's ``mis``: OMNEE's vertex from ``u[0:3]`` always and,
    when ``u3 < c = 0.05``, an equiangular companion from ``(u3/c, u4, u5)``
    kept behind the cone θ ≥ 3π/4, balance heuristic there
    (``pdf = p_O + c p_E``, ``w = p/(p_O + c p_E)``), OMNEE alone in front of
    it. ``sample`` returns two vertices per draw (shape ``(..., 2, 3)``).
    No ``invert``: OMNEE and the companion can draw the same point."""

    def __new__(
        cls,
        x0: _Point,
        x2: _Point,
        phase: _PhaseLike,
        theta_max: float = 3.141592653589793,
        normal: Optional[_Point] = None,
        slab: Optional[Tuple[float, float]] = None,
    ) -> Mis: ...

@final
class EquiangularSegment:
    """Equiangular sampling of the distance ``t`` along rays
    ``origin + t · direction`` restricted to their medium segments
    ``[t_min, t_max]``, towards a light point ``x0`` (Kulla & Fajardo 2012):
    ``pdf(t) = c / d1(t)²`` with ``d1 = |origin + t ω − x0|`` and
    ``c = D/(θ_b − θ_a)`` (``D`` the distance of ``x0`` from the ray's line,
    ``θ_b − θ_a`` the angle the segment subtends at ``x0``). The distance
    sampler of a renderer that draws its ray directions itself (BSDF, phase
    function) and finds the segment by tracing; the vertex's volume density
    about ``origin`` is ``pdf_ω(ω) · pdf(t) / t²``.

    ``x0``, ``origin``, ``direction`` (any non-zero length): ``(3,)`` or
    ``(N, 3)``; ``t_min`` ∈ [0, ∞), ``t_max`` ∈ (t_min, ∞]: a number or
    ``(N,)``. With any argument per row, the first axis of ``u`` and ``t`` is
    the row. Raises ValueError naming the argument (and the row) for
    non-finite points, a zero direction, bad bounds, and ``x0`` on the
    segment itself."""

    def __new__(
        cls,
        x0: _Point,
        origin: _Point,
        direction: _Point,
        t_min: _ArrayLike = 0.0,
        t_max: _ArrayLike = ...,
    ) -> EquiangularSegment: ...
    def sample(self, u: _ArrayLike) -> DistanceSamples:
        """``t = Δ + D tan(θ_a + u (θ_b − θ_a))`` from ``u`` ∈ [0, 1]:
        ``DistanceSamples(t, pdf, valid)``."""
    def pdf(self, t: _ArrayLike) -> Any:
        """``pdf(t)`` per metre, 0 outside the segment."""
    def invert(self, t: _ArrayLike) -> Any:
        """The ``u`` that ``sample`` maps to ``t``
        (``atan2(D (t − t_a), D² + a v)/(θ_b − θ_a)``, clamped to [0, 1])."""
    @property
    def rows(self) -> Optional[int]:
        """The number of rays given per row, or None for one."""

def estimate(
    *,
    x0: _Point,
    x2: _Point,
    sigma_s: float,
    sigma_t: float,
    phase: Optional[_PhaseLike] = None,
    technique: str = "auto",
    samples: int = 100000,
    seed: int = 1,
    theta_max: float = 3.141592653589793,
    receiver_normal: Optional[_Point] = None,
    dtype: Optional[npt.DTypeLike] = None,
    reference: bool = True,
    threads: int = 0,
    vertices: Union[int, str] = 1,
    max_vertices: Optional[int] = None,
) -> Estimate:
    """The once-more scattered transfer from a unit point light at x0 to a
    point receiver at x2 through an infinite homogeneous medium,
    ``I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1`` over θ < θmax,
    estimated exactly as ``omnee estimate --json`` with the same arguments
    (``technique`` omnee, equiangular, distance, mis or auto; ``dtype``
    float64 (default) or float32; ``phase`` default ``iso``; ``threads`` 0:
    one per core), with the f64 quadrature reference when ``reference`` is
    True. Ctrl-C interrupts it between chunks of draws."""

class NotConvergedError(RuntimeError):
    """A quadrature reference spent its evaluation budget before meeting its
    tolerance: no value is returned (the input was valid)."""

@final
class Bridge:
    """Bridges of k scattering vertices between x0 and x2 with ``phase`` at
    every vertex (docs/math.md §14); density
    ``s³ k! Π q(θ_i) / (Π d_j² D^{k+1})`` in the product of volume measures."""

    def __new__(cls, *, x0: _Point, x2: _Point, phase: Optional[_PhaseLike] = None) -> "Bridge": ...
    def sample(self, u: _ArrayLike) -> BridgeSamples:
        """Bridges from ``u`` of shape ``(..., k, 3)`` in [0, 1], k in [1, 32]."""
    def pdf(self, vertices: _ArrayLike) -> Any:
        """The density of ``sample`` at the paths ``x0, vertices[..., :, :], x2``."""
    def invert(self, vertices: _ArrayLike) -> Inversion:
        """The uniform numbers ``sample`` maps to the paths: ``Inversion(u, valid)``,
        ``u`` of shape ``(..., k, 3)``."""
    @property
    def x0(self) -> Tuple[float, float, float]: ...
    @property
    def x2(self) -> Tuple[float, float, float]: ...
    @property
    def phase(self) -> Phase: ...

@final
class VertexCount:
    """The number of bridge vertices k in [1, k_max] drawn per connection: a
    Poisson distribution of mean ``μ = σs s (1 + (1 − |g|) σt s / 2)``
    truncated to [1, k_max], mixed with the uniform one for the share 0.2."""

    def __new__(
        cls,
        k_max: int = 8,
        *,
        s: float,
        sigma_s: float,
        sigma_t: float,
        phase: Optional[_PhaseLike] = None,
    ) -> "VertexCount": ...
    def sample(self, u: _ArrayLike) -> Tuple[Any, Any]:
        """``(k, P(k))`` (int64, float64) for each uniform number of ``u`` in [0, 1]."""
    def pmf(self, k: _ArrayLike) -> Any:
        """``P(k)``, 0 outside [1, k_max]; a ``k`` that is not an integer
        (2.5, NaN) is a ``ValueError``."""
    @property
    def k_max(self) -> int: ...
    @property
    def mean(self) -> float: ...

def isotropic_transfer(
    k: int, *, s: float, sigma_s: float, sigma_t: float, budget: int = 1000000
) -> float:
    """The exact I_k for isotropic scattering (docs/math.md §14.6); raises
    ``NotConvergedError`` when the quadrature spends ``budget`` evaluations,
    and ``ValueError`` naming ``k`` where both of its integrals' cancellation
    would leave fewer than ten digits (dense media: none for σt s up to 20,
    k = 17 … 28 at 30)."""
