//! `omnee.Bridge`: bridges of `k` scattering vertices between `x0` and `x2`
//! (the core's [`omnee_core::bridge::Bridge`], docs/math.md §14) over numpy
//! arrays, and `omnee.isotropic_transfer`, the exact `I_k` for isotropic
//! scattering (the core's [`isotropic_transfer`]).

use crate::array::{
    Bad, Floats, check_finite, first_outside, floats, number, rows, shape_text, slice, slice_mut,
    vec3, with_axes, zeros,
};
use crate::chunks::{Items, run};
use crate::error;
use crate::phase::Phase;
use numpy::{Element, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use omnee_core::Real;
use omnee_core::Vector;
use omnee_core::bridge::{self as core_bridge, MAX_VERTICES, isotropic_transfer};
use omnee_render::phase::TableStorage;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Bridges of `k` scattering vertices `x_1 … x_k` from `x0` (light side) to
/// `x2` (receiver side) with the phase function `phase` at every vertex
/// (docs/math.md §14): a chain of `k + 1` edges with deflections drawn from
/// the phase function and edge proportions uniform on the simplex, turned and
/// scaled about `x0` until it ends at `x2`. Its density in the product of
/// volume measures is `s³ k! Π q(θ_i) / (Π d_j² D^{k+1})` (`D` the path's
/// length) and the estimator's weight, the kernel `Π p(θ_i) / Π d_j²` over
/// the density, `(p/q) D^{k+1}/(s³ k!)`; one estimate of
/// `I_k = ∫…∫ Π σs p(θ_i) e^{−σt D} / Π d_j² dx_1 ⋯ dx_k` is
/// `σs^k e^{−σt D} · weight`.
#[pyclass(module = "omnee", frozen)]
#[derive(Clone, Debug)]
pub struct Bridge {
    x0: [f64; 3],
    x2: [f64; 3],
    phase: Phase,
}

/// `k` as the length of the second-to-last axis of `arg`'s `shape`, checked
/// against `1 ..= MAX_VERTICES`; the leading shape.
fn order(arg: &str, shape: &[usize]) -> PyResult<(usize, Vec<usize>)> {
    let lead = rows(arg, shape, 3)?;
    match lead.split_last() {
        Some((&k, rest)) if (1..=MAX_VERTICES).contains(&k) => Ok((k, rest.to_vec())),
        _ => Err(PyValueError::new_err(format!(
            "{arg}: shape {}; allowed: (..., k, 3) with k in [1, {MAX_VERTICES}], three numbers \
             per vertex",
            shape_text(shape)
        ))),
    }
}

impl Bridge {
    /// The core's bridge in precision `F` over `storage`.
    fn core<'a, F: Real>(
        &self,
        storage: &'a mut TableStorage<F>,
    ) -> PyResult<core_bridge::Bridge<F, omnee_core::phase::Phase<'a, F>>> {
        let phase = self.phase.instantiate::<F>(storage)?;
        core_bridge::Bridge::new(vec3::<F>(self.x0), vec3::<F>(self.x2), phase).map_err(|e| {
            PyValueError::new_err(format!(
                "x0/x2: {e} (in {})",
                crate::array::dtype_name::<F>()
            ))
        })
    }

    /// [`sample`](Bridge::sample) in precision `F`.
    fn sample_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArrayDyn<'py, F>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let shape = u.shape().to_vec();
        let (k, lead) = order("u", &shape)?;
        let data = slice(&u);
        if let Some((at, v)) = first_outside(data, F::ZERO, F::ONE) {
            return Err(Bad::Element {
                arg: "u",
                at,
                value: number(v),
                allowed: "[0, 1]",
            }
            .into_err(&shape));
        }
        let mut storage = TableStorage::<F>::default();
        let bridge = self.core::<F>(&mut storage)?;
        let (vertices, pdf, weight, length, valid) = (
            zeros::<F>(py, &with_axes(&lead, &[k, 3])),
            zeros::<F>(py, &lead),
            zeros::<F>(py, &lead),
            zeros::<F>(py, &lead),
            zeros::<bool>(py, &lead),
        );
        {
            let (mut xv, mut pv, mut wv, mut lv, mut vv) = (
                vertices.readwrite(),
                pdf.readwrite(),
                weight.readwrite(),
                length.readwrite(),
                valid.readwrite(),
            );
            let all = (
                Items { data, k: 3 * k },
                (
                    Items {
                        data: slice_mut(&mut xv),
                        k: 3 * k,
                    },
                    Items {
                        data: slice_mut(&mut pv),
                        k: 1,
                    },
                ),
                Items {
                    data: slice_mut(&mut wv),
                    k: 1,
                },
                Items {
                    data: slice_mut(&mut lv),
                    k: 1,
                },
                Items {
                    data: slice_mut(&mut vv),
                    k: 1,
                },
            );
            let bridge = &bridge;
            // The GIL released, on all cores for long arrays; nothing fails.
            let Ok(()) = py.detach(|| {
                run(all, |_, (u, (xs, ps), ws, ls, vs)| {
                    let mut ui = [[F::ZERO; 3]; MAX_VERTICES];
                    let mut x = [bridge.axis.x0; MAX_VERTICES];
                    for (row, numbers) in u.data.chunks_exact(3 * k).enumerate() {
                        for (slot, c) in ui.iter_mut().zip(numbers.chunks_exact(3)) {
                            *slot = [c[0], c[1], c[2]];
                        }
                        if let Some(s) = bridge.sample(&ui[..k], &mut x[..k]) {
                            let out = &mut xs.data[row * 3 * k..(row + 1) * 3 * k];
                            for (o, xj) in out.chunks_exact_mut(3).zip(&x[..k]) {
                                o.copy_from_slice(&xj.to_array());
                            }
                            ps.data[row] = s.pdf;
                            ws.data[row] = s.weight;
                            ls.data[row] = s.length;
                            vs.data[row] = true;
                        }
                    }
                    Ok::<(), std::convert::Infallible>(())
                })
            });
        }
        py.import("omnee")?.getattr("BridgeSamples")?.call1((
            crate::array::result(vertices)?,
            crate::array::result(pdf)?,
            crate::array::result(weight)?,
            crate::array::result(length)?,
            crate::array::result(valid)?,
        ))
    }

    /// [`pdf`](Bridge::pdf) in precision `F`.
    fn pdf_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        vertices: PyReadonlyArrayDyn<'py, F>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let shape = vertices.shape().to_vec();
        let (k, lead) = order("vertices", &shape)?;
        let data = slice(&vertices);
        check_finite("vertices", data, 0).map_err(|e| e.into_err(&shape))?;
        let mut storage = TableStorage::<F>::default();
        let bridge = self.core::<F>(&mut storage)?;
        let out = zeros::<F>(py, &lead);
        {
            let mut ov = out.readwrite();
            let all = (
                Items { data, k: 3 * k },
                Items {
                    data: slice_mut(&mut ov),
                    k: 1,
                },
            );
            let bridge = &bridge;
            let Ok(()) = py.detach(|| {
                run(all, |_, (points, out)| {
                    let mut x = [bridge.axis.x0; MAX_VERTICES];
                    for (slot, row) in out.data.iter_mut().zip(points.data.chunks_exact(3 * k)) {
                        for (xj, c) in x[..k].iter_mut().zip(row.chunks_exact(3)) {
                            *xj = F::Vec3::new(c[0], c[1], c[2]);
                        }
                        *slot = bridge.pdf(&x[..k]);
                    }
                    Ok::<(), std::convert::Infallible>(())
                })
            });
        }
        crate::array::result(out)
    }
}

