//! `omnee.Omnee`, `omnee.Equiangular`, `omnee.Distance` and `omnee.Mis`:
//! the techniques that place the once-more vertex `x1`, each the
//! sample / pdf / invert trio of the core over arrays of uniform numbers or
//! points (Mitsuba's `square_to_X`, `square_to_X_pdf`, `X_to_square`).
//!
//! They share one base class, `omnee.Technique`, whose methods do the work;
//! the subclasses only construct it.

use crate::array::{Floats, Values, coords, floats, output, point, vec3, with_axes};
use crate::error;
use crate::phase::{PARALLEL_MIN, Phase};
use omnee_core::medium::Region;
use omnee_core::method::{Method, Setup};
use omnee_core::phase::Phase as CorePhase;
use omnee_core::sampling::{
    Connection, Directions, Distance as CoreDistance, Equiangular as CoreEquiangular,
    Omnee as CoreOmnee, Sample, Technique as CoreTechnique,
};
use omnee_core::{Real, Vector};
use omnee_render::phase::TableStorage;
use pyo3::exceptions::PyNotImplementedError;
use pyo3::prelude::*;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Uniform numbers per draw of `method`: 3, or 6 for MIS (OMNEE's, then
/// the companion's).
fn uniforms(method: Method) -> usize {
    match method {
        Method::Mis => 6,
        _ => 3,
    }
}

/// Vertices per draw of `method`: 1, or 2 for MIS.
fn vertices(method: Method) -> usize {
    match method {
        Method::Mis => 2,
        _ => 1,
    }
}

/// The Python class of `method`.
fn class_name(method: Method) -> &'static str {
    match method {
        Method::Omnee => "Omnee",
        Method::Equiangular => "Equiangular",
        Method::Distance => "Distance",
        Method::Mis => "Mis",
    }
}

/// A technique's parameters in f64, as given (validated in f64 by the
/// constructor; a computation in f32 validates them again in f32).
#[derive(Clone, Debug)]
struct Config {
    method: Method,
    x0: [f64; 3],
    x2: [f64; 3],
    theta_max: f64,
    phase: Phase,
    /// Cosine-weighted ray directions about this normal; `None`: the sphere.
    normal: Option<[f64; 3]>,
    /// The slab `z_min ≤ z ≤ z_max` the medium fills; `None`: everywhere.
    slab: Option<(f64, f64)>,
    /// Distance sampling's free-flight coefficient σt (0 for the others).
    sigma_t: f64,
}

/// The configuration in precision `F`: the core's [`Setup`] (borrowing the
/// phase function) with the method and the connection it draws for.
#[derive(Clone, Copy)]
struct Parts<'a, F: Real> {
    method: Method,
    connection: Connection<F>,
    setup: Setup<F, &'a CorePhase<'a, F>>,
}

