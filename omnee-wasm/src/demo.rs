//! The demo's computations in plain Rust (no JavaScript types), so that native
//! tests and the browser run the very same code.
//!
//! The demo lives in a plane: `x0` and `x2` are 2-D points `[x, y]`, embedded
//! in 3-D as `(x, y, 0)`. Sampled vertices `x1` are 3-D; for display they are
//! rotated about the axis `x0 x2` into the plane (the half-plane on the side
//! they came from), which keeps `d1`, `d2` and θ: an OMNEE sample of angle θ
//! lands exactly on the drawn arc of that θ.
//!
//! Everything runs in f64, sampling too (from PCG32's 24-bit uniforms,
//! widened): one copy of each phase function and technique in the module.
//! Sampling in f32 (a renderer's precision, as the demo did before the lobe
//! at `x0`) next to the f64 references made the module 70,537 B with the
//! lobe, over the 64 KiB limit; in f64 it was 65,373 B (README.md).
//!
//! One file for the page's four panels (the convergence [`Problem`], the
//! sample cloud, the phase histogram, the waterlevel and arc geometry), each a
//! handful of short functions that [`crate::bindings`] exposes one to one.

use crate::phase::DemoPhase;
use crate::rng::Pcg32;
use alloc::vec;
use alloc::vec::Vec;
use omnee_core::Error;
use omnee_core::circumcircle::{Angles, Axis, circumradius, fractional_distance, side_lengths};
use omnee_core::lobe::{LobeMis, LobeToPoint, PhaseLobe};
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::mis::OmneeMis;
use omnee_core::phase::{Deflection, PhaseFunction};
use omnee_core::quadrature::Budget;
use omnee_core::real::{Real, Vector};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{self, Connection, Directions, Draw, Equiangular, Omnee, Sample};

type Vec3 = <f64 as Real>::Vec3;

/// Most samples one call may draw (keeps a call under a second or so).
pub const MAX_RUN: u32 = 1 << 24;
/// Most points one sample cloud may hold.
pub const MAX_CLOUD: u32 = 1 << 20;
/// Most histogram bins.
pub const MAX_BINS: u32 = 4096;

/// The largest θmax of the quadrature reference, `π − 10⁻⁴`.
///
/// `PointToPoint::integral` with θmax = π takes seconds instead of
/// milliseconds in an attenuating medium (the adaptive quadrature chases the
/// boundary layer of width ∝ π − θ of the inner integrand at θ → π). The
/// integrand's share of θ ∈ (π − δ, π) is at most
/// `(σs/s) · max p · 2π² δ`, 2·10⁻³ σs max p / s for δ = 10⁻⁴ without attenuation and
/// `∝ δ²/(σt s)` with it: below the Monte Carlo error bars the demo shows.
pub const REFERENCE_THETA_MAX: f64 = core::f64::consts::PI - 1e-4;

/// An estimator the demo runs, by the name the page uses ([`name`](Self::name)).
///
/// Without a lobe at `x0` the demo compares the core's methods but distance
/// sampling (whose weight grows like 1/d1² near the demo's point light:
/// infinite variance, nothing to watch converge): [`PLAIN`]. With a lobe at
/// `x0` (docs/math.md §12) it runs those three with the lobe's value
/// `p0(ω01)` multiplied into their weights (what `omnee_core::lobe::WithLobe`
/// does), and the two techniques that sample the lobe: [`TECHNIQUES`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Technique {
    /// OMNEE over the whole restriction θ < θmax (`Method::Omnee`).
    Omnee,
    /// Equiangular sampling along uniformly distributed rays from `x2`
    /// (`Method::Equiangular`).
    Equiangular,
    /// The core's recommended MIS of OMNEE and equiangular sampling
    /// (`Method::Mis`, `OmneeMis::recommended`, the CLI's `mis`): OMNEE's
    /// vertex over θ < θmax, and with probability 0.05 an equiangular vertex
    /// behind the cone θ ≥ 3π/4 (balance heuristic there, OMNEE alone in
    /// front of it).
    Mis,
    /// The lobe technique (`lobe::LobeRay`), with a lobe at `x0` only: the
    /// direction at `x0` from the lobe, then the deflection at `x1` from the
    /// phase function restricted to `[α, θmax)`, which fixes the distance.
    Lobe,
    /// The recommended combination with a lobe at `x0`
    /// (`LobeMis::recommended`, the CLI's `mis` with `--x0-phase`), with a
    /// lobe only: one-sample balance-heuristic MIS that draws the lobe
    /// technique with probability `c = (1 − ρ)/2` where the lobe's value
    /// along the axis is `ρ < 0.1` of its peak, else OMNEE alone.
    LobeMis,
}

