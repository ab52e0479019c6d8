//! `omnee.EquiangularSegment`: the equiangular distance along rays the
//! caller traced (the core's [`CoreSegment`]), one ray per row, as the trio
//! `sample(u)`, `pdf(t)`, `invert(t)` over arrays: the distance sampler a
//! renderer pairs with its own direction sampling (a BSDF, a phase
//! function) and its own intersection of the medium's boundary.

use crate::array::{
    Bad, Floats, first_outside, floats, number, result, shape_text, slice, slice_mut, vec3, zeros,
};
use crate::chunks::{Items, run};
use numpy::{Element, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use omnee_core::Real;
use omnee_core::sampling::EquiangularSegment as CoreSegment;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// One argument's numbers in f64: one value (or point) for every row, or
/// one per row.
#[derive(Clone, Debug, PartialEq)]
struct PerRow {
    /// `k` numbers per row (3 for points, 1 for distances), C order.
    values: Vec<f64>,
    /// Numbers per row.
    k: usize,
    /// `Some(N)` for one entry per row, `None` for one shared by all.
    rows: Option<usize>,
}

impl PerRow {
    /// A point argument: `(3,)` or `(N, 3)`.
    fn points(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (shape, values) = f64_values(arg, obj)?;
        match shape.as_slice() {
            [3] => Ok(Self {
                values,
                k: 3,
                rows: None,
            }),
            [n, 3] => Ok(Self {
                values,
                k: 3,
                rows: Some(*n),
            }),
            _ => Err(PyValueError::new_err(format!(
                "{arg}: shape {}; allowed: (3,), a point x, y, z, or (N, 3), one per row",
                shape_text(&shape)
            ))),
        }
    }

    /// A distance argument: a number or `(N,)`.
    fn distances(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (shape, values) = f64_values(arg, obj)?;
        match shape.as_slice() {
            [] => Ok(Self {
                values,
                k: 1,
                rows: None,
            }),
            [n] => Ok(Self {
                values,
                k: 1,
                rows: Some(*n),
            }),
            _ => Err(PyValueError::new_err(format!(
                "{arg}: shape {}; allowed: a number, or (N,), one per row",
                shape_text(&shape)
            ))),
        }
    }

    /// The entry of `row` (the shared one for every row).
    #[inline(always)]
    fn get(&self, row: usize) -> &[f64] {
        let i = if self.rows.is_some() { row } else { 0 };
        &self.values[self.k * i..self.k * (i + 1)]
    }
}

/// The shape and the values of `obj` in f64, as the dtype rule reads them.
fn f64_values(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<(Vec<usize>, Vec<f64>)> {
    Ok(match floats(arg, obj)? {
        Floats::F32(a) => (
            a.shape().to_vec(),
            slice(&a).iter().map(|&x| f64::from(x)).collect(),
        ),
        Floats::F64(a) => (a.shape().to_vec(), slice(&a).to_vec()),
    })
}

/// Equiangular sampling of the distance `t` along rays `origin + t ω`
/// restricted to their medium segments `[t_min, t_max]`, towards a light
/// point `x0` (Kulla & Fajardo 2012): `pdf(t) = c / d1(t)²` with
/// `d1 = |origin + t ω − x0|`, `c = D/(θ_b − θ_a)` (`D` the distance of `x0`
/// from the ray's line, `θ_b − θ_a` the angle the segment subtends at it).
/// The vertex's volume density about `origin` is `pdf_ω(ω) pdf(t) / t²`
/// with the caller's own direction density `pdf_ω`.
///
/// Every argument is one value for every row or one per row (points
/// `(N, 3)`, distances `(N,)`); the numbers are copied when the segments are
/// made and checked in f64.
#[pyclass(module = "omnee", frozen)]
pub struct EquiangularSegment {
    x0: PerRow,
    origin: PerRow,
    direction: PerRow,
    t_min: PerRow,
    t_max: PerRow,
    rows: Option<usize>,
}

impl EquiangularSegment {
    /// The core's segment of `row` in precision `F`; its refusal names the
    /// row.
    #[inline(always)]
    fn at<F: Real>(&self, row: usize) -> Result<CoreSegment<F>, Bad> {
        let p = |a: &PerRow| {
            let v = a.get(row);
            vec3::<F>([v[0], v[1], v[2]])
        };
        CoreSegment::new(
            p(&self.x0),
            p(&self.origin),
            p(&self.direction),
            F::from_f64(self.t_min.get(row)[0]),
            F::from_f64(self.t_max.get(row)[0]),
        )
        .map_err(|error| Bad::Row {
            row,
            error,
            precision: crate::array::dtype_name::<F>(),
        })
    }

    /// The leading shape of an argument and the items per row.
    fn lead(&self, arg: &str, shape: &[usize]) -> PyResult<usize> {
        match self.rows {
            None => Ok(1),
            Some(n) if shape.first() == Some(&n) => Ok(shape[1..].iter().product()),
            Some(n) => Err(PyValueError::new_err(format!(
                "{arg}: shape {}; allowed: ({n}, ...), one row per ray (the segments have {n} \
                 rows)",
                shape_text(shape)
            ))),
        }
    }

    fn sample_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArrayDyn<'py, F>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let shape = u.shape().to_vec();
        let per_row = self.lead("u", &shape)?;
        let (t, pdf, valid) = (
            zeros::<F>(py, &shape),
            zeros::<F>(py, &shape),
            zeros::<bool>(py, &shape),
        );
        {
            let (mut a, mut b, mut c) = (t.readwrite(), pdf.readwrite(), valid.readwrite());
            let u_values = slice(&u);
            let out = (
                Items {
                    data: u_values,
                    k: 1,
                },
                Items {
                    data: slice_mut(&mut a),
                    k: 1,
                },
                Items {
                    data: slice_mut(&mut b),
                    k: 1,
                },
                Items {
                    data: slice_mut(&mut c),
                    k: 1,
                },
            );
            py.detach(|| {
                if let Some((i, v)) = first_outside(u_values, F::ZERO, F::ONE) {
                    return Err(Bad::Element {
                        arg: "u",
                        at: i,
                        value: number(v),
                        allowed: "[0, 1]",
                    });
                }
                run(out, |start, (u, t, pdf, valid)| {
                    for (i, &ui) in u.data.iter().enumerate() {
                        let segment = self.at::<F>((start + i) / per_row)?;
                        if let Some(d) = segment.sample(ui) {
                            (t.data[i], pdf.data[i], valid.data[i]) = (d.t, d.pdf, true);
                        }
                    }
                    Ok(())
                })
            })
            .map_err(|bad| bad.into_err(&shape))?;
        }
        py.import("omnee")?.getattr("DistanceSamples")?.call1((
            result(t)?,
            result(pdf)?,
            result(valid)?,
        ))
    }

    /// `f(segment, t)` for every element of `t`, into a new array of
    /// `t`'s shape.
    fn map_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArrayDyn<'py, F>,
        f: impl Fn(&CoreSegment<F>, F) -> F + Sync,
    ) -> PyResult<Bound<'py, PyArrayDyn<F>>> {
        let shape = t.shape().to_vec();
        let per_row = self.lead("t", &shape)?;
        let out = zeros::<F>(py, &shape);
        {
            let mut a = out.readwrite();
            let items = (
                Items {
                    data: slice(&t),
                    k: 1,
                },
                Items {
                    data: slice_mut(&mut a),
                    k: 1,
                },
            );
            py.detach(|| {
                run(items, |start, (t, out)| -> Result<(), Bad> {
                    for (i, &ti) in t.data.iter().enumerate() {
                        out.data[i] = f(&self.at::<F>((start + i) / per_row)?, ti);
                    }
                    Ok(())
                })
            })
            .map_err(|bad| bad.into_err(&shape))?;
        }
        Ok(out)
    }
}

