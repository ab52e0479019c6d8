//! `omnee.Omnee`, `omnee.Equiangular`, `omnee.Distance` and `omnee.Mis`:
//! the techniques that place the once-more vertex `x1`, each the
//! sample / pdf / invert trio of the core over arrays of uniform numbers or
//! points (Mitsuba's `square_to_X`, `square_to_X_pdf`, `X_to_square`),
//! for one connection or one per row.
//!
//! They share one base class, `omnee.Technique`, whose methods do the work;
//! the subclasses construct it, and those that have an inverse (all but
//! MIS) offer `invert`.

use crate::array::{
    Floats, floats, out_array, readwrite, result, rows, shape_text, slice, slice_mut, with_axes,
    zeros,
};
use crate::config::{Config, End};
use crate::kernel::{SampleOut, uniforms, vertices};
use crate::phase::Phase;
use numpy::{Element, PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use omnee_core::Real;
use omnee_core::method::Method;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::f64::consts::PI;

/// The Python class of `method`.
fn class_name(method: Method) -> &'static str {
    match method {
        Method::Omnee => "Omnee",
        Method::Equiangular => "Equiangular",
        Method::Distance => "Distance",
        Method::Mis => "Mis",
    }
}

/// The arrays `out` names (a sequence of `names.len()` arrays), or `None`.
fn outs<'py>(
    out: Option<&Bound<'py, PyAny>>,
    names: &[&str],
) -> PyResult<Option<Vec<Bound<'py, PyAny>>>> {
    let Some(out) = out else { return Ok(None) };
    let items: Vec<Bound<'py, PyAny>> = out
        .try_iter()
        .map_err(|_| {
            PyTypeError::new_err(format!("out: allowed: a sequence ({})", names.join(", ")))
        })?
        .collect::<PyResult<_>>()?;
    if items.len() != names.len() {
        return Err(PyValueError::new_err(format!(
            "out: {} arrays; allowed: {} ({})",
            items.len(),
            names.len(),
            names.join(", ")
        )));
    }
    Ok(Some(items))
}

/// Output `k` of `out` (called `name`) checked against `shape`, or a new
/// zeroed array.
fn output<'py, T: Element>(
    py: Python<'py>,
    out: &Option<Vec<Bound<'py, PyAny>>>,
    k: usize,
    name: &str,
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    match out {
        Some(items) => out_array::<T>(&format!("out[{k}] ({name})"), &items[k], shape),
        None => Ok(zeros::<T>(py, shape)),
    }
}

/// What a call returns: the caller's `out` arrays as given, or the new
/// ones, a 0-d result as a numpy scalar.
fn returned<'py, T: Element>(
    a: Bound<'py, PyArrayDyn<T>>,
    given: bool,
) -> PyResult<Bound<'py, PyAny>> {
    if given { Ok(a.into_any()) } else { result(a) }
}

/// A technique for placing the scattering vertex `x1` of the once-more
/// scattered connection `x0 → x1 → x2`, restricted to deflections θ < θmax.
///
/// Not constructed directly: use `Omnee`, `Equiangular`, `Distance` or `Mis`.
#[pyclass(module = "omnee", subclass, frozen)]
pub struct Technique {
    config: Config,
    /// The number of connections given per row (`None`: one connection).
    rows: Option<usize>,
}

impl Technique {
    /// The leading shape of an argument of shape `(..., k)` and the items
    /// per row: with connections per row the first axis must be theirs.
    fn lead(&self, arg: &str, shape: &[usize], k: usize) -> PyResult<(Vec<usize>, usize)> {
        let lead = rows(arg, shape, k)?;
        match self.rows {
            None => Ok((lead, 1)),
            Some(n) if lead.first() == Some(&n) => {
                let per_row = lead[1..].iter().product();
                Ok((lead, per_row))
            }
            Some(n) => Err(PyValueError::new_err(format!(
                "{arg}: shape {}; allowed: ({n}, ..., {k}), one row per connection (x0 and x2 \
                 have {n} rows)",
                shape_text(shape)
            ))),
        }
    }

