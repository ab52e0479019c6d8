"""omnee.Phase: normalisation, CDF and mean cosine against scipy's
quadrature, sample/invert round trips, a χ² test of θ, dtypes and errors."""

import pickle

import numpy as np
import pytest
from scipy import integrate

import omnee
from conftest import CHI2_LEVEL, chi2_test

INVERTIBLE = ["iso", "hg:0.9", "hg:-0.6", "hg:0.997", "rayleigh", "ff:0.0183,1.1", "draine:0.5557,22"]
MIXTURES = ["tthg:0.99,-0.44,0.96", "mie:10"]
ALL = INVERTIBLE + MIXTURES


def quad_theta(f, a=0.0, b=np.pi):
    """∫_a^b f(θ) dθ, with breakpoints towards θ = 0 for forward peaks."""
    points = [p for p in (1e-4, 1e-3, 1e-2, 0.1) if a < p < b]
    value, _ = integrate.quad(f, a, b, points=points or None, limit=500, epsabs=1e-12, epsrel=1e-10)
    return value


@pytest.mark.parametrize("spec", ALL)
def test_normalised_and_cdf_matches_quadrature(spec):
    p = omnee.Phase(spec)
    density = lambda t: 2 * np.pi * float(p.eval(t)) * np.sin(t)
    assert quad_theta(density) == pytest.approx(1.0, abs=2e-6)
    for theta in (0.01, 0.3, 1.0, 2.0, 3.0):
        assert float(p.cdf(theta)) == pytest.approx(quad_theta(density, 0, theta), abs=2e-6)
    g = quad_theta(lambda t: density(t) * np.cos(t))
    assert p.mean_cosine() == pytest.approx(g, abs=2e-6)


@pytest.mark.parametrize("spec", ALL)
def test_pdf_is_eval(spec):
    p = omnee.Phase(spec)
    theta = np.linspace(0, np.pi, 101)
    np.testing.assert_array_equal(p.pdf(theta), p.eval(theta))


@pytest.mark.parametrize("spec", INVERTIBLE)
def test_sample_invert_round_trip(spec):
    p = omnee.Phase(spec)
    u = np.random.default_rng(7).random(10_000)
    np.testing.assert_allclose(p.invert(p.sample(u)), u, atol=1e-9)
    u32 = u.astype(np.float32)
    back = p.invert(p.sample(u32))
    assert back.dtype == np.float32
    np.testing.assert_allclose(back, u32, atol=2e-5)


@pytest.mark.parametrize("spec", ALL)
def test_cdf_of_sample_is_uniform_in_order(spec):
    """sample is monotone in u for inverse-CDF samplers; for every phase
    function cdf(sample(u)) is uniform (checked by the χ² test below)."""
    p = omnee.Phase(spec)
    u = np.linspace(0, 1, 1001, endpoint=False)
    theta = p.sample(u)
    assert np.all((theta >= 0) & (theta <= np.pi))
    if spec in INVERTIBLE:
        assert np.all(np.diff(theta) >= 0)


@pytest.mark.parametrize("spec", MIXTURES)
def test_mixtures_refuse_invert(spec):
    with pytest.raises(ValueError, match="not invertible"):
        omnee.Phase(spec).invert([0.5])


