//! Circumcircle geometry: the triangle `x0, x1, x2` in the coordinates
//! (θ, β, φ) of docs/math.md §2.
//!
//! `α` is the angle at `x0` (between the axis `e` and `x1 − x0`), `β` the angle
//! at `x2` (between `−e` and `x1 − x2`), and θ = α + β the deflection at `x1`.
//! For fixed θ every `x1` on the circular arc through `x0` and `x2` has the same
//! deflection (inscribed angle theorem): the talk's "waterlevel". φ rotates the
//! triangle's plane about the axis.
//!
//! The map keeps `β` as the fraction `β/θ ∈ [0, 1]` (the sampler's `u2`), which
//! stays meaningful at θ = 0, where `x1` lies on the segment at `d1 = (β/θ) s`.
//! Lengths come from the law of sines written with `sinc`, so nothing divides
//! zero by zero:
//!
//! `d1 = s sin β / sin θ = s (β/θ) sinc β / sinc θ`,
//! `d2 = s sin α / sin θ = s (α/θ) sinc α / sinc θ`.

use crate::error::Error;
use crate::phase::Deflection;
use crate::real::{Real, Vector, sinc, sinc_is_series, sinc_with_sin};

/// The fixed end points `x0` (light side) and `x2` (receiver side) with the
/// orthonormal frame `(b1, b2, e)` about the axis `e = (x2 − x0)/s`, and
/// the connection's [`Unit`] of length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis<F: Real> {
    /// The light-side end point.
    pub x0: F::Vec3,
    /// The receiver-side end point.
    pub x2: F::Vec3,
    /// `s = |x2 − x0| > 0` (rounded to the precision, subnormal for a
    /// distance below its normal range).
    pub s: F,
    /// The unit axis `e = (x2 − x0)/s`.
    pub e: F::Vec3,
    /// First unit vector perpendicular to `e` (φ = 0).
    pub b1: F::Vec3,
    /// Second unit vector perpendicular to `e` (φ = π/2), `b1 × b2 = e`.
    pub b2: F::Vec3,
    /// The power of two `L` near `s` in which lengths are measured where
    /// their squares or products could leave the range (docs/math.md §15).
    pub unit: Unit<F>,
    /// `s/L`, exact: `s` itself inside the [`Unit`]'s band, else in
    /// `[1, 2)` (down to 2⁻²³ in f32, 2⁻⁵² in f64 for a subnormal `s`, up to
    /// 4 for `s ≥ 2^MAX_EXPONENT`).
    pub s_unit: F,
}

/// The length unit of a connection: the power of two `L = 2ᵏ` in which
/// lengths are measured where their squares, products or inverses could
/// leave the range (docs/math.md §15).
///
/// `L = 1` for `2⁻ᵇ ≤ s < 2ᵇ⁺¹` with `b = MAX_EXPONENT/16` (7 in f32,
/// 63 in f64: s from 0.008 to 256 m in f32), where lengths of order `s`,
/// their squares and the products of four of them stay far inside the
/// range, so that at ordinary scales the core computes in metres and
/// skips every scaling. Outside that band `2ᵏ ≤ s < 2ᵏ⁺¹`, `k` clamped to
/// `[MIN_EXPONENT, MAX_EXPONENT − 1]` so that `L` and `1/L` are normal
/// numbers: lengths divided by `L` are of order one at any `s` from the
/// smallest subnormal to `F::MAX`, and a density `q` computed in the unit
/// (per `L³`) is `q L⁻³` in the volume measure. Multiplying by `L` or `1/L`
/// is exact (a power of two), so scaling a problem by a power of two scales
/// every result exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit<F> {
    /// `k`, with `L = 2ᵏ`.
    pub exponent: i32,
    /// `L = 2ᵏ`.
    pub length: F,
    /// `1/L = 2⁻ᵏ`.
    pub inverse: F,
}

impl<F: Real> Unit<F> {
    /// The band `[2⁻ᵇ, 2ᵇ⁺¹)` of distances `s` whose unit is 1,
    /// `b = MAX_EXPONENT/16`.
    #[inline]
    pub fn band() -> (F, F) {
        let b = F::MAX_EXPONENT / 16;
        (F::ONE.scale_pow2(-b), F::ONE.scale_pow2(b + 1))
    }

