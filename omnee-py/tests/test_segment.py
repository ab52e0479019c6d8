"""omnee.EquiangularSegment (the equiangular distance along a ray the
caller traced) and omnee.Phase.table (a phase function from bin arrays):
the density against an independent numpy formula, sample → pdf and
sample → invert round trips, one row per ray against one ray at a time,
f32 against f64, a χ² test of the distances, and the errors."""

import pickle

import numpy as np
import pytest

import omnee
from conftest import CHI2_LEVEL, chi2_test

X0 = np.array([0.3, 0.9, 1.1])
O = np.array([-0.2, 0.1, 0.0])
D = np.array([1.0, 0.2, 0.3])


def density(x0, o, d, t_min, t_max, t):
    """Kulla & Fajardo's equiangular density, written out: with the foot
    Δ = (x0 − o)·ω, the distance h of x0 from the line and the angles
    θ = atan((t − Δ)/h) at x0, pdf(t) = h / ((θ_b − θ_a)(h² + (t − Δ)²))."""
    w = d / np.linalg.norm(d)
    delta = (x0 - o) @ w
    h = np.linalg.norm(np.cross(x0 - o, w))
    theta_a = np.arctan((t_min - delta) / h)
    theta_b = np.arctan((t_max - delta) / h) if np.isfinite(t_max) else np.pi / 2
    inside = (t >= t_min) & (t <= t_max)
    return np.where(inside, h / ((theta_b - theta_a) * (h * h + (t - delta) ** 2)), 0.0)


@pytest.mark.parametrize("t_max", [2.5, np.inf])
def test_density_sampling_and_inverse(t_max):
    seg = omnee.EquiangularSegment(X0, O, D, 0.1, t_max)
    u = np.random.default_rng(1).random(20000)
    s = seg.sample(u)
    assert s.valid.all() and s.t.shape == u.shape and s.t.dtype == np.float64
    assert (s.t >= 0.1).all() and (s.t <= t_max).all()
    expected = density(X0, O, D, 0.1, t_max, s.t)
    np.testing.assert_allclose(s.pdf, expected, rtol=1e-12)
    np.testing.assert_allclose(seg.pdf(s.t), expected, rtol=1e-12)
    np.testing.assert_allclose(seg.invert(s.t), u, atol=1e-12)
    t = np.linspace(-1.0, 4.0, 101)
    np.testing.assert_allclose(seg.pdf(t), density(X0, O, D, 0.1, t_max, t), rtol=1e-12)


def test_distances_follow_the_density():
    seg = omnee.EquiangularSegment(X0, O, D, 0.0, 3.0)
    n = 400_000
    t = seg.sample(np.random.default_rng(7).random(n)).t
    edges = np.linspace(0.0, 3.0, 61)
    observed, _ = np.histogram(t, edges)
    fine = np.linspace(0.0, 3.0, 60 * 64 + 1)
    mid = 0.5 * (fine[1:] + fine[:-1])
    mass = (density(X0, O, D, 0.0, 3.0, mid) * np.diff(fine)).reshape(60, 64).sum(axis=1)
    p, chi2, dof = chi2_test(observed, mass, n)
    assert p > CHI2_LEVEL, (p, chi2, dof)


def test_one_row_per_ray_equals_one_ray_at_a_time():
    rng = np.random.default_rng(2)
    x0 = rng.normal(size=(50, 3))
    o = rng.normal(size=(50, 3))
    d = rng.normal(size=(50, 3))
    t_max = rng.uniform(0.5, 3.0, 50)
    u = rng.random((50, 4))
    rows = omnee.EquiangularSegment(x0, o, d, 0.0, t_max)
    assert rows.rows == 50
    s = rows.sample(u)
    for i in range(50):
        one = omnee.EquiangularSegment(x0[i], o[i], d[i], 0.0, t_max[i])
        assert one.rows is None
        r = one.sample(u[i])
        np.testing.assert_array_equal(s.t[i], r.t)
        np.testing.assert_array_equal(s.pdf[i], r.pdf)
    # pdf(t) forms t − Δ from the rounded t; the sample keeps its own offset.
    np.testing.assert_allclose(rows.pdf(s.t), s.pdf, rtol=1e-12)