impl Technique {
    /// The name the page uses: `omnee`, `equiangular`, `mis` (the core's
    /// method names), `lobe` and `lobe-mis` (the CLI's JSON name of the
    /// combination).
    pub const fn name(self) -> &'static str {
        match self {
            Technique::Omnee => "omnee",
            Technique::Equiangular => "equiangular",
            Technique::Mis => "mis",
            Technique::Lobe => "lobe",
            Technique::LobeMis => "lobe-mis",
        }
    }
}

/// Every technique, in the order of the statistics and of the generators'
/// streams, which is the enum's (`technique as usize` is its slot); with a
/// lobe at `x0` the demo runs all of them.
pub const TECHNIQUES: [Technique; 5] = [
    Technique::Omnee,
    Technique::Equiangular,
    Technique::Mis,
    Technique::Lobe,
    Technique::LobeMis,
];

/// The techniques without a lobe at `x0`: the first three of [`TECHNIQUES`].
pub const PLAIN: [Technique; 3] = [Technique::Omnee, Technique::Equiangular, Technique::Mis];

/// Mean and variance of a stream of estimates (Welford's update), kept
/// relative to a power of two `scale` (exact), so that the squares of
/// estimates near 1e300 or 1e-300 neither overflow nor underflow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Running {
    count: u64,
    mean: f64,
    m2: f64,
    scale: f64,
}

impl Default for Running {
    /// No estimates, scale 1.
    fn default() -> Self {
        Self::relative_to(1.0)
    }
}

impl Running {
    /// No estimates, kept relative to `2⁻ᵉ` with `2ᵉ ≤ |r| < 2ᵉ⁺¹` (the
    /// estimates of an integral `r` are then near 1); scale 1 for a zero,
    /// subnormal or non-finite `r`.
    pub fn relative_to(r: f64) -> Self {
        let e = ((r.to_bits() >> 52) & 0x7ff).min(2045);
        let scale = if r.is_normal() {
            f64::from_bits((2046 - e) << 52)
        } else {
            1.0
        };
        Self {
            count: 0,
            mean: 0.0,
            m2: 0.0,
            scale,
        }
    }

    /// Adds one estimate.
    #[inline]
    pub fn push(&mut self, x: f64) {
        let x = x * self.scale;
        self.count += 1;
        let delta = x - self.mean;
        self.mean += delta / self.count as f64;
        self.m2 += delta * (x - self.mean);
    }

    /// Number of estimates.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Their mean, the running estimate of the integral (0 before any).
    pub fn mean(&self) -> f64 {
        self.mean / self.scale
    }

    /// The standard error of the mean, `√(s²/n)` (0 for fewer than 2).
    pub fn std_error(&self) -> f64 {
        if self.count < 2 {
            0.0
        } else {
            let n = self.count as f64;
            Real::sqrt(self.m2 / (n - 1.0) / n) / self.scale
        }
    }
}

/// The allowed range of a seed, as errors name it.
pub const SEED_RANGE: &str = "an integer in [0, 4294967295]";
/// The allowed range of [`Problem::run`]'s and [`histogram`]'s `n`.
pub const RUN_RANGE: &str = "an integer in [1, 16777216]";
/// The allowed range of [`Problem::cloud`]'s `n`.
pub const CLOUD_RANGE: &str = "an integer in [1, 1048576]";
/// The allowed range of [`histogram`]'s `bins` and [`arc`]'s `segments`.
pub const BINS_RANGE: &str = "an integer in [1, 4096]";

