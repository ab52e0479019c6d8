//! A technique's parameters as given: the end points and the receiver
//! normal (one point, or one per row), θmax, the phase function, the slab
//! and σt; checked in f64 when the technique is made, built in the
//! computing precision for each call, compared and hashed by value.

use crate::array::{Floats, canonical, shape_text, slice, vec3};
use crate::chunks::run;
use crate::error;
use crate::kernel::{Context, Coords, Geometry};
use crate::phase::Phase;
use numpy::{PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use omnee_core::Real;
use omnee_core::medium::Region;
use omnee_core::method::{Method, Setup};
use omnee_core::sampling::{Connection, Directions};
use omnee_render::phase::TableStorage;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::hash::{Hash, Hasher};

/// A point argument: one point for every row, or an `(N, 3)` array of one
/// per row, read in place (C-contiguous float32 or float64) at every call.
pub enum End {
    /// The same point for every row.
    Point([f64; 3]),
    /// One point per row, from a float32 array.
    F32(Py<PyArrayDyn<f32>>),
    /// One point per row, from a float64 array.
    F64(Py<PyArrayDyn<f64>>),
}

/// An [`End`] borrowed for one call.
enum Borrowed<'py> {
    Point([f64; 3]),
    F32(PyReadonlyArrayDyn<'py, f32>),
    F64(PyReadonlyArrayDyn<'py, f64>),
}

impl Borrowed<'_> {
    fn coords(&self) -> Coords<'_> {
        match self {
            Borrowed::Point(p) => Coords::One(*p),
            Borrowed::F32(a) => Coords::F32(slice(a)),
            Borrowed::F64(a) => Coords::F64(slice(a)),
        }
    }
}

impl End {
    /// The argument `arg`: shape `(3,)` or `(N, 3)`.
    pub fn parse(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        let floats = crate::array::floats(arg, obj)?;
        let shape = match &floats {
            Floats::F32(a) => a.shape().to_vec(),
            Floats::F64(a) => a.shape().to_vec(),
        };
        match (shape.as_slice(), floats) {
            ([3], _) => crate::array::point(arg, obj).map(End::Point),
            ([_, 3], Floats::F32(a)) => Ok(End::F32(a.as_unbound().clone_ref(obj.py()))),
            ([_, 3], Floats::F64(a)) => Ok(End::F64(a.as_unbound().clone_ref(obj.py()))),
            _ => Err(PyValueError::new_err(format!(
                "{arg}: shape {}; allowed: (3,), a point x, y, z, or (N, 3), one point per row",
                shape_text(&shape)
            ))),
        }
    }

    /// The number of rows, if there is one point per row.
    fn rows(&self, py: Python<'_>) -> Option<usize> {
        match self {
            End::Point(_) => None,
            End::F32(a) => Some(a.bind(py).shape().first().copied().unwrap_or(0)),
            End::F64(a) => Some(a.bind(py).shape().first().copied().unwrap_or(0)),
        }
    }

    /// The points for one call, each array still of shape `(rows, 3)`
    /// (numpy lets its owner reshape it in place).
    fn borrow<'py>(&self, py: Python<'py>, rows: Option<usize>) -> PyResult<Borrowed<'py>> {
        let borrowed = match self {
            End::Point(p) => return Ok(Borrowed::Point(*p)),
            End::F32(a) => a.bind(py).try_readonly().map(Borrowed::F32),
            End::F64(a) => a.bind(py).try_readonly().map(Borrowed::F64),
        };
        let borrowed = borrowed.map_err(|_| {
            PyValueError::new_err("an end point or normal array is being written by this call")
        })?;
        let shape = match &borrowed {
            Borrowed::F32(a) => a.shape().to_vec(),
            Borrowed::F64(a) => a.shape().to_vec(),
            Borrowed::Point(_) => vec![3],
        };
        match rows {
            Some(n) if shape == [n, 3] => Ok(borrowed),
            _ => Err(PyValueError::new_err(format!(
                "an end point or normal array was reshaped to {} after the technique was made; \
                 allowed: ({}, 3)",
                shape_text(&shape),
                rows.unwrap_or(0)
            ))),
        }
    }

    /// The argument as given back: a tuple `(x, y, z)` or the array.
    pub fn to_object<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(match self {
            End::Point([x, y, z]) => (*x, *y, *z).into_pyobject(py)?.into_any(),
            End::F32(a) => a.bind(py).clone().into_any(),
            End::F64(a) => a.bind(py).clone().into_any(),
        })
    }

    /// The coordinates in f64, in C order (3 per row).
    fn values(&self, py: Python<'_>) -> PyResult<Vec<f64>> {
        Ok(match self.borrow(py, self.rows(py))? {
            Borrowed::Point(p) => p.to_vec(),
            Borrowed::F32(a) => slice(&a).iter().map(|&x| f64::from(x)).collect(),
            Borrowed::F64(a) => slice(&a).to_vec(),
        })
    }

    /// Equal shapes and coordinates.
    fn equals(&self, other: &End, py: Python<'_>) -> PyResult<bool> {
        Ok(self.rows(py) == other.rows(py) && self.values(py)? == other.values(py)?)
    }

    /// Hashes what [`End::equals`] compares.
    fn hash(&self, py: Python<'_>, h: &mut impl Hasher) -> PyResult<()> {
        self.rows(py).hash(h);
        self.values(py)?.iter().for_each(|&x| canonical(x).hash(h));
        Ok(())
    }

    /// `[x, y, z]`, or `<array of shape (N, 3)>`.
    fn text(&self, py: Python<'_>) -> String {
        match (self, self.rows(py)) {
            (End::Point(p), _) => format!("{p:?}"),
            (_, n) => format!("<array of shape ({}, 3)>", n.unwrap_or(0)),
        }
    }
}

