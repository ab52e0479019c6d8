//! The techniques' loops over arrays, run with the GIL released: one
//! connection for every item, or one per row (`x0`, `x2` and the receiver
//! normal of shape `(N, 3)`), each item drawn, evaluated or inverted by the
//! core's scalar calls ([`CoreTechnique::sample`], [`OmneeMis::sample`],
//! their `pdf` and `invert`) straight into the output arrays, OMNEE's and
//! MIS's draws in f32 by the core's batch over connections (module
//! `batch`), the same bits. The technique of a connection is made once per
//! chunk (one connection) or once per row.

use crate::array::{Bad, check_finite, first_outside, number, vec3};
use crate::chunks::{Items, run};
use omnee_core::method::{Method, Setup};
use omnee_core::mis::OmneeMis;
use omnee_core::phase::Phase as CorePhase;
use omnee_core::sampling::{
    Connection, Directions, Distance, Equiangular, Omnee, Sample, Technique as CoreTechnique,
};
use omnee_core::{Real, Vector};

/// Uniform numbers per draw of `method`: 3, or 6 for MIS (OMNEE's, then
/// the companion's).
pub fn uniforms(method: Method) -> usize {
    match method {
        Method::Mis => 6,
        _ => 3,
    }
}

/// Vertices per draw of `method`: 1, or 2 for MIS.
pub fn vertices(method: Method) -> usize {
    match method {
        Method::Mis => 2,
        _ => 1,
    }
}

/// Points read in place: one for every row, or row `i` at `3i..3i + 3` of
/// a float32 or float64 array.
#[derive(Clone, Copy, Debug)]
pub enum Coords<'a> {
    /// The same point for every row.
    One([f64; 3]),
    /// Per row, from a float32 array.
    F32(&'a [f32]),
    /// Per row, from a float64 array.
    F64(&'a [f64]),
}

impl Coords<'_> {
    /// The point of `row`, in f64 (exact for both dtypes).
    #[inline(always)]
    pub fn get(&self, row: usize) -> [f64; 3] {
        match *self {
            Coords::One(p) => p,
            Coords::F32(a) => {
                let p = &a[3 * row..3 * row + 3];
                [p[0], p[1], p[2]].map(f64::from)
            }
            Coords::F64(a) => {
                let p = &a[3 * row..3 * row + 3];
                [p[0], p[1], p[2]]
            }
        }
    }
}

/// The connections of a call, and the receiver's directions where they
/// change per row.
#[derive(Clone, Copy, Debug)]
pub enum Geometry<'a, F: Real> {
    /// One connection for every item.
    One(Connection<F>),
    /// One connection per row: `x0`, `x2` (at least one per row), the
    /// normal (per row, or `None`: the setup's), and θmax.
    Rows {
        /// The light-side end points.
        x0: Coords<'a>,
        /// The receiver-side end points.
        x2: Coords<'a>,
        /// The receiver normals, if they change per row.
        normal: Option<Coords<'a>>,
        /// The restriction θ < θmax.
        theta_max: F,
    },
}

impl<F: Real> Geometry<'_, F> {
    /// The connection of `row` and its directions (`None`: the setup's), as
    /// the core builds them in precision `F`; its refusal names the row.
    #[inline(always)]
    pub fn at(&self, row: usize) -> Result<(Connection<F>, Option<Directions<F>>), Bad> {
        match *self {
            Geometry::One(c) => Ok((c, None)),
            Geometry::Rows {
                x0,
                x2,
                normal,
                theta_max,
            } => {
                let bad = |error| Bad::Row {
                    row,
                    error,
                    precision: crate::array::dtype_name::<F>(),
                };
                let (a, b) = (vec3::<F>(x0.get(row)), vec3::<F>(x2.get(row)));
                let c = Connection::new(a, b, theta_max).map_err(bad)?;
                let d = match normal {
                    Some(n) => Some(Directions::cosine(vec3::<F>(n.get(row))).map_err(bad)?),
                    None => None,
                };
                Ok((c, d))
            }
        }
    }
}