impl Bridge {
    /// [`invert`](Bridge::invert) in precision `F`.
    fn invert_in<'py, F: Real + Element>(
        &self,
        py: Python<'py>,
        vertices: PyReadonlyArrayDyn<'py, F>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let shape = vertices.shape().to_vec();
        let (k, lead) = order("vertices", &shape)?;
        let data = slice(&vertices);
        check_finite("vertices", data, 0).map_err(|e| e.into_err(&shape))?;
        let mut storage = TableStorage::<F>::default();
        let bridge = self.core::<F>(&mut storage)?;
        let (u, valid) = (zeros::<F>(py, &shape), zeros::<bool>(py, &lead));
        {
            let (mut uv, mut vv) = (u.readwrite(), valid.readwrite());
            let all = (
                Items { data, k: 3 * k },
                Items {
                    data: slice_mut(&mut uv),
                    k: 3 * k,
                },
                Items {
                    data: slice_mut(&mut vv),
                    k: 1,
                },
            );
            let bridge = &bridge;
            let Ok(()) = py.detach(|| {
                run(all, |_, (points, us, vs)| {
                    let mut x = [bridge.axis.x0; MAX_VERTICES];
                    let mut numbers = [[F::ZERO; 3]; MAX_VERTICES];
                    let rows = points.data.chunks_exact(3 * k);
                    let outs = us.data.chunks_exact_mut(3 * k);
                    for ((row, out), ok) in rows.zip(outs).zip(vs.data.iter_mut()) {
                        for (xj, c) in x[..k].iter_mut().zip(row.chunks_exact(3)) {
                            *xj = F::Vec3::new(c[0], c[1], c[2]);
                        }
                        if bridge.invert(&x[..k], &mut numbers[..k]).is_some() {
                            out.copy_from_slice(numbers[..k].as_flattened());
                            *ok = true;
                        }
                    }
                    Ok::<(), std::convert::Infallible>(())
                })
            });
        }
        py.import("omnee")?
            .getattr("Inversion")?
            .call1((crate::array::result(u)?, crate::array::result(valid)?))
    }
}

