"""Uses the API as a typed program would; `mypy --strict` checks it against
the stubs (omnee-py/ci.sh). Not a pytest module: it only has to type-check
(and runs, as a smoke test, when executed)."""

import pickle
from typing import Optional

import numpy as np
import numpy.typing as npt

import omnee


def once_more(x2: npt.NDArray[np.float32], u: npt.NDArray[np.float32]) -> npt.NDArray[np.float32]:
    """OMNEE's weights for connections from one light to many receivers."""
    t: omnee.Technique = omnee.Omnee(x0=(0.0, 0.0, 2.0), x2=x2, phase=omnee.Phase("hg:0.9"))
    rows: Optional[int] = t.rows
    assert rows == len(x2)
    s: omnee.Samples = t.sample(u)
    out = (np.empty_like(s.x1), np.empty_like(s.pdf), np.empty_like(s.weight), np.empty_like(s.valid))
    t.sample(u, out=out)
    pdf: npt.NDArray[np.float32] = np.asarray(t.pdf(s.x1, out=np.empty_like(s.pdf)))
    assert pdf.shape == s.pdf.shape
    return np.asarray(s.weight, dtype=np.float32)


def main() -> None:
    rng = np.random.default_rng(1)
    x2 = rng.random((10, 3), dtype=np.float32)
    weights = once_more(x2, rng.random((10, 3), dtype=np.float32))
    phase = omnee.Phase("hg:0.5")
    g: float = phase.mean_cosine()
    theta = phase.sample(np.linspace(0, 1, 5))
    inverse: omnee.Inversion = omnee.Equiangular((0, 0, 1), (0, 0, 0), phase, normal=(0, 0, 1)).invert(
        np.zeros((2, 3))
    )
    m = omnee.Mis((0, 0, 1), (0, 0, 0), "iso", slab=(-1.0, 2.0))
    same: bool = pickle.loads(pickle.dumps(m)) == m and hash(m) == hash(m)
    d = omnee.Distance((0, 0, 1), (0, 0, 0), "iso", sigma_t=0.5, theta_max=np.pi / 2)
    e: omnee.Estimate = omnee.estimate(
        x0=(0, 0, 1), x2=(0, 0, 0), sigma_s=0.5, sigma_t=0.6, samples=1000, dtype=np.float32, threads=1
    )
    reference: Optional[float] = e.reference
    print(weights.sum(), g, theta, inverse.valid, same, d.dimension, e.mean, reference)
    print(bridges(rng.random((100, 3, 3))))


def bridges(u: npt.NDArray[np.float64]) -> float:
    """I_3 by bridges, by hand and by estimate, against the closed form."""
    b = omnee.Bridge(x0=(0, 0, 1), x2=(0, 0, 0), phase=omnee.Phase("iso"))
    s: omnee.BridgeSamples = b.sample(u)
    density = np.asarray(b.pdf(s.vertices))
    assert density.shape == s.pdf.shape
    by_hand = float(np.mean(0.5**3 * np.exp(-0.55 * s.length) * s.weight))
    e = omnee.estimate(x0=(0, 0, 1), x2=(0, 0, 0), sigma_s=0.5, sigma_t=0.55, vertices="auto", max_vertices=4)
    try:
        closed = omnee.isotropic_transfer(3, s=1.0, sigma_s=0.5, sigma_t=0.55, budget=10)
    except omnee.NotConvergedError:
        closed = omnee.isotropic_transfer(3, s=1.0, sigma_s=0.5, sigma_t=0.55)
    return by_hand - closed + e.mean


if __name__ == "__main__":
    main()