    fn sample_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArrayDyn<'py, F>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let method = self.config.method;
        let (lead, per_row) = self.lead("u", u.shape(), uniforms(method))?;
        let shape = match vertices(method) {
            1 => lead,
            v => with_axes(&lead, &[v]),
        };
        let given = outs(out, &["x1", "pdf", "weight", "valid"])?;
        let x1 = output::<F>(py, &given, 0, "x1", &with_axes(&shape, &[3]))?;
        let pdf = output::<F>(py, &given, 1, "pdf", &shape)?;
        let weight = output::<F>(py, &given, 2, "weight", &shape)?;
        let valid = output::<bool>(py, &given, 3, "valid", &shape)?;
        {
            let (mut a, mut b) = (
                readwrite("out[0] (x1)", &x1)?,
                readwrite("out[1] (pdf)", &pdf)?,
            );
            let mut c = readwrite("out[2] (weight)", &weight)?;
            let mut d = readwrite("out[3] (valid)", &valid)?;
            let out = SampleOut {
                x1: slice_mut(&mut a),
                pdf: slice_mut(&mut b),
                weight: slice_mut(&mut c),
                valid: slice_mut(&mut d),
            };
            let u_values = slice(&u);
            self.config
                .with::<F, _>(py, self.rows, per_row, |cx| {
                    py.detach(|| cx.sample(u_values, out))
                })?
                .map_err(|bad| bad.into_err(u.shape()))?;
        }
        let given = given.is_some();
        py.import("omnee")?.getattr("Samples")?.call1((
            returned(x1, given)?,
            returned(pdf, given)?,
            returned(weight, given)?,
            returned(valid, given)?,
        ))
    }

    fn pdf_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        x1: PyReadonlyArrayDyn<'py, F>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (lead, per_row) = self.lead("x1", x1.shape(), 3)?;
        let given = out.map(|o| vec![o.clone()]);
        let pdf = output::<F>(py, &given, 0, "pdf", &lead)?;
        {
            let mut a = readwrite("out", &pdf)?;
            let (points, out) = (slice(&x1), slice_mut(&mut a));
            self.config
                .with::<F, _>(py, self.rows, per_row, |cx| {
                    py.detach(|| cx.pdf(points, out))
                })?
                .map_err(|bad| bad.into_err(x1.shape()))?;
        }
        returned(pdf, given.is_some())
    }

    fn invert_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        x1: PyReadonlyArrayDyn<'py, F>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (lead, per_row) = self.lead("x1", x1.shape(), 3)?;
        let given = outs(out, &["u", "valid"])?;
        let u = output::<F>(py, &given, 0, "u", &with_axes(&lead, &[3]))?;
        let valid = output::<bool>(py, &given, 1, "valid", &lead)?;
        {
            let (mut a, mut b) = (
                readwrite("out[0] (u)", &u)?,
                readwrite("out[1] (valid)", &valid)?,
            );
            let (points, u, valid) = (slice(&x1), slice_mut(&mut a), slice_mut(&mut b));
            self.config
                .with::<F, _>(py, self.rows, per_row, |cx| {
                    py.detach(|| cx.invert(points, u, valid))
                })?
                .map_err(|bad| bad.into_err(x1.shape()))?;
        }
        let given = given.is_some();
        py.import("omnee")?
            .getattr("Inversion")?
            .call1((returned(u, given)?, returned(valid, given)?))
    }

    /// `invert` of the subclasses that have one.
    fn invert<'py>(
        &self,
        py: Python<'py>,
        x1: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        match floats("x1", x1)? {
            Floats::F32(v) => self.invert_in(py, v, out),
            Floats::F64(v) => self.invert_in(py, v, out),
        }
    }
}

#[pymethods]
impl Technique {
    /// Draws `x1` from uniform numbers `u` of shape `(..., 3)` (`(..., 6)`
    /// for `Mis`; with connections per row `(N, ..., 3)`, row `i` of `u`
    /// for connection `i`), each in [0, 1], returning
    /// `Samples(x1, pdf, weight, valid)`; into the arrays of `out` if given.
    #[pyo3(signature = (u, out = None))]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        match floats("u", u)? {
            Floats::F32(v) => self.sample_in(py, v, out),
            Floats::F64(v) => self.sample_in(py, v, out),
        }
    }

    /// The volume density (m⁻³) with which `sample` draws `x1` of shape
    /// `(..., 3)` (per row: `(N, ..., 3)`); 0 where it never samples; into
    /// `out` if given.
    #[pyo3(signature = (x1, out = None))]
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        x1: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        match floats("x1", x1)? {
            Floats::F32(v) => self.pdf_in(py, v, out),
            Floats::F64(v) => self.pdf_in(py, v, out),
        }
    }

    /// The light-side end point: `(x, y, z)`, or the `(N, 3)` array.
    #[getter]
    fn x0<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.config.x0.to_object(py)
    }

    /// The receiver-side end point: `(x, y, z)`, or the `(N, 3)` array.
    #[getter]
    fn x2<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.config.x2.to_object(py)
    }

    /// The restriction θ < θmax of the integrand, θmax ∈ (0, π].
    #[getter]
    fn theta_max(&self) -> f64 {
        self.config.theta_max
    }

    /// The phase function at `x1`.
    #[getter]
    fn phase(&self) -> Phase {
        self.config.phase.clone()
    }

    /// Uniform numbers per draw: 3, or 6 for `Mis`.
    #[getter]
    fn dimension(&self) -> usize {
        uniforms(self.config.method)
    }

    /// The number of connections given per row (the first axis of `x0`,
    /// `x2` or `normal`), or `None` for one connection.
    #[getter]
    fn rows(&self) -> Option<usize> {
        self.rows
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let name = class_name(self.config.method);
        format!("omnee.{name}({})", self.config.text(py))
    }

    /// Equal by value: the same technique with equal parameters (end
    /// points and normals compared coordinate by coordinate, the phase
    /// functions by their parameters).
    fn __eq__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<bool> {
        match other.cast::<Technique>() {
            Ok(o) => self.config.equals(&o.get().config, py),
            Err(_) => Ok(false),
        }
    }

    /// A hash of the values `==` compares.
    fn __hash__(&self, py: Python<'_>) -> PyResult<u64> {
        self.config.hash(py)
    }

    /// The constructor's arguments, for pickle (`copyreg.__newobj_ex__`).
    fn __getnewargs_ex__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyTuple>, Bound<'py, PyDict>)> {
        let c = &self.config;
        let args = PyTuple::new(
            py,
            [
                c.x0.to_object(py)?,
                c.x2.to_object(py)?,
                Bound::new(py, c.phase.clone())?.into_any(),
            ],
        )?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("theta_max", c.theta_max)?;
        if c.method == Method::Distance {
            kwargs.set_item("sigma_t", c.sigma_t)?;
        }
        if c.method != Method::Omnee {
            let normal = c.normal.as_ref().map(|n| n.to_object(py)).transpose()?;
            kwargs.set_item("normal", normal)?;
            kwargs.set_item("slab", c.slab)?;
        }
        Ok((args, kwargs))
    }
}