/// `x` as a `u32` if it is an integer in `[lo, hi]`, else `OutOfRange`
/// naming `field`, `x` as given and `allowed`. The demo takes counts and
/// seeds as f64, the numbers JavaScript has, and checks them here: as a
/// `u32` wasm-bindgen would take them modulo 2³² (2³² + 5 would run 5
/// samples, −1 would be 2³² − 1).
pub fn integer(
    field: &'static str,
    x: f64,
    lo: u32,
    hi: u32,
    allowed: &'static str,
) -> Result<u32, Error> {
    // `as` saturates (NaN → 0): the round trip holds for integers in range only.
    let n = x as u32;
    if f64::from(n) == x && n >= lo && n <= hi {
        Ok(n)
    } else {
        Err(Error::OutOfRange {
            field,
            value: x,
            allowed,
        })
    }
}

/// The plane point `p` in 3-D, `(x, y, 0)`. Not inlined (55 B less,
/// measured: four callers).
#[inline(never)]
fn plane_point(p: [f64; 2]) -> Vec3 {
    Vec3::new(p[0], p[1], 0.0)
}

/// The phase function's lobe at `x0`.
type Lobe = PhaseLobe<f64, DemoPhase<f64>>;

/// The recommended combination with a lobe at `x0`, which also holds its two
/// techniques: OMNEE with the lobe in its weight and the lobe technique.
type Lobed = LobeMis<f64, Lobe, DemoPhase<f64>>;

/// The point-to-point problem of `omnee_core::reference` in the demo plane,
/// optionally with a lobe at `x0` (`omnee_core::lobe`), with running
/// estimates of its integral by the [`PLAIN`] techniques, or with the lobe by
/// all [`TECHNIQUES`].
#[derive(Clone, Debug)]
pub struct Problem {
    phase: DemoPhase<f64>,
    problem: PointToPoint<f64>,
    lobe: Option<Lobed>,
    reference: f64,
    /// The generators and statistics to start from (and restart from,
    /// [`reset`](Self::reset), a copy: recomputing them there was 0.3 KiB
    /// of the module).
    start: ([Pcg32; 5], [Running; 5]),
    rngs: [Pcg32; 5],
    stats: [Running; 5],
}