/// A technique's parameters as given (checked in f64 by
/// [`Config::check`]; each call builds them in its precision again).
pub struct Config {
    /// The technique.
    pub method: Method,
    /// The light-side end point(s).
    pub x0: End,
    /// The receiver-side end point(s).
    pub x2: End,
    /// The restriction θ < θmax.
    pub theta_max: f64,
    /// The phase function at `x1`.
    pub phase: Phase,
    /// Cosine-weighted ray directions about this normal (one, or one per
    /// row); `None`: the sphere.
    pub normal: Option<End>,
    /// The slab `z_min ≤ z ≤ z_max` the medium fills; `None`: everywhere.
    pub slab: Option<(f64, f64)>,
    /// Distance sampling's free-flight coefficient σt (0 for the others).
    pub sigma_t: f64,
}

impl Config {
    /// The number of connections if they are given per row: the common
    /// first axis of the per-row arguments.
    pub fn rows(&self, py: Python<'_>) -> PyResult<Option<usize>> {
        let ends = [("x0", Some(&self.x0)), ("x2", Some(&self.x2))];
        let ends = ends.into_iter().chain([("normal", self.normal.as_ref())]);
        let mut rows: Option<(&str, usize)> = None;
        for (arg, end) in ends {
            let Some(n) = end.and_then(|e| e.rows(py)) else {
                continue;
            };
            match rows {
                Some((first, m)) if m != n => {
                    return Err(PyValueError::new_err(format!(
                        "{arg}: {n} rows; allowed: {m} rows, as {first} has, or one point (3,)"
                    )));
                }
                _ => rows = Some((arg, n)),
            }
        }
        Ok(rows.map(|(_, n)| n))
    }

    /// Checks every parameter in f64 (each row's, in parallel with the GIL
    /// released): the core's error, naming the field (and the row), or
    /// distance sampling that could never end (σt = 0 without a slab). Rows
    /// are checked again at every call, in its precision (they are read in
    /// place, and a row valid in f64 may not be in f32).
    pub fn check(&self, py: Python<'_>, rows: Option<usize>) -> PyResult<()> {
        if self.method == Method::Distance && self.sigma_t == 0.0 && self.slab.is_none() {
            return Err(PyValueError::new_err(
                "sigma_t = 0 is out of range; allowed: (0, inf) in a medium without bounds \
                 (slab=None: a free flight with sigma_t = 0 never ends), [0, inf) with a slab",
            ));
        }
        self.with::<f64, _>(py, rows, 1, |cx| {
            let Geometry::Rows { x0, x2, normal, .. } = cx.geometry else {
                return Ok(());
            };
            let all = 0..rows.unwrap_or(0);
            py.detach(|| {
                run(all, |_, rows| {
                    // A scan for what the core refuses (non-finite or
                    // coincident points, a zero normal), the core's own
                    // check (and message) for a row the scan flags.
                    let flagged = |&row: &usize| {
                        let (a, b) = (x0.get(row), x2.get(row));
                        let n = normal.map_or([1.0; 3], |n| n.get(row));
                        let finite = a.iter().chain(&b).chain(&n).all(|v| v.is_finite());
                        !finite || a == b || n == [0.0; 3]
                    };
                    rows.filter(flagged)
                        .try_for_each(|row| cx.geometry.at(row).map(drop))
                })
            })
        })?
        .map_err(|bad| bad.into_err(&[]))
    }