impl Config {
    /// Runs `f` with the configuration in precision `F`; fails with the
    /// core's error (a `ValueError` naming the field) where `F` cannot hold it.
    fn with<F: Real, T>(&self, f: impl FnOnce(Parts<'_, F>) -> T) -> PyResult<T> {
        let connection = Connection::new(
            vec3::<F>(self.x0),
            vec3::<F>(self.x2),
            F::from_f64(self.theta_max),
        )
        .map_err(error::core)?;
        let directions = match self.normal {
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
        Ok(f(Parts {
            method: self.method,
            connection,
            setup,
        }))
    }
}

/// One draw's vertices (the second only for MIS's companion).
type Vertices<F> = [Option<Sample<F>>; 2];

impl<F: Real> Parts<'_, F> {
    /// The draws for consecutive rows of `uniforms(method)` numbers, each
    /// row the number source of one [`Setup::draw`].
    fn draws(&self, u: &[F]) -> Vec<Vertices<F>> {
        u.chunks_exact(uniforms(self.method))
            .map(|row| {
                let mut next = row.iter().copied();
                let draw = self.setup.draw(self.method, self.connection, || {
                    next.next().unwrap_or(F::ZERO)
                });
                draw.vertices
            })
            .collect()
    }

    /// The density the vertices come with, at each point ([`Setup::pdf`]).
    fn pdfs(&self, x1: &[F]) -> Vec<F> {
        x1.chunks_exact(3)
            .map(|p| {
                let x1 = F::Vec3::new(p[0], p[1], p[2]);
                self.setup.pdf(self.method, self.connection, x1)
            })
            .collect()
    }

    /// `f` with the method's own technique, whose [`CoreTechnique::invert`]
    /// gives the uniform numbers of a point (the core's [`Setup`] has no
    /// inverse); MIS has none (OMNEE and the companion can draw the same
    /// point).
    fn invertible<T>(&self, f: impl FnOnce(&(dyn CoreTechnique<F> + Sync)) -> T) -> PyResult<T> {
        let (s, c) = (&self.setup, self.connection);
        let (phase, directions, region) = (*s.phase(), s.directions(), s.region());
        Ok(match self.method {
            Method::Omnee => f(&CoreOmnee::new(c, phase)),
            Method::Equiangular => f(&CoreEquiangular::new(c, phase, directions, region)),
            Method::Distance => f(
                &CoreDistance::new(c, phase, directions, region, s.sigma_t())
                    .map_err(error::core)?,
            ),
            Method::Mis => return Err(mis_not_invertible()),
        })
    }
}

/// The uniform numbers that give each point of `x1`, where `technique`'s
/// map is invertible.
fn inverses<F: Real>(technique: &dyn CoreTechnique<F>, x1: &[F]) -> Vec<Option<[F; 3]>> {
    x1.chunks_exact(3)
        .map(|p| technique.invert(F::Vec3::new(p[0], p[1], p[2])))
        .collect()
}

/// `Mis.invert`'s error.
fn mis_not_invertible() -> PyErr {
    PyNotImplementedError::new_err(
        "Mis.invert: MIS is not invertible (OMNEE and the companion can draw the same x1); \
         invert Omnee or Equiangular",
    )
}

/// `f` over `data` in tuples of `k`, in parallel for long inputs, results in order.
fn chunked<F: Sync, T: Send>(
    data: &[F],
    k: usize,
    f: impl Fn(&[F]) -> Vec<T> + Sync + Send,
) -> Vec<T> {
    if data.len() < PARALLEL_MIN {
        return f(data);
    }
    let rows = (PARALLEL_MIN / k).max(1) * k;
    data.par_chunks(rows).flat_map_iter(f).collect()
}

/// A technique for placing the scattering vertex `x1` of the once-more
/// scattered connection `x0 → x1 → x2`, restricted to deflections θ < θmax.
///
/// Not constructed directly: use `Omnee`, `Equiangular`, `Distance` or `Mis`.
#[pyclass(module = "omnee", subclass, frozen)]
pub struct Technique {
    config: Config,
}

impl Technique {
    fn sample_in<'py, F: Real + numpy::Element>(
        &self,
        py: Python<'py>,
        u: Values<F>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let method = self.config.method;
        let lead = u.rows("u", uniforms(method))?;
        let draws = self.config.with::<F, _>(|parts| {
            py.detach(|| chunked(&u.data, uniforms(method), |u| parts.draws(u)))
        })?;
        let vertices = vertices(method);
        let n = draws.len() * vertices;
        let (mut x1, mut pdf, mut weight, mut valid) = (
            Vec::with_capacity(3 * n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for vertex in draws.iter().flat_map(|d| &d[..vertices]) {
            let s = vertex.unwrap_or(Sample {
                x1: F::Vec3::new(F::ZERO, F::ZERO, F::ZERO),
                pdf: F::ZERO,
                weight: F::ZERO,
            });
            x1.extend(coords::<F>(s.x1));
            pdf.push(s.pdf);
            weight.push(s.weight);
            valid.push(vertex.is_some());
        }
        let per_draw = if vertices == 1 {
            vec![]
        } else {
            vec![vertices]
        };
        let shape = with_axes(&lead, &per_draw);
        let samples = py.import("omnee")?.getattr("Samples")?;
        samples.call1((
            output(py, with_axes(&shape, &[3]), x1)?,
            output(py, shape.clone(), pdf)?,
            output(py, shape.clone(), weight)?,
            output(py, shape, valid)?,
        ))
    }

    fn pdf_in<'py, F: Real + numpy::Element>(
        &self,
        py: Python<'py>,
        x1: Values<F>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let lead = x1.rows("x1", 3)?;
        let pdf = self
            .config
            .with::<F, _>(|parts| py.detach(|| chunked(&x1.data, 3, |x| parts.pdfs(x))))?;
        output(py, lead, pdf)
    }