    /// The unit of a connection of length `s` (finite, > 0; any other `s`
    /// gives the unit 1): 1 inside the band `|⌊log₂ s⌋| ≤ MAX_EXPONENT/16`,
    /// else `k = ⌊log₂ s⌋` clamped to `[MIN_EXPONENT, MAX_EXPONENT − 1]`.
    #[inline]
    pub fn of(s: F) -> Self {
        let band = F::MAX_EXPONENT / 16;
        let k = if s > F::ZERO && s.is_finite() {
            let k = s.exponent();
            if (-band..=band).contains(&k) {
                0
            } else {
                k.clamp(F::MIN_EXPONENT, F::MAX_EXPONENT - 1)
            }
        } else {
            0
        };
        Self {
            exponent: k,
            length: F::ONE.scale_pow2(k),
            inverse: F::ONE.scale_pow2(-k),
        }
    }

    /// A length `x` in the unit in metres, `x L` (no multiplication for
    /// `L = 1`, the common case: the samplers' latency counts).
    #[inline(always)]
    pub fn to_metres(&self, x: F) -> F {
        if self.exponent == 0 {
            x
        } else {
            x * self.length
        }
    }

    /// A volume density `q` per `L³` in the volume measure, `q L⁻³`
    /// (rounded once where it leaves the normal range, 0 below it, ∞
    /// above).
    #[inline(always)]
    pub fn density_from_unit(&self, q: F) -> F {
        if self.exponent == 0 {
            q
        } else {
            q.scale_pow2(-3 * self.exponent)
        }
    }

    /// A volume density `p` (m⁻³) per `L³`, `p L³`.
    #[inline]
    pub fn density_to_unit(&self, p: F) -> F {
        p.scale_pow2(3 * self.exponent)
    }
}

/// The coordinates (θ, β/θ, φ) of a point `x1` relative to an [`Axis`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Angles<F> {
    /// The deflection θ = α + β ∈ [0, π].
    pub theta: F,
    /// `β/θ ∈ [0, 1]`, the share of θ at `x2`; at θ = 0 the limit `d1/s`.
    pub beta_ratio: F,
    /// The azimuth φ ∈ [0, 2π) of the triangle's plane about the axis.
    pub phi: F,
}

impl<F: Real> Angles<F> {
    /// β = (β/θ) θ, the angle at `x2`.
    #[inline]
    pub fn beta(&self) -> F {
        self.beta_ratio * self.theta
    }

    /// α = (1 − β/θ) θ, the angle at `x0`.
    #[inline]
    pub fn alpha(&self) -> F {
        (F::ONE - self.beta_ratio) * self.theta
    }
}

impl<F: Real> Axis<F> {
    /// The axis from `x0` to `x2`: any two finite, distinct points whose
    /// distance `s` is at most `F::MAX` (docs/math.md §15). `s` and `e` are
    /// computed on `x2 − x0` in the [`Unit`] of `s` (`(x2 − x0)/L`, an exact
    /// scaling), so neither `s²` nor `1/s` over- or underflows: end points
    /// 1e-45 or 3e38 apart in f32 have their exact axis.
    ///
    /// Fails for non-finite points (`NotFinite`, field `"x0"` or `"x2"`),
    /// for `x0 == x2` (`Degenerate`, `"x2"`) and for a distance above
    /// `F::MAX` (`NotFinite`, `"x2 - x0"`: it has no value in the precision).
    pub fn new(x0: F::Vec3, x2: F::Vec3) -> Result<Self, Error> {
        if !x0.is_finite() {
            return Err(Error::not_finite("x0"));
        }
        if !x2.is_finite() {
            return Err(Error::not_finite("x2"));
        }
        // A component of x2 − x0 overflows only if s > F::MAX.
        let d = x2 - x0;
        if !d.is_finite() {
            return Err(Error::not_finite("x2 - x0"));
        }
        let s = d.length();
        if !(s > F::ZERO) {
            return Err(Error::Degenerate {
                field: "x2",
                reason: "coincides with x0 (s = 0)",
            });
        }
        if !s.is_finite() {
            return Err(Error::not_finite("x2 - x0"));
        }
        let unit = Unit::of(s);
        // s/L from (x2 − x0)/L itself: for a subnormal s, whose rounding
        // lost bits, d/L still has them all.
        let d_unit = d * unit.inverse;
        let s_unit = d_unit.length();
        let e = d_unit * (F::ONE / s_unit);
        let (b1, b2) = e.orthonormal_pair();
        Ok(Self {
            x0,
            x2,
            s,
            e,
            b1,
            b2,
            unit,
            s_unit,
        })
    }

