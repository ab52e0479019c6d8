//! Bridges of `k` vertices for the point-to-point problem (docs/math.md
//! §14): the estimate of
//!
//! `I_K = ∫…∫ Π_i σs p(θ_i) e^{−σt (d_1 + … + d_{K+1})} / (d_1² ⋯ d_{K+1}²) dx_1 ⋯ dx_K`
//!
//! for a fixed `K` ([`VertexNumber::Fixed`]), or of `Σ_{K=1}^{K_max} I_K` with
//! `K` drawn per sample ([`VertexNumber::Auto`]), and the exact reference for
//! isotropic scattering (the core's [`isotropic_transfer`]). One draw: `k`
//! (one uniform number, when drawn), then `3k` uniform numbers for the
//! bridge ([`Bridge::sample`]), and the estimate `σs^k e^{−σt D} · weight / P(k)`.

use super::problem::{Prepared, vec3};
use crate::error::{RenderError, Result, core_error, not_converged};
use crate::moments::Moments;
use crate::phase::TableStorage;
use crate::rng::Rng;
use crate::vertices::{Orders, VertexNumber};
use omnee_core::Real;
use omnee_core::bridge::{
    Bridge, BridgeSample, MAX_VERTICES, REFERENCE_BUDGET, isotropic_transfer,
};
use omnee_core::medium::Homogeneous;
use omnee_core::phase::{AnyPhase, Phase, PhaseFunction};

/// One order `k` of a bridge estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Order {
    /// The number of vertices `k`.
    pub k: usize,
    /// The probability `P(k)` with which a draw takes `k` vertices.
    pub probability: f64,
    /// The estimate of `I_k` alone: the draws of `k` vertices, each
    /// divided by `P(k)`, averaged over all draws.
    pub mean: f64,
    /// Its standard error.
    pub stderr: f64,
    /// The closed form of `I_k` (isotropic scattering), if asked for.
    pub reference: Option<f64>,
}

/// What the bridges of an estimate were and what each order gave.
#[derive(Clone, Debug, PartialEq)]
pub struct BridgeEstimate {
    /// The number of vertices, as asked for.
    pub vertices: VertexNumber,
    /// With [`VertexNumber::Auto`]: the Poisson mean μ of the core's
    /// [`VertexCount`](omnee_core::bridge::VertexCount) (docs/math.md §14.7).
    pub mean_count: Option<f64>,
    /// Every order a draw can take, in increasing `k`.
    pub orders: Vec<Order>,
}

/// The problem's bridges in precision `F`, ready to draw.
pub struct BridgeSampler<'p, F: Real> {
    /// The bridge from `x0` to `x2` with the phase function at every vertex.
    pub bridge: Bridge<F, &'p Phase<'p, F>>,
    /// The infinite homogeneous medium.
    pub medium: Homogeneous<F>,
    /// How many vertices a draw takes.
    pub orders: Orders<F>,
}

/// One draw of [`BridgeSampler::draw`]: `k`, its probability, the bridge
/// (`None` where its numbers give no path) with its vertices and numbers in
/// the caller's arrays.
#[derive(Clone, Copy, Debug)]
pub struct BridgeDraw<F: Real> {
    /// The number of vertices.
    pub k: usize,
    /// `P(k)`.
    pub probability: F,
    /// The bridge's sample.
    pub sample: Option<BridgeSample<F>>,
}

impl<F: Real> BridgeSampler<'_, F> {
    /// One draw from `rng`: `k` from one uniform number (when drawn), then
    /// `3k` numbers into `u[..k]`, the vertices into `x[..k]`.
    pub fn draw(
        &self,
        rng: &mut Rng,
        u: &mut [[F; 3]; MAX_VERTICES],
        x: &mut [F::Vec3; MAX_VERTICES],
    ) -> BridgeDraw<F> {
        let uk = if self.orders.is_drawn() {
            rng.uniform()
        } else {
            F::ZERO
        };
        let (k, probability) = self.orders.draw(uk);
        for ui in u[..k].iter_mut() {
            *ui = [rng.uniform(), rng.uniform(), rng.uniform()];
        }
        BridgeDraw {
            k,
            probability,
            sample: self.bridge.sample(&u[..k], &mut x[..k]),
        }
    }

    /// The draw's estimate `σs^k e^{−σt D} · weight / P(k)` in f64 (0
    /// without a path): the core's [`Bridge::estimate_f64`], right at scales
    /// where the estimate leaves `F`'s range.
    pub fn estimate(&self, draw: &BridgeDraw<F>) -> f64 {
        draw.sample.map_or(0.0, |s| {
            self.bridge.estimate_f64(&s, &self.medium) / draw.probability.to_f64()
        })
    }
}

impl Prepared {
    /// Whether this problem is drawn by bridges (any number of vertices but
    /// a fixed one, which is the once-more problem of the techniques).
    pub fn bridges(&self) -> bool {
        self.vertices != VertexNumber::Fixed(1)
    }