@pytest.mark.parametrize("spec", ALL)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_chi2_theta_against_cdf(spec, dtype):
    """θ drawn by `sample` binned in 40 bins of equal probability, whose edges
    are found by bisection on `cdf` in f64 (validated against quadrature above)."""
    p = omnee.Phase(spec)
    bins = 40
    target = np.arange(1, bins) / bins
    lo, hi = np.zeros(bins - 1), np.full(bins - 1, np.pi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        below = p.cdf(mid) < target
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    edges = np.concatenate([[0.0], 0.5 * (lo + hi), [np.pi]])
    expected = np.diff(p.cdf(edges))
    draws = 200_000
    u = np.random.default_rng(12345).random(draws).astype(dtype)
    theta = p.sample(u).astype(np.float64)
    observed, _ = np.histogram(theta, bins=edges)
    pvalue, chi2, dof = chi2_test(observed, expected, draws)
    assert pvalue > CHI2_LEVEL, f"{spec} {dtype}: χ² = {chi2:.1f} with {dof} dof, p = {pvalue:.2e}"


def test_dtype_rule_and_shapes():
    p = omnee.Phase("hg:0.5")
    assert p.eval(np.zeros(3, np.float32)).dtype == np.float32
    assert p.eval(np.zeros(3)).dtype == np.float64
    assert p.eval(np.zeros(3, np.int64)).dtype == np.float64
    assert p.eval([0, 1]).dtype == np.float64
    assert p.eval(np.zeros((2, 3, 4))).shape == (2, 3, 4)
    assert p.eval(np.zeros(0)).shape == (0,)
    scalar = p.eval(0.5)
    assert np.ndim(scalar) == 0 and isinstance(scalar, np.floating)
    a = np.linspace(0, 3, 20)
    np.testing.assert_array_equal(p.eval(a[::-3]), p.eval(a[::-3].copy()))
    np.testing.assert_array_equal(p.eval(a.reshape(4, 5).T), p.eval(a.reshape(4, 5).T.copy()))
    big_endian = a.astype(">f8")
    np.testing.assert_array_equal(p.eval(big_endian), p.eval(a))
    for bad in (np.zeros(2, np.complex128), np.zeros(2, np.float16), np.array(["a"]), [None]):
        with pytest.raises(TypeError):
            p.eval(bad)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_values_outside_the_domain_are_value_errors_naming_them(dtype):
    p = omnee.Phase("hg:0.9")
    theta_methods = [p.eval, p.pdf, p.cdf, p.invert]
    for method in theta_methods:
        for bad, text in [(np.nan, "nan"), (-0.2, "-0.2"), (4.0, "4"), (np.inf, "inf")]:
            with pytest.raises(ValueError, match=rf"^theta = {text}\d* is out of range; allowed: \[0, pi\]$"):
                method(dtype(bad))
        x = np.linspace(0, 3, 6).astype(dtype).reshape(2, 3)
        x[1, 2] = np.nan
        with pytest.raises(ValueError, match=r"^theta\[1, 2\] = nan is out of range"):
            method(x)
        ends = method(np.array([0.0, np.pi], dtype))
        assert np.all(np.isfinite(ends))
    assert np.isfinite(p.eval(np.float32(np.pi)))  # π rounded up in f32
    for bad, text in [(np.nan, "nan"), (1.5, "1.5"), (-1.0, "-1")]:
        with pytest.raises(ValueError, match=rf"^u = {text}\d* is out of range; allowed: \[0, 1\]$"):
            p.sample(dtype(bad))
    theta = p.sample(np.array([0.0, 1.0], dtype))
    assert np.all((theta >= 0) & (theta <= np.pi))


def test_phase_functions_compare_and_hash_by_value():
    a, b = omnee.Phase("hg:0.9"), omnee.Phase(" hg:0.90")
    assert a == b and hash(a) == hash(b) and not (a != b)
    assert omnee.Phase("hg:0") == omnee.Phase("hg:-0") and hash(omnee.Phase("hg:0")) == hash(omnee.Phase("hg:-0"))
    others = [omnee.Phase(s) for s in ALL + ["hg:0.91", "iso"]]
    for i, x in enumerate(others):
        for j, y in enumerate(others):
            same = x.spec == y.spec
            assert (x == y) == same, (x, y)
    assert omnee.Phase("iso") != "iso" and len({a, b, omnee.Phase("iso")}) == 2
    assert omnee.Phase("hg:0") != omnee.Phase("iso")  # equal values, different functions


@pytest.mark.parametrize(
    "spec, message",
    [
        ("hg:1.5", r"g = 1.5 is out of range; allowed: \(-1, 1\)"),
        ("ff:0.7,1.1", r"backscatter = 0.7 is out of range; allowed: \(0, 0.5\)"),
        ("mie:0", r"diameter_um = 0 is out of range"),
        ("blob", "unknown phase function"),
        ("hg:x", "not a number"),
    ],
)
def test_bad_specs_are_value_errors_naming_the_field(spec, message):
    with pytest.raises(ValueError, match=message):
        omnee.Phase(spec)


def test_a_table_value_beyond_float32_is_out_of_range(tmp_path):
    """A table's values feed the renderer's f32 phase function too: 1e300, a
    finite number, is out of range there (before, it was called a
    non-finite value); the largest float32 values are a table whose sum,
    taken in float64, is finite."""
    path = tmp_path / "huge.csv"
    path.write_text("0,1e300\n180,1\n")
    with pytest.raises(ValueError, match=r"line 1: value = 1\d+ is out of range; allowed: \[0, 3.4028235e38\]"):
        omnee.Phase(f"table:{path}")
    path.write_text("0,3.4e38\n180,3.4e38\n")
    p = omnee.Phase(f"table:{path}")
    assert float(p.eval(1.0)) == pytest.approx(0.25 / np.pi, rel=1e-6)


def test_repr_and_pickle():
    p = omnee.Phase("tthg:0.99,-0.44,0.96")
    assert repr(p) == 'omnee.Phase("tthg:0.99,-0.44,0.96")'
    q = pickle.loads(pickle.dumps(p))
    assert q == p and q.spec == p.spec and q.mean_cosine() == p.mean_cosine()