    fn invert_in<'py, F: Real + numpy::Element>(
        &self,
        py: Python<'py>,
        x1: Values<F>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let lead = x1.rows("x1", 3)?;
        let inverses = self.config.with::<F, _>(|parts| {
            parts.invertible(|t| py.detach(|| chunked(&x1.data, 3, |x| inverses(t, x))))
        })??;
        let u: Vec<F> = inverses
            .iter()
            .flat_map(|u| u.unwrap_or([F::ZERO; 3]))
            .collect();
        let valid: Vec<bool> = inverses.iter().map(Option::is_some).collect();
        let inversion = py.import("omnee")?.getattr("Inversion")?;
        inversion.call1((
            output(py, with_axes(&lead, &[3]), u)?,
            output(py, lead, valid)?,
        ))
    }
}

#[pymethods]
impl Technique {
    /// Draws `x1` from uniform numbers `u` of shape `(..., 3)` (`(..., 6)`
    /// for `Mis`), returning `Samples(x1, pdf, weight, valid)`.
    fn sample<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match floats("u", u)? {
            Floats::F32(v) => self.sample_in(py, v),
            Floats::F64(v) => self.sample_in(py, v),
        }
    }

    /// The volume density (m⁻³) with which `sample` draws `x1` of shape
    /// `(..., 3)`; 0 where it never samples.
    fn pdf<'py>(&self, py: Python<'py>, x1: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match floats("x1", x1)? {
            Floats::F32(v) => self.pdf_in(py, v),
            Floats::F64(v) => self.pdf_in(py, v),
        }
    }

    /// The uniform numbers that `sample` maps to `x1` (shape `(..., 3)`),
    /// returning `Inversion(u, valid)`.
    fn invert<'py>(&self, py: Python<'py>, x1: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        if self.config.method == Method::Mis {
            return Err(mis_not_invertible());
        }
        match floats("x1", x1)? {
            Floats::F32(v) => self.invert_in(py, v),
            Floats::F64(v) => self.invert_in(py, v),
        }
    }

    /// The light-side end point.
    #[getter]
    fn x0(&self) -> (f64, f64, f64) {
        let [x, y, z] = self.config.x0;
        (x, y, z)
    }

    /// The receiver-side end point.
    #[getter]
    fn x2(&self) -> (f64, f64, f64) {
        let [x, y, z] = self.config.x2;
        (x, y, z)
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

    fn __repr__(&self) -> String {
        let c = &self.config;
        let mut s = format!(
            "omnee.{}(x0={:?}, x2={:?}, phase={:?}, theta_max={}",
            class_name(c.method),
            c.x0,
            c.x2,
            c.phase.spec.to_string(),
            c.theta_max
        );
        if c.method == Method::Distance {
            s += &format!(", sigma_t={}", c.sigma_t);
        }
        if c.method != Method::Omnee {
            if let Some(n) = c.normal {
                s += &format!(", normal={n:?}");
            }
            if let Some(z) = c.slab {
                s += &format!(", slab={z:?}");
            }
        }
        s + ")"
    }
}

/// The phase argument: an `omnee.Phase` or its spec string.
pub(crate) fn phase_arg(obj: &Bound<'_, PyAny>) -> PyResult<Phase> {
    if let Ok(p) = obj.cast::<Phase>() {
        return Ok(p.get().clone());
    }
    let spec: String = obj.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(
            "phase: expected an omnee.Phase or a spec string such as \"hg:0.9\"",
        )
    })?;
    Phase::parse(&spec)
}