#[pymethods]
impl Bridge {
    #[new]
    #[pyo3(signature = (*, x0, x2, phase = None), text_signature = "(*, x0, x2, phase=None)")]
    fn new(
        x0: &Bound<'_, PyAny>,
        x2: &Bound<'_, PyAny>,
        phase: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let bridge = Self {
            x0: crate::array::point("x0", x0)?,
            x2: crate::array::point("x2", x2)?,
            phase: match phase {
                Some(p) => crate::technique::phase_arg(p)?,
                None => Phase::parse("iso")?,
            },
        };
        // Refused here in f64 (non-finite or coincident end points); a
        // float32 call checks float32 itself (end points 1e-300 apart are
        // a bridge in f64, and coincide in f32).
        bridge.core::<f64>(&mut TableStorage::default())?;
        Ok(bridge)
    }

    /// Bridges from uniform numbers `u` of shape `(..., k, 3)`, three per
    /// vertex (u_θ, u_φ, u_t) in [0, 1] (else `ValueError`, NaN included),
    /// `k` in [1, 32]. Returns `BridgeSamples(vertices, pdf, weight, length,
    /// valid)`: `vertices` of shape `(..., k, 3)`, the others `(...)`; where
    /// the numbers give no path (`valid` False) everything is 0. float32 in,
    /// f32 computed and float32 out; anything else in f64.
    fn sample<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match floats("u", u)? {
            Floats::F32(a) => self.sample_in::<f32>(py, a),
            Floats::F64(a) => self.sample_in::<f64>(py, a),
        }
    }

    /// The density of `sample` at the paths `x0, vertices[..., 0, :], …,
    /// vertices[..., k-1, :], x2` (`vertices` of shape `(..., k, 3)`, finite),
    /// `s³ k! Π q(θ_i) / (Π d_j² D^{k+1})`; 0 where two consecutive points
    /// coincide.
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        vertices: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        match floats("vertices", vertices)? {
            Floats::F32(a) => self.pdf_in::<f32>(py, a),
            Floats::F64(a) => self.pdf_in::<f64>(py, a),
        }
    }

    /// The uniform numbers that `sample` maps to the paths (`vertices` of
    /// shape `(..., k, 3)`, finite): `Inversion(u, valid)` with `u` of shape
    /// `(..., k, 3)`; `valid` False (and `u` 0) where the map has no inverse
    /// (coincident points, a first deflection of 0 or π, a mixture phase
    /// function).
    fn invert<'py>(
        &self,
        py: Python<'py>,
        vertices: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        match floats("vertices", vertices)? {
            Floats::F32(a) => self.invert_in::<f32>(py, a),
            Floats::F64(a) => self.invert_in::<f64>(py, a),
        }
    }

    /// The light-side end point.
    #[getter]
    fn x0(&self) -> (f64, f64, f64) {
        (self.x0[0], self.x0[1], self.x0[2])
    }

    /// The receiver-side end point.
    #[getter]
    fn x2(&self) -> (f64, f64, f64) {
        (self.x2[0], self.x2[1], self.x2[2])
    }

    /// The phase function at every vertex.
    #[getter]
    fn phase(&self) -> Phase {
        self.phase.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "omnee.Bridge(x0={:?}, x2={:?}, phase={:?})",
            self.x0,
            self.x2,
            self.phase.spec.to_string()
        )
    }
}