impl Problem {
    /// The problem for the phase function `spec` between the plane points
    /// `x0` (unit point light) and `x2` (point receiver) in an infinite
    /// medium (`sigma_s`, `sigma_a`), restricted to θ < `theta_max`. `seed`
    /// seeds the estimators.
    ///
    /// With `tilt` (radians, in `[0, π]`) a lobe at `x0`: the same phase
    /// function, for light arriving at `x0` along the axis `x0 → x2` turned
    /// by `tilt` in the plane (counter-clockwise; 0: the light continues
    /// towards `x2`, π: it arrives from `x2`), as in the table of docs/math.md §12.4
    /// (g0 = g1). Without a lobe the 2-D quadrature reference is computed
    /// here (milliseconds); with one the reference is the 3-D quadrature
    /// `LobeToPoint::integral` (seconds natively), which the module does not
    /// link: [`reference`](Self::reference) is NaN and the page takes it
    /// from `web/lobe-references.js` (generated natively by the native
    /// tests).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        spec: &str,
        x0: [f64; 2],
        x2: [f64; 2],
        sigma_s: f64,
        sigma_a: f64,
        theta_max: f64,
        tilt: Option<f64>,
        seed: f64,
    ) -> Result<Self, Error> {
        let seed = integer("seed", seed, 0, u32::MAX, SEED_RANGE)?;
        let phase = phase(spec)?;
        let connection = Connection::new(plane_point(x0), plane_point(x2), theta_max)?;
        let problem = PointToPoint::new(connection, Homogeneous::new(sigma_s, sigma_a)?, None)?;
        let (lobe, reference) = match tilt {
            None => (None, Self::plain_reference(&problem, &phase)?),
            Some(tilt) => {
                let lobe = Lobe::new(phase, incoming(&connection, tilt)?)?;
                let lobed = LobeMis::recommended(connection, lobe, phase);
                (Some(lobed), f64::NAN)
            }
        };
        let (rngs, stats) = (fresh_rngs(seed), [Running::relative_to(reference); 5]);
        Ok(Self {
            phase,
            problem,
            lobe,
            reference,
            start: (rngs, stats),
            rngs,
            stats,
        })
    }

    /// `PointToPoint::try_integral` with θmax capped at
    /// [`REFERENCE_THETA_MAX`]: `NotConverged` (field `"reference"`) when
    /// the quadrature spent its budget or its value left f64's range (an
    /// extreme problem such as σs = 1e300 at s = 1e-300, whose integral is
    /// 1e600), so that the page never shows NaN or ∞. Through the point
    /// receiver's quadrature (`point_integral_within`, what `try_integral`
    /// runs without a receiver normal), which keeps the normal's kinks and
    /// azimuthal integral out of the module (1.6 KiB). Not inlined into
    /// `new` (8 B less, measured).
    #[inline(never)]
    fn plain_reference(problem: &PointToPoint<f64>, phase: &DemoPhase<f64>) -> Result<f64, Error> {
        let mut capped = *problem;
        capped.connection.theta_max = capped.connection.theta_max.min(REFERENCE_THETA_MAX);
        let budget = Budget::new(PointToPoint::<f64>::BUDGET);
        let value = capped.point_integral_within(phase, &budget);
        budget.finish("reference", value)
    }

    /// The techniques estimating this problem: all [`TECHNIQUES`] with a
    /// lobe at `x0`, else [`PLAIN`].
    pub fn techniques(&self) -> &'static [Technique] {
        if self.lobe.is_some() {
            &TECHNIQUES
        } else {
            &PLAIN
        }
    }

    /// The position of `technique` in [`TECHNIQUES`] if this problem
    /// estimates it; for `lobe` and `lobe-mis` without a lobe an error.
    pub fn slot(&self, technique: Technique) -> Result<usize, Error> {
        let slot = technique as usize;
        if slot < self.techniques().len() {
            Ok(slot)
        } else {
            Err(Error::Syntax {
                field: "technique",
                reason: "lobe and lobe-mis need a lobe at x0 (a tilt)",
            })
        }
    }

    /// The quadrature reference value of the integral without a lobe at
    /// `x0` (f64); NaN with one (see [`new`](Self::new)).
    pub fn reference(&self) -> f64 {
        self.reference
    }

    /// With a lobe at `x0`, the reference value of the integral by the 3-D
    /// quadrature `LobeToPoint::integral` (docs/math.md §12; θmax capped at
    /// [`REFERENCE_THETA_MAX`]); `None` without a lobe. Seconds natively:
    /// the bindings do not call it, so the module does not link it (6.4 KiB,
    /// measured); the native tests write it into `web/lobe-references.js`
    /// for the page.
    pub fn lobe_reference(&self) -> Option<f64> {
        let lobed = self.lobe.as_ref()?;
        let mut point = self.problem;
        point.connection.theta_max = point.connection.theta_max.min(REFERENCE_THETA_MAX);
        let problem = LobeToPoint::new(point, Some(lobed.ray().lobe)).ok()?;
        Some(problem.integral(&self.phase))
    }

    /// With a lobe at `x0`, the probability `c` with which the recommended
    /// combination (`lobe-mis`) draws the lobe technique (0: OMNEE alone).
    pub fn lobe_probability(&self) -> Option<f64> {
        self.lobe.map(|l| l.probability())
    }

    /// The running statistics of `technique` (one of
    /// [`techniques`](Self::techniques)).
    pub fn stats(&self, technique: Technique) -> Result<Running, Error> {
        Ok(self.stats[self.slot(technique)?])
    }

    /// Forgets all estimates and restarts the generators from the seed.
    pub fn reset(&mut self) {
        (self.rngs, self.stats) = self.start;
    }

    /// Draws `n` more samples (1 ..= [`MAX_RUN`]) with each of the
    /// [`techniques`](Self::techniques) and adds their estimates
    /// `f_c · k/pdf` (0 where a technique returns no sample) to the running
    /// statistics.
    pub fn run(&mut self, n: f64) -> Result<(), Error> {
        let n = integer("n", n, 1, MAX_RUN, RUN_RANGE)?;
        // Copies, written back (the draws borrow `self`).
        let (mut rngs, mut stats) = (self.rngs, self.stats);
        for ((&technique, rng), stats) in self.techniques().iter().zip(&mut rngs).zip(&mut stats) {
            for _ in 0..n {
                let draw = self.draw(technique, rng);
                stats.push(draw.sum(|s| self.estimate(technique, s)));
            }
        }
        (self.rngs, self.stats) = (rngs, stats);
        Ok(())
    }

    /// One draw of `technique` with numbers from `rng`.
    fn draw(&self, technique: Technique, rng: &mut Pcg32) -> Draw<f64> {
        draw(
            &self.phase,
            &self.problem,
            self.lobe.as_ref(),
            technique,
            rng,
        )
    }

    /// The estimate `f_c · k/pdf` of the vertex `s` of `technique`: with a
    /// lobe at `x0` the techniques that do not sample it ([`PLAIN`]) have
    /// its value `p0(ω01)` multiplied in (the kernel's factor their weight
    /// lacks).
    fn estimate(&self, technique: Technique, s: &Sample<f64>) -> f64 {
        let f = self.problem.estimate(s);
        match &self.lobe {
            Some(lobed) if (technique as usize) < PLAIN.len() => f * lobed.omnee().lobe_at(s.x1),
            _ => f,
        }
    }

    /// `n` samples (1 ..= [`MAX_CLOUD`]) of `technique` (one of
    /// [`techniques`](Self::techniques)) from generator `seed`, rotated into
    /// the plane: `[x, y, estimate, …]`, one triple per vertex the draws
    /// returned (fewer than `n` when some fell outside θmax, a few more for
    /// MIS's companion vertices). The estimate is `f_c · k/pdf`; its sum over
    /// a draw's vertices has the integral as its mean. (With a lobe at `x0`
    /// the rotation loses the azimuth about the axis, on which the integrand
    /// then depends.)
    pub fn cloud(&self, technique: Technique, n: f64, seed: f64) -> Result<Vec<f32>, Error> {
        let n = integer("n", n, 1, MAX_CLOUD, CLOUD_RANGE)?;
        let seed = integer("seed", seed, 0, u32::MAX, SEED_RANGE)?;
        let mut rng = Pcg32::new(u64::from(seed), 16 + self.slot(technique)? as u64);
        let axis = &self.problem.connection.axis;
        let e = axis.e;
        // The in-plane normal of the axis (the plane is z = 0).
        let normal = Vec3::new(-e.y(), e.x(), 0.0);
        // Written in place and truncated: a Vec that never grows (its growth
        // path is half a KiB of the module).
        let mut out = vec![0.0; 6 * n as usize];
        let mut len = 0;
        for _ in 0..n {
            for s in self.draw(technique, &mut rng).samples() {
                let p = s.x1 - axis.x0;
                let along = p.dot(e);
                let radial = p - e * along;
                let h = radial.length().copysign(radial.dot(normal));
                let q = axis.x0 + e * along + normal * h;
                if let Some([x, y, f]) = out.get_mut(len..len + 3) {
                    (*x, *y) = (q.x() as f32, q.y() as f32);
                    *f = self.estimate(technique, s) as f32;
                    len += 3;
                }
            }
        }
        out.truncate(len);
        Ok(out)
    }
}