/// The phase function as the loops borrow it.
type PhaseRef<'a, F> = &'a CorePhase<'a, F>;

/// A method's technique for one connection: a draw's vertices from its
/// uniform numbers, the density the vertices come with, the inverse.
trait Kernel<F: Real> {
    /// The vertices of one draw from `u` (3 numbers, or 6 for MIS).
    fn draw(&self, u: &[F]) -> [Option<Sample<F>>; 2];
    /// The density at `x1`.
    fn pdf(&self, x1: F::Vec3) -> F;
    /// The uniform numbers of `x1`, where there are.
    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]>;
}

/// The three single-vertex techniques: [`CoreTechnique`]'s trio.
macro_rules! single_kernel {
    ($t:ident) => {
        impl<'a, F: Real> Kernel<F> for $t<F, PhaseRef<'a, F>> {
            #[inline]
            fn draw(&self, u: &[F]) -> [Option<Sample<F>>; 2] {
                [self.sample([u[0], u[1], u[2]]), None]
            }
            #[inline]
            fn pdf(&self, x1: F::Vec3) -> F {
                CoreTechnique::pdf(self, x1)
            }
            #[inline]
            fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
                CoreTechnique::invert(self, x1)
            }
        }
    };
}

single_kernel!(Omnee);
single_kernel!(Equiangular);
single_kernel!(Distance);

/// MIS as the core's [`OmneeMis::recommended`]: OMNEE and the equiangular
/// companion on the same connection.
struct Mis<'a, F: Real> {
    omnee: Omnee<F, PhaseRef<'a, F>>,
    companion: Equiangular<F, PhaseRef<'a, F>>,
}

impl<F: Real> Kernel<F> for Mis<'_, F> {
    #[inline]
    fn draw(&self, u: &[F]) -> [Option<Sample<F>>; 2] {
        let u = [u[0], u[1], u[2], u[3], u[4], u[5]];
        OmneeMis::recommended(self.omnee, &self.companion).sample(u)
    }
    #[inline]
    fn pdf(&self, x1: F::Vec3) -> F {
        OmneeMis::recommended(self.omnee, &self.companion).pdf(x1)
    }
    /// Not offered (OMNEE and the companion can draw the same point).
    #[inline]
    fn invert(&self, _: F::Vec3) -> Option<[F; 3]> {
        None
    }
}

/// Everything a loop needs: the method, the core's setup (phase function,
/// directions, region, σt), the connections, and how many consecutive items
/// share a row (`per_row`; 1 with one connection).
#[derive(Clone, Copy)]
pub struct Context<'a, F: Real> {
    /// The technique.
    pub method: Method,
    /// The core's setup, borrowing the phase function.
    pub setup: Setup<F, PhaseRef<'a, F>>,
    /// The connections.
    pub geometry: Geometry<'a, F>,
    /// Items per row (the product of the leading axes after the first).
    pub per_row: usize,
}

/// Calls `$body` with `$make`, the maker of `$cx.method`'s technique for a
/// connection and its setup (each method's loop compiled on its own).
macro_rules! with_kernel {
    ($cx:expr, $make:ident => $body:expr) => {
        match $cx.method {
            Method::Omnee => {
                let $make = |c, s: Setup<F, PhaseRef<'a, F>>| Ok(Omnee::new(c, *s.phase()));
                $body
            }
            Method::Equiangular => {
                let $make = |c, s: Setup<F, PhaseRef<'a, F>>| {
                    Ok(Equiangular::new(c, *s.phase(), s.directions(), s.region()))
                };
                $body
            }
            Method::Distance => {
                // σt was checked by `Setup::new`: `new` does not fail.
                let $make = |c, s: Setup<F, PhaseRef<'a, F>>| {
                    let (p, d, r) = (*s.phase(), s.directions(), s.region());
                    Distance::new(c, p, d, r, s.sigma_t())
                };
                $body
            }
            Method::Mis => {
                let $make = |c, s: Setup<F, PhaseRef<'a, F>>| {
                    Ok(Mis {
                        omnee: Omnee::new(c, *s.phase()),
                        companion: Equiangular::new(c, *s.phase(), s.directions(), s.region()),
                    })
                };
                $body
            }
        }
    };
}

