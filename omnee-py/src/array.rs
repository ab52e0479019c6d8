//! numpy in, numpy out: the dtype rule, shape checks, and the copy of the
//! caller's array that the samplers read while the GIL is released.
//!
//! The dtype rule: a float32 array is computed in f32; float64, integer and
//! bool arrays, Python numbers and sequences in f64 (as numpy.asarray makes
//! them); every other dtype (float16, longdouble, complex, object, strings)
//! is a `TypeError`. Results have the computing precision's dtype.

use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{Element, IntoPyArray, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use omnee_core::{Real, Vector};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// The caller's numbers, copied, in the precision the dtype rule picked.
pub enum Floats {
    /// From a float32 array.
    F32(Values<f32>),
    /// From anything else the rule accepts.
    F64(Values<f64>),
}

/// An owned copy of an array in C order with its shape.
pub struct Values<F> {
    /// The shape the caller passed.
    pub shape: Vec<usize>,
    /// The elements in C order.
    pub data: Vec<F>,
}

/// Applies the dtype rule to `obj`, naming the argument `arg` in errors,
/// and copies the numbers (so that other Python threads may write to the
/// caller's array while the GIL is released).
pub fn floats(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<Floats> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let array = np.getattr("asarray")?.call1((obj,))?;
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let itemsize: usize = dtype.getattr("itemsize")?.extract()?;
    let target = match (kind.as_str(), itemsize) {
        ("f", 4) => "=f4",
        ("f", 8) | ("i" | "u" | "b", _) => "=f8",
        _ => {
            return Err(PyTypeError::new_err(format!(
                "{arg}: dtype {} is not supported; allowed: float32 (computed in f32), float64, \
                 integers or bool (computed in f64)",
                dtype.str()?
            )));
        }
    };
    let array = array.call_method1("astype", (target,))?;
    Ok(if target == "=f4" {
        Floats::F32(copy(array.cast::<PyArrayDyn<f32>>()?)?)
    } else {
        Floats::F64(copy(array.cast::<PyArrayDyn<f64>>()?)?)
    })
}

fn copy<F: Element + Copy>(array: &Bound<'_, PyArrayDyn<F>>) -> PyResult<Values<F>> {
    let shape = array.shape().to_vec();
    let readonly = array
        .try_readonly()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let data = readonly.as_array().iter().copied().collect();
    Ok(Values { shape, data })
}

impl<F: Copy> Values<F> {
    /// Checks that the last axis has length `k` (points or uniform tuples of
    /// `k` numbers) and returns the leading shape.
    pub fn rows(&self, arg: &str, k: usize) -> PyResult<Vec<usize>> {
        match self.shape.split_last() {
            Some((&last, lead)) if last == k => Ok(lead.to_vec()),
            _ => Err(PyValueError::new_err(format!(
                "{arg}: shape {}; allowed: (..., {k}), the last axis holding {k} numbers",
                shape_text(&self.shape)
            ))),
        }
    }
}

/// `(2, 3)` as numpy prints a shape.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// A numpy array of `shape` from elements in C order; a 0-d result becomes
/// a numpy scalar, as numpy's own functions return for scalar input.
pub fn output<'py, T: Element>(
    py: Python<'py>,
    shape: Vec<usize>,
    data: Vec<T>,
) -> PyResult<Bound<'py, PyAny>> {
    let scalar = shape.is_empty();
    let array = ArrayD::from_shape_vec(IxDyn(&shape), data)
        .map_err(|e| PyValueError::new_err(e.to_string()))?
        .into_pyarray(py)
        .into_any();
    if scalar {
        array.get_item(())
    } else {
        Ok(array)
    }
}

/// `shape` with `extra` axes appended.
pub fn with_axes(shape: &[usize], extra: &[usize]) -> Vec<usize> {
    shape.iter().chain(extra).copied().collect()
}

/// The three coordinates of a point argument in f64, as given.
pub fn point(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    let values = match floats(arg, obj)? {
        Floats::F32(v) => Values {
            shape: v.shape,
            data: v.data.into_iter().map(f64::from).collect(),
        },
        Floats::F64(v) => v,
    };
    if values.shape != [3] {
        return Err(PyValueError::new_err(format!(
            "{arg}: shape {}; allowed: (3,), a point x, y, z",
            shape_text(&values.shape)
        )));
    }
    Ok([values.data[0], values.data[1], values.data[2]])
}

/// A point in precision `F`.
pub fn vec3<F: Real>(a: [f64; 3]) -> F::Vec3 {
    F::Vec3::new(F::from_f64(a[0]), F::from_f64(a[1]), F::from_f64(a[2]))
}

/// The coordinates of a point in precision `F`.
pub fn coords<F: Real>(v: F::Vec3) -> [F; 3] {
    v.to_array()
}
