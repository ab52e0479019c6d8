"""omnee.Omnee, Equiangular, Distance, Mis: shapes and dtypes, sample → pdf
and sample → invert → u round trips, the weight against the kernel, f32
against f64, a χ² test of x1 in the circumcircle coordinates (θ, β/θ) with
expected counts integrated from `pdf` (Mitsuba's ChiSquareTest idea), and
adversarial input that must never crash."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import omnee
from conftest import CHI2_LEVEL, chi2_test, circumcircle_angles, circumcircle_point

X0, X2 = (0.3, -0.2, 1.0), (0.0, 0.1, -0.4)


def techniques(phase="hg:0.9", theta_max=np.pi):
    return {
        "omnee": omnee.Omnee(X0, X2, phase, theta_max=theta_max),
        "equiangular": omnee.Equiangular(X0, X2, phase, theta_max=theta_max),
        "equiangular-slab-cosine": omnee.Equiangular(
            X0, X2, phase, theta_max=theta_max, normal=(0, 0.3, 1), slab=(-0.5, 0.8)
        ),
        "distance": omnee.Distance(X0, X2, phase, sigma_t=0.7, theta_max=theta_max),
        "distance-slab": omnee.Distance(X0, X2, phase, sigma_t=2.0, theta_max=theta_max, slab=(-1.0, 1.2)),
    }


SINGLE = list(techniques())


def uniforms(n, k=3, seed=1, dtype=np.float64):
    return np.random.default_rng(seed).random((n, k)).astype(dtype)


@pytest.mark.parametrize("name", SINGLE)
def test_shapes_and_dtypes(name):
    t = techniques()[name]
    for dtype in (np.float32, np.float64):
        s = t.sample(uniforms(10, dtype=dtype))
        assert s.x1.shape == (10, 3) and s.pdf.shape == s.weight.shape == s.valid.shape == (10,)
        assert s.x1.dtype == s.pdf.dtype == s.weight.dtype == dtype and s.valid.dtype == bool
        assert t.pdf(s.x1).dtype == dtype and t.invert(s.x1).u.dtype == dtype
    s = t.sample(uniforms(24).reshape(2, 4, 3, 3))
    assert s.x1.shape == (2, 4, 3, 3) and s.pdf.shape == (2, 4, 3)
    single = t.sample([0.3, 0.6, 0.1])
    assert single.x1.shape == (3,) and np.ndim(single.pdf) == 0
    empty = t.sample(np.zeros((0, 3)))
    assert empty.x1.shape == (0, 3) and empty.pdf.shape == (0,)
    assert t.pdf(np.zeros((0, 3))).shape == (0,)
    assert t.dimension == 3


def test_mis_draws_two_vertices():
    m = omnee.Mis(X0, X2, "iso")
    assert m.dimension == 6
    s = m.sample(uniforms(1000, 6))
    assert s.x1.shape == (1000, 2, 3) and s.pdf.shape == (1000, 2)
    assert s.valid[:, 0].all()
    # The companion is drawn for u3 < 0.05 and kept behind θ = 3π/4 only.
    u = uniforms(1000, 6)
    companion = m.sample(u).valid[:, 1]
    assert not companion[u[:, 3] >= 0.05].any()
    with pytest.raises(ValueError, match=r"shape \(10, 3\); allowed: \(\.\.\., 6\)"):
        m.sample(uniforms(10, 3))
    assert not hasattr(m, "invert") and not hasattr(omnee.Mis, "invert")
    assert not hasattr(omnee.Technique, "invert")
    assert all(hasattr(c, "invert") for c in (omnee.Omnee, omnee.Equiangular, omnee.Distance))


@pytest.mark.parametrize("name", SINGLE + ["mis"])
def test_sample_then_pdf(name):
    t = omnee.Mis(X0, X2, "hg:0.3") if name == "mis" else techniques("hg:0.3")[name]
    s = t.sample(uniforms(20_000, t.dimension, seed=3))
    x1, pdf, valid = s.x1.reshape(-1, 3), s.pdf.ravel(), s.valid.ravel()
    np.testing.assert_allclose(t.pdf(x1[valid]), pdf[valid], rtol=1e-7)
    assert np.all(pdf[~valid] == 0) and np.all(s.weight.ravel()[~valid] == 0)
    assert np.all(x1[~valid] == 0)


@pytest.mark.parametrize("name", SINGLE)
def test_sample_invert_round_trip(name):
    t = techniques()[name]
    u = uniforms(20_000, seed=4)
    s = t.sample(u)
    inv = t.invert(s.x1)
    ok = s.valid & inv.valid
    assert ok.mean() > 0.5
    np.testing.assert_allclose(inv.u[ok], u[ok], atol=1e-6)
    assert np.all(inv.u[~inv.valid] == 0)


@pytest.mark.parametrize("name", SINGLE)
def test_weight_is_kernel_over_pdf(name):
    """weight = k(x1)/pdf(x1) with the kernel k = p(θ)/(d1² d2²) computed
    here in numpy from the points."""
    phase = omnee.Phase("hg:0.6")
    t = techniques(phase)[name]
    s = t.sample(uniforms(5000, seed=5))
    x1 = s.x1[s.valid]
    a, b = x1 - np.array(X0), np.array(X2) - x1
    d1, d2 = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    cos = np.clip(np.sum(a * b, axis=1) / (d1 * d2), -1, 1)
    kernel = phase.eval(np.arccos(cos)) / (d1**2 * d2**2)
    np.testing.assert_allclose(s.weight[s.valid] * s.pdf[s.valid], kernel, rtol=1e-6)


@pytest.mark.parametrize("name", SINGLE + ["mis"])
def test_float32_against_float64(name):
    t = omnee.Mis(X0, X2, "hg:0.9") if name == "mis" else techniques()[name]
    u = uniforms(5000, t.dimension, seed=6).astype(np.float32)
    s32, s64 = t.sample(u), t.sample(u.astype(np.float64))
    both = s32.valid & s64.valid
    assert (s32.valid == s64.valid).mean() > 0.999
    np.testing.assert_allclose(s32.x1[both], s64.x1[both], rtol=1e-3, atol=1e-4)
    np.testing.assert_allclose(s32.weight[both], s64.weight[both], rtol=1e-3)
    close = np.isclose(s32.pdf[both], s64.pdf[both], rtol=1e-3)
    assert close.mean() > 0.999


CHI2_CASES = [
    ("omnee", "hg:0.9", np.pi),
    ("omnee", "hg:-0.5", np.pi / 2),
    ("omnee", "tthg:0.99,-0.44,0.96", np.pi),
    ("equiangular", "iso", np.pi),
    ("distance", "iso", np.pi),
]


@pytest.mark.parametrize("name, spec, theta_max", CHI2_CASES)
def test_chi2_of_x1_in_circumcircle_coordinates(name, spec, theta_max):
    """x1 binned in (θ, r = β/θ), 16 × 8 bins, θ's edges where the phase
    function's sampler puts 1/16 of its mass, r's of equal width;
    the expected probability of a bin is ∫ pdf(x1) dV over it, with
    dV = (d1² d2² / s) θ dθ dr dφ (docs/math.md §2), by 16×4-point
    Gauss–Legendre in (θ, r) per bin and 8 azimuths, with x1(θ, r, φ)
    computed here in numpy (law of sines), not by the library."""
    phase = omnee.Phase(spec)
    t = {
        "omnee": lambda: omnee.Omnee(X0, X2, phase, theta_max=theta_max),
        "equiangular": lambda: omnee.Equiangular(X0, X2, phase, theta_max=theta_max),
        "distance": lambda: omnee.Distance(X0, X2, phase, sigma_t=0.5, theta_max=theta_max),
    }[name]()
    s_len = np.linalg.norm(np.subtract(X2, X0))
    nw, nr = 16, 8
    w_edges = np.linspace(0, float(phase.cdf(theta_max)), nw + 1)
    theta_edges = phase.sample(w_edges)
    theta_edges[-1] = theta_max
    r_edges = np.linspace(0, 1, nr + 1)

    def nodes(edges, k):
        gx, gw = np.polynomial.legendre.leggauss(k)
        mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * np.diff(edges)
        return (mid[:, None] + half[:, None] * gx).ravel(), (half[:, None] * gw).ravel()

    theta, wt = nodes(theta_edges, 16)
    r, wr = nodes(r_edges, 4)
    phi = (np.arange(8) + 0.5) * 2 * np.pi / 8
    TH, R, PHI = np.meshgrid(theta, r, phi, indexing="ij")
    x1, d1, d2 = circumcircle_point(X0, X2, TH, R, PHI)
    density = t.pdf(x1) * d1**2 * d2**2 / s_len * TH
    density = density.mean(axis=2) * 2 * np.pi  # over φ
    cell = (wt[:, None] * wr[None, :]) * density
    expected = cell.reshape(nw, 16, nr, 4).sum(axis=(1, 3))
    draws = 200_000
    s = t.sample(uniforms(draws, seed=8))
    th, ratio = circumcircle_angles(X0, X2, s.x1[s.valid])
    observed, _, _ = np.histogram2d(th, ratio, bins=[theta_edges, r_edges])
    pvalue, chi2, dof = chi2_test(observed, expected, draws)
    assert pvalue > CHI2_LEVEL, f"χ² = {chi2:.1f} with {dof} dof, p = {pvalue:.2e}"


def test_non_contiguous_and_big_endian_inputs_equal_their_copies():
    t = techniques()["omnee"]
    u = uniforms(200, 6)
    for view in (u[:, ::2], u[::-1, 3:], np.asfortranarray(u[:, :3]), u[:, :3].astype(">f8")):
        a, b = t.sample(view), t.sample(np.ascontiguousarray(view, dtype=np.float64))
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: omnee.Omnee(X0, X0, "iso"), "x2"),
        (lambda: omnee.Omnee(X0, X2, "iso", theta_max=4.0), r"theta_max = 4 is out of range; allowed: \(0, pi\]"),
        (lambda: omnee.Omnee(X0, X2, "iso", theta_max=0.0), "theta_max"),
        (lambda: omnee.Omnee((0, 0, np.inf), X2, "iso"), r"x0\[2\] = inf is out of range; allowed: finite coordinates"),
        (lambda: omnee.Omnee((0, 0), X2, "iso"), r"x0: shape \(2,\); allowed: \(3,\)"),
        (lambda: omnee.Equiangular(X0, X2, "iso", slab=(1.0, -1.0)), r"z_max = -1 is out of range"),
        (lambda: omnee.Equiangular(X0, X2, "iso", normal=(0, 0, 0)), "normal"),
        (lambda: omnee.Distance(X0, X2, "iso", sigma_t=-1.0), r"sigma_t = -1 is out of range; allowed: \[0, inf\)"),
        (lambda: omnee.Distance(X0, X2, "iso", sigma_t=0.0),
         r"sigma_t = 0 is out of range; allowed: \(0, inf\) in a medium without bounds"),
        (lambda: omnee.Distance(X0, X2, "iso", sigma_t=np.nan), r"sigma_t = NaN is out of range"),
        (lambda: omnee.Omnee(X0, X2, "iso", theta_max=np.nan), r"theta_max = NaN is out of range; allowed: \(0, pi\]"),
        (lambda: omnee.Equiangular(X0, X2, "iso", slab=(np.nan, 1.0)), r"z_min"),
        (lambda: omnee.Omnee(X0, X2, "hg:2"), r"g = 2 is out of range"),
    ],
)
def test_bad_parameters_are_value_errors_naming_the_field(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_bad_arrays():
    t = techniques()["omnee"]
    with pytest.raises(ValueError, match=r"u: shape \(4, 2\)"):
        t.sample(np.zeros((4, 2)))
    with pytest.raises(ValueError, match=r"x1: shape \(\); allowed"):
        t.pdf(1.0)
    with pytest.raises(TypeError, match="dtype complex128"):
        t.sample(np.zeros((4, 3), complex))
    with pytest.raises(TypeError):
        t.sample("0.5")
    with pytest.raises(TypeError):
        omnee.Omnee(X0, X2, 0.9)


ANY_FLOAT = st.floats(allow_nan=True, allow_infinity=True, width=64)
# Mostly valid numbers, now and then anything.
UNIFORM = st.one_of(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0), ANY_FLOAT)
COORDINATE = st.one_of(st.floats(-1e6, 1e6), st.floats(-1e6, 1e6), ANY_FLOAT)


@settings(max_examples=150, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(
    u=hnp.arrays(np.float64, st.tuples(st.integers(0, 4), st.just(6)), elements=UNIFORM),
    x=hnp.arrays(np.float64, st.tuples(st.integers(0, 4), st.just(3)), elements=COORDINATE),
    f32=st.booleans(),
)
def test_adversarial_input_is_refused_by_name_or_gives_finite_outputs(u, x, f32):
    """Uniform numbers outside [0, 1] (NaN included) and non-finite points
    raise ValueError naming the first bad element; everything else gives
    finite, non-negative outputs."""
    dtype = np.float32 if f32 else np.float64
    with np.errstate(over="ignore", invalid="ignore"):
        u, x = u.astype(dtype), x.astype(dtype)
    all_techniques = list(techniques("hg:0.99").values()) + [omnee.Mis(X0, X2, "hg:-0.9")]
    for t in all_techniques:
        uu = u[:, : t.dimension]
        bad = ~((uu >= 0) & (uu <= 1))
        if bad.any():
            i, j = np.argwhere(bad)[0]
            with pytest.raises(ValueError, match=rf"u\[{i}, {j}\] = .* is out of range; allowed: \[0, 1\]"):
                t.sample(uu)
        else:
            s = t.sample(uu)
            assert np.all(np.isfinite(s.x1)) and np.all(np.isfinite(s.pdf)) and np.all(np.isfinite(s.weight))
            assert np.all(s.pdf >= 0) and np.all(s.weight >= 0)
        calls = [t.pdf] + ([] if isinstance(t, omnee.Mis) else [lambda p: t.invert(p).u])
        bad = ~np.isfinite(x)
        for call in calls:
            if bad.any():
                i, j = np.argwhere(bad)[0]
                with pytest.raises(ValueError, match=rf"x1\[{i}, {j}\] = .* allowed: finite coordinates"):
                    call(x)
            else:
                out = call(x)
                assert np.all(np.isfinite(out)) and np.all(out >= 0)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_uniform_numbers_outside_the_unit_interval_are_value_errors(dtype):
    t = techniques()["omnee"]
    for bad, text in [(np.nan, "nan"), (1.5, "1.5"), (-0.0001, "-0.0001"), (np.inf, "inf")]:
        u = np.full((2, 4, 3), 0.5, dtype)
        u[1, 2, 1] = bad
        with pytest.raises(ValueError, match=rf"^u\[1, 2, 1\] = {text}\d* is out of range; allowed: \[0, 1\]$"):
            t.sample(u)
    with pytest.raises(ValueError, match=r"^u\[2\] = nan is out of range"):
        t.sample(np.array([0.5, 0.5, np.nan], dtype))
    s = t.sample(np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.5, 0.5, 0.5]], dtype))
    assert np.all(np.isfinite(s.pdf)) and np.all(np.isfinite(s.x1))


def test_help_shows_the_real_defaults():
    import inspect

    for cls in (omnee.Omnee, omnee.Equiangular, omnee.Distance, omnee.Mis):
        parameters = inspect.signature(cls).parameters
        assert parameters["theta_max"].default == np.pi, cls
        assert "Ellipsis" not in str(inspect.signature(cls))
    parameters = inspect.signature(omnee.estimate).parameters
    assert parameters["theta_max"].default == np.pi and parameters["samples"].default == 100_000
    assert "Ellipsis" not in str(inspect.signature(omnee.estimate))
    assert "out=None" in str(inspect.signature(omnee.Technique.sample))


def test_accessors_and_repr():
    t = omnee.Distance(X0, X2, "hg:0.5", sigma_t=0.25, slab=(-1.0, 2.0))
    assert t.x0 == X0 and t.x2 == X2 and t.theta_max == np.pi and t.phase.spec == "hg:0.5"
    assert isinstance(t, omnee.Technique)
    assert repr(t).startswith("omnee.Distance(x0=[0.3, -0.2, 1.0]") and "sigma_t=0.25" in repr(t)


def test_concurrent_calls_from_python_threads_agree_with_serial_ones():
    """The GIL is released while the core samples: calls from several Python
    threads run at the same time and give the serial results."""
    from concurrent.futures import ThreadPoolExecutor

    t = techniques()["omnee"]
    inputs = [uniforms(50_000, seed=k) for k in range(8)]
    serial = [t.sample(u) for u in inputs]
    with ThreadPoolExecutor(max_workers=4) as pool:
        parallel = list(pool.map(t.sample, inputs))
    for a, b in zip(serial, parallel):
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)