/// The maker of a method's technique for a connection and its setup.
trait Make<'a, F: Real, K>:
    Fn(Connection<F>, Setup<F, PhaseRef<'a, F>>) -> Result<K, omnee_core::Error> + Sync
{
}

impl<'a, F: Real, K, M> Make<'a, F, K> for M where
    M: Fn(Connection<F>, Setup<F, PhaseRef<'a, F>>) -> Result<K, omnee_core::Error> + Sync
{
}

impl<'a, F: Real> Context<'a, F> {
    /// Calls `f(technique, j)` for the items `start + j`, `j < n`, with the
    /// technique of each item's connection: made once for one connection;
    /// per row, made again where the row changes (counted, not divided).
    #[inline]
    fn each<K: Kernel<F>>(
        &self,
        make: &impl Make<'a, F, K>,
        start: usize,
        n: usize,
        mut f: impl FnMut(&K, usize),
    ) -> Result<(), Bad> {
        if n == 0 {
            return Ok(());
        }
        if let Geometry::One(_) = self.geometry {
            let kernel = self.kernel(make, 0)?;
            (0..n).for_each(|j| f(&kernel, j));
            return Ok(());
        }
        let mut row = start / self.per_row;
        let mut left = self.per_row - start % self.per_row;
        let mut kernel = self.kernel(make, row)?;
        for j in 0..n {
            if left == 0 {
                (row, left) = (row + 1, self.per_row);
                kernel = self.kernel(make, row)?;
            }
            left -= 1;
            f(&kernel, j);
        }
        Ok(())
    }

    /// The technique of `row`, made by `make`; the core's refusal names the
    /// row.
    #[inline(always)]
    fn kernel<K: Kernel<F>>(&self, make: &impl Make<'a, F, K>, row: usize) -> Result<K, Bad> {
        let (connection, directions) = self.geometry.at(row)?;
        let setup = match directions {
            Some(d) => self.setup.with_directions(d),
            None => self.setup,
        };
        make(connection, setup).map_err(|error| Bad::Row {
            row,
            error,
            precision: crate::array::dtype_name::<F>(),
        })
    }

    /// Draws for consecutive rows of `uniforms(method)` numbers in `u`
    /// (each in [0, 1], else an error naming it), writing each draw's
    /// vertices to `out` (zeros where a vertex does not exist).
    /// OMNEE and MIS go through the core's batch over connections
    /// ([`Context::sample_batched`]), the same draws bit for bit.
    pub fn sample(&self, u: &[F], out: SampleOut<'_, F>) -> Result<(), Bad> {
        if self.batched() {
            return self.sample_batched(u, out);
        }
        with_kernel!(self, make => self.sample_with(&make, u, out))
    }

    fn sample_with<K: Kernel<F>>(
        &self,
        make: &impl Make<'a, F, K>,
        u: &[F],
        out: SampleOut<'_, F>,
    ) -> Result<(), Bad> {
        let (k, v) = (uniforms(self.method), vertices(self.method));
        self.sample_chunks(u, out, |start, u, out| {
            let n = u.len() / k;
            self.each(make, start, n, |kernel, j| {
                let vertices = kernel.draw(&u[k * j..k * j + k]);
                for (t, vertex) in vertices[..v].iter().enumerate() {
                    let (point, values) = match vertex {
                        Some(s) => (s.x1.to_array(), (s.pdf, s.weight, true)),
                        None => ([F::ZERO; 3], (F::ZERO, F::ZERO, false)),
                    };
                    let at = v * j + t;
                    out.x1[3 * at..3 * at + 3].copy_from_slice(&point);
                    (out.pdf[at], out.weight[at], out.valid[at]) = values;
                }
            })
        })
    }

    /// Runs `body(start, u, out)` over the chunks of a draw: `u`'s rows of
    /// [`uniforms`] numbers, checked in [0, 1] first (an error naming the
    /// element), and the chunk's [`vertices`] outputs per row, `start` the
    /// chunk's first row.
    pub fn sample_chunks(
        &self,
        u: &[F],
        out: SampleOut<'_, F>,
        body: impl Fn(usize, &[F], SampleOut<'_, F>) -> Result<(), Bad> + Sync,
    ) -> Result<(), Bad> {
        let (k, v) = (uniforms(self.method), vertices(self.method));
        let all = (
            Items { data: u, k },
            Items {
                data: out.x1,
                k: 3 * v,
            },
            Items {
                data: out.pdf,
                k: v,
            },
            Items {
                data: out.weight,
                k: v,
            },
            Items {
                data: out.valid,
                k: v,
            },
        );
        run(all, |start, (u, x1, pdf, weight, valid)| {
            if let Some((i, x)) = first_outside(u.data, F::ZERO, F::ONE) {
                let (at, value) = (start * k + i, number(x));
                return Err(Bad::Element {
                    arg: "u",
                    at,
                    value,
                    allowed: "[0, 1]",
                });
            }
            let out = SampleOut {
                x1: x1.data,
                pdf: pdf.data,
                weight: weight.data,
                valid: valid.data,
            };
            body(start, u.data, out)
        })
    }

    /// The density the vertices come with (the technique's `pdf`, for MIS
    /// the combined one) at each point of `x1` (finite coordinates, else an
    /// error naming it), into `out`.
    pub fn pdf(&self, x1: &[F], out: &mut [F]) -> Result<(), Bad> {
        with_kernel!(self, make => self.pdf_with(&make, x1, out))
    }

    fn pdf_with<K: Kernel<F>>(
        &self,
        make: &impl Make<'a, F, K>,
        x1: &[F],
        out: &mut [F],
    ) -> Result<(), Bad> {
        let all = (Items { data: x1, k: 3 }, Items { data: out, k: 1 });
        run(all, |start, (x1, out)| {
            check_points(x1.data, start)?;
            self.each(make, start, out.data.len(), |kernel, j| {
                let p = &x1.data[3 * j..3 * j + 3];
                out.data[j] = kernel.pdf(F::Vec3::new(p[0], p[1], p[2]));
            })
        })
    }

    /// The uniform numbers that the method's technique maps to each point
    /// of `x1` (finite coordinates, else an error naming it), into `u`
    /// (zeros and `valid` false where there are none).
    pub fn invert(&self, x1: &[F], u: &mut [F], valid: &mut [bool]) -> Result<(), Bad> {
        with_kernel!(self, make => self.invert_with(&make, x1, u, valid))
    }

    fn invert_with<K: Kernel<F>>(
        &self,
        make: &impl Make<'a, F, K>,
        x1: &[F],
        u: &mut [F],
        valid: &mut [bool],
    ) -> Result<(), Bad> {
        let all = (
            Items { data: x1, k: 3 },
            Items { data: u, k: 3 },
            Items { data: valid, k: 1 },
        );
        run(all, |start, (x1, u, valid)| {
            check_points(x1.data, start)?;
            self.each(make, start, valid.data.len(), |kernel, j| {
                let p = &x1.data[3 * j..3 * j + 3];
                let inverse = kernel.invert(F::Vec3::new(p[0], p[1], p[2]));
                u.data[3 * j..3 * j + 3].copy_from_slice(&inverse.unwrap_or([F::ZERO; 3]));
                valid.data[j] = inverse.is_some();
            })
        })
    }
}

/// Points must have finite coordinates.
fn check_points<F: Real>(x1: &[F], start: usize) -> Result<(), Bad> {
    check_finite("x1", x1, 3 * start)
}

/// The output arrays of [`Context::sample`], in C order: `x1` (3 per
/// vertex), `pdf`, `weight`, `valid` (1 per vertex).
pub struct SampleOut<'a, F> {
    /// The vertices.
    pub x1: &'a mut [F],
    /// Their densities.
    pub pdf: &'a mut [F],
    /// Their weights.
    pub weight: &'a mut [F],
    /// Whether each exists.
    pub valid: &'a mut [bool],
}
