"""Connections per row: x0, x2 (and the receiver normal) of shape (N, 3),
u of shape (N, ..., k), bit-identical to one single-connection call per
row; `out=` arrays; the arrays read in place; techniques compared, hashed
and pickled by value, and sent to worker processes."""

import multiprocessing
import pickle

import numpy as np
import pytest

import omnee

N = 64


def ends(seed=0, n=N):
    """End points and normals per row, away from each other."""
    rng = np.random.default_rng(seed)
    x0 = rng.normal(size=(n, 3))
    x2 = x0 + rng.normal(size=(n, 3)) + [0.0, 0.0, 0.5]
    normal = rng.normal(size=(n, 3))
    return x0, x2, normal


def make(kind, x0, x2, normal=None, phase="hg:0.7", theta_max=np.pi):
    """A technique of `kind` with the given end points (and normal, slab)."""
    if kind == "omnee":
        return omnee.Omnee(x0, x2, phase, theta_max=theta_max)
    if kind == "equiangular":
        return omnee.Equiangular(x0, x2, phase, theta_max=theta_max, normal=normal, slab=(-3.0, 4.0))
    if kind == "distance":
        return omnee.Distance(x0, x2, phase, sigma_t=0.8, theta_max=theta_max, normal=normal)
    return omnee.Mis(x0, x2, phase, theta_max=theta_max, normal=normal)


KINDS = ["omnee", "equiangular", "distance", "mis"]


def assert_same(a, b):
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
        assert np.asarray(x).dtype == np.asarray(y).dtype


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("ends_dtype", [np.float32, np.float64])
def test_each_row_is_the_single_connection_call_bit_for_bit(kind, dtype, ends_dtype):
    x0, x2, normal = (a.astype(ends_dtype) for a in ends(1))
    with_normal = None if kind == "omnee" else normal
    rows = make(kind, x0, x2, with_normal, theta_max=2.5)
    assert rows.rows == N
    k = rows.dimension
    u = np.random.default_rng(2).random((N, k)).astype(dtype)
    s = rows.sample(u)
    points = np.random.default_rng(3).normal(size=(N, 3)).astype(dtype)
    pdf = rows.pdf(points)
    pdf_at_samples = rows.pdf(s.x1[:, 0] if kind == "mis" else s.x1)
    inverse = None if kind == "mis" else rows.invert(points)
    for i in range(N):
        one = make(kind, x0[i], x2[i], None if with_normal is None else with_normal[i], theta_max=2.5)
        assert one.rows is None
        assert_same([a[i] for a in s], one.sample(u[i]))
        assert_same([pdf[i]], [one.pdf(points[i])])
        x1 = s.x1[i, 0] if kind == "mis" else s.x1[i]
        assert_same([pdf_at_samples[i]], [one.pdf(x1)])
        if inverse is not None:
            assert_same([a[i] for a in inverse], one.invert(points[i]))


@pytest.mark.parametrize("kind", KINDS)
def test_a_shared_end_point_broadcasts_and_rows_may_hold_several_draws(kind):
    x0, x2, normal = ends(4)
    light = np.array([0.1, -0.2, 3.0])
    rows = make(kind, light, x2, None if kind == "omnee" else normal)
    k = rows.dimension
    u = np.random.default_rng(5).random((N, 2, 5, k))
    s = rows.sample(u)
    vertex = (2, 5, 2, 3) if kind == "mis" else (2, 5, 3)
    assert s.x1.shape == (N, *vertex)
    x1 = s.x1[..., 0, :] if kind == "mis" else s.x1
    pdf = rows.pdf(x1)
    assert pdf.shape == (N, 2, 5)
    for i in (0, 17, N - 1):
        one = make(kind, light, x2[i], None if kind == "omnee" else normal[i])
        assert_same([a[i] for a in s], one.sample(u[i]))
        np.testing.assert_array_equal(pdf[i], one.pdf(x1[i]))


def test_rows_must_match_the_connections():
    x0, x2, _ = ends(6)
    rows = omnee.Omnee(x0, x2, "iso")
    with pytest.raises(ValueError, match=r"u: shape \(63, 3\); allowed: \(64, \.\.\., 3\)"):
        rows.sample(np.zeros((N - 1, 3)))
    with pytest.raises(ValueError, match=r"u: shape \(3,\); allowed: \(64, \.\.\., 3\)"):
        rows.sample(np.zeros(3))
    with pytest.raises(ValueError, match=r"x1: shape \(2, 64, 3\)"):
        rows.pdf(np.zeros((2, N, 3)))
    with pytest.raises(ValueError, match=r"x2: 10 rows; allowed: 64 rows, as x0 has"):
        omnee.Omnee(x0, x2[:10], "iso")
    with pytest.raises(ValueError, match=r"normal: 10 rows; allowed: 64 rows"):
        omnee.Equiangular(x0, x2, "iso", normal=np.ones((10, 3)))
    with pytest.raises(ValueError, match=r"x0: shape \(64, 2\); allowed: \(3,\), a point x, y, z, or \(N, 3\)"):
        omnee.Omnee(x0[:, :2], x2, "iso")


