"""Shared helpers of the omnee Python tests: the CLI binary, a χ² test in the
manner of Mitsuba 3's ChiSquareTest, and the circumcircle map written
independently in numpy."""

import os
import pathlib
import shutil

import numpy as np
import pytest
from scipy import stats

REPO = pathlib.Path(__file__).resolve().parents[2]

# Every χ² test runs at this level; the suite has 24 of them, so a correct
# implementation fails one with probability below 24 · 4e-6 = 9.6e-5
# (Bonferroni over the family), whatever the seeds; the 5σ unbiasedness
# tests add 6 · 5.7e-7.
CHI2_LEVEL = 4e-6


@pytest.fixture(scope="session")
def omnee_bin():
    """The `omnee` binary: $OMNEE_BIN, else target/{release,debug}/omnee, else
    `omnee` on PATH. Missing is a failure under CI (CI=true), a skip elsewhere."""
    candidates = [os.environ.get("OMNEE_BIN")]
    candidates += [str(REPO / "target" / p / "omnee") for p in ("release", "debug")]
    candidates += [shutil.which("omnee")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    message = "no omnee binary: set OMNEE_BIN or run `cargo build -p omnee-cli`"
    if os.environ.get("CI"):
        pytest.fail(message)
    pytest.skip(message)


def chi2_test(observed, expected_probability, draws):
    """Pearson's χ² test of binned counts against bin probabilities, as
    Mitsuba's ChiSquareTest does it: bins expecting fewer than 5 draws are
    pooled into one (kept if the pool reaches 5), the mass outside all bins
    is a bin of its own; the caller asserts P(χ² ≥ observed) > CHI2_LEVEL.
    Returns (p-value, χ², degrees of freedom)."""
    observed = np.asarray(observed, dtype=np.float64).ravel()
    expected = draws * np.asarray(expected_probability, dtype=np.float64).ravel()
    rest_obs = draws - observed.sum()
    rest_exp = max(draws - expected.sum(), 0.0)
    observed = np.append(observed, rest_obs)
    expected = np.append(expected, rest_exp)
    small = expected < 5
    pooled_obs, pooled_exp = observed[small].sum(), expected[small].sum()
    observed, expected = observed[~small], expected[~small]
    if pooled_exp >= 5:
        observed = np.append(observed, pooled_obs)
        expected = np.append(expected, pooled_exp)
    elif pooled_obs > 0 and pooled_exp == 0:
        raise AssertionError(f"{pooled_obs} draws where the pdf is 0")
    chi2 = float(((observed - expected) ** 2 / expected).sum())
    dof = len(observed) - 1
    p = float(stats.chi2.sf(chi2, dof))
    return p, chi2, dof


def frame(x0, x2):
    """`(s, e, b1, b2)`: the distance and an orthonormal frame about the axis."""
    x0, x2 = np.asarray(x0, float), np.asarray(x2, float)
    s = np.linalg.norm(x2 - x0)
    e = (x2 - x0) / s
    helper = np.array([1.0, 0, 0]) if abs(e[0]) < 0.9 else np.array([0, 1.0, 0])
    b1 = np.cross(e, helper)
    b1 /= np.linalg.norm(b1)
    return s, e, b1, np.cross(e, b1)


def circumcircle_point(x0, x2, theta, r, phi):
    """x1 for the deflection θ, β = rθ (the angle at x2), α = θ − β (at x0) and
    the azimuth φ about the axis: d1 = s sin β / sin θ (law of sines).
    Returns (x1, d1, d2)."""
    s, e, b1, b2 = frame(x0, x2)
    beta = r * theta
    alpha = theta - beta
    d1 = s * np.sin(beta) / np.sin(theta)
    d2 = s * np.sin(alpha) / np.sin(theta)
    radial = np.cos(phi)[..., None] * b1 + np.sin(phi)[..., None] * b2
    x1 = (np.asarray(x0, float) + d1[..., None] * (np.cos(alpha)[..., None] * e
                                                   + np.sin(alpha)[..., None] * radial))
    return x1, d1, d2


def circumcircle_angles(x0, x2, x1):
    """(θ, β/θ) of points x1: α = atan2(h, p1), β = atan2(h, p2) with the foot
    coordinates p1, p2 along the axis and the distance h from it."""
    s, e, _, _ = frame(x0, x2)
    a = x1 - np.asarray(x0, float)
    p1 = a @ e
    p2 = (np.asarray(x2, float) - x1) @ e
    h = np.linalg.norm(np.cross(a, e), axis=-1)
    alpha, beta = np.arctan2(h, p1), np.arctan2(h, p2)
    theta = alpha + beta
    return theta, beta / theta