#[pymethods]
impl EquiangularSegment {
    /// The segments `[t_min, t_max]` of the rays `origin + t · direction`,
    /// sampled towards `x0`.
    #[new]
    #[pyo3(
        signature = (x0, origin, direction, t_min = None, t_max = None),
        text_signature = "(x0, origin, direction, t_min=0.0, t_max=inf)"
    )]
    fn new(
        py: Python<'_>,
        x0: &Bound<'_, PyAny>,
        origin: &Bound<'_, PyAny>,
        direction: &Bound<'_, PyAny>,
        t_min: Option<&Bound<'_, PyAny>>,
        t_max: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let distances = |arg, obj: Option<&Bound<'_, PyAny>>, default: f64| match obj {
            Some(obj) => PerRow::distances(arg, obj),
            None => Ok(PerRow {
                values: vec![default],
                k: 1,
                rows: None,
            }),
        };
        let args = [
            ("x0", PerRow::points("x0", x0)?),
            ("origin", PerRow::points("origin", origin)?),
            ("direction", PerRow::points("direction", direction)?),
            ("t_min", distances("t_min", t_min, 0.0)?),
            ("t_max", distances("t_max", t_max, f64::INFINITY)?),
        ];
        let mut rows: Option<(&str, usize)> = None;
        for (arg, a) in &args {
            match (rows, a.rows) {
                (Some((first, m)), Some(n)) if m != n => {
                    return Err(PyValueError::new_err(format!(
                        "{arg}: {n} rows; allowed: {m} rows, as {first} has, or one value for \
                         every row"
                    )));
                }
                (None, Some(n)) => rows = Some((arg, n)),
                _ => {}
            }
        }
        let [x0, origin, direction, t_min, t_max] = args.map(|(_, a)| a);
        let segments = Self {
            x0,
            origin,
            direction,
            t_min,
            t_max,
            rows: rows.map(|(_, n)| n),
        };
        let n = segments.rows.unwrap_or(1);
        py.detach(|| {
            run(0..n, |_, mut range| {
                range.try_for_each(|row| segments.at::<f64>(row).map(drop))
            })
        })
        .map_err(|bad| bad.into_err(&[n]))?;
        Ok(segments)
    }

    /// `t` from uniform numbers `u` in [0, 1] (shape `(N, ...)` with one
    /// segment per row): `DistanceSamples(t, pdf, valid)`, `pdf` per metre;
    /// `valid` is False (and `t`, `pdf` 0) where `u = 1` on an infinite
    /// segment.
    fn sample<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match floats("u", u)? {
            Floats::F32(u) => self.sample_in(py, u),
            Floats::F64(u) => self.sample_in(py, u),
        }
    }

    /// `pdf(t)` per metre: `c / d1(t)²` inside the segment, 0 outside.
    fn pdf<'py>(&self, py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match floats("t", t)? {
            Floats::F32(t) => result(self.map_in(py, t, |s, t| s.pdf(t))?),
            Floats::F64(t) => result(self.map_in(py, t, |s, t| s.pdf(t))?),
        }
    }

    /// The `u` that `sample` maps to `t` (distances outside the segment give
    /// 0 or 1).
    fn invert<'py>(&self, py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match floats("t", t)? {
            Floats::F32(t) => result(self.map_in(py, t, |s, t| s.invert(t))?),
            Floats::F64(t) => result(self.map_in(py, t, |s, t| s.invert(t))?),
        }
    }

    /// The number of rays given per row, or None for one.
    #[getter]
    fn rows(&self) -> Option<usize> {
        self.rows
    }

    fn __repr__(&self) -> String {
        match self.rows {
            Some(n) => format!("EquiangularSegment(<{n} rows>)"),
            None => format!(
                "EquiangularSegment(x0={:?}, origin={:?}, direction={:?}, t_min={:?}, t_max={:?})",
                self.x0.values,
                self.origin.values,
                self.direction.values,
                self.t_min.values[0],
                self.t_max.values[0]
            ),
        }
    }
}