/// One generator stream per technique, `1 + slot`.
fn fresh_rngs(seed: u32) -> [Pcg32; 5] {
    core::array::from_fn(|i| Pcg32::new(u64::from(seed), 1 + i as u64))
}

/// The incoming propagation direction at `x0`: the unit axis `e` turned by
/// `tilt ∈ [0, π]` in the plane, `cos(tilt) e + sin(tilt) n` with `n` the
/// in-plane normal (`e` turned by +90°).
fn incoming(connection: &Connection<f64>, tilt: f64) -> Result<Vec3, Error> {
    if !(0.0..=core::f64::consts::PI).contains(&tilt) {
        return Err(Error::OutOfRange {
            field: "tilt",
            value: tilt,
            allowed: "[0, pi]",
        });
    }
    let e = connection.axis.e;
    let normal = Vec3::new(-e.y(), e.x(), 0.0);
    let (sin, cos) = Real::sin_cos(tilt);
    Ok(e * cos + normal * sin)
}

/// One draw of `technique` (one of the problem's techniques, checked by the
/// callers) with numbers from `rng`: the module's one copy of the sampling
/// loop, each technique behind `&dyn Technique` (one copy of each sampler),
/// as `omnee_core::method::Setup::draw` draws with uniform directions in an
/// infinite medium, without linking distance sampling, which the demo does
/// not offer (`Setup::draw` made the module 2.5 KiB larger).
#[inline(never)]
fn draw(
    phase: &DemoPhase<f64>,
    problem: &PointToPoint<f64>,
    lobe: Option<&Lobed>,
    technique: Technique,
    rng: &mut Pcg32,
) -> Draw<f64> {
    let next = || f64::from(rng.uniform());
    let connection = problem.connection;
    let omnee = Omnee::new(connection, *phase);
    let equiangular = Equiangular::new(connection, *phase, Directions::Sphere, Region::Everywhere);
    let equiangular = NoInverse(&equiangular);
    let single: &dyn sampling::Technique<f64> = match (technique, lobe) {
        (Technique::Mis, _) => return OmneeMis::recommended(omnee, &equiangular).draw(next),
        (Technique::Equiangular, _) => &equiangular,
        (Technique::Lobe, Some(lobed)) => &NoInverse(lobed.ray()),
        (Technique::LobeMis, Some(lobed)) => lobed,
        // Omnee; the lobe techniques without a lobe are refused by `slot`
        // before any draw.
        _ => &NoInverse(&omnee),
    };
    Draw::single(single, next)
}