    /// Runs `f` with the parameters in precision `F` (`per_row` items per
    /// row, `rows` connections given per row); fails with the core's error (a `ValueError` naming the field)
    /// where `F` cannot hold a parameter given once (one given per row is
    /// checked by the loops, row by row).
    pub fn with<F: Real, T>(
        &self,
        py: Python<'_>,
        rows: Option<usize>,
        per_row: usize,
        f: impl FnOnce(Context<'_, F>) -> T,
    ) -> PyResult<T> {
        let (x0, x2) = (self.x0.borrow(py, rows)?, self.x2.borrow(py, rows)?);
        let normal = self
            .normal
            .as_ref()
            .map(|n| n.borrow(py, rows))
            .transpose()?;
        let theta_max = F::from_f64(self.theta_max);
        let (one_normal, row_normal) = match &normal {
            Some(Borrowed::Point(n)) => (Some(*n), None),
            Some(b) => (None, Some(b.coords())),
            None => (None, None),
        };
        let geometry = match (&x0, &x2, row_normal) {
            (Borrowed::Point(a), Borrowed::Point(b), None) => Geometry::One(
                Connection::new(vec3::<F>(*a), vec3::<F>(*b), theta_max).map_err(error::core)?,
            ),
            _ => {
                // θmax is the same for every row: refused once, as the
                // core refuses it for a unit connection.
                let (o, z) = ([0.0; 3], [0.0, 0.0, 1.0]);
                Connection::new(vec3::<F>(o), vec3::<F>(z), theta_max).map_err(error::core)?;
                Geometry::Rows {
                    x0: x0.coords(),
                    x2: x2.coords(),
                    normal: row_normal,
                    theta_max,
                }
            }
        };
        let directions = match one_normal {
            Some(n) => Directions::cosine(vec3::<F>(n)).map_err(error::core)?,
            None => Directions::Sphere,
        };
        let region = match self.slab {
            Some((lo, hi)) => {
                Region::slab(F::from_f64(lo), F::from_f64(hi)).map_err(error::core)?
            }
            None => Region::Everywhere,
        };
        let mut storage = TableStorage::<F>::default();
        let phase = self.phase.instantiate::<F>(&mut storage)?;
        let setup = Setup::new(&phase, directions, region, F::from_f64(self.sigma_t))
            .map_err(error::core)?;
        Ok(f(Context {
            method: self.method,
            setup,
            geometry,
            per_row: per_row.max(1),
        }))
    }

    /// Equal methods and parameters, the phase functions by value.
    pub fn equals(&self, other: &Config, py: Python<'_>) -> PyResult<bool> {
        let normals = match (&self.normal, &other.normal) {
            (Some(a), Some(b)) => a.equals(b, py)?,
            (a, b) => a.is_none() && b.is_none(),
        };
        Ok(self.method == other.method
            && self.theta_max == other.theta_max
            && self.slab == other.slab
            && self.sigma_t == other.sigma_t
            && normals
            && self.phase.equals(&other.phase)?
            && self.x0.equals(&other.x0, py)?
            && self.x2.equals(&other.x2, py)?)
    }

    /// A hash of what [`Config::equals`] compares.
    pub fn hash(&self, py: Python<'_>) -> PyResult<u64> {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.method.hash(&mut h);
        let slab = self.slab.map(|(a, b)| (canonical(a), canonical(b)));
        (canonical(self.theta_max), slab, canonical(self.sigma_t)).hash(&mut h);
        self.phase.hash_value()?.hash(&mut h);
        self.x0.hash(py, &mut h)?;
        self.x2.hash(py, &mut h)?;
        if let Some(n) = &self.normal {
            n.hash(py, &mut h)?;
        }
        Ok(h.finish())
    }

    /// `x0=..., x2=..., phase=..., theta_max=...` and the method's others.
    pub fn text(&self, py: Python<'_>) -> String {
        let mut s = format!(
            "x0={}, x2={}, phase={:?}, theta_max={}",
            self.x0.text(py),
            self.x2.text(py),
            self.phase.spec.to_string(),
            self.theta_max
        );
        if self.method == Method::Distance {
            s += &format!(", sigma_t={}", self.sigma_t);
        }
        if let Some(n) = &self.normal {
            s += &format!(", normal={}", n.text(py));
        }
        if let Some(z) = self.slab {
            s += &format!(", slab={z:?}");
        }
        s
    }
}