def test_a_bad_row_is_named():
    x0, x2, normal = ends(7)
    x2[40] = x0[40]
    with pytest.raises(ValueError, match=r"row 40: x2: coincides with x0"):
        omnee.Omnee(x0, x2, "iso")
    x2 = x0 + 1.0
    x0[9, 1] = np.nan
    with pytest.raises(ValueError, match=r"row 9: x0 has a non-finite component .*; allowed: finite coordinates"):
        omnee.Omnee(x0, x2, "iso")
    x0 = x2 - 1.0
    normal[3] = 0.0
    with pytest.raises(ValueError, match=r"row 3: normal: must be finite and non-zero"):
        omnee.Mis(x0, x2, "iso", normal=normal)
    with pytest.raises(ValueError, match=r"theta_max = 4 is out of range"):
        omnee.Omnee(x0, x2, "iso", theta_max=4.0)


def test_a_row_valid_in_f64_but_not_in_f32_is_named_at_the_call():
    x0 = np.zeros((3, 3))
    x2 = np.array([[0, 0, 1.0], [0, 0, 1e-60], [0, 0, 2.0]])
    rows = omnee.Omnee(x0, x2, "iso")
    rows.sample(np.full((3, 3), 0.5))
    with pytest.raises(ValueError, match=r"row 1: x2: coincides with x0 .*\(in float32\)"):
        rows.sample(np.full((3, 3), 0.5, np.float32))


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_out_arrays_are_filled_and_returned(kind, dtype):
    x0, x2, normal = ends(8)
    t = make(kind, x0, x2, None if kind == "omnee" else normal)
    u = np.random.default_rng(9).random((N, 3, t.dimension)).astype(dtype)
    want = t.sample(u)
    out = tuple(np.full(a.shape, 7, a.dtype) for a in want)
    got = t.sample(u, out=out)
    assert all(g is o for g, o in zip(got, out))
    assert_same(got, want)
    got = t.sample(u, out=omnee.Samples(*out))
    assert_same(got, want)
    pdf = np.full(want.pdf.shape[:2], -1, dtype)
    assert t.pdf(want.x1[:, :, 0] if kind == "mis" else want.x1, out=pdf) is pdf
    if kind != "mis":
        np.testing.assert_array_equal(pdf, t.pdf(want.x1))
        inv = (np.empty((N, 3, 3), dtype), np.ones((N, 3), bool))
        got = t.invert(want.x1, out=inv)
        assert got.u is inv[0] and got.valid is inv[1]
        assert_same(got, t.invert(want.x1))


def test_bad_out_arrays():
    t = omnee.Omnee((0, 0, 1), (0, 0, 0), "iso")
    u = np.full((5, 3), 0.5)
    good = lambda: [np.zeros((5, 3)), np.zeros(5), np.zeros(5), np.zeros(5, bool)]
    cases = [
        (0, np.zeros((5, 3), np.float32), TypeError, r"out\[0\] \(x1\): dtype float32; allowed: a numpy array of dtype float64"),
        (1, np.zeros(4), ValueError, r"out\[1\] \(pdf\): shape \(4,\); allowed: \(5,\)"),
        (3, np.zeros(5), TypeError, r"out\[3\] \(valid\): dtype float64; allowed: .* bool"),
        (0, np.zeros((3, 5)).T, ValueError, r"out\[0\] \(x1\): not C-contiguous"),
        (2, [0.0] * 5, TypeError, r"out\[2\] \(weight\): dtype none"),
    ]
    for k, bad, error, message in cases:
        out = good()
        out[k] = bad
        with pytest.raises(error, match=message):
            t.sample(u, out=out)
    with pytest.raises(ValueError, match=r"out: 3 arrays; allowed: 4"):
        t.sample(u, out=good()[:3])
    frozen = good()
    frozen[1].flags.writeable = False
    with pytest.raises(ValueError, match=r"out\[1\] \(pdf\): read-only"):
        t.sample(u, out=frozen)
    shared = good()
    shared[2] = shared[1]
    with pytest.raises(ValueError, match=r"out\[2\] \(weight\): read-only, or overlaps"):
        t.sample(u, out=shared)
    buffer = np.full(20, 0.5)
    assert t.pdf(buffer[:15].reshape(5, 3), out=buffer[15:]) is not None
    with pytest.raises(ValueError, match=r"out: read-only, or overlaps"):
        t.pdf(buffer[:15].reshape(5, 3), out=buffer[10:15])
    with pytest.raises(ValueError, match=r"overlap"):
        t.sample(buffer[:15].reshape(5, 3), out=[buffer[5:].reshape(5, 3), *good()[1:]])


