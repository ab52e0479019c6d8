//! OMNEE and MIS through the core's batch over connections
//! ([`Connections::sample_omnee`], [`Connections::sample_mis`]): the draws
//! of a chunk gathered [`LANES`] at a time into structure-of-arrays columns
//! on the stack (each lane's end points, its uniform numbers), drawn in one
//! call, and scattered into the caller's arrays of points. Each lane is the
//! scalar call on its own connection bit for bit, so a row's vertex is the
//! vertex a single-connection technique draws from the same numbers.

use crate::array::{Bad, dtype_name};
use crate::kernel::{Context, Geometry, SampleOut, uniforms, vertices};
use omnee_core::method::Method;
use omnee_core::sampling::{Connections, Points, PointsMut, SampleArrays, Uniforms};
use omnee_core::{Real, Vector};

/// Lanes per call of the core's batch.
const LANES: usize = 256;

/// One block's columns: the lanes' end points and uniform numbers, and the
/// vertices drawn (OMNEE's and, for MIS, the companion's).
struct Block<F> {
    x0: [[F; LANES]; 3],
    x2: [[F; LANES]; 3],
    u: [[F; LANES]; 6],
    x1: [[[F; LANES]; 3]; 2],
    pdf: [[F; LANES]; 2],
    weight: [[F; LANES]; 2],
    valid: [[bool; LANES]; 2],
}

impl<F: Real> Block<F> {
    fn new() -> Self {
        let column = [F::ZERO; LANES];
        Self {
            x0: [column; 3],
            x2: [column; 3],
            u: [column; 6],
            x1: [[column; 3]; 2],
            pdf: [column; 2],
            weight: [column; 2],
            valid: [[false; LANES]; 2],
        }
    }
}

/// The first `m` lanes of three columns as points.
fn points<F>(c: &[[F; LANES]; 3], m: usize) -> Points<'_, F> {
    let [x, y, z] = c;
    Points {
        x: &x[..m],
        y: &y[..m],
        z: &z[..m],
    }
}

/// The first `m` lanes of three uniform columns.
fn numbers<F>(c: &[[F; LANES]], m: usize) -> Uniforms<'_, F> {
    Uniforms {
        u0: &c[0][..m],
        u1: &c[1][..m],
        u2: &c[2][..m],
    }
}

/// The first `m` lanes of one vertex's output columns.
fn arrays<'b, F>(
    x1: &'b mut [[F; LANES]; 3],
    pdf: &'b mut [F; LANES],
    weight: &'b mut [F; LANES],
    valid: &'b mut [bool; LANES],
    m: usize,
) -> SampleArrays<'b, F> {
    let [x, y, z] = x1;
    SampleArrays {
        x1: PointsMut {
            x: &mut x[..m],
            y: &mut y[..m],
            z: &mut z[..m],
        },
        pdf: &mut pdf[..m],
        weight: &mut weight[..m],
        valid: &mut valid[..m],
    }
}