    /// `x − x0` in the connection's unit, `(x − x0)/L`, formed as
    /// `x/L − x0/L` (exact scalings), so that it does not overflow for
    /// points on opposite sides near `F::MAX`.
    #[inline]
    pub fn from_x0_unit(&self, x: F::Vec3) -> F::Vec3 {
        x * self.unit.inverse - self.x0 * self.unit.inverse
    }

    /// `x − x2` in the connection's unit, `(x − x2)/L`.
    #[inline]
    pub fn from_x2_unit(&self, x: F::Vec3) -> F::Vec3 {
        x * self.unit.inverse - self.x2 * self.unit.inverse
    }

    /// The point `x1 = x0 + d1 (cos α e + sin α (cos φ b1 + sin φ b2))` with the
    /// given angles (docs/math.md §2), the triangle solved in the
    /// connection's [`Unit`]. `None` where the map has no point: θ ≥ π
    /// (`x1` at infinity), a point beyond `F::MAX`, or non-finite input.
    #[inline]
    pub fn point(&self, angles: Angles<F>) -> Option<F::Vec3> {
        let triangle = Triangle::from_angles(self.s_unit, angles)?.in_metres(&self.unit);
        self.place(&triangle, angles.phi)
    }

    /// The apex `x1 = x0 + d1 cos α · e + d1 sin α · (cos φ b1 + sin φ b2)` of a
    /// solved triangle turned by φ about the axis; `None` if it is not finite.
    #[inline]
    pub fn place(&self, triangle: &Triangle<F>, phi: F) -> Option<F::Vec3> {
        let (sin_phi, cos_phi) = phi.sin_cos();
        self.place_radial(triangle, self.b1 * cos_phi + self.b2 * sin_phi)
    }

    /// [`place`](Self::place) with the azimuth in turns, `φ = 2π turn`
    /// (`turn ∈ [0, 1]`, the sampler's uniform number), through
    /// [`Real::sin_cos_turn`]: the samplers' form, without rounding φ first.
    #[inline(always)]
    pub fn place_turn(&self, triangle: &Triangle<F>, turn: F) -> Option<F::Vec3> {
        let (sin_phi, cos_phi) = turn.sin_cos_turn();
        self.place_radial(triangle, self.b1 * cos_phi + self.b2 * sin_phi)
    }

    /// `x0 + d1 cos α · e + d1 sin α · radial` for a unit `radial ⊥ e`.
    #[inline(always)]
    fn place_radial(&self, triangle: &Triangle<F>, radial: F::Vec3) -> Option<F::Vec3> {
        let x1 = self.x0
            + self.e * (triangle.d1 * triangle.cos_alpha)
            + radial * (triangle.d1 * triangle.sin_alpha);
        x1.is_finite().then_some(x1)
    }

    /// The angles of `x1`, the inverse of [`point`](Self::point). With the
    /// foot coordinates `p1 = e·(x1 − x0)`, `p2 = e·(x2 − x1)` and the distance
    /// from the axis `h = |e × (x1 − x0)|`, all in the connection's [`Unit`]:
    /// `α = atan2(h, p1)`, `β = atan2(h, p2)`, θ = α + β,
    /// `φ = atan2((x1 − x0)·b2, (x1 − x0)·b1)`.
    ///
    /// One `h` serves both angles, so the rounding noise of a point near the
    /// axis cancels in `β/θ → p1/(p1 + p2)`. On the axis φ = 0, and between
    /// the end points θ = 0 and `β/θ = d1/s`. `None` for non-finite `x1`.
    #[inline]
    pub fn angles(&self, x1: F::Vec3) -> Option<Angles<F>> {
        if !x1.is_finite() {
            return None;
        }
        // In the connection's unit (atan2 and the ratios are scale-free).
        let a = self.from_x0_unit(x1);
        let h = self.e.cross(a).length();
        let p1 = self.e.dot(a);
        let p2 = -self.e.dot(self.from_x2_unit(x1));
        let alpha = h.atan2(p1);
        let beta = h.atan2(p2);
        let theta = alpha + beta;
        let beta_ratio = if theta > F::ZERO {
            beta / theta
        } else {
            (p1 / self.s_unit).clamp_to(F::ZERO, F::ONE)
        };
        let mut phi = a.dot(self.b2).atan2(a.dot(self.b1));
        if phi < F::ZERO {
            phi += F::TAU;
        }
        if phi >= F::TAU {
            phi = F::ZERO;
        }
        Some(Angles {
            theta: theta.min(F::PI),
            beta_ratio,
            phi,
        })
    }
}

