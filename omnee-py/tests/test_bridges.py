"""omnee.Bridge and omnee.estimate(vertices=...): bridges of k vertices, the
same numbers as the C API and the omnee binary, estimates of I_K against the
isotropic closed form within 4.5 standard errors (fixed seeds), bad input as
ValueErrors naming the argument, a spent budget as NotConvergedError."""

import json
import struct
import subprocess

import numpy as np
import pytest

import omnee

X0, X2 = (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
MEDIUM = dict(sigma_s=0.5, sigma_t=0.55)


def test_sample_shapes_density_and_precision():
    b = omnee.Bridge(x0=X0, x2=X2, phase="hg:0.7")
    u = np.random.default_rng(5).random((200, 3, 3))
    s = b.sample(u)
    assert s.vertices.shape == (200, 3, 3) and s.pdf.shape == (200,) and s.valid.all()
    # The density at the sampled vertices is the sampled density.
    np.testing.assert_allclose(b.pdf(s.vertices), s.pdf, rtol=1e-9)
    # For an exactly sampled phase function weight = D^(k+1)/(s^3 k!), s = 1.
    np.testing.assert_allclose(s.weight, s.length**4 / 6.0, rtol=1e-12)
    # Back to the numbers, and from them to the same vertices.
    inv = b.invert(s.vertices)
    assert inv.u.shape == u.shape and inv.valid.all()
    np.testing.assert_allclose(inv.u, u, atol=1e-9)
    np.testing.assert_allclose(b.sample(inv.u).vertices, s.vertices, atol=1e-9)
    # A vertex on x0 has no inverse: valid False, u 0.
    on_x0 = s.vertices[:1].copy()
    on_x0[0, 0] = X0
    assert not b.invert(on_x0).valid[0] and (b.invert(on_x0).u == 0).all()
    with pytest.raises(ValueError, match=r"vertices\[0, 1, 2\] = nan is out of range"):
        b.invert([[[0.1, 0.2, 0.3], [0.1, 0.1, np.nan]]])
    # float32 in, f32 computed, float32 out, close to f64.
    s32 = b.sample(u.astype(np.float32))
    assert s32.vertices.dtype == np.float32 and s32.pdf.dtype == np.float32
    np.testing.assert_allclose(s32.vertices, s.vertices, atol=1e-4)
    # The last edge's end is x2: every path closes (a single vertex lies on
    # the sphere through x0 and x2 scaled by D, here just finite).
    assert np.isfinite(s.vertices).all()


# The bridge lines of `cargo run -p omnee-ffi --example expected` (the Rust
# API's bit patterns, which omnee-ffi/ci.sh checks the C API against) for
# k = 2: length, pdf, phase_ratio, weight, then the vertices.
BITS_K2 = {
    np.float64: "40005f7872600347 3fc312d77e613177 3ff0000000000000 40065b1b6f772cee "
    "bf899ed3458fb380 3fc4e414f0396f58 3fc3471bfbbb3ef8 bfc704d77774baea 3fd50d6bcca21dbf "
    "bfd1f0e086e4a2c0",
    np.float32: "4002fbd0 3e18962c 3f800000 4032d90d bc4cfa80 3e27212b 3e1a38b8 be382714 "
    "3ea86bbc be8f8720",
}


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_same_numbers_as_rust_and_c_bit_for_bit(dtype):
    # bits_body.inc: u[j] = u3[j % 4][j % 3] * 0.999 in the precision, hg:0.9.
    u3 = [[0.1, 0.2, 0.3], [0.5, 0.5, 0.5], [0.9, 0.05, 0.77], [0.999, 0.6, 0.1]]
    u = np.array([dtype(u3[j % 4][j % 3]) * dtype(0.999) for j in range(6)], dtype=dtype)
    b = omnee.Bridge(x0=(0.3, -0.2, 1.1), x2=(-0.1, 0.4, 0.2), phase="hg:0.9")
    s = b.sample(u.reshape(1, 2, 3))
    numbers = [s.length[0], s.pdf[0], 1.0, s.weight[0], *s.vertices[0].ravel()]
    width = 16 if dtype == np.float64 else 8
    got = " ".join(format(int(np.array(x, dtype=dtype).view(
        np.uint64 if dtype == np.float64 else np.uint32)), f"0{width}x") for x in numbers)
    assert got == BITS_K2[dtype]


@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_estimate_of_i_k_against_the_closed_form(k):
    e = omnee.estimate(x0=X0, x2=X2, phase="iso", samples=200_000, seed=11, vertices=k, **MEDIUM)
    closed = omnee.isotropic_transfer(k, s=1.0, **MEDIUM)
    assert e.reference == pytest.approx(closed, rel=1e-12)
    assert abs(e.mean - closed) < 4.5 * e.stderr, (e.mean, e.stderr, closed)
    assert e.stderr < 0.01 * closed


def test_estimate_with_the_number_of_vertices_drawn():
    e = omnee.estimate(x0=X0, x2=X2, phase="iso", samples=200_000, seed=3, vertices="auto",
                       max_vertices=4, **MEDIUM)
    closed = sum(omnee.isotropic_transfer(k, s=1.0, **MEDIUM) for k in range(1, 5))
    assert e.reference == pytest.approx(closed, rel=1e-12)
    assert abs(e.mean - closed) < 4.5 * e.stderr, (e.mean, e.stderr, closed)


def test_bridge_samples_estimate_i_k_by_hand():
    # The per-sample estimate sigma_s^k e^(-sigma_t D) weight from Bridge.sample.
    k = 2
    b = omnee.Bridge(x0=X0, x2=X2)
    s = b.sample(np.random.default_rng(8).random((200_000, k, 3)))
    x = MEDIUM["sigma_s"] ** k * np.exp(-MEDIUM["sigma_t"] * s.length) * s.weight
    closed = omnee.isotropic_transfer(k, s=1.0, **MEDIUM)
    assert abs(x.mean() - closed) < 4.5 * x.std(ddof=1) / np.sqrt(len(x))


def test_same_numbers_as_the_binary(omnee_bin):
    args = [omnee_bin, "estimate", "--json", "--reference", "--x0", "0,0,1", "--x2", "0,0,0",
            "--phase", "iso", "--sigma-s", "0.5", "--sigma-t", "0.55", "--samples", "20000",
            "--seed", "4", "--precision", "f64", "--vertices", "3"]
    cli = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    e = omnee.estimate(x0=X0, x2=X2, phase="iso", samples=20_000, seed=4, vertices=3, **MEDIUM)
    assert (e.mean, e.stderr) == (cli["mean"], cli["stderr"])


def test_bad_input_names_the_argument():
    b = omnee.Bridge(x0=X0, x2=X2)
    with pytest.raises(ValueError, match=r"u\[0, 1, 2\] = nan is out of range; allowed: \[0, 1\]"):
        b.sample([[[0.5, 0.5, 0.5], [0.5, 0.5, np.nan]]])
    with pytest.raises(ValueError, match=r"u\[0, 0, 1\] = 1.5 is out of range"):
        b.sample([[[0.5, 1.5, 0.5]]])
    with pytest.raises(ValueError, match=r"u: shape \(0, 3\); allowed: \(\.\.\., k, 3\) with k in \[1, 32\]"):
        b.sample(np.zeros((0, 3)))
    with pytest.raises(ValueError, match=r"k in \[1, 32\]"):
        b.sample(np.full((33, 3), 0.5))
    with pytest.raises(ValueError, match=r"vertices\[0, 0, 0\] = inf is out of range; allowed: finite coordinates"):
        b.pdf([[[np.inf, 0, 0]]])
    with pytest.raises(ValueError, match="x0/x2"):
        omnee.Bridge(x0=X0, x2=X0)
    with pytest.raises(ValueError, match=r"vertices = 0 is out of range; allowed: \[1, 32\]"):
        omnee.estimate(x0=X0, x2=X2, vertices=0, **MEDIUM)
    with pytest.raises(ValueError, match=r"vertices = 33 is out of range"):
        omnee.estimate(x0=X0, x2=X2, vertices=33, **MEDIUM)
    with pytest.raises(ValueError, match=r"vertices = \"three\"; allowed"):
        omnee.estimate(x0=X0, x2=X2, vertices="three", **MEDIUM)
    with pytest.raises(ValueError, match=r"max_vertices = 0 is out of range"):
        omnee.estimate(x0=X0, x2=X2, vertices="auto", max_vertices=0, **MEDIUM)
    with pytest.raises(ValueError, match=r"max_vertices = 4 applies to vertices=\"auto\" only"):
        omnee.estimate(x0=X0, x2=X2, vertices=2, max_vertices=4, **MEDIUM)
    with pytest.raises(ValueError, match="theta_max"):
        omnee.estimate(x0=X0, x2=X2, vertices=2, theta_max=3.0, **MEDIUM)
    # No closed form for anisotropic scattering: reference=False estimates.
    with pytest.raises(ValueError, match="phase = hg:0.9 has no reference"):
        omnee.estimate(x0=X0, x2=X2, vertices=2, phase="hg:0.9", **MEDIUM)
    assert omnee.estimate(x0=X0, x2=X2, vertices=2, phase="hg:0.9", reference=False,
                          samples=1000, **MEDIUM).reference is None
    with pytest.raises(ValueError, match=r"k = 0 is out of range"):
        omnee.isotropic_transfer(0, s=1.0, **MEDIUM)
    with pytest.raises(ValueError, match=r"sigma_t = 0 is out of range; allowed: \(0, inf\) for k >= 2"):
        omnee.isotropic_transfer(2, s=1.0, sigma_s=0.0, sigma_t=0.0)
    with pytest.raises(ValueError, match=r"s = -1"):
        omnee.isotropic_transfer(2, s=-1.0, **MEDIUM)
    with pytest.raises(ValueError, match=r"budget = 0 is out of range"):
        omnee.isotropic_transfer(2, s=1.0, budget=0, **MEDIUM)


def test_a_spent_budget_is_not_converged_error():
    assert issubclass(omnee.NotConvergedError, RuntimeError)
    with pytest.raises(omnee.NotConvergedError,
                       match="reference: the quadrature did not converge within its budget"):
        omnee.isotropic_transfer(3, s=1.0, budget=20, **MEDIUM)
    # The same with its default budget converges.
    assert omnee.isotropic_transfer(3, s=1.0, **MEDIUM) > 0.0


def test_vertex_count_matches_the_c_api_and_its_frequencies():
    x0, x2 = np.array([0.3, -0.2, 1.1]), np.array([-0.1, 0.4, 0.2])
    count = omnee.VertexCount(8, s=float(np.linalg.norm(x2 - x0)), phase="hg:0.9", **MEDIUM)
    # The f64 "vertex count" line of omnee-ffi's bit patterns (u = 0.1, 0.5, 0.9, 0.999).
    k, p = count.sample(np.array([0.1, 0.5, 0.9, 0.999]))
    assert k.dtype == np.int64 and list(k) == [1, 1, 5, 8]
    c_bits = ["3fe38923d77466a7", "3fe38923d77466a7", "3f9a39d05c2e2400", "3f9999b34d5051e0"]
    c_values = [struct.unpack(">d", bytes.fromhex(h))[0] for h in c_bits]
    # s is formed here by numpy, in the C API by the connection: equal to an ulp.
    np.testing.assert_allclose(p, c_values, rtol=1e-13)
    pmf = count.pmf(np.arange(0, 10))
    assert pmf[0] == 0.0 and pmf[9] == 0.0 and pmf[1:9].sum() == pytest.approx(1.0, abs=1e-12)
    # Drawn frequencies against P(k), each within 4.5 binomial standard errors.
    n = 200_000
    k, p = count.sample(np.random.default_rng(6).random(n))
    np.testing.assert_array_equal(p, pmf[k])
    freq = np.bincount(k, minlength=9)[1:9] / n
    assert (np.abs(freq - pmf[1:9]) < 4.5 * np.sqrt(pmf[1:9] * (1 - pmf[1:9]) / n)).all()
    with pytest.raises(ValueError, match=r"k_max = 0 is out of range; allowed: \[1, 32\]"):
        omnee.VertexCount(0, s=1.0, **MEDIUM)
    with pytest.raises(ValueError, match=r"u\[1\] = nan is out of range; allowed: \[0, 1\]"):
        count.sample([0.5, np.nan])
    with pytest.raises(ValueError, match=r"s = -1"):
        omnee.VertexCount(4, s=-1.0, **MEDIUM)
    # pmf takes integers of any dtype (and huge or negative ones are 0), never
    # a truncated 2.5 or a NaN.
    assert count.pmf(2) == pmf[2] and count.pmf(np.float32(3.0)) == pmf[3]
    assert list(count.pmf([-5, 2**62, 1e300])) == [0.0, 0.0, 0.0]
    for bad, shown in [(2.5, "2.5"), (np.nan, "nan"), (np.inf, "inf")]:
        with pytest.raises(ValueError, match=rf"k\[1\] = {shown} is out of range; allowed: integers"):
            count.pmf([1, bad])


def test_bridges_at_extreme_scales_keep_the_scale_law():
    """End points λ apart: a float64 bridge at λ = 1e±300 and a float32 one at
    1e±30 give the unit bridge's numbers scaled (vertices λ, weight λ^{k-2}
    for k = 2: the same), its density and inverse hold, and the estimate of
    I_k (σ scaled by 1/λ) is λ⁻² times the unit one. A float32 call on a
    bridge whose end points coincide in float32 is a ValueError naming them."""
    u = np.array([[0.3, 0.4, 0.5], [0.6, 0.2, 0.7]])
    x2 = np.array([1.0, -0.25, 0.5])
    unit = omnee.Bridge(x0=(0, 0, 0), x2=x2, phase="hg:0.9").sample(u)
    for lam, dtype in [(1e-300, np.float64), (1e300, np.float64), (1e-30, np.float32),
                       (1e30, np.float32)]:
        b = omnee.Bridge(x0=(0, 0, 0), x2=x2 * lam, phase="hg:0.9")
        s = b.sample(u.astype(dtype))
        rtol = 1e-12 if dtype == np.float64 else 1e-5
        assert s.valid
        np.testing.assert_allclose(s.vertices / lam, unit.vertices, rtol=rtol * 10, atol=1e-6)
        assert s.weight == pytest.approx(unit.weight, rel=rtol * 10)
        assert b.pdf(s.vertices) == pytest.approx(s.pdf, rel=rtol * 100) or s.pdf == np.finfo(dtype).max
        back = b.invert(s.vertices)
        assert back.valid
        np.testing.assert_allclose(back.u, u, atol=rtol * 100)
    with pytest.raises(ValueError, match=r"x0/x2: .* \(in float32\)"):
        omnee.Bridge(x0=(0, 0, 0), x2=x2 * 1e-300).sample(u.astype(np.float32))
    one = omnee.estimate(x0=(0, 0, 0), x2=(0, 0, 1), sigma_s=0.5, sigma_t=0.55, phase="iso",
                         vertices=2, samples=20_000)
    for lam, dtype in [(1e-30, np.float32), (1e30, np.float32), (1e-150, np.float64)]:
        e = omnee.estimate(x0=(0, 0, 0), x2=(0, 0, lam), sigma_s=0.5 / lam, sigma_t=0.55 / lam,
                           phase="iso", vertices=2, samples=20_000, dtype=dtype)
        assert e.mean * lam * lam == pytest.approx(one.mean, rel=1e-4), (lam, e)
        assert e.reference * lam * lam == pytest.approx(one.reference, rel=1e-9)