/// The phase argument: an `omnee.Phase` or its spec string.
pub(crate) fn phase_arg(obj: &Bound<'_, PyAny>) -> PyResult<Phase> {
    if let Ok(p) = obj.cast::<Phase>() {
        return Ok(p.get().clone());
    }
    let spec: String = obj.extract().map_err(|_| {
        PyTypeError::new_err("phase: expected an omnee.Phase or a spec string such as \"hg:0.9\"")
    })?;
    Phase::parse(&spec)
}

/// The parameters of a technique as its constructor takes them.
struct Args<'a, 'py> {
    x0: &'a Bound<'py, PyAny>,
    x2: &'a Bound<'py, PyAny>,
    phase: &'a Bound<'py, PyAny>,
    theta_max: f64,
    normal: Option<&'a Bound<'py, PyAny>>,
    slab: Option<(f64, f64)>,
    sigma_t: f64,
}

/// Builds the base class, checking every parameter (every row's) in f64.
fn technique(method: Method, a: Args<'_, '_>) -> PyResult<PyClassInitializer<Technique>> {
    let py = a.x0.py();
    let config = Config {
        method,
        x0: End::parse("x0", a.x0)?,
        x2: End::parse("x2", a.x2)?,
        theta_max: a.theta_max,
        phase: phase_arg(a.phase)?,
        normal: a.normal.map(|n| End::parse("normal", n)).transpose()?,
        slab: a.slab,
        sigma_t: a.sigma_t,
    };
    let rows = config.rows(py)?;
    config.check(py, rows)?;
    Ok(PyClassInitializer::from(Technique { config, rows }))
}

/// OMNEE (docs/math.md §3): θ from the phase function with `u0`, `β = u1 θ`,
/// `φ = 2π u2` on the circumcircle arc through `x0` and `x2`;
/// `pdf(x1) = p(θ) (sin θ/θ) s / (d1² d2²)`, weight `k/pdf = θ/(s sin θ)`.
///
/// `x0`, `x2`: points of shape `(3,)`, or `(N, 3)` for one connection per row.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Omnee;

#[pymethods]
impl Omnee {
    #[new]
    #[pyo3(
        signature = (x0, x2, phase, theta_max = PI),
        text_signature = "(x0, x2, phase, theta_max=3.141592653589793)"
    )]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: &Bound<'_, PyAny>,
        theta_max: f64,
    ) -> PyResult<PyClassInitializer<Self>> {
        let (normal, slab, sigma_t) = (None, None, 0.0);
        let args = Args {
            x0,
            x2,
            phase,
            theta_max,
            normal,
            slab,
            sigma_t,
        };
        Ok(technique(Method::Omnee, args)?.add_subclass(Omnee))
    }

    /// The uniform numbers that `sample` maps to points `x1` of shape
    /// `(..., 3)` (per row: `(N, ..., 3)`), returning `Inversion(u, valid)`;
    /// into the arrays of `out` if given.
    #[pyo3(signature = (x1, out = None))]
    fn invert<'py>(
        slf: &Bound<'py, Self>,
        x1: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        slf.as_super().get().invert(slf.py(), x1, out)
    }
}