def test_arrays_are_read_in_place():
    """A technique made from arrays reads them at every call (no copy), and
    sees a write to them; a reshape of one in place is refused."""
    x0, x2, _ = ends(10, n=4)
    t = omnee.Omnee(x0, x2, "iso")
    assert t.x0 is x0 and t.x2 is x2
    u = np.full((4, 3), 0.5)
    before = t.sample(u).x1.copy()
    x0 += 1.0
    x2 += 1.0
    np.testing.assert_allclose(t.sample(u).x1, before + 1.0, rtol=1e-12, atol=1e-12)
    x2[2] = x0[2]
    with pytest.raises(ValueError, match=r"row 2: x2: coincides with x0"):
        t.sample(u)
    x2 += 1.0
    x2.shape = (12,)
    with pytest.raises(ValueError, match=r"reshaped"):
        t.sample(u)


def techniques_to_compare():
    x0, x2, normal = ends(11, n=5)
    phase = omnee.Phase("hg:0.9")
    return [
        omnee.Omnee((0, 0, 1), (0, 0, 0), phase),
        omnee.Omnee((0, 0, 1), (0, 0, 0), "hg:0.9", theta_max=1.0),
        omnee.Equiangular((0, 0, 1), (0, 0, 0), "hg:0.9", normal=(0, 0, 2), slab=(-1, 2)),
        omnee.Distance((0, 0, 1), (0, 0, 0), "iso", sigma_t=0.5, slab=(-1.0, 2.0)),
        omnee.Distance((0, 0, 1), (0, 0, 0), "iso", sigma_t=0.0, slab=(-1.0, 2.0)),
        omnee.Mis(x0, x2, "rayleigh", normal=normal),
        omnee.Mis(x0.astype(np.float32), x2, "rayleigh", normal=(0, 0, 1)),
        omnee.Omnee(x0, (1.0, 2.0, 3.0), phase),
    ]


def test_techniques_compare_and_hash_by_value_and_pickle():
    ts = techniques_to_compare()
    again = techniques_to_compare()
    for i, (a, b) in enumerate(zip(ts, again)):
        assert a == b and hash(a) == hash(b) and not (a != b)
        for j, c in enumerate(ts):
            assert (a == c) == (i == j)
        p = pickle.loads(pickle.dumps(a))
        assert type(p) is type(a) and p == a and hash(p) == hash(a) and repr(p) == repr(a)
    assert ts[0] != "omnee" and ts[0] != ts[0].phase
    assert omnee.Omnee([0, 0, 1], [0, 0, 0.0], "hg:0.90") == omnee.Omnee(
        np.array([0, 0, 1], np.float32), (-0.0, 0, 0), " hg:0.9 ")
    assert len({*ts, *again}) == len(ts)
    rows = ts[5]
    u = np.random.default_rng(12).random((5, 6))
    assert_same(pickle.loads(pickle.dumps(rows)).sample(u), rows.sample(u))


def sample_in_worker(args):
    technique, u = args
    return technique.sample(u)


def test_techniques_travel_to_worker_processes():
    ts = techniques_to_compare()
    rng = np.random.default_rng(13)
    jobs = [(t, rng.random((5, t.dimension))) for t in ts]
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        results = pool.map(sample_in_worker, jobs)
    for (t, u), got in zip(jobs, results):
        assert_same(got, t.sample(u))


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_the_core_batch_and_the_scalar_loop_draw_the_same_bits(dtype):
    """OMNEE and MIS in f32 go through the core's batch over connections,
    everything else through the scalar calls; MIS with one normal per row
    (the scalar loop) and with the same normal once (the batch in f32)
    draw the same bits, as do OMNEE's draws and MIS's first vertex where
    MIS leaves OMNEE's alone (no companion, in front of the cone)."""
    x0, x2, _ = ends(14, n=3000)
    normal = np.array([0.2, -0.1, 1.0])
    u = np.random.default_rng(15).random((3000, 6)).astype(dtype)
    batch = omnee.Mis(x0, x2, "hg:0.5", normal=normal).sample(u)
    scalar = omnee.Mis(x0, x2, "hg:0.5", normal=np.tile(normal, (3000, 1))).sample(u)
    assert_same(batch, scalar)
    o = omnee.Omnee(x0, x2, "hg:0.5").sample(u[:, :3])
    alone = (u[:, 3] >= 0.05) & batch.valid[:, 0] & (batch.weight[:, 0] == o.weight)
    assert alone.mean() > 0.5
    np.testing.assert_array_equal(batch.x1[alone, 0], o.x1[alone])
    np.testing.assert_array_equal(batch.pdf[alone, 0], o.pdf[alone])