/// The exact `k`-times scattered transfer `I_k` for an isotropic phase
/// function in an infinite homogeneous medium, from a unit point light to a
/// point receiver `s` apart (docs/math.md §14.6), by adaptive quadrature of
/// a 1-D integral to about 1e-10. `k` in [1, 32], `s > 0`, `0 ≤ sigma_s ≤
/// sigma_t` finite, `sigma_t > 0` for `k ≥ 2` (else `ValueError`). At most
/// `budget` evaluations of the integrand: a quadrature that spends them
/// raises `omnee.NotConvergedError`. Of its two integrals it takes the one
/// whose signs cancel little; where both would leave fewer than ten digits
/// (dense media: none for σt s up to 20, k = 17 … 28 at 30) it is a
/// `ValueError` naming `k`, never a wrong value.
#[pyfunction]
#[pyo3(name = "isotropic_transfer", signature = (k, *, s, sigma_s, sigma_t, budget = 1_000_000),
       text_signature = "(k, *, s, sigma_s, sigma_t, budget=1000000)")]
pub fn isotropic_transfer_py(
    k: i128,
    s: f64,
    sigma_s: f64,
    sigma_t: f64,
    budget: i128,
) -> PyResult<f64> {
    let k = usize::try_from(k)
        .ok()
        .filter(|k| (1..=MAX_VERTICES).contains(k))
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "k = {k} is out of range; allowed: [1, {MAX_VERTICES}]"
            ))
        })?;
    let budget = usize::try_from(budget)
        .ok()
        .filter(|&b| b >= 1)
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "budget = {budget} is out of range; allowed: [1, 2^64)"
            ))
        })?;
    if !(sigma_t >= sigma_s) {
        return Err(PyValueError::new_err(format!(
            "sigma_t = {sigma_t} is out of range; allowed: [sigma_s, inf) = [{sigma_s}, inf)"
        )));
    }
    isotropic_transfer(k, s, sigma_s, sigma_t, budget).map_err(error::core)
}

/// The number of bridge vertices `k ∈ [1, k_max]` drawn per connection
/// (docs/math.md §14.7): a Poisson distribution of mean
/// `μ = σs s (1 + (1 − |g|) σt s / 2)` truncated to `[1, k_max]`, mixed with
/// the uniform one for the share 0.2, `g` the phase function's mean cosine.
/// Drawing `k`, a bridge of `k` vertices, and dividing its estimate by `P(k)`
/// estimates `Σ_{k=1}^{k_max} I_k` without bias. Computed in f64.
#[pyclass(module = "omnee", frozen)]
#[derive(Clone, Debug)]
pub struct VertexCount {
    count: core_bridge::VertexCount<f64>,
}