/// The triangle `x0 x1 x2` with base `s`, deflection θ at `x1` and `β = (β/θ) θ`
/// at `x2`, solved once: what both the point and its density need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle<F> {
    /// `d1 = |x1 − x0| = s sin β / sin θ`.
    pub d1: F,
    /// `d2 = |x2 − x1| = s sin α / sin θ`.
    pub d2: F,
    /// `sinc θ = sin θ / θ` (1 at θ = 0): the OMNEE weight is `1 / (s sinc θ)`.
    pub sinc_theta: F,
    /// sin α, α the angle at `x0`.
    pub sin_alpha: F,
    /// cos α.
    pub cos_alpha: F,
}

impl<F: Real> Triangle<F> {
    /// A triangle solved in a connection's [`Unit`], its sides in metres
    /// (`d L`; its angles unchanged).
    #[inline(always)]
    pub fn in_metres(self, unit: &Unit<F>) -> Self {
        Self {
            d1: unit.to_metres(self.d1),
            d2: unit.to_metres(self.d2),
            ..self
        }
    }

    /// [`solve`](Self::solve) for plain angles, θ ∈ [0, π) (its versines from θ).
    #[inline]
    pub fn from_angles(s: F, angles: Angles<F>) -> Option<Self> {
        if !(angles.theta >= F::ZERO && angles.theta < F::PI) {
            return None;
        }
        Self::solve(s, Deflection::from_theta(angles.theta), angles.beta_ratio)
    }

    /// Solves the triangle by the law of sines (docs/math.md §2, §4),
    /// `d1 = s sin β / sin θ`, `d2 = s sin α / sin θ`, with
    /// `sin θ = √((1 − cos θ)(1 + cos θ))` from the deflection's versines.
    ///
    /// Only the smaller angle `x` of α and β goes through `sin_cos`; the
    /// larger one, θ − x, follows from the addition theorems
    /// `sin(θ − x) = sin θ cos x − cos θ sin x` and
    /// `cos(θ − x) = cos θ cos x + sin θ sin x`. For θ > π/2 both terms of the
    /// sine are non-negative, so the angle near π keeps its digits even where
    /// the rounded θ has lost those of π − θ; for θ ≤ π/2 the sine loses at
    /// most log2(3) bits (θ − x ≥ θ/2). For θ so small that `sin θ / θ` is its
    /// series (θ = 0 included) the lengths are in `sinc` form,
    /// `d1 = s (β/θ) sinc β / sinc θ`, `d2 = s (α/θ) sinc α / sinc θ`
    /// (`d1 = (β/θ) s` at θ = 0).
    ///
    /// `None` for θ ≥ π (the triangle does not close), `β/θ ∉ [0, 1]` or
    /// non-finite input.
    #[inline(always)]
    pub fn solve(s: F, deflection: Deflection<F>, beta_ratio: F) -> Option<Self> {
        Self::solve_with_beta(s, deflection, beta_ratio).map(|(t, _, _)| t)
    }

    /// [`solve`](Self::solve) with `(sin β, cos β)` of the angle at `x2`,
    /// which place `x1` from `x2`: `x1 − x2 = d2 (sin β ρ − cos β e)`.
    #[inline(always)]
    pub(crate) fn solve_with_beta(
        s: F,
        deflection: Deflection<F>,
        beta_ratio: F,
    ) -> Option<(Self, F, F)> {
        let theta = deflection.theta;
        if !(theta >= F::ZERO
            && theta < F::PI
            && deflection.one_plus_cos > F::ZERO
            && (F::ZERO..=F::ONE).contains(&beta_ratio))
        {
            return None;
        }
        let (beta, alpha) = (beta_ratio * theta, (F::ONE - beta_ratio) * theta);
        let (sin_theta, cos_theta) = (deflection.sin(), deflection.cos());
        // min(β, α) = θ min(β/θ, 1 − β/θ) exactly (rounding is monotone), with
        // the comparison off the path from θ.
        let beta_is_smaller = beta_ratio <= F::ONE - beta_ratio;
        let small = theta * beta_ratio.min(F::ONE - beta_ratio);
        let (sin_small, cos_small) = small.sin_cos_acute();
        let sin_large = sin_theta * cos_small - cos_theta * sin_small;
        let cos_large = cos_theta * cos_small + sin_theta * sin_small;
        let (sin_alpha, cos_alpha, sin_beta, cos_beta) = if beta_is_smaller {
            (sin_large, cos_large, sin_small, cos_small)
        } else {
            (sin_small, cos_small, sin_large, cos_large)
        };
        let (d1, d2, sinc_theta) = if sinc_is_series(theta) {
            let sinc_theta = sinc(theta);
            let scale = s / sinc_theta;
            let d1 = scale * beta_ratio * sinc_with_sin(beta, sin_beta);
            let d2 = scale * (F::ONE - beta_ratio) * sinc_with_sin(alpha, sin_alpha);
            (d1, d2, sinc_theta)
        } else {
            let scale = s / sin_theta;
            (scale * sin_beta, scale * sin_alpha, sin_theta / theta)
        };
        (d1.is_finite() && d2.is_finite() && sinc_theta > F::ZERO).then_some((
            Self {
                d1,
                d2,
                sinc_theta,
                sin_alpha,
                cos_alpha,
            },
            sin_beta,
            cos_beta,
        ))
    }
}