def test_f32_against_f64():
    seg = omnee.EquiangularSegment(X0, O, D, 0.0, 3.0)
    u = np.random.default_rng(3).random(1000)
    a, b = seg.sample(u), seg.sample(u.astype(np.float32))
    assert b.t.dtype == np.float32 and b.pdf.dtype == np.float32
    np.testing.assert_allclose(b.t, a.t, rtol=2e-6, atol=2e-6)
    np.testing.assert_allclose(b.pdf, a.pdf, rtol=2e-5)


def test_the_last_number_of_an_infinite_segment_gives_no_distance():
    s = omnee.EquiangularSegment(X0, O, D).sample(np.array([0.0, 0.5, 1.0]))
    assert s.valid.tolist() == [True, True, False]
    assert s.t[2] == 0.0 and s.pdf[2] == 0.0 and np.isfinite(s.t).all()


@pytest.mark.parametrize(
    "args, message",
    [
        ((X0, O, D, 0.0, 0.0), "t_max"),
        ((X0, O, D, -1.0, 2.0), "t_min"),
        ((X0, O, (0, 0, 0)), "direction"),
        (((np.nan, 0, 0), O, D), "x0"),
        ((X0, (0, np.inf, 0), D), "origin"),
        ((O + 0.5 * D, O, D, 0.0, 3.0), "x0: lies on the ray inside the segment"),
        ((np.zeros((3, 3)), np.zeros((2, 3)), D), "2 rows; allowed: 3 rows"),
        ((X0, O, D, 0.0, np.ones((2, 2))), "t_max: shape (2, 2)"),
        (((1, 2), O, D), "x0: shape (2,)"),
    ],
)
def test_bad_segments_raise_value_errors_naming_the_argument(args, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        omnee.EquiangularSegment(*args)


def test_bad_numbers_raise_value_errors():
    seg = omnee.EquiangularSegment(X0, np.zeros((4, 3)), D)
    with pytest.raises(ValueError, match=r"u\[2\] = 1.5 is out of range; allowed: \[0, 1\]"):
        seg.sample([0.1, 0.2, 1.5, 0.3])
    with pytest.raises(ValueError, match=r"one row per ray"):
        seg.sample(np.zeros(5))
    with pytest.raises(TypeError, match="dtype"):
        seg.pdf(np.zeros(4, dtype=np.complex64))


def test_table_phase_is_constant_per_bin_and_pickles():
    theta = np.array([0.0, 0.2, 1.0, np.pi])
    values = np.array([5.0, 1.0, 0.5])
    p = omnee.Phase.table(theta, values)
    assert p.spec == "table"
    mass = values * (np.cos(theta[:-1]) - np.cos(theta[1:]))
    scale = 1.0 / (2 * np.pi * mass.sum())
    probe = np.array([0.1, 0.5, 2.0])
    np.testing.assert_allclose(p.eval(probe), values * scale, rtol=1e-12)
    q = pickle.loads(pickle.dumps(p))
    assert q == p and q.spec == "table"
    np.testing.assert_array_equal(q.eval(probe), p.eval(probe))
    assert pickle.loads(pickle.dumps(omnee.Phase("hg:0.5"))) == omnee.Phase("hg:0.5")


@pytest.mark.parametrize(
    "theta, values, field",
    [
        ([0.0, 1.0, np.pi], [1.0], "theta"),
        ([0.1, np.pi], [1.0], "theta"),
        ([0.0, 1.0], [1.0], "theta"),
        ([0.0, np.pi], [-1.0], "values"),
        ([0.0, np.pi], [0.0], "values"),
    ],
)
def test_bad_tables_raise_value_errors_naming_the_field(theta, values, field):
    with pytest.raises(ValueError, match=field):
        omnee.Phase.table(theta, values)
