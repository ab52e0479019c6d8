//! `omnee.Phase`: a phase function from its spec string, evaluated and
//! sampled elementwise over arrays of deflections θ or uniform numbers u.

use crate::array::{
    Bad, Floats, canonical, first_outside, floats, number, result, slice, slice_mut, zeros,
};
use crate::chunks::{Items, run};
use crate::error;
use numpy::{Element, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use omnee_core::Real;
use omnee_core::phase::{Deflection, Phase as CorePhase, PhaseFunction};
use omnee_render::phase::{PhaseSpec, TableStorage};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::hash::{Hash, Hasher};

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
            Op::Invert => p.invert(Deflection::from_theta(x)).unwrap_or(F::ZERO),
        }
    }

    /// The argument's name, its allowed range `[0, hi]` in precision `F`
    /// (π rounded up counts as π), and the range as printed.
    fn domain<F: Real>(self) -> (&'static str, F, &'static str) {
        match self {
            Op::Sample => ("u", F::ONE, "[0, 1]"),
            _ => {
                let pi = F::PI.max(F::from_f64(std::f64::consts::PI));
                ("theta", pi, "[0, pi]")
            }
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
        x: &Bound<'py, PyAny>,
        op: Op,
    ) -> PyResult<Bound<'py, PyAny>> {
        let arg = op.domain::<f64>().0;
        match floats(arg, x)? {
            Floats::F32(v) => self.map_in(py, v, op),
            Floats::F64(v) => self.map_in(py, v, op),
        }
    }

    fn map_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArrayDyn<'py, F>,
        op: Op,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut storage = TableStorage::<F>::default();
        let phase = self.instantiate::<F>(&mut storage)?;
        if matches!(op, Op::Invert) && phase.invert(Deflection::from_theta(F::ONE)).is_none() {
            return Err(PyValueError::new_err(format!(
                "invert: the sampler of {} is not invertible (a mixture picks its lobe with u); \
                 cdf(theta) is its distribution function",
                self.spec
            )));
        }
        let (arg, hi, allowed) = op.domain::<F>();
        let out = zeros::<F>(py, x.shape());
        {
            let mut guard = out.readwrite();
            let all = (
                Items {
                    data: slice(&x),
                    k: 1,
                },
                Items {
                    data: slice_mut(&mut guard),
                    k: 1,
                },
            );
            let phase = &phase;
            py.detach(|| {
                run(all, |start, (x, out)| {
                    if let Some((i, value)) = first_outside(x.data, F::ZERO, hi) {
                        let value = number(value);
                        return Err(Bad::Element {
                            arg,
                            at: start + i,
                            value,
                            allowed,
                        });
                    }
                    for (y, &v) in out.data.iter_mut().zip(x.data) {
                        *y = op.apply(phase, v);
                    }
                    Ok(())
                })
            })
            .map_err(|bad| bad.into_err(x.shape()))?;
        }
        result(out)
    }

    /// Equal phase functions: the same kind with the same parameters (a
    /// table: the same bins and values), compared in f64.
    pub fn equals(&self, other: &Phase) -> PyResult<bool> {
        let (mut a, mut b) = (TableStorage::default(), TableStorage::default());
        Ok(self.instantiate::<f64>(&mut a)? == other.instantiate::<f64>(&mut b)?)
    }

    /// A hash of what [`Phase::equals`] compares: the kind, `g` and `B`
    /// (equal phase functions have equal moments).
    pub fn hash_value(&self) -> PyResult<u64> {
        let mut storage = TableStorage::<f64>::default();
        let p = self.instantiate::<f64>(&mut storage)?;
        let mut h = std::collections::hash_map::DefaultHasher::new();
        std::mem::discriminant(&p).hash(&mut h);
        canonical(p.mean_cosine()).hash(&mut h);
        canonical(p.backscatter_fraction()).hash(&mut h);
        Ok(h.finish())
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

    /// p(θ) per steradian, θ ∈ [0, π] (else `ValueError`, NaN included).
    fn eval<'py>(&self, py: Python<'py>, theta: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, theta, Op::Eval)
    }

    /// θ = P⁻¹(u): the deflection drawn from the uniform number u ∈ [0, 1]
    /// (else `ValueError`, NaN included), with solid-angle density `pdf(θ)`.
    fn sample<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, u, Op::Sample)
    }

    /// The solid-angle density of `sample` at θ ∈ [0, π]; equal to
    /// `eval(θ)` (every phase function here is sampled exactly).
    fn pdf<'py>(&self, py: Python<'py>, theta: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, theta, Op::Eval)
    }

    /// `P(Θ ≤ θ) = 2π ∫₀^θ p(θ') sin θ' dθ'`, θ ∈ [0, π].
    fn cdf<'py>(&self, py: Python<'py>, theta: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, theta, Op::Cdf)
    }

    /// The u with `sample(u) = θ` (`cdf(θ)` for inverse-CDF samplers),
    /// θ ∈ [0, π].
    /// Raises ValueError for mixtures (tthg, mie), which pick a lobe with u.
    fn invert<'py>(
        &self,
        py: Python<'py>,
        theta: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.map(py, theta, Op::Invert)
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

    /// A measured phase function from arrays (as Mitsuba's `tabphase`
    /// holds one): `theta`, the `n + 1` bin edges in radians, strictly
    /// increasing from 0 to π, and `values`, the `n` bin values (≥ 0, not
    /// all 0), the density constant per solid angle within each bin:
    /// `p(θ) = v_i / (2π Σ_j v_j (cos θ_j − cos θ_{j+1}))` on bin `i`. Its
    /// `spec` is `table`.
    #[staticmethod]
    fn table(theta: Vec<f64>, values: Vec<f64>) -> PyResult<Self> {
        Ok(Self {
            spec: PhaseSpec::table(theta, values).map_err(error::render)?,
        })
    }

    /// Pickles by value: the spec, or a table's bins.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let class = py.get_type::<Phase>();
        match self
            .spec
            .bins()
            .filter(|_| self.spec.to_string() == "table")
        {
            Some((theta, values)) => PyTuple::new(
                py,
                [
                    class.getattr("table")?,
                    (theta, values).into_pyobject(py)?.into_any(),
                ],
            ),
            None => PyTuple::new(
                py,
                [
                    class.into_any(),
                    (self.spec.to_string(),).into_pyobject(py)?.into_any(),
                ],
            ),
        }
    }

    /// Equal by value: the same kind of phase function with the same
    /// parameters (`Phase("hg:0.9") == Phase(" hg:0.90")`).
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> PyResult<bool> {
        match other.cast::<Phase>() {
            Ok(o) => self.equals(o.get()),
            Err(_) => Ok(false),
        }
    }

    /// A hash of the values `==` compares.
    fn __hash__(&self) -> PyResult<u64> {
        self.hash_value()
    }
}