/// Equiangular sampling (Kulla & Fajardo 2012; docs/math.md §8): a direction
/// ω from `x2` with `(u0, u1)` (uniform on the sphere, or cosine-weighted
/// about `normal`), then the distance along it with density ∝ 1/d1² inside
/// the medium (all of space, or the `slab` (z_min, z_max)):
/// `pdf(x1) = pdf_ω(ω) c / (d1² d2²)`, weight `p(θ) / (pdf_ω(ω) c)`.
///
/// `x0`, `x2`, `normal`: points of shape `(3,)`, or `(N, 3)` per row.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Equiangular;

#[pymethods]
impl Equiangular {
    #[new]
    #[pyo3(
        signature = (x0, x2, phase, theta_max = PI, normal = None, slab = None),
        text_signature = "(x0, x2, phase, theta_max=3.141592653589793, normal=None, slab=None)"
    )]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: &Bound<'_, PyAny>,
        theta_max: f64,
        normal: Option<&Bound<'_, PyAny>>,
        slab: Option<(f64, f64)>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let args = Args {
            x0,
            x2,
            phase,
            theta_max,
            normal,
            slab,
            sigma_t: 0.0,
        };
        Ok(technique(Method::Equiangular, args)?.add_subclass(Equiangular))
    }

    /// The uniform numbers that `sample` maps to points `x1` of shape
    /// `(..., 3)` (per row: `(N, ..., 3)`), returning `Inversion(u, valid)`;
    /// into the arrays of `out` if given.
    #[pyo3(signature = (x1, out = None))]
    fn invert<'py>(
        slf: &Bound<'py, Self>,
        x1: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        slf.as_super().get().invert(slf.py(), x1, out)
    }
}

/// Distance sampling (docs/math.md §9): a direction ω from `x2` as for
/// `Equiangular`, then the exponential free-flight distance with
/// coefficient `sigma_t` on the medium segment [t_a, t_b]:
/// `pdf(t) = σ e^{−σ (t − t_a)} / (1 − e^{−σ L})`, `pdf(x1) = pdf_ω(ω) pdf(t) / t²`.
/// `sigma_t` ∈ (0, ∞) in a medium without bounds, [0, ∞) with a slab.
///
/// `x0`, `x2`, `normal`: points of shape `(3,)`, or `(N, 3)` per row.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Distance;

#[pymethods]
impl Distance {
    #[new]
    #[pyo3(
        signature = (x0, x2, phase, sigma_t, theta_max = PI, normal = None, slab = None),
        text_signature = "(x0, x2, phase, sigma_t, theta_max=3.141592653589793, normal=None, slab=None)"
    )]
    #[allow(clippy::too_many_arguments)]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: &Bound<'_, PyAny>,
        sigma_t: f64,
        theta_max: f64,
        normal: Option<&Bound<'_, PyAny>>,
        slab: Option<(f64, f64)>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let args = Args {
            x0,
            x2,
            phase,
            theta_max,
            normal,
            slab,
            sigma_t,
        };
        Ok(technique(Method::Distance, args)?.add_subclass(Distance))
    }

    /// The uniform numbers that `sample` maps to points `x1` of shape
    /// `(..., 3)` (per row: `(N, ..., 3)`), returning `Inversion(u, valid)`;
    /// into the arrays of `out` if given.
    #[pyo3(signature = (x1, out = None))]
    fn invert<'py>(
        slf: &Bound<'py, Self>,
        x1: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        slf.as_super().get().invert(slf.py(), x1, out)
    }
}

/// MIS as the CLI's `mis` (docs/math.md §10): OMNEE's vertex from `u[0:3]`
/// always, and when `u3 < c = 0.05` an equiangular companion from
/// `(u3/c, u4, u5)` kept behind the cone θ ≥ 3π/4; balance heuristic
/// there (`pdf = p_O + c p_E`), OMNEE alone in front of it. The estimate is
/// the sum of `f_c · weight` over both vertices of a draw. It has no
/// `invert` (OMNEE and the companion can draw the same `x1`).
///
/// `x0`, `x2`, `normal`: points of shape `(3,)`, or `(N, 3)` per row.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Mis;

#[pymethods]
impl Mis {
    #[new]
    #[pyo3(
        signature = (x0, x2, phase, theta_max = PI, normal = None, slab = None),
        text_signature = "(x0, x2, phase, theta_max=3.141592653589793, normal=None, slab=None)"
    )]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: &Bound<'_, PyAny>,
        theta_max: f64,
        normal: Option<&Bound<'_, PyAny>>,
        slab: Option<(f64, f64)>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let args = Args {
            x0,
            x2,
            phase,
            theta_max,
            normal,
            slab,
            sigma_t: 0.0,
        };
        Ok(technique(Method::Mis, args)?.add_subclass(Mis))
    }
}
