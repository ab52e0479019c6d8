//! Adaptive Gauss–Kronrod quadrature in f64, for references and tests.
//!
//! `no_std` and allocation-free: bisection recurses on the stack to a fixed
//! depth. Integrands with a known narrow feature (a forward peak at θ = 0)
//! should be split there by the caller, e.g. with [`integrate_geometric`].
//!
//! The public functions are generic over the integrand, but the work is done
//! by private functions that call it through `&mut dyn FnMut(f64) -> f64`:
//! one copy of the adaptive bisection in a binary instead of one per
//! integrand (the browser demo's module had six), for the price of an
//! indirect call per evaluation.
//!
//! Every integral runs against a [`Budget`] of integrand evaluations,
//! shared by nested integrals: once it is spent, no panel evaluates its
//! integrand any more, every pending integral returns at once, and the
//! caller learns from [`Budget::finish`] that the value did not converge
//! (`Error::NotConverged`). The depth limit already bounds the work of one
//! adaptive integral, but nested ones multiply those bounds (a kink the
//! inner rule cannot resolve costs its depth at every outer node); the
//! budget turns "slow" into a named outcome. [`integrate`] and
//! [`integrate_geometric`] run with an unlimited budget.

/// Nodes of the 15-point Kronrod rule on [−1, 1] (non-negative half).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights for [`XGK`].
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_728_8,
];
/// Weights of the embedded 7-point Gauss rule (at XGK[1], XGK[3], XGK[5], XGK[7]).
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

use crate::error::Error;
use core::cell::Cell;

/// An integrand as the private functions take it.
type Integrand<'a> = &'a mut dyn FnMut(f64) -> f64;

/// A budget of integrand evaluations for one quadrature, nested integrals
/// included: each G7–K15 panel costs 15. When it is spent, panels return
/// 0 without evaluating (so nested integrals unwind at once) and
/// [`finish`](Self::finish) reports `Error::NotConverged`.
#[derive(Debug)]
pub struct Budget {
    used: Cell<u64>,
    limit: u64,
}

impl Budget {
    /// A budget of `limit` evaluations.
    pub const fn new(limit: u64) -> Self {
        Self {
            used: Cell::new(0),
            limit,
        }
    }

    /// No limit (the depth limits alone bound the work).
    pub const fn unlimited() -> Self {
        Self::new(u64::MAX)
    }

    /// The evaluations spent so far.
    pub fn used(&self) -> u64 {
        self.used.get()
    }

    /// Whether the budget is spent: every later panel is 0.
    pub fn exhausted(&self) -> bool {
        self.used.get() >= self.limit
    }

    /// Takes the evaluations of one panel; `false` (and nothing taken)
    /// once the budget is spent.
    fn take_panel(&self) -> bool {
        if self.exhausted() {
            return false;
        }
        self.used.set(self.used.get().saturating_add(15));
        true
    }

    /// `value` if the budget was not spent computing it (and it is
    /// finite), else `Error::NotConverged` naming `field` with the
    /// evaluations spent.
    pub fn finish(&self, field: &'static str, value: f64) -> Result<f64, Error> {
        if self.exhausted() || !value.is_finite() {
            Err(Error::NotConverged {
                field,
                evaluations: self.used(),
            })
        } else {
            Ok(value)
        }
    }

    /// [`integrate`] against this budget.
    pub fn integrate<G: FnMut(f64) -> f64>(
        &self,
        mut f: G,
        a: f64,
        b: f64,
        rel_tol: f64,
        abs_tol: f64,
    ) -> f64 {
        integrate_dyn(&mut f, a, b, rel_tol, abs_tol, self)
    }

    /// [`integrate_geometric`] against this budget.
    pub fn integrate_geometric<G: FnMut(f64) -> f64>(
        &self,
        mut f: G,
        a: f64,
        b: f64,
        levels: u32,
        rel_tol: f64,
    ) -> f64 {
        geometric_dyn(&mut f, a, b, levels, rel_tol, self)
    }
}