/// A technique without its inverse map, which the demo never uses: behind
/// `&dyn Technique` ([`OmneeMis`]'s companion) every trait method is linked
/// through the vtable, and equiangular sampling's `invert` is most of a KiB
/// of the module. Sampling and densities are the technique's own.
struct NoInverse<'a, T>(&'a T);

impl<T: sampling::Technique<f64>> sampling::Technique<f64> for NoInverse<'_, T> {
    #[inline]
    fn sample(&self, u: [f64; 3]) -> Option<Sample<f64>> {
        self.0.sample(u)
    }

    #[inline]
    fn pdf(&self, x1: Vec3) -> f64 {
        self.0.pdf(x1)
    }

    /// `None`: not offered by the demo (see the type).
    fn invert(&self, _x1: Vec3) -> Option<[f64; 3]> {
        None
    }
}

/// A histogram of `n` deflections θ sampled (in f64, as the demo samples)
/// from the phase function `spec`, over `bins` equal bins of
/// `[0, theta_hi]`, against the exact bin averages of the density of θ,
/// `2π p(θ) sin θ` (from the CDF). Returns `2·bins` numbers: the sampled
/// densities, then the exact ones (both per radian; samples above
/// `theta_hi` count in neither).
pub fn histogram(
    spec: &str,
    n: f64,
    bins: f64,
    theta_hi: f64,
    seed: f64,
) -> Result<Vec<f64>, Error> {
    let n = integer("n", n, 1, MAX_RUN, RUN_RANGE)?;
    let bins = integer("bins", bins, 1, MAX_BINS, BINS_RANGE)?;
    let seed = integer("seed", seed, 0, u32::MAX, SEED_RANGE)?;
    if !(theta_hi > 0.0 && theta_hi <= core::f64::consts::PI) {
        return Err(Error::OutOfRange {
            field: "theta_hi",
            value: theta_hi,
            allowed: "(0, pi]",
        });
    }
    let phase = phase(spec)?;
    let bins = bins as usize;
    let width = theta_hi / bins as f64;
    let mut out = vec![0.0; 2 * bins];
    let mut rng = Pcg32::new(u64::from(seed), 32);
    for _ in 0..n {
        let theta = phase.sample(f64::from(rng.uniform())).theta;
        let k = (theta / width) as usize;
        if let Some(c) = out.get_mut(k).filter(|_| k < bins) {
            *c += 1.0;
        }
    }
    let scale = 1.0 / (f64::from(n) * width);
    // (`bins` ≤ the length: the checked split only keeps a panic out of the module.)
    let (sampled, exact) = out.split_at_mut_checked(bins).unwrap_or_default();
    for c in sampled.iter_mut() {
        *c *= scale;
    }
    let cdf = |theta: f64| phase.cdf(Deflection::from_theta(theta));
    let mut lower = cdf(0.0);
    for (k, c) in exact.iter_mut().enumerate() {
        let upper = cdf((k + 1) as f64 * width);
        *c = (upper - lower) / width;
        lower = upper;
    }
    Ok(out)
}