impl<F: Real> Context<'_, F> {
    /// Whether [`Context::sample_batched`] draws: in f32 (where the batch
    /// runs in SIMD lanes; in f64 it is the scalar sampler lane by lane, and
    /// the scalar loop makes one connection's frame once), for OMNEE, and
    /// for MIS where the receiver's directions are the same for every row.
    pub fn batched(&self) -> bool {
        if dtype_name::<F>() != "float32" {
            return false;
        }
        match (self.method, self.geometry) {
            (Method::Omnee, _) => true,
            (Method::Mis, Geometry::Rows { normal, .. }) => normal.is_none(),
            (Method::Mis, Geometry::One(_)) => true,
            _ => false,
        }
    }

    /// [`Context::sample`] for the methods [`Context::batched`] accepts,
    /// through the core's batch over connections, bit for bit the same.
    pub fn sample_batched(&self, u: &[F], out: SampleOut<'_, F>) -> Result<(), Bad> {
        let (k, v) = (uniforms(self.method), vertices(self.method));
        self.sample_chunks(u, out, |start, u, out| {
            let mut block = Block::new();
            if let Geometry::One(c) = self.geometry {
                // The same end points in every lane, once.
                let (a, b) = (c.axis.x0.to_array(), c.axis.x2.to_array());
                for d in 0..3 {
                    (block.x0[d], block.x2[d]) = ([a[d]; LANES], [b[d]; LANES]);
                }
            }
            let rows = matches!(self.geometry, Geometry::Rows { .. });
            let n = u.len() / k;
            for first in (0..n).step_by(LANES) {
                let m = LANES.min(n - first);
                if rows {
                    self.gather_ends(&mut block, start + first, m);
                }
                let numbers = &u[first * k..(first + m) * k];
                match k {
                    3 => transpose::<F, 3>(numbers, &mut block.u),
                    _ => transpose::<F, 6>(numbers, &mut block.u),
                }
                self.draw_block(&mut block, start + first, m)?;
                if rows {
                    // A lane without OMNEE's vertex: its numbers give none,
                    // or the core refuses its row's end points (named).
                    for l in (0..m).filter(|&l| !block.valid[0][l]) {
                        self.geometry.at((start + first + l) / self.per_row)?;
                    }
                }
                let at = first * v..(first + m) * v;
                let lanes = SampleOut {
                    x1: &mut out.x1[3 * at.start..3 * at.end],
                    pdf: &mut out.pdf[at.clone()],
                    weight: &mut out.weight[at.clone()],
                    valid: &mut out.valid[at],
                };
                scatter(&block, v, m, lanes);
            }
            Ok(())
        })
    }

    /// The end points of the rows of items `item..item + m` into the
    /// block's columns.
    fn gather_ends(&self, block: &mut Block<F>, item: usize, m: usize) {
        let Geometry::Rows { x0, x2, .. } = self.geometry else {
            return;
        };
        // The row counted, not divided (a 64-bit division per lane costs
        // what the lane's frame does).
        let (mut row, mut left) = (item / self.per_row, self.per_row - item % self.per_row);
        for l in 0..m {
            if left == 0 {
                (row, left) = (row + 1, self.per_row);
            }
            left -= 1;
            let (a, b) = (x0.get(row), x2.get(row));
            for d in 0..3 {
                block.x0[d][l] = F::from_f64(a[d]);
                block.x2[d][l] = F::from_f64(b[d]);
            }
        }
    }

    /// The first `m` lanes of `block` drawn by the core's batch (items
    /// from `item` on).
    fn draw_block(&self, block: &mut Block<F>, item: usize, m: usize) -> Result<(), Bad> {
        let theta_max = match self.geometry {
            Geometry::One(c) => c.theta_max,
            Geometry::Rows { theta_max, .. } => theta_max,
        };
        let bad = |error| Bad::Row {
            row: item / self.per_row,
            error,
            precision: dtype_name::<F>(),
        };
        let lanes =
            Connections::new(points(&block.x0, m), points(&block.x2, m), theta_max).map_err(bad)?;
        let [x1_0, x1_1] = &mut block.x1;
        let [pdf_0, pdf_1] = &mut block.pdf;
        let [weight_0, weight_1] = &mut block.weight;
        let [valid_0, valid_1] = &mut block.valid;
        let omnee = arrays(x1_0, pdf_0, weight_0, valid_0, m);
        let drawn = match self.method {
            Method::Mis => {
                let companion = arrays(x1_1, pdf_1, weight_1, valid_1, m);
                let (u, v) = block.u.split_at(3);
                lanes.sample_mis(&self.setup, numbers(u, m), numbers(v, m), omnee, companion)
            }
            _ => lanes.sample_omnee(self.setup.phase(), numbers(&block.u, m), omnee),
        };
        drawn.map(drop).map_err(bad)
    }
}

/// Rows of `K` uniform numbers into the first `K` columns.
#[inline]
fn transpose<F: Real, const K: usize>(u: &[F], columns: &mut [[F; LANES]; 6]) {
    let (rows, _) = u.as_chunks::<K>();
    for (l, row) in rows.iter().enumerate().take(LANES) {
        for c in 0..K {
            columns[c][l] = row[c];
        }
    }
}

/// The first `m` lanes' `v` vertices from the block's columns into `out`
/// (its items in C order: lane by lane, vertex by vertex).
#[inline]
fn scatter<F: Real>(block: &Block<F>, v: usize, m: usize, out: SampleOut<'_, F>) {
    let (points, _) = out.x1.as_chunks_mut::<3>();
    for t in 0..v {
        let [x, y, z] = &block.x1[t];
        for l in 0..m {
            let at = l * v + t;
            points[at] = [x[l], y[l], z[l]];
            out.pdf[at] = block.pdf[t][l];
            out.weight[at] = block.weight[t][l];
            out.valid[at] = block.valid[t][l];
        }
    }
}
