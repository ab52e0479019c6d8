//! The recommended combination of OMNEE and the lobe technique
//! (docs/math.md §12).

use super::{Lobe, LobeRay, Restricted, WithLobe};
use crate::error::{Error, check_closed};
use crate::mis::Heuristic;
use crate::real::Real;
use crate::sampling::{Connection, Omnee, Sample, Technique, Vertex, saturate};

/// One-sample MIS with the balance heuristic (Veach 1997, §9.2.4) of OMNEE
/// (the lobe in its weight, [`WithLobe`]) and [`LobeRay`], choosing the lobe
/// technique with probability `c` and OMNEE with `1 − c`: sampling the
/// mixture `q = (1 − c) p_OMNEE + c p_lobe` with weight `k / q`.
///
/// The two cover each other's weak spots: OMNEE's weight grows with `p0`
/// where the lobe points away from the axis, the lobe technique's with
/// `1/sin α` where its ray passes close to `x2`.
///
/// [`recommended`](Self::recommended) sets, per connection, with
/// `ρ = p0(e)/p0_peak` the lobe's value along the axis `e` over its largest,
///
/// `c = (1 − ρ)/2` if `ρ < 0.1`, else `c = 0`.
///
/// Where the axis lies in the lobe's tail (`ρ < 0.1`) the integrand has two
/// parts of comparable size, `p1`'s peak along the axis (OMNEE's) and `p0`'s
/// along its own axis (the lobe technique's), and `c ≈ 1/2` serves both.
/// Elsewhere (an isotropic lobe, one pointing along the axis, a mild one)
/// OMNEE's weight hardly varies with `p0`, a share `c` of samples spent on
/// the lobe technique adds a relative variance of about `c/(1 − c)`, and
/// its density costs every OMNEE sample 0.7× OMNEE's time: `c = 0` draws
/// OMNEE alone at OMNEE's cost. The threshold 0.1 is measured
/// (`benches/lobe.rs`, docs/math.md §12.4): with `c = (1 − ρ)/2` at every
/// ρ the combination was 0.5–0.75× as efficient as OMNEE for
/// 0.1 < ρ < 1 and 1.0–27000× for ρ < 0.1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeMis<F: Real, L, P> {
    omnee: WithLobe<F, Omnee<F, P>, L>,
    ray: LobeRay<F, L, P>,
    c: F,
}

impl<F: Real, L: Lobe<F> + Copy, P: Restricted<F> + Copy> LobeMis<F, L, P> {
    /// The combination with the lobe technique chosen with probability
    /// `c ∈ [0, 1]` (field `"c"`).
    pub fn new(connection: Connection<F>, lobe: L, phase: P, c: F) -> Result<Self, Error> {
        check_closed("c", c.to_f64(), 0.0, 1.0, "[0, 1]")?;
        let omnee = WithLobe::new(Omnee::new(connection, phase), lobe, connection.axis.x0);
        Ok(Self {
            omnee,
            ray: LobeRay::new(connection, lobe, phase),
            c,
        })
    }

    /// The ratio `ρ = p0(e)/p0_peak` below which
    /// [`recommended`](Self::recommended) draws the lobe technique.
    pub const RATIO: f64 = 0.1;

    /// [`new`](Self::new) with `c = (1 − ρ)/2` for `ρ = p0(e)/p0_peak <`
    /// [`RATIO`](Self::RATIO), else `c = 0` (OMNEE alone).
    pub fn recommended(connection: Connection<F>, lobe: L, phase: P) -> Self {
        let along = lobe.eval(connection.axis.e);
        let peak = lobe.peak();
        let ratio = if peak > F::ZERO && along < F::from_f64(Self::RATIO) * peak {
            (along / peak).max(F::ZERO)
        } else {
            F::ONE
        };
        let omnee = WithLobe::new(Omnee::new(connection, phase), lobe, connection.axis.x0);
        Self {
            omnee,
            ray: LobeRay::new(connection, lobe, phase),
            c: (F::ONE - ratio) * F::HALF,
        }
    }

    /// The probability `c` of choosing the lobe technique.
    #[inline]
    pub fn probability(&self) -> F {
        self.c
    }

    /// OMNEE with the lobe in its weight.
    #[inline]
    pub fn omnee(&self) -> &WithLobe<F, Omnee<F, P>, L> {
        &self.omnee
    }

    /// The lobe technique.
    #[inline]
    pub fn ray(&self) -> &LobeRay<F, L, P> {
        &self.ray
    }
}

impl<F: Real, L: Lobe<F> + Copy, P: Restricted<F> + Copy> Technique<F> for LobeMis<F, L, P> {
    /// The lobe technique if `u0 < c` (with `u0/c`), else OMNEE (with
    /// `(u0 − c)/(1 − c)`); weight `w · weight_i / c_i` with the balance
    /// weight `w = c_i p_i / q`, i.e. `k/q`, and pdf `q`, the densities
    /// compared per `L³` of the connection's unit (docs/math.md §15). With
    /// `c = 0` the lobe technique's density is not evaluated.
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        let c = self.c;
        let connection = &self.ray.connection;
        let unit = &connection.axis.unit;
        let u0 = u[0].clamp_to(F::ZERO, F::ONE);
        let (s, own, other) = if u0 < c {
            let v = (u0 / c).min(F::ONE_MINUS_EPSILON);
            let (s, vertex, own) = self.ray.sample_vertex_unit([v, u[1], u[2]], unit)?;
            let other = (F::ONE - c) * self.omnee.pdf_vertex_unit(&vertex, unit);
            (s, c * own, other)
        } else {
            let v = ((u0 - c) / (F::ONE - c)).clamp_to(F::ZERO, F::ONE_MINUS_EPSILON);
            let (s, vertex, own) = self.omnee.sample_vertex_unit([v, u[1], u[2]], unit)?;
            let own = (F::ONE - c) * own;
            let other = if c > F::ZERO {
                c * self.ray.pdf_vertex_unit(&vertex, unit)
            } else {
                F::ZERO
            };
            (s, own, other)
        };
        let share = if u0 < c { c } else { F::ONE - c };
        let w = Heuristic::Balance.weight(own, [other]);
        Some(Sample {
            x1: s.x1,
            pdf: saturate(unit.density_from_unit(own + other)),
            weight: saturate(w * s.weight / share),
        })
    }

    /// The mixture density `(1 − c) p_OMNEE + c p_lobe`, summed per `L³`.
    fn pdf(&self, x1: F::Vec3) -> F {
        let connection = &self.ray.connection;
        let unit = &connection.axis.unit;
        let vertex = Vertex::at(connection, x1);
        let omnee = (F::ONE - self.c) * self.omnee.pdf_vertex_unit(&vertex, unit);
        let total = if self.c > F::ZERO {
            omnee + self.c * self.ray.pdf_vertex_unit(&vertex, unit)
        } else {
            omnee
        };
        saturate(unit.density_from_unit(total))
    }

    /// Not invertible: both techniques reach every point.
    fn invert(&self, _x1: F::Vec3) -> Option<[F; 3]> {
        None
    }
}
