"""The once-more irradiance of a point light by deterministic quadrature, in
numpy and scipy only (no omnee, no Mitsuba): the reference the head-to-head
checks both renderers' means against (`head_to_head.py --point-light`).

A point light of intensity I at x0, a receiver at p below the slab
z_min ≤ z ≤ z_max with normal +z, a homogeneous medium (σs, σt) in the slab
and Henyey–Greenstein scattering:

    E = ∫_slab σs I p(θ) T(x0, x1) T(x1, p) cos θ2 / (d1² d2²) dx1.

Rays from p: x1 = p + t ω, dx1 = t² dt dω, so 1/d2² cancels. Directions ω
are measured from c = (x0 − p)/|x0 − p| by the polar angle a and the azimuth
b; along the ray, the distance D = |x0 − p| sin a of x0 from it and the
closest approach t0 = |x0 − p| cos a turn t into the angle ψ with
t = t0 + D tan ψ, so that dt/d1² = dψ/D and sin a da/D = da/|x0 − p|:

    E = σs I / |x0 − p| ∫₀^π da ∫₀^{2π} db ∫_{ψ_in}^{ψ_out} p(θ) T1 T2 cos θ2 dψ,

with θ = π/2 + ψ (cos θ = −sin ψ) and cos θ2 = ω_z. Every singularity is
gone: ψ by Gauss–Legendre on panels graded towards the forward peak at
θ = 0, b by the trapezoidal rule (periodic), a adaptively (scipy's quad).
"""

import numpy as np
from scipy import integrate


def hg(cos_theta, g):
    """Henyey–Greenstein per steradian, g > 0 forward."""
    return (1 - g * g) / (4 * np.pi * (1 + g * g - 2 * g * cos_theta) ** 1.5)


def once_more_irradiance(x0, p, intensity, sigma_s, sigma_t, g, z_min, z_max,
                         azimuths=256, rtol=1e-7):
    x0, p = np.asarray(x0, float), np.asarray(p, float)
    assert p[2] < z_min, "the receiver is below the slab"
    dist = np.linalg.norm(x0 - p)
    c = (x0 - p) / dist
    e1 = np.cross(c, [0.0, 1.0, 0.0] if abs(c[1]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(c, e1)
    b = (np.arange(azimuths) + 0.5) * 2 * np.pi / azimuths
    # Panels in θ from the entry angle: widths 1e-5·2^k, 12 Gauss nodes each.
    gx, gw = np.polynomial.legendre.leggauss(12)
    steps = 1e-5 * 2.0 ** np.arange(0, 19)

    def over_b_and_psi(a):
        omega = (np.cos(a) * c[None, :] + np.sin(a) * (np.cos(b)[:, None] * e1 + np.sin(b)[:, None] * e2))
        oz = omega[:, 2]
        up = oz > 1e-12
        omega, oz = omega[up], oz[up]
        if len(oz) == 0:
            return 0.0
        t_in = (z_min - p[2]) / oz
        t_out = (z_max - p[2]) / oz
        t0, D = dist * np.cos(a), dist * np.sin(a)
        psi_in = np.arctan2(t_in - t0, D)
        psi_out = np.arctan2(t_out - t0, D)
        # Graded panels [ψ_in + s_k, ψ_in + s_{k+1}] clipped to ψ_out.
        edges = np.minimum(psi_in[:, None] + np.concatenate([[0.0], steps, [np.pi]])[None, :], psi_out[:, None])
        lo, hi = edges[:, :-1], edges[:, 1:]
        half = 0.5 * (hi - lo)
        psi = (0.5 * (hi + lo))[..., None] + half[..., None] * gx
        weight = half[..., None] * gw
        t = t0 + D * np.tan(psi)
        x1 = p + t[..., None] * omega[:, None, None, :]
        d1 = np.linalg.norm(x1 - x0, axis=-1)
        inside = (x0[2] - x1[..., 2])
        if z_min <= x0[2] <= z_max:
            len1 = d1
        else:
            # The part of x0 → x1 inside the slab (the light above it).
            len1 = d1 * (z_max - x1[..., 2]) / np.where(inside != 0, inside, 1.0)
        T = np.exp(-sigma_t * (len1 + (t - t_in[:, None, None])))
        f = hg(-np.sin(psi), g) * T * oz[:, None, None]
        return float((f * weight).sum()) * (2 * np.pi / azimuths)

    value, _ = integrate.quad(over_b_and_psi, 0.0, np.pi, limit=400, epsrel=rtol, epsabs=0.0,
                              points=[1e-3, 1e-2, 0.1])
    return sigma_s * intensity / dist * value