    /// Runs `f` with the problem's bridges in precision `F`.
    pub fn with_bridge<F: Real, T>(&self, f: impl FnOnce(&BridgeSampler<'_, F>) -> T) -> Result<T> {
        let (p, name) = (&self.problem, |fields: &[&str]| self.spelling.list(fields));
        let mut storage = TableStorage::<F>::default();
        let phase = self.phase.instantiate::<F>(&mut storage)?;
        let bridge = Bridge::new(vec3::<F>(p.x0), vec3::<F>(p.x2), &phase)
            .map_err(|e| core_error(&name(&["x0", "x2"]), e))?;
        let medium = Homogeneous::from_extinction(F::from_f64(p.sigma_s), F::from_f64(p.sigma_t))
            .map_err(|e| core_error(&name(&["sigma_s", "sigma_t"]), e))?;
        let orders = Orders::new(
            self.vertices,
            1,
            bridge.axis.s,
            medium.sigma_s(),
            medium.sigma_t(),
            F::from_f64(self.g),
        );
        Ok(f(&BridgeSampler {
            bridge,
            medium,
            orders,
        }))
    }
}

/// The per-chunk sums of the bridge estimate: the total, each order's
/// share (index `k`), and the draws that gave a path.
pub type BridgeSums = (Moments, Vec<Moments>, u64);

/// The sums of `count` draws from the stream `rng` in precision `F`.
pub fn chunk_sums<F: Real>(
    sampler: &BridgeSampler<'_, F>,
    rng: &mut Rng,
    count: u64,
) -> BridgeSums {
    let (mut total, mut orders, mut accepted) = (
        Moments::default(),
        vec![Moments::default(); MAX_VERTICES + 1],
        0,
    );
    let mut u = [[F::ZERO; 3]; MAX_VERTICES];
    let mut x = [sampler.bridge.axis.x0; MAX_VERTICES];
    for _ in 0..count {
        let draw = sampler.draw(rng, &mut u, &mut x);
        let value = sampler.estimate(&draw);
        accepted += u64::from(draw.sample.is_some());
        total.push(value);
        orders[draw.k].push(value);
    }
    (total, orders, accepted)
}

/// The report of a bridge estimate over `samples` draws from its sums
/// (`references`: the closed forms `I_k`, index `k`, if asked for).
pub fn report(
    p: &Prepared,
    samples: u64,
    orders: &[Moments],
    references: Option<&[f64]>,
) -> Result<BridgeEstimate> {
    p.with_bridge::<f64, _>(|b| {
        let (lo, hi) = p.vertices.range(1);
        BridgeEstimate {
            vertices: p.vertices,
            mean_count: b.orders.mean(),
            orders: (lo..=hi)
                .map(|k| {
                    let (mean, stderr) = orders[k].mean_stderr(samples);
                    Order {
                        k,
                        probability: b.orders.probability(k),
                        mean,
                        stderr,
                        reference: references.map(|r| r[k]),
                    }
                })
                .collect(),
        }
    })
}

/// Whether `phase` is isotropic (`iso`, or Henyey–Greenstein with g = 0).
fn isotropic(phase: &Phase<'_, f64>) -> bool {
    match phase {
        AnyPhase::Isotropic(_) => true,
        AnyPhase::HenyeyGreenstein(_) => phase.mean_cosine() == 0.0,
        _ => false,
    }
}

/// The closed forms `I_k` (index `k`, 0 at index 0) of the orders the
/// problem's bridges take: isotropic scattering only (docs/math.md §14.6);
/// any other phase function is an error naming `phase`.
pub fn references(p: &Prepared) -> Result<Vec<f64>> {
    let problem = &p.problem;
    let mut storage = TableStorage::<f64>::default();
    let phase = p.phase.instantiate::<f64>(&mut storage)?;
    if !isotropic(&phase) {
        return Err(RenderError::Input(format!(
            "{} = {} has no reference with {} = {}: the closed form (docs/math.md §14.6) is for \
             isotropic scattering; allowed: iso (or hg:0), or {} = 1 (the quadrature), or no {}",
            p.spelling.of("phase"),
            p.phase,
            p.spelling.of("vertices"),
            p.vertices,
            p.spelling.of("vertices"),
            p.spelling.of("reference"),
        )));
    }
    let s = super::problem::distance(problem.x0, problem.x2);
    let (lo, hi) = p.vertices.range(1);
    let mut out = vec![0.0; hi + 1];
    for (k, slot) in out.iter_mut().enumerate().skip(lo) {
        *slot = isotropic_transfer(k, s, problem.sigma_s, problem.sigma_t, REFERENCE_BUDGET)
            .map_err(|e| {
                let field = match e {
                    omnee_core::Error::OutOfRange {
                        field: "sigma_t", ..
                    } => p.spelling.list(&["sigma_t"]),
                    omnee_core::Error::NotConverged { .. } => {
                        return not_converged(p.spelling, e);
                    }
                    _ => p.spelling.list(&["reference"]),
                };
                core_error(&field, e)
            })?;
    }
    Ok(out)
}
