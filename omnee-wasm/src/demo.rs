//! The demo's computations in plain Rust (no JavaScript types), so that native
//! tests and the browser run the very same code.
//!
//! The demo lives in a plane: `x0` and `x2` are 2-D points `[x, y]`, embedded
//! in 3-D as `(x, y, 0)`. Sampled vertices `x1` are 3-D; for display they are
//! rotated about the axis `x0 x2` into the plane (the half-plane on the side
//! they came from), which keeps `d1`, `d2` and θ: an OMNEE sample of angle θ
//! lands exactly on the drawn arc of that θ.

use crate::phase::{Analytic, Spec};
use crate::rng::Pcg32;
use alloc::vec;
use alloc::vec::Vec;
use omnee_core::Error;
use omnee_core::circumcircle::{Angles, circumradius, fractional_distance, side_lengths};
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::method::Method;
use omnee_core::mis::OmneeMis;
use omnee_core::phase::{Deflection, PhaseFunction};
use omnee_core::real::{Real, Vector};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Directions, Draw, Equiangular, Omnee, Sample, Technique};

/// The precision of sampling: f32, a renderer's (references are f64). It was
/// 1.7× faster in the browser than f64 sampling; f64 makes the module smaller
/// (one copy of each routine; README.md has the measured options).
pub type S = f32;
type Vec3 = <S as Real>::Vec3;

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

/// The techniques the demo compares, in the order of its statistics and of
/// its generators' streams: the core's [`Method`]s but distance sampling
/// (whose weight grows like 1/d1² near the demo's point light: infinite
/// variance, nothing to watch converge).
///
/// - [`Method::Omnee`]: OMNEE over the whole restriction θ < θmax;
/// - [`Method::Equiangular`]: equiangular sampling along uniformly
///   distributed rays from `x2`;
/// - [`Method::Mis`]: the core's recommended MIS (the CLI's `mis`): OMNEE's
///   vertex over θ < θmax, and with probability 0.05 an equiangular vertex
///   behind the cone θ ≥ 3π/4 (balance heuristic there, OMNEE alone in front
///   of it).
pub const METHODS: [Method; 3] = [Method::Omnee, Method::Equiangular, Method::Mis];

/// The position of `method` in [`METHODS`]; an error naming the allowed
/// ones for distance sampling.
pub fn slot(method: Method) -> Result<usize, Error> {
    METHODS
        .iter()
        .position(|&m| m == method)
        .ok_or(Error::Syntax {
            field: "technique",
            reason: "not in the demo; allowed: omnee, equiangular, mis",
        })
}

/// Mean and variance of a stream of estimates (Welford's update).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Running {
    count: u64,
    mean: f64,
    m2: f64,
}

impl Running {
    /// Adds one estimate.
    #[inline]
    pub fn push(&mut self, x: f64) {
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
        self.mean
    }

    /// The standard error of the mean, `√(s²/n)` (0 for fewer than 2).
    pub fn std_error(&self) -> f64 {
        if self.count < 2 {
            0.0
        } else {
            let n = self.count as f64;
            Real::sqrt(self.m2 / (n - 1.0) / n)
        }
    }
}

fn check_count(field: &'static str, n: u32, max: u32, allowed: &'static str) -> Result<(), Error> {
    if n == 0 || n > max {
        Err(Error::OutOfRange {
            field,
            value: f64::from(n),
            allowed,
        })
    } else {
        Ok(())
    }
}

fn plane_point(p: [f64; 2]) -> Vec3 {
    Vec3::new(S::from_f64(p[0]), S::from_f64(p[1]), 0.0)
}

/// The point-to-point problem of `omnee_core::reference` in the demo plane,
/// with running estimates of its integral by the [`METHODS`].
#[derive(Clone, Debug)]
pub struct Problem {
    phase: Analytic<S>,
    problem: PointToPoint<S>,
    reference: f64,
    seed: u32,
    rngs: [Pcg32; 3],
    stats: [Running; 3],
}

impl Problem {
    /// The problem for the phase function `spec` between the plane points
    /// `x0` (unit point light) and `x2` (point receiver) in an infinite
    /// medium (`sigma_s`, `sigma_a`), restricted to θ < `theta_max`; the
    /// quadrature reference is computed here. `seed` seeds the estimators.
    pub fn new(
        spec: &str,
        x0: [f64; 2],
        x2: [f64; 2],
        sigma_s: f64,
        sigma_a: f64,
        theta_max: f64,
        seed: u32,
    ) -> Result<Self, Error> {
        let (phase, phase64) = phases(spec)?;
        let (a, b) = (plane_point(x0), plane_point(x2));
        let connection = Connection::<S>::new(a, b, S::from_f64(theta_max))?;
        let medium = Homogeneous::<S>::new(S::from_f64(sigma_s), S::from_f64(sigma_a))?;
        let problem = PointToPoint::new(connection, medium, None)?;
        // The reference describes exactly the problem sampled: `integral`
        // widens the f32 problem's s, σs, σt and θmax and integrates in f64
        // (no f64 copy of the problem is built). θmax is capped at
        // REFERENCE_THETA_MAX rounded to f32, which is below π (the f32 π is
        // above it).
        let mut capped = problem;
        capped.connection.theta_max = connection.theta_max.min(S::from_f64(REFERENCE_THETA_MAX));
        let reference = capped.integral(&phase64);
        Ok(Self {
            phase,
            problem,
            reference,
            seed,
            rngs: Self::fresh_rngs(seed),
            stats: [Running::default(); 3],
        })
    }