/// The deflection θ with `P(Θ ≤ θ) = u` (`u ∈ [0, 1)`): for choosing a
/// histogram range that shows the forward peak.
///
/// By bisection of the f64 CDF, the one the histogram is drawn against (a
/// sampler is the inverse CDF only for a single lobe: a mixture's spends part
/// of `u` on choosing the lobe). The bracket is halved in the bit patterns of
/// its ends, which order non-negative doubles as their values do, so that 64
/// halvings end at two adjacent doubles whatever the scale of θ (the forward
/// peak of Fournier–Forand holds mass 3e-11 below θ = 1e-19). Returns the
/// upper one: the smallest double with `cdf(θ) ≥ u`.
pub fn quantile(spec: &str, u: f64) -> Result<f64, Error> {
    if !(0.0..1.0).contains(&u) {
        return Err(Error::OutOfRange {
            field: "u",
            value: u,
            allowed: "[0, 1)",
        });
    }
    let phase = phase(spec)?;
    let cdf = |bits| phase.cdf(Deflection::from_theta(f64::from_bits(bits)));
    if cdf(0) >= u {
        return Ok(0.0);
    }
    // cdf(lo) < u ≤ cdf(hi) (cdf(π) = 1 > u).
    let (mut lo, mut hi) = (0, core::f64::consts::PI.to_bits());
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if cdf(mid) < u {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(f64::from_bits(hi))
}

/// The phase function of `spec` (the module's one copy of parsing and
/// building a spec).
#[inline(never)]
fn phase(spec: &str) -> Result<DemoPhase<f64>, Error> {
    crate::phase::build::<f64>(spec)
}

/// The mean cosine ⟨cos θ⟩ of the phase function `spec`.
pub fn mean_cosine(spec: &str) -> Result<f64, Error> {
    Ok(phase(spec)?.mean_cosine())
}

/// The talk's "waterlevel" triangle `x0, x1, x2` in the plane, with `x1` on
/// the arc of constant θ on the left of the axis `x0 → x2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waterlevel {
    /// The vertex `x1`.
    pub x1: [f64; 2],
    /// The deflection θ = α + β at `x1`.
    pub theta: f64,
    /// The angle α at `x0`.
    pub alpha: f64,
    /// The angle β at `x2`.
    pub beta: f64,
    /// `β/θ` (the sampler's uniform number u2, the talk's ξ).
    pub xi: f64,
    /// The talk's fractional distance `t = sin β cos(θ − β)/sin θ` of the
    /// foot of `x1` along the axis.
    pub t: f64,
    /// `s = |x2 − x0|`.
    pub s: f64,
    /// `d1 = |x1 − x0|`.
    pub d1: f64,
    /// `d2 = |x2 − x1|`.
    pub d2: f64,
    /// The circumradius `R = s / (2 sin θ)`.
    pub radius: f64,
    /// The centre of the circumcircle through `x0, x1, x2`.
    pub centre: [f64; 2],
}

/// The distance `s` between two plane points, the unit direction `e` from
/// `x0` to `x2` and the in-plane normal `n` (`e` turned by +90°), from the
/// core's `Axis::new` (its checks and errors).
fn axis2(x0: [f64; 2], x2: [f64; 2]) -> Result<(f64, [f64; 2], [f64; 2]), Error> {
    let axis = Axis::<f64>::new(plane_point(x0), plane_point(x2))?;
    let e = [axis.e.x(), axis.e.y()];
    Ok((axis.s, e, [-e[1], e[0]]))
}

