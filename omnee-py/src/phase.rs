//! `omnee.Phase`: a phase function from its spec string, evaluated and
//! sampled elementwise over arrays of deflections θ or uniform numbers u.

use crate::array::{Floats, Values, floats, output};
use crate::error;
use omnee_core::Real;
use omnee_core::phase::{Deflection, Phase as CorePhase, PhaseFunction};
use omnee_render::phase::{PhaseSpec, TableStorage};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::prelude::*;

/// Inputs at least this long are split over rayon's threads.
pub const PARALLEL_MIN: usize = 1 << 14;

/// A phase function p(θ) of the deflection θ ∈ [0, π] between the incoming
/// and the outgoing propagation direction (θ = 0: straight on), normalised
/// over the sphere: `2π ∫₀^π p(θ) sin θ dθ = 1`.
///
/// `spec` is one of `iso`, `hg:G`, `tthg:G1,G2,W`, `ff:B,N`, `draine:G,ALPHA`,
/// `mie:DIAMETER_UM`, `rayleigh`, `table:FILE.csv` (see `omnee estimate --help`).
/// Every method works elementwise on arrays of any shape: float32 in, float32
/// out; float64 (or integers, or Python numbers) in, float64 out.
#[pyclass(module = "omnee", frozen)]
#[derive(Clone, Debug)]
pub struct Phase {
    pub(crate) spec: PhaseSpec,
}

/// What to compute per element.
#[derive(Clone, Copy)]
enum Op {
    Eval,
    Sample,
    Cdf,
    Invert,
}

impl Op {
    fn apply<F: Real>(self, p: &CorePhase<'_, F>, x: F) -> F {
        match self {
            Op::Eval => p.eval(Deflection::from_theta(x)),
            Op::Sample => p.sample(x).theta,
            Op::Cdf => p.cdf(Deflection::from_theta(x)),
            // Only mixtures (no sample-invertible map) give None; rejected
            // before the loop.
            Op::Invert => p
                .invert(Deflection::from_theta(x))
                .unwrap_or(F::from_f64(f64::NAN)),
        }
    }
}

impl Phase {
    /// The phase function from `spec`, as `omnee estimate --phase` takes it.
    pub fn parse(spec: &str) -> PyResult<Self> {
        Ok(Self {
            spec: PhaseSpec::parse(spec).map_err(error::render)?,
        })
    }

    /// `op` over every element of `x`, in the precision of its dtype.
    fn map<'py>(
        &self,
        py: Python<'py>,
        arg: &str,
        x: &Bound<'py, PyAny>,
        op: Op,
    ) -> PyResult<Bound<'py, PyAny>> {
        match floats(arg, x)? {
            Floats::F32(v) => self.map_in(py, v, op),
            Floats::F64(v) => self.map_in(py, v, op),
        }
    }

    fn map_in<'py, F: Real + numpy::Element>(
        &self,
        py: Python<'py>,
        x: Values<F>,
        op: Op,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut storage = TableStorage::<F>::default();
        let phase = self
            .spec
            .instantiate::<F>(&mut storage)
            .map_err(error::render)?;
        if matches!(op, Op::Invert) && phase.invert(Deflection::from_theta(F::ONE)).is_none() {
            return Err(PyValueError::new_err(format!(
                "invert: the sampler of {} is not invertible (a mixture picks its lobe with u); \
                 cdf(theta) is its distribution function",
                self.spec
            )));
        }
        let phase = &phase;
        let data = py.detach(|| {
            if x.data.len() >= PARALLEL_MIN {
                x.data.par_iter().map(|&v| op.apply(phase, v)).collect()
            } else {
                x.data.iter().map(|&v| op.apply(phase, v)).collect()
            }
        });
        output(py, x.shape, data)
    }

    /// `g = ⟨cos θ⟩` in f64.
    pub fn mean_cosine_f64(&self) -> PyResult<f64> {
        let mut storage = TableStorage::<f64>::default();
        Ok(self.instantiate::<f64>(&mut storage)?.mean_cosine())
    }

    /// The phase function in precision `F`, borrowing `storage` for a table.
    pub fn instantiate<'a, F: Real>(
        &self,
        storage: &'a mut TableStorage<F>,
    ) -> PyResult<CorePhase<'a, F>> {
        self.spec.instantiate::<F>(storage).map_err(error::render)
    }
}

#[pymethods]
impl Phase {
    #[new]
    fn new(spec: &str) -> PyResult<Self> {
        Self::parse(spec)
    }

    /// p(θ) per steradian.
    fn eval<'py>(&self, py: Python<'py>, theta: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, "theta", theta, Op::Eval)
    }

    /// θ = P⁻¹(u): the deflection drawn from the uniform number u ∈ [0, 1),
    /// with solid-angle density `pdf(θ)` (u is clamped to [0, 1], NaN to 0).
    fn sample<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, "u", u, Op::Sample)
    }

    /// The solid-angle density of `sample` at θ; equal to `eval(θ)` (every
    /// phase function here is sampled exactly).
    fn pdf<'py>(&self, py: Python<'py>, theta: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, "theta", theta, Op::Eval)
    }

    /// `P(Θ ≤ θ) = 2π ∫₀^θ p(θ') sin θ' dθ'`.
    fn cdf<'py>(&self, py: Python<'py>, theta: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, "theta", theta, Op::Cdf)
    }

    /// The u with `sample(u) = θ` (`cdf(θ)` for inverse-CDF samplers).
    /// Raises ValueError for mixtures (tthg, mie), which pick a lobe with u.
    fn invert<'py>(
        &self,
        py: Python<'py>,
        theta: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, "theta", theta, Op::Invert)
    }

    /// `g = ⟨cos θ⟩ = 2π ∫₀^π p(θ) cos θ sin θ dθ` (in f64).
    fn mean_cosine(&self) -> PyResult<f64> {
        self.mean_cosine_f64()
    }

    /// `B = P(Θ > π/2)`, the fraction scattered backwards (in f64).
    fn backscatter_fraction(&self) -> PyResult<f64> {
        let mut storage = TableStorage::<f64>::default();
        Ok(self
            .instantiate::<f64>(&mut storage)?
            .backscatter_fraction())
    }

    /// The spec string, as given (trimmed).
    #[getter]
    fn spec(&self) -> String {
        self.spec.to_string()
    }

    fn __repr__(&self) -> String {
        format!("omnee.Phase({:?})", self.spec.to_string())
    }

    fn __getnewargs__(&self) -> (String,) {
        (self.spec.to_string(),)
    }
}