#[pymethods]
impl VertexCount {
    #[new]
    #[pyo3(signature = (k_max = 8, *, s, sigma_s, sigma_t, phase = None),
           text_signature = "(k_max=8, *, s, sigma_s, sigma_t, phase=None)")]
    fn new(
        k_max: i128,
        s: f64,
        sigma_s: f64,
        sigma_t: f64,
        phase: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let k_max = usize::try_from(k_max)
            .ok()
            .filter(|k| (1..=MAX_VERTICES).contains(k))
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "k_max = {k_max} is out of range; allowed: [1, {MAX_VERTICES}]"
                ))
            })?;
        let g = match phase {
            Some(p) => crate::technique::phase_arg(p)?.mean_cosine_f64()?,
            None => 0.0,
        };
        let count =
            core_bridge::VertexCount::new(k_max, s, sigma_s, sigma_t, g).map_err(error::core)?;
        Ok(Self { count })
    }

    /// `(k, probability)`: `k` (int64) drawn by inversion from each uniform
    /// number of `u` in [0, 1] (else `ValueError`, NaN included) and `P(k)`
    /// (float64), both of `u`'s shape.
    fn sample<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let u = match floats("u", u)? {
            Floats::F32(a) => a.as_array().mapv(f64::from).into_dyn(),
            Floats::F64(a) => a.as_array().to_owned(),
        };
        let shape = u.shape().to_vec();
        let data: Vec<f64> = u.iter().copied().collect();
        if let Some((at, v)) = first_outside(&data, 0.0, 1.0) {
            return Err(Bad::Element {
                arg: "u",
                at,
                value: number(v),
                allowed: "[0, 1]",
            }
            .into_err(&shape));
        }
        let (k, p) = (zeros::<i64>(py, &shape), zeros::<f64>(py, &shape));
        {
            let (mut kv, mut pv) = (k.readwrite(), p.readwrite());
            for ((ki, pi), &ui) in slice_mut(&mut kv)
                .iter_mut()
                .zip(slice_mut(&mut pv))
                .zip(&data)
            {
                let (kk, pk) = self.count.sample(ui);
                (*ki, *pi) = (kk as i64, pk);
            }
        }
        Ok((crate::array::result(k)?, crate::array::result(p)?))
    }

    /// `P(k)` for each integer of `k` (0 outside `[1, k_max]`); a value
    /// that is not an integer (2.5, NaN, ∞) is a `ValueError` naming it.
    fn pmf<'py>(&self, py: Python<'py>, k: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let np = py.import("numpy")?;
        // Every integer a count can be is exact in float64 (|k| < 2⁵³);
        // larger ones are outside [1, k_max] either way.
        let k = np.getattr("asarray")?.call1((k, "float64"))?;
        let k = k.cast::<numpy::PyArrayDyn<f64>>()?.readonly();
        let shape = k.shape().to_vec();
        let out = zeros::<f64>(py, &shape);
        {
            let mut ov = out.readwrite();
            for (at, (o, &ki)) in slice_mut(&mut ov)
                .iter_mut()
                .zip(k.as_array().iter())
                .enumerate()
            {
                if !(ki.is_finite() && ki == ki.trunc()) {
                    return Err(Bad::Element {
                        arg: "k",
                        at,
                        value: number(ki),
                        allowed: "integers (P(k) = 0 outside [1, k_max])",
                    }
                    .into_err(&shape));
                }
                *o = if (1.0..=MAX_VERTICES as f64).contains(&ki) {
                    self.count.pmf(ki as usize)
                } else {
                    0.0
                };
            }
        }
        crate::array::result(out)
    }

    /// The largest `k`.
    #[getter]
    fn k_max(&self) -> usize {
        self.count.k_max()
    }

    /// The Poisson mean μ before truncation.
    #[getter]
    fn mean(&self) -> f64 {
        self.count.mean()
    }

    fn __repr__(&self) -> String {
        // Not a constructor call (the constructor takes the medium, the
        // repr shows what it made of it): Python's angle-bracket form.
        format!(
            "<omnee.VertexCount k_max={} mean={}>",
            self.count.k_max(),
            self.count.mean()
        )
    }
}