/// The side lengths `(d1, d2)` of the triangle with base `s` and the given
/// angles ([`Triangle::solve`] in the [`Unit`] of `s`, so that a side is
/// finite wherever its value is); `None` for θ ≥ π or non-finite input.
#[inline]
pub fn side_lengths<F: Real>(s: F, angles: Angles<F>) -> Option<(F, F)> {
    let unit = Unit::of(s);
    let t = Triangle::from_angles(s * unit.inverse, angles)?.in_metres(&unit);
    (t.d1.is_finite() && t.d2.is_finite()).then_some((t.d1, t.d2))
}

/// The talk's fractional distance of the foot of `x1` along the axis,
/// `t = d1 cos α / s = sin β cos(θ − β) / sin θ = (β/θ) sinc β cos α / sinc θ`;
/// `t ∈ [0, 1]` exactly when θ ≤ π/2. Sampling `β = u θ` is the talk's
/// `t = P⁻¹(u | θ) = cos(θ − uθ) sin(uθ) / sin θ`. `None` for θ ≥ π.
#[inline]
pub fn fractional_distance<F: Real>(angles: Angles<F>) -> Option<F> {
    let t = Triangle::from_angles(F::ONE, angles)?;
    Some(t.d1 * t.cos_alpha)
}

/// The circumradius of the triangle, `R = s / (2 sin θ)` (∞ at θ = 0, where
/// the arc is the segment itself).
#[inline]
pub fn circumradius<F: Real>(s: F, theta: F) -> F {
    let sin_theta = theta.sin().abs();
    if sin_theta > F::ZERO {
        s / (F::TWO * sin_theta)
    } else {
        F::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn axis() -> Axis<f64> {
        Axis::new(DVec3::new(0.3, -1.0, 2.0), DVec3::new(1.1, 0.5, 1.2)).unwrap()
    }

    #[test]
    fn point_and_angles_are_inverse() {
        let ax = axis();
        for &theta in &[1e-7, 0.01, 0.5, 1.5, 2.5, 3.1] {
            for &ratio in &[1e-6, 0.25, 0.5, 0.9, 0.999] {
                for &phi in &[0.0, 1.0, 3.0, 6.0] {
                    let a = Angles {
                        theta,
                        beta_ratio: ratio,
                        phi,
                    };
                    let x1 = ax.point(a).unwrap();
                    let back = ax.angles(x1).unwrap();
                    // x1 is rounded to about ε(|x0| + s) in each coordinate, which
                    // moves the angles at x0 and x2 by that over d1 and d2.
                    let (d1, d2) = side_lengths(ax.s, a).unwrap();
                    let noise =
                        8.0 * f64::EPSILON * (ax.x0.length() + ax.s) * (1.0 / d1 + 1.0 / d2);
                    assert!(
                        (back.theta - theta).abs() < 1e-12 + noise,
                        "{a:?} -> {back:?}"
                    );
                    assert!(
                        (back.beta_ratio - ratio).abs() < 1e-9 + noise / theta,
                        "{a:?} -> {back:?}"
                    );
                    let phi_err = (back.phi - phi)
                        .abs()
                        .min(core::f64::consts::TAU - (back.phi - phi).abs());
                    assert!(phi_err < 1e-9 + noise / theta.sin(), "{a:?} -> {back:?}");
                }
            }
        }
    }

    #[test]
    fn constructed_point_has_the_requested_triangle() {
        let ax = axis();
        let a = Angles {
            theta: 0.7,
            beta_ratio: 0.3,
            phi: 2.0,
        };
        let x1 = ax.point(a).unwrap();
        let (w1, w2) = ((x1 - ax.x0).normalize(), (ax.x2 - x1).normalize());
        assert!(
            (w1.dot(w2) - 0.7f64.cos()).abs() < 1e-12,
            "deflection at x1"
        );
        let (d1, d2) = side_lengths(ax.s, a).unwrap();
        assert!(((x1 - ax.x0).length() - d1).abs() < 1e-12);
        assert!(((ax.x2 - x1).length() - d2).abs() < 1e-12);
        // x1 lies on the circumcircle of radius s/(2 sin θ).
        let r = circumradius(ax.s, 0.7);
        let centre_dist = r * 0.7f64.cos(); // centre to chord midpoint
        let mid = (ax.x0 + ax.x2) * 0.5;
        let radial = (x1 - mid) - ax.e * (x1 - mid).dot(ax.e);
        let centre = mid - radial.normalize() * centre_dist;
        assert!(((x1 - centre).length() - r).abs() < 1e-12);
    }

    #[test]
    fn theta_zero_puts_x1_on_the_segment() {
        let ax = axis();
        let x1 = ax
            .point(Angles {
                theta: 0.0,
                beta_ratio: 0.25,
                phi: 1.0,
            })
            .unwrap();
        assert!((x1 - (ax.x0 + ax.e * 0.25 * ax.s)).length() < 1e-15);
        let back = ax.angles(x1).unwrap();
        assert!(
            back.theta < 1e-14 && (back.beta_ratio - 0.25).abs() < 1e-14,
            "{back:?}"
        );
    }

    #[test]
    fn fractional_distance_is_the_talks_formula() {
        for &(theta, u) in &[(0.3f64, 0.2f64), (1.2, 0.7), (1.5, 0.5), (1e-6, 0.4)] {
            let t = fractional_distance(Angles {
                theta,
                beta_ratio: u,
                phi: 0.0,
            })
            .unwrap();
            let talk = (theta - u * theta).cos() * (u * theta).sin() / theta.sin();
            assert!((t - talk).abs() < 1e-9, "theta {theta}: {t} vs {talk}");
            assert!((0.0..=1.0).contains(&t));
        }
        // Past π/2 the foot leaves the segment.
        let t = fractional_distance(Angles {
            theta: 2.5,
            beta_ratio: 0.1,
            phi: 0.0,
        })
        .unwrap();
        assert!(t < 0.0);
    }

    #[test]
    fn f32_is_stable_across_scales_and_near_the_axis() {
        for &s in &[1e-6f32, 1.0, 1e6] {
            let ax = Axis::<f32>::new(glam::Vec3::ZERO, glam::Vec3::new(0.0, 0.0, s)).unwrap();
            for &theta in &[0.0f32, 1e-30, 1e-6, 3e-3, 1.0, 3.0] {
                let a = Angles {
                    theta,
                    beta_ratio: 0.5,
                    phi: 1.0,
                };
                let x1 = ax.point(a).unwrap();
                let back = ax.angles(x1).unwrap();
                assert!(back.theta.is_finite() && back.beta_ratio.is_finite());
                assert!(
                    (back.beta_ratio - 0.5).abs() < 1e-3,
                    "s {s} theta {theta}: {back:?}"
                );
                assert!(
                    (back.theta - theta).abs() <= 1e-5 * theta.max(1e-3),
                    "s {s} θ {theta}: {back:?}"
                );
            }
        }
    }

    #[test]
    fn degenerate_input_is_refused() {
        let p = DVec3::new(1.0, 2.0, 3.0);
        assert!(Axis::<f64>::new(p, p).is_err());
        assert!(Axis::<f64>::new(DVec3::new(f64::NAN, 0.0, 0.0), p).is_err());
        assert!(Axis::<f64>::new(p, DVec3::new(0.0, f64::INFINITY, 0.0)).is_err());
        let ax = axis();
        assert!(
            ax.point(Angles {
                theta: core::f64::consts::PI,
                beta_ratio: 0.5,
                phi: 0.0
            })
            .is_none()
        );
        assert!(
            ax.point(Angles {
                theta: f64::NAN,
                beta_ratio: 0.5,
                phi: 0.0
            })
            .is_none()
        );
        assert!(ax.angles(DVec3::new(f64::NAN, 0.0, 0.0)).is_none());
    }
}