/// One G7–K15 panel: `(Kronrod estimate, |Kronrod − Gauss|)` of `∫_a^b f`;
/// `(0, 0)` without evaluating `f` once the budget is spent.
fn gauss_kronrod(f: Integrand<'_>, a: f64, b: f64, budget: &Budget) -> (f64, f64) {
    if !budget.take_panel() {
        return (0.0, 0.0);
    }
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    let fc = f(c);
    let (mut kronrod, mut gauss) = (WGK[7] * fc, WG[3] * fc);
    for i in 0..7 {
        let pair = f(c - h * XGK[i]) + f(c + h * XGK[i]);
        kronrod += WGK[i] * pair;
        if i % 2 == 1 {
            gauss += WG[i / 2] * pair;
        }
    }
    (kronrod * h, ((kronrod - gauss) * h).abs())
}

/// Bisects `[a, b]` (whose panel gave `whole`) until each piece meets its
/// share of `tol`, to `depth` more levels, or the budget is spent.
fn adapt(
    f: Integrand<'_>,
    (a, b): (f64, f64),
    whole: (f64, f64),
    tol: f64,
    depth: u32,
    budget: &Budget,
) -> f64 {
    let (estimate, error) = whole;
    // Below ~100 ulp of the panel's value the error estimate is round-off, and
    // halving the tolerance further would only bisect noise.
    let floor = 128.0 * f64::EPSILON * estimate.abs();
    if error <= tol.max(floor) || depth == 0 || !error.is_finite() || budget.exhausted() {
        return estimate;
    }
    let m = 0.5 * (a + b);
    let left = gauss_kronrod(f, a, m, budget);
    let right = gauss_kronrod(f, m, b, budget);
    adapt(f, (a, m), left, 0.5 * tol, depth - 1, budget)
        + adapt(f, (m, b), right, 0.5 * tol, depth - 1, budget)
}

/// `∫_a^b f(x) dx` by adaptive G7–K15 bisection to an absolute error of about
/// `max(abs_tol, rel_tol · |∫ f|)` (depth at most 40).
pub fn integrate<G: FnMut(f64) -> f64>(
    mut f: G,
    a: f64,
    b: f64,
    rel_tol: f64,
    abs_tol: f64,
) -> f64 {
    integrate_dyn(&mut f, a, b, rel_tol, abs_tol, &Budget::unlimited())
}

/// [`integrate`] through a `dyn` integrand.
fn integrate_dyn(
    f: Integrand<'_>,
    a: f64,
    b: f64,
    rel_tol: f64,
    abs_tol: f64,
    budget: &Budget,
) -> f64 {
    if a == b {
        return 0.0;
    }
    let whole = gauss_kronrod(f, a, b, budget);
    let tol = abs_tol.max(rel_tol * whole.0.abs());
    adapt(f, (a, b), whole, tol, 40, budget)
}

/// `∫_a^b f(x) dx` with panels split geometrically towards `a`:
/// `[a, a + w], [a + w, a + 2w], [a + 2w, a + 4w], …` with `w = (b − a)·2^{−levels}`,
/// each integrated by [`integrate`]. For integrands with a narrow feature at `a`
/// (a forward-peaked phase function at θ = 0), whose width can be 10⁻⁴ of the range.
///
/// The tolerance is relative to the whole integral: a first pass estimates it
/// panel by panel, and every panel then gets the absolute tolerance
/// `rel_tol · |total| / panels`, so panels whose values are negligible (or
/// subnormal) are not refined for their own sake.
pub fn integrate_geometric<G: FnMut(f64) -> f64>(
    mut f: G,
    a: f64,
    b: f64,
    levels: u32,
    rel_tol: f64,
) -> f64 {
    geometric_dyn(&mut f, a, b, levels, rel_tol, &Budget::unlimited())
}

/// [`integrate_geometric`] through a `dyn` integrand.
fn geometric_dyn(
    f: Integrand<'_>,
    a: f64,
    b: f64,
    levels: u32,
    rel_tol: f64,
    budget: &Budget,
) -> f64 {
    pieces_dyn(f, &[(a, b, Towards::Start)], levels, rel_tol, budget)
}

/// Where a piece of [`Budget::integrate_pieces`] has a narrow feature that
/// geometric panels resolve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Towards {
    /// Panels `[a, a + w], [a + w, a + 2w], [a + 2w, a + 4w], …` towards `a`.
    Start,
    /// The same, mirrored, towards `b`.
    End,
    /// One panel `[a, b]`, bisected adaptively.
    Neither,
}