    /// One generator stream per method, `1 + slot`.
    fn fresh_rngs(seed: u32) -> [Pcg32; 3] {
        core::array::from_fn(|i| Pcg32::new(u64::from(seed), 1 + i as u64))
    }

    /// The quadrature reference value of the integral (f64).
    pub fn reference(&self) -> f64 {
        self.reference
    }

    /// The running statistics of `method` (one of [`METHODS`]).
    pub fn stats(&self, method: Method) -> Result<Running, Error> {
        Ok(self.stats[slot(method)?])
    }

    /// Forgets all estimates and restarts the generators from the seed.
    pub fn reset(&mut self) {
        self.rngs = Self::fresh_rngs(self.seed);
        self.stats = [Running::default(); 3];
    }

    /// Draws `n` more samples (1 ..= [`MAX_RUN`]) with each of the
    /// [`METHODS`] and adds their estimates `f_c · k/pdf` (0 where a technique
    /// returns no sample) to the running statistics.
    pub fn run(&mut self, n: u32) -> Result<(), Error> {
        check_count("n", n, MAX_RUN, "[1, 16777216]")?;
        for (i, method) in METHODS.into_iter().enumerate() {
            let (rng, stats) = (&mut self.rngs[i], &mut self.stats[i]);
            for _ in 0..n {
                let draw = draw(&self.phase, method, &self.problem, rng);
                stats.push(draw.sum(|s| self.problem.estimate(s).to_f64()));
            }
        }
        Ok(())
    }

    /// `n` samples (1 ..= [`MAX_CLOUD`]) of `method` (one of [`METHODS`])
    /// from generator `seed`, rotated into the plane: `[x, y, estimate, …]`,
    /// one triple per vertex the draws returned (fewer than `n` when some
    /// fell outside θmax, a few more for MIS's companion vertices). The
    /// estimate is `f_c · k/pdf`; its sum over a draw's vertices has the
    /// integral as its mean.
    pub fn cloud(&self, method: Method, n: u32, seed: u32) -> Result<Vec<f32>, Error> {
        check_count("n", n, MAX_CLOUD, "[1, 1048576]")?;
        let mut rng = Pcg32::new(u64::from(seed), 16 + slot(method)? as u64);
        let problem = &self.problem;
        let axis = &problem.connection.axis;
        let e = axis.e;
        // The in-plane normal of the axis (the plane is z = 0).
        let normal = Vec3::new(-e.y(), e.x(), 0.0);
        // Written in place and truncated: a Vec that never grows (its growth
        // path is half a KiB of the module).
        let mut out = vec![0.0; 6 * n as usize];
        let mut len = 0;
        for _ in 0..n {
            for s in draw(&self.phase, method, problem, &mut rng).samples() {
                let p = s.x1 - axis.x0;
                let along = p.dot(e);
                let radial = p - e * along;
                let h = radial.length().copysign(radial.dot(normal));
                let q = axis.x0 + e * along + normal * h;
                if let Some(point) = out.get_mut(len..len + 3) {
                    point.copy_from_slice(&[
                        q.x().to_f32(),
                        q.y().to_f32(),
                        problem.estimate(s).to_f32(),
                    ]);
                    len += 3;
                }
            }
        }
        out.truncate(len);
        Ok(out)
    }
}

/// One draw of `method` (one of [`METHODS`]) for the problem's connection
/// with numbers from `rng`, the module's one copy of each technique's
/// sampling (a closure per call site would be a copy each): as
/// `omnee_core::method::Setup::draw` draws with uniform directions in an
/// infinite medium, without linking distance sampling, which the demo does
/// not offer (`Setup::draw` made the module 2.5 KiB larger, over the limit).
#[inline(never)]
fn draw(
    phase: &Analytic<S>,
    method: Method,
    problem: &PointToPoint<S>,
    rng: &mut Pcg32,
) -> Draw<S> {
    let connection = problem.connection;
    let next = || S::from_f32(rng.uniform());
    let omnee = Omnee::new(connection, phase);
    let equiangular = NoInverse(Equiangular::new(
        connection,
        phase,
        Directions::Sphere,
        Region::Everywhere,
    ));
    match method {
        Method::Omnee => Draw::single(&omnee, next),
        Method::Equiangular => Draw::single(&equiangular, next),
        Method::Mis => OmneeMis::recommended(omnee, &equiangular).draw(next),
        // Refused by `slot` before any draw.
        Method::Distance => Draw {
            u: [0.0; 6],
            taken: 0,
            vertices: [None, None],
        },
    }
}