fn check_theta(theta: f64) -> Result<(), Error> {
    if theta > 0.0 && theta < core::f64::consts::PI {
        Ok(())
    } else {
        Err(Error::OutOfRange {
            field: "theta",
            value: theta,
            allowed: "(0, pi)",
        })
    }
}

/// The point of the arc of constant θ at `β/θ = xi`, on the side `side` (±1)
/// of the axis, with its side lengths.
fn arc_point(
    x0: [f64; 2],
    e: [f64; 2],
    n: [f64; 2],
    s: f64,
    angles: Angles<f64>,
    side: f64,
) -> Option<([f64; 2], f64, f64)> {
    let (d1, d2) = side_lengths(s, angles)?;
    let (sin_a, cos_a) = Real::sin_cos(angles.alpha());
    let (a, b) = (d1 * cos_a, side * d1 * sin_a);
    Some((
        [x0[0] + a * e[0] + b * n[0], x0[1] + a * e[1] + b * n[1]],
        d1,
        d2,
    ))
}

/// The triangle for the angle `theta ∈ (0, π)` and `xi = β/θ ∈ [0, 1]`
/// between the plane points `x0` and `x2`.
pub fn waterlevel(x0: [f64; 2], x2: [f64; 2], theta: f64, xi: f64) -> Result<Waterlevel, Error> {
    let (s, e, n) = axis2(x0, x2)?;
    check_theta(theta)?;
    if !(0.0..=1.0).contains(&xi) {
        return Err(Error::OutOfRange {
            field: "xi",
            value: xi,
            allowed: "[0, 1]",
        });
    }
    let angles = Angles {
        theta,
        beta_ratio: xi,
        phi: 0.0,
    };
    let bad = Error::Degenerate {
        field: "theta",
        reason: "the triangle does not close",
    };
    let (x1, d1, d2) = arc_point(x0, e, n, s, angles, 1.0).ok_or(bad)?;
    let t = fractional_distance(angles).ok_or(bad)?;
    let radius = circumradius(s, theta);
    // The centre lies on the bisector of x0 x2, R cos θ away from the chord,
    // on the far side from x1 when θ < π/2 (x1 on the minor arc).
    let h = radius * Real::cos(theta);
    let mid = [(x0[0] + x2[0]) * 0.5, (x0[1] + x2[1]) * 0.5];
    Ok(Waterlevel {
        x1,
        theta,
        alpha: angles.alpha(),
        beta: angles.beta(),
        xi,
        t,
        s,
        d1,
        d2,
        radius,
        centre: [mid[0] - h * n[0], mid[1] - h * n[1]],
    })
}

/// The locus of constant θ in the plane: `segments + 1` points from `x0` to
/// `x2` on the left of the axis, then the same on the right, flattened as
/// `[x, y, …]` (`4 (segments + 1)` numbers; `segments` in 1 ..= 4096).
pub fn arc(x0: [f64; 2], x2: [f64; 2], theta: f64, segments: f64) -> Result<Vec<f64>, Error> {
    let (s, e, n) = axis2(x0, x2)?;
    check_theta(theta)?;
    let segments = integer("segments", segments, 1, MAX_BINS, BINS_RANGE)?;
    let mut out = vec![0.0; 4 * (segments as usize + 1)];
    let mut points = out.chunks_exact_mut(2);
    for side in [1.0, -1.0] {
        for k in 0..=segments {
            let angles = Angles {
                theta,
                beta_ratio: f64::from(k) / f64::from(segments),
                phi: 0.0,
            };
            let (p, _, _) = arc_point(x0, e, n, s, angles, side).ok_or(Error::Degenerate {
                field: "theta",
                reason: "the triangle does not close",
            })?;
            if let Some([x, y]) = points.next() {
                [*x, *y] = p;
            }
        }
    }
    Ok(out)
}