/// The most panels [`Budget::integrate_pieces`] makes (the last piece's
/// last panel takes the rest of it).
const MAX_PANELS: usize = 256;

impl Budget {
    /// `Σ ∫ f` over `pieces` `(a, b, towards)`, each cut into panels
    /// ([`Towards`], `w = (b − a) 2^{−levels}`) and every panel integrated
    /// adaptively to the absolute tolerance `rel_tol · Σ|coarse| / panels`
    /// of a first pass over all of them, as [`integrate_geometric`] does for
    /// one piece: a piece whose integrand is negligible (or underflows to
    /// subnormal noise) is not refined for its own sake. For an integrand
    /// with kinks, pieces split at the kinks keep every panel smooth.
    pub fn integrate_pieces<G: FnMut(f64) -> f64>(
        &self,
        mut f: G,
        pieces: &[(f64, f64, Towards)],
        levels: u32,
        rel_tol: f64,
    ) -> f64 {
        pieces_dyn(&mut f, pieces, levels, rel_tol, self)
    }
}

/// [`Budget::integrate_pieces`] through a `dyn` integrand.
fn pieces_dyn(
    f: Integrand<'_>,
    pieces: &[(f64, f64, Towards)],
    levels: u32,
    rel_tol: f64,
    budget: &Budget,
) -> f64 {
    let mut panels = [(0.0, 0.0); MAX_PANELS];
    let mut count = 0;
    for &(a, b, towards) in pieces {
        if let Some(room) = panels.get_mut(count..).filter(|r| !r.is_empty() && b > a) {
            count += split(a, b, towards, levels, room);
        }
    }
    let panels = panels.get(..count).unwrap_or(&[]);
    let coarse: f64 = panels
        .iter()
        .map(|&(lo, hi)| gauss_kronrod(f, lo, hi, budget).0.abs())
        .sum();
    let abs_tol = rel_tol * coarse / count.max(1) as f64;
    panels
        .iter()
        .map(|&(lo, hi)| integrate_dyn(f, lo, hi, rel_tol, abs_tol, budget))
        .sum()
}

/// Cuts `[a, b]` into `out` ([`Towards`]); returns the panels made (at
/// least one: the last takes what is left when `out` is full).
fn split(a: f64, b: f64, towards: Towards, levels: u32, out: &mut [(f64, f64)]) -> usize {
    let room = out.len();
    let mut width = (b - a) / (1u64 << levels.min(62)) as f64;
    let mut count = 0;
    // A piece too narrow for a first panel of positive width is one panel.
    let towards = if width > 0.0 {
        towards
    } else {
        Towards::Neither
    };
    match towards {
        Towards::Neither => {
            out[0] = (a, b);
            count = 1;
        }
        Towards::Start => {
            let mut lo = a;
            while lo < b && count < room {
                let hi = if count + 1 == room {
                    b
                } else {
                    (lo + width).min(b)
                };
                out[count] = (lo, hi);
                count += 1;
                lo = hi;
                if count > 1 {
                    width *= 2.0;
                }
            }
        }
        Towards::End => {
            let mut hi = b;
            while hi > a && count < room {
                let lo = if count + 1 == room {
                    a
                } else {
                    (hi - width).max(a)
                };
                out[count] = (lo, hi);
                count += 1;
                hi = lo;
                if count > 1 {
                    width *= 2.0;
                }
            }
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly_and_smooth_functions_tightly() {
        // G7 is exact to degree 13, K15 to degree 22.
        let poly = integrate(|x| 3.0 * x * x - 2.0 * x + 1.0, -1.0, 2.0, 1e-14, 0.0);
        assert!((poly - 9.0).abs() < 1e-13);
        let s = integrate(libm::sin, 0.0, core::f64::consts::PI, 1e-12, 0.0);
        assert!((s - 2.0).abs() < 1e-12);
    }

    #[test]
    fn resolves_a_narrow_peak_with_geometric_panels() {
        // ∫_0^π w/(w² + x²) dx = atan(π/w) with w = 1e-5.
        let w = 1e-5;
        let exact = libm::atan(core::f64::consts::PI / w);
        let got = integrate_geometric(
            |x| w / (w * w + x * x),
            0.0,
            core::f64::consts::PI,
            24,
            1e-11,
        );
        assert!((got - exact).abs() < 1e-9 * exact, "{got} vs {exact}");
    }
}