/// Builds the base class, checking the configuration in f64.
#[allow(clippy::too_many_arguments)]
fn technique(
    method: Method,
    x0: &Bound<'_, PyAny>,
    x2: &Bound<'_, PyAny>,
    phase: &Bound<'_, PyAny>,
    theta_max: f64,
    normal: Option<&Bound<'_, PyAny>>,
    slab: Option<(f64, f64)>,
    sigma_t: f64,
) -> PyResult<PyClassInitializer<Technique>> {
    let config = Config {
        method,
        x0: point("x0", x0)?,
        x2: point("x2", x2)?,
        theta_max,
        phase: phase_arg(phase)?,
        normal: normal.map(|n| point("normal", n)).transpose()?,
        slab,
        sigma_t,
    };
    config.with::<f64, _>(|_| ())?;
    Ok(PyClassInitializer::from(Technique { config }))
}

/// OMNEE (docs/math.md §3): θ from the phase function with `u0`, `β = u1 θ`,
/// `φ = 2π u2` on the circumcircle arc through `x0` and `x2`;
/// `pdf(x1) = p(θ) (sin θ/θ) s / (d1² d2²)`, weight `k/pdf = θ/(s sin θ)`.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Omnee;

#[pymethods]
impl Omnee {
    #[new]
    #[pyo3(signature = (x0, x2, phase, theta_max = PI))]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: &Bound<'_, PyAny>,
        theta_max: f64,
    ) -> PyResult<PyClassInitializer<Self>> {
        Ok(
            technique(Method::Omnee, x0, x2, phase, theta_max, None, None, 0.0)?
                .add_subclass(Omnee),
        )
    }
}

/// Equiangular sampling (Kulla & Fajardo 2012; docs/math.md §8): a direction
/// ω from `x2` with `(u0, u1)` (uniform on the sphere, or cosine-weighted
/// about `normal`), then the distance along it with density ∝ 1/d1² inside
/// the medium (all of space, or the `slab` (z_min, z_max)):
/// `pdf(x1) = pdf_ω(ω) c / (d1² d2²)`, weight `p(θ) / (pdf_ω(ω) c)`.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Equiangular;

#[pymethods]
impl Equiangular {
    #[new]
    #[pyo3(signature = (x0, x2, phase, theta_max = PI, normal = None, slab = None))]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: &Bound<'_, PyAny>,
        theta_max: f64,
        normal: Option<&Bound<'_, PyAny>>,
        slab: Option<(f64, f64)>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let method = Method::Equiangular;
        let base = technique(method, x0, x2, phase, theta_max, normal, slab, 0.0)?;
        Ok(base.add_subclass(Equiangular))
    }
}

/// Distance sampling (docs/math.md §9): a direction ω from `x2` as for
/// `Equiangular`, then the exponential free-flight distance with
/// coefficient `sigma_t` on the medium segment [t_a, t_b]:
/// `pdf(t) = σ e^{−σ (t − t_a)} / (1 − e^{−σ L})`, `pdf(x1) = pdf_ω(ω) pdf(t) / t²`.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Distance;

#[pymethods]
impl Distance {
    #[new]
    #[pyo3(signature = (x0, x2, phase, sigma_t, theta_max = PI, normal = None, slab = None))]
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
        let method = Method::Distance;
        let base = technique(method, x0, x2, phase, theta_max, normal, slab, sigma_t)?;
        Ok(base.add_subclass(Distance))
    }
}

/// MIS as the CLI's `mis` (docs/math.md §10): OMNEE's vertex from `u[0:3]`
/// always, and when `u3 < c = 0.05` an equiangular companion from
/// `(u3/c, u4, u5)` kept behind the cone θ ≥ 3π/4; balance heuristic
/// there (`pdf = p_O + c p_E`), OMNEE alone in front of it. The estimate is
/// the sum of `f_c · weight` over both vertices of a draw.
#[pyclass(module = "omnee", extends = Technique, frozen)]
pub struct Mis;

#[pymethods]
impl Mis {
    #[new]
    #[pyo3(signature = (x0, x2, phase, theta_max = PI, normal = None, slab = None))]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: &Bound<'_, PyAny>,
        theta_max: f64,
        normal: Option<&Bound<'_, PyAny>>,
        slab: Option<(f64, f64)>,
    ) -> PyResult<PyClassInitializer<Self>> {
        Ok(technique(Method::Mis, x0, x2, phase, theta_max, normal, slab, 0.0)?.add_subclass(Mis))
    }
}
