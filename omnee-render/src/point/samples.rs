//! The vertices `x1` of a technique's draws for the point-to-point problem,
//! with their uniform numbers, pdf, weight and estimate: `omnee samples`.
//! They are drawn in the chunks and streams of [`super::estimate`], so the
//! same seed lists the draws an estimate averages. With bridges
//! ([`super::bridge`]) a draw has `k` vertices, one row each, all with the
//! bridge's pdf, weight and estimate (the number that drew `k`, when drawn,
//! is not listed).

use super::estimate::STREAM;
use super::problem::{Precision, Prepared, Problem, contribution, x1_f64};
use crate::error::{RenderError, Result, Spelling};
use crate::parallel::{CHUNK, chunks};
use crate::rng::Rng;
use omnee_core::bridge::MAX_VERTICES;
use omnee_core::sampling::Technique;
use omnee_core::{Real, Vector};

/// One vertex of a draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// The draw's index.
    pub draw: u64,
    /// Which of the draw's vertices it is (0: the technique's own, 1: the
    /// MIS companion; with bridges `i − 1` for `x_i`).
    pub vertex: usize,
    /// The three uniform numbers that placed it.
    pub u: [f64; 3],
    /// The vertex `x1`.
    pub x1: [f64; 3],
    /// Its density in the volume measure (a bridge's in the product of the
    /// `k` volume measures), in the problem's precision: saturated at its
    /// largest number where the density is beyond it ([`Samples::saturated`];
    /// f32 at s = 1e-30: `∝ 1/s³`, about 1e90).
    pub pdf: f64,
    /// The technique's weight `k/pdf`, saturated as the density is.
    pub weight: f64,
    /// Its contribution `f_c · weight` (a bridge's divided by `P(k)`).
    pub estimate: f64,
}

/// The vertices of `count` draws and, with a lobe at `x0`, the lobe
/// technique's probability.
#[derive(Clone, Debug)]
pub struct Samples {
    /// The problem as checked, with its technique resolved.
    pub prepared: Prepared,
    /// The draws that gave a vertex, in draw order.
    pub rows: Vec<Row>,
    /// With a lobe: the probability of the lobe technique.
    pub lobe_probability: Option<f64>,
}

impl Samples {
    /// How many rows have a density or weight saturated at the largest number
    /// of the problem's precision (their estimates are right: formed in f64).
    pub fn saturated(&self) -> usize {
        let max = match self.prepared.problem.precision {
            Precision::F32 => f64::from(f32::MAX),
            Precision::F64 => f64::MAX,
        };
        self.rows
            .iter()
            .filter(|r| r.pdf >= max || r.weight >= max)
            .count()
    }
}

/// The most draws [`samples`] lists, `2²⁴`: every row is kept in memory
/// (about 100 bytes each) and printed.
pub const MAX_COUNT: u64 = 1 << 24;

/// The vertices of `count` draws of `problem` (`count` spelled by
/// `spelling` as `count`, in `[1, MAX_COUNT]`).
pub fn samples(problem: &Problem, count: u64, spelling: Spelling) -> Result<Samples> {
    if !(1..=MAX_COUNT).contains(&count) {
        return Err(RenderError::range(
            &spelling.of("count"),
            count,
            "[1, 2^24]",
        ));
    }
    let p = problem.check(spelling)?;
    let (rows, lobe_probability) = match (p.lobe.is_some(), problem.precision) {
        _ if p.bridges() => match problem.precision {
            Precision::F32 => (bridge_rows::<f32>(&p, count)?, None),
            Precision::F64 => (bridge_rows::<f64>(&p, count)?, None),
        },
        (false, Precision::F32) => (rows::<f32>(&p, count)?, None),
        (false, Precision::F64) => (rows::<f64>(&p, count)?, None),
        (true, Precision::F32) => lobe_rows::<f32>(&p, count)?,
        (true, Precision::F64) => lobe_rows::<f64>(&p, count)?,
    };
    Ok(Samples {
        prepared: p,
        rows,
        lobe_probability,
    })
}

/// The vertices of `count` draws in precision `F`.
fn rows<F: Real>(p: &Prepared, count: u64) -> Result<Vec<Row>> {
    p.with_sampler::<F, _>(|sampler| {
        let mut rows = Vec::new();
        for (k, n) in chunks(count) {
            let mut rng = Rng::stream(p.problem.seed, k, STREAM);
            for j in 0..n {
                let draw = sampler.draw(&mut rng);
                for (v, vertex) in draw.vertices.iter().enumerate() {
                    if let (Some(s), Some(u)) = (vertex, draw.vertex_numbers(v)) {
                        rows.push(Row {
                            draw: k * CHUNK + j,
                            vertex: v,
                            u: u.map(|x| x.to_f64()),
                            x1: x1_f64(s),
                            pdf: s.pdf.to_f64(),
                            weight: s.weight.to_f64(),
                            estimate: sampler.estimate(s),
                        });
                    }
                }
            }
        }
        rows
    })
}

/// The vertices of `count` bridges in precision `F`.
fn bridge_rows<F: Real>(p: &Prepared, count: u64) -> Result<Vec<Row>> {
    p.with_bridge::<F, _>(|b| {
        let mut rows = Vec::new();
        let mut u = [[F::ZERO; 3]; MAX_VERTICES];
        let mut x = [b.bridge.axis.x0; MAX_VERTICES];
        for (k, n) in chunks(count) {
            let mut rng = Rng::stream(p.problem.seed, k, STREAM);
            for j in 0..n {
                let draw = b.draw(&mut rng, &mut u, &mut x);
                let Some(s) = draw.sample else { continue };
                let estimate = b.estimate(&draw);
                for i in 0..draw.k {
                    rows.push(Row {
                        draw: k * CHUNK + j,
                        vertex: i,
                        u: u[i].map(|v| v.to_f64()),
                        x1: x[i].to_array().map(|v| v.to_f64()),
                        pdf: s.pdf.to_f64(),
                        weight: s.weight.to_f64(),
                        estimate,
                    });
                }
            }
        }
        rows
    })
}

/// The vertices of `count` draws with a lobe at `x0` (one vertex a draw,
/// from three uniform numbers), and the lobe technique's probability.
fn lobe_rows<F: Real>(p: &Prepared, count: u64) -> Result<(Vec<Row>, Option<f64>)> {
    p.with_lobe::<F, _>(|t, problem| {
        let mut rows = Vec::new();
        for (k, n) in chunks(count) {
            let mut rng = Rng::stream(p.problem.seed, k, STREAM);
            for j in 0..n {
                let u: [F; 3] = [rng.uniform(), rng.uniform(), rng.uniform()];
                if let Some(s) = t.sample(u) {
                    rows.push(Row {
                        draw: k * CHUNK + j,
                        vertex: 0,
                        u: u.map(|x| x.to_f64()),
                        x1: x1_f64(&s),
                        pdf: s.pdf.to_f64(),
                        weight: s.weight.to_f64(),
                        estimate: contribution(problem.f_c(s.x1), &s),
                    });
                }
            }
        }
        Ok((rows, Some(t.lobe_probability().to_f64())))
    })
}