/// A technique without its inverse map, which the demo never uses: behind
/// `&dyn Technique` ([`OmneeMis`]'s companion) every trait method is linked
/// through the vtable, and equiangular sampling's `invert` is most of a KiB
/// of the module. Sampling and densities are the technique's own.
struct NoInverse<T>(T);

impl<T: Technique<S>> Technique<S> for NoInverse<T> {
    #[inline]
    fn sample(&self, u: [S; 3]) -> Option<Sample<S>> {
        self.0.sample(u)
    }

    #[inline]
    fn pdf(&self, x1: Vec3) -> S {
        self.0.pdf(x1)
    }

    /// `None`: not offered by the demo (see the type).
    fn invert(&self, _x1: Vec3) -> Option<[S; 3]> {
        None
    }
}

/// A histogram of `n` deflections θ sampled (in f32, as a renderer does) from
/// the phase function `spec`, over `bins` equal bins of `[0, theta_hi]`,
/// against the exact bin averages of the density of θ, `2π p(θ) sin θ`
/// (from the f64 CDF). Returns `2·bins` numbers: the sampled densities, then
/// the exact ones (both per radian; samples above `theta_hi` count in neither).
pub fn histogram(
    spec: &str,
    n: u32,
    bins: u32,
    theta_hi: f64,
    seed: u32,
) -> Result<Vec<f64>, Error> {
    check_count("n", n, MAX_RUN, "[1, 16777216]")?;
    check_count("bins", bins, MAX_BINS, "[1, 4096]")?;
    if !(theta_hi > 0.0 && theta_hi <= core::f64::consts::PI) {
        return Err(Error::OutOfRange {
            field: "theta_hi",
            value: theta_hi,
            allowed: "(0, pi]",
        });
    }
    let (phase, phase64) = phases(spec)?;
    let bins = bins as usize;
    let width = theta_hi / bins as f64;
    let mut out = vec![0.0; 2 * bins];
    let mut rng = Pcg32::new(u64::from(seed), 32);
    for _ in 0..n {
        let theta = phase.sample(S::from_f32(rng.uniform())).theta.to_f64();
        let k = (theta / width) as usize;
        if let Some(c) = out.get_mut(k).filter(|_| k < bins) {
            *c += 1.0;
        }
    }
    let scale = 1.0 / (f64::from(n) * width);
    let (sampled, exact) = out.split_at_mut(bins);
    for c in sampled.iter_mut() {
        *c *= scale;
    }
    let cdf = |theta: f64| phase64.cdf(Deflection::from_theta(theta));
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
    let phase = reference_phase(spec)?;
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

/// The phase function of `spec` in the sampling precision and in f64 (one
/// copy of the parsing and building for the exports that sample).
#[inline(never)]
fn phases(spec: &str) -> Result<(Analytic<S>, Analytic<f64>), Error> {
    let spec = Spec::parse(spec)?;
    Ok((spec.build::<S>()?, spec.build::<f64>()?))
}

/// The f64 phase function of `spec` (one copy of the parsing and building
/// for the exports that need no f32 one).
#[inline(never)]
fn reference_phase(spec: &str) -> Result<Analytic<f64>, Error> {
    Spec::parse(spec)?.build::<f64>()
}

/// The mean cosine ⟨cos θ⟩ of the phase function `spec`.
pub fn mean_cosine(spec: &str) -> Result<f64, Error> {
    Ok(reference_phase(spec)?.mean_cosine())
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
/// `x0` to `x2` and the in-plane normal `n` (`e` turned by +90°): the plane
/// case of the core's `Axis::new`, with its checks and errors and the same
/// arithmetic (`s = √(dx² + dy²)`, `e = d · (1/s)`), without the 3-D frame.
fn axis2(x0: [f64; 2], x2: [f64; 2]) -> Result<(f64, [f64; 2], [f64; 2]), Error> {
    let finite = |p: [f64; 2]| p[0].is_finite() && p[1].is_finite();
    if !finite(x0) {
        return Err(Error::NotFinite { field: "x0" });
    }
    if !finite(x2) {
        return Err(Error::NotFinite { field: "x2" });
    }
    let d = [x2[0] - x0[0], x2[1] - x0[1]];
    let s = Real::sqrt(d[0] * d[0] + d[1] * d[1]);
    if !(s > 0.0) {
        return Err(Error::Degenerate {
            field: "x2",
            reason: "coincides with x0 (s = 0)",
        });
    }
    if !s.is_finite() {
        return Err(Error::NotFinite { field: "x2 - x0" });
    }
    let inv = 1.0 / s;
    let e = [d[0] * inv, d[1] * inv];
    Ok((s, e, [-e[1], e[0]]))
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
pub fn arc(x0: [f64; 2], x2: [f64; 2], theta: f64, segments: u32) -> Result<Vec<f64>, Error> {
    let (s, e, n) = axis2(x0, x2)?;
    check_theta(theta)?;
    check_count("segments", segments, MAX_BINS, "[1, 4096]")?;
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
            if let Some(point) = points.next() {
                point.copy_from_slice(&p);
            }
        }
    }
    Ok(out)
}
