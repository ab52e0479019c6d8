//! numpy in, numpy out: the dtype rule, shape checks, the caller's arrays
//! read in place, output arrays (new or the caller's `out=`), and the
//! messages that name an element by its index.
//!
//! The dtype rule: a float32 array is computed in f32; float64, integer and
//! bool arrays, Python numbers and sequences in f64 (as numpy.asarray makes
//! them); every other dtype (float16, longdouble, complex, object, strings)
//! is a `TypeError`. Results have the computing precision's dtype.
//!
//! A C-contiguous float32 or float64 array in native byte order is read in
//! place, without a copy, while the GIL is released (as numpy's own
//! functions do, the caller must not write to it from another thread during
//! the call); anything else is converted once by numpy.

use numpy::ndarray::IxDyn;
use numpy::{
    Element, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyReadwriteArrayDyn,
    PyUntypedArrayMethods,
};
use omnee_core::Real;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The caller's numbers in the precision the dtype rule picked, borrowed
/// read-only (in place where the rule allows).
pub enum Floats<'py> {
    /// From a float32 array.
    F32(PyReadonlyArrayDyn<'py, f32>),
    /// From anything else the rule accepts.
    F64(PyReadonlyArrayDyn<'py, f64>),
}

/// Applies the dtype rule to `obj`, naming the argument `arg` in errors.
pub fn floats<'py>(arg: &str, obj: &Bound<'py, PyAny>) -> PyResult<Floats<'py>> {
    if let Some(a) = in_place::<f32>(obj) {
        return Ok(Floats::F32(readonly(arg, &a)?));
    }
    if let Some(a) = in_place::<f64>(obj) {
        return Ok(Floats::F64(readonly(arg, &a)?));
    }
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
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", target)?;
    kwargs.set_item("order", "C")?;
    let array = np.getattr("asarray")?.call((array,), Some(&kwargs))?;
    Ok(if target == "=f4" {
        Floats::F32(readonly(arg, array.cast::<PyArrayDyn<f32>>()?)?)
    } else {
        Floats::F64(readonly(arg, array.cast::<PyArrayDyn<f64>>()?)?)
    })
}

/// `obj` itself if it is a C-contiguous array of `F` in native byte order.
fn in_place<'py, F: Element>(obj: &Bound<'py, PyAny>) -> Option<Bound<'py, PyArrayDyn<F>>> {
    let a = obj.cast::<PyArrayDyn<F>>().ok()?;
    a.is_c_contiguous().then(|| a.clone())
}

/// A read-only borrow of `a` (refused while this call writes to it: an
/// input that overlaps `out=`).
fn readonly<'py, F: Element>(
    arg: &str,
    a: &Bound<'py, PyArrayDyn<F>>,
) -> PyResult<PyReadonlyArrayDyn<'py, F>> {
    a.try_readonly().map_err(|_| {
        PyValueError::new_err(format!(
            "{arg}: overlaps an output array of this call; allowed: an input separate from out"
        ))
    })
}

/// The elements of a borrowed C-contiguous array, in C order.
pub fn slice<'a, F: Element>(a: &'a PyReadonlyArrayDyn<'_, F>) -> &'a [F] {
    // Contiguous by construction (`floats` and `Points` make them so); an
    // empty slice can only come from an empty array.
    a.as_slice().unwrap_or(&[])
}

/// Checks that the last axis of `shape` has length `k` (points or uniform
/// tuples of `k` numbers) and returns the leading shape.
pub fn rows(arg: &str, shape: &[usize], k: usize) -> PyResult<Vec<usize>> {
    match shape.split_last() {
        Some((&last, lead)) if last == k => Ok(lead.to_vec()),
        _ => Err(PyValueError::new_err(format!(
            "{arg}: shape {}; allowed: (..., {k}), the last axis holding {k} numbers",
            shape_text(shape)
        ))),
    }
}

/// `(2, 3)` as numpy prints a shape.
pub fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", join(shape)),
    }
}

/// `2, 3`.
fn join(index: &[usize]) -> String {
    index
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// `shape` with `extra` axes appended.
pub fn with_axes(shape: &[usize], extra: &[usize]) -> Vec<usize> {
    shape.iter().chain(extra).copied().collect()
}

/// `arg[i, j]` for the element at flat position `flat` of an array of
/// `shape` (C order); `arg` alone for a 0-d array.
pub fn element(arg: &str, shape: &[usize], flat: usize) -> String {
    if shape.is_empty() {
        return arg.to_string();
    }
    let mut index = vec![0; shape.len()];
    let mut rest = flat;
    for (i, &n) in shape.iter().enumerate().rev() {
        if n > 0 {
            index[i] = rest % n;
            rest /= n;
        }
    }
    format!("{arg}[{}]", join(&index))
}

/// The first element of `data` outside `[lo, hi]` (NaN included), with its
/// position.
#[inline]
pub fn first_outside<F: Real>(data: &[F], lo: F, hi: F) -> Option<(usize, F)> {
    data.iter()
        .position(|&v| !(v >= lo && v <= hi))
        .map(|i| (i, data[i]))
}

/// The first element of `data` that is not finite, with its position.
#[inline]
pub fn first_non_finite<F: Real>(data: &[F]) -> Option<(usize, F)> {
    data.iter()
        .position(|v| !v.is_finite())
        .map(|i| (i, data[i]))
}

/// Coordinates of `arg` all finite, else an error naming the first other one
/// at its flat position (`offset` plus its index in `data`).
pub fn check_finite<F: Real>(arg: &'static str, data: &[F], offset: usize) -> Result<(), Bad> {
    match first_non_finite(data) {
        Some((i, value)) => Err(Bad::Element {
            arg,
            at: offset + i,
            value: number(value),
            allowed: "finite coordinates",
        }),
        None => Ok(()),
    }
}

/// An element out of its range, found while the GIL was released: its
/// argument, flat position, value and the allowed range, or the core's
/// refusal of a row's parameters.
#[derive(Clone, Debug)]
pub enum Bad {
    /// `arg[index] = value is out of range; allowed: allowed`.
    Element {
        /// The argument.
        arg: &'static str,
        /// The flat position in the argument's array.
        at: usize,
        /// The value found, as [`number`] prints it.
        value: String,
        /// The allowed range, as the message prints it.
        allowed: &'static str,
    },
    /// The core refused the end points or normal of a row.
    Row {
        /// The row.
        row: usize,
        /// The core's error (naming the field).
        error: omnee_core::Error,
        /// The precision in which it was refused.
        precision: &'static str,
    },
}

impl Bad {
    /// The `ValueError`, with the element's index in an array of `shape`.
    pub fn into_err(self, shape: &[usize]) -> PyErr {
        match self {
            Bad::Element {
                arg,
                at,
                value,
                allowed,
            } => PyValueError::new_err(format!(
                "{} = {value} is out of range; allowed: {allowed}",
                element(arg, shape, at)
            )),
            Bad::Row {
                row,
                error,
                precision,
            } => {
                let allowed = match error {
                    omnee_core::Error::NotFinite { .. } => "; allowed: finite coordinates",
                    _ => "",
                };
                PyValueError::new_err(format!("row {row}: {error} (in {precision}){allowed}"))
            }
        }
    }
}

/// `x` as Python prints it: the shortest decimal that reads back in the
/// precision `F` (`1.5`, `-0.0001` from float32 too), `nan`, `inf`.
pub fn number<F: Real>(x: F) -> String {
    let v = x.to_f64();
    if v.is_nan() {
        "nan".into()
    } else if dtype_name::<F>() == "float32" {
        format!("{}", v as f32)
    } else {
        format!("{v}")
    }
}

/// The name of precision `F` as numpy spells its dtype.
pub fn dtype_name<F: Real>() -> &'static str {
    if F::EPSILON.to_f64() < 1e-10 {
        "float64"
    } else {
        "float32"
    }
}

/// A new array of `shape`, zeroed (numpy's calloc: the pages are mapped
/// when first written, by the threads that fill them).
pub fn zeros<'py, T: Element>(py: Python<'py>, shape: &[usize]) -> Bound<'py, PyArrayDyn<T>> {
    PyArrayDyn::<T>::zeros(py, IxDyn(shape), false)
}

/// The caller's output array `obj` (argument `arg`), checked: dtype `T`,
/// `shape`, C-contiguous, writeable.
pub fn out_array<'py, T: Element>(
    arg: &str,
    obj: &Bound<'py, PyAny>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let want = T::get_dtype(obj.py());
    let a = obj.cast::<PyArrayDyn<T>>().map_err(|_| {
        let got = obj
            .getattr("dtype")
            .and_then(|d| d.str().map(|s| s.to_string()))
            .unwrap_or_else(|_| "none (not a numpy array)".into());
        PyTypeError::new_err(format!(
            "{arg}: dtype {got}; allowed: a numpy array of dtype {want}"
        ))
    })?;
    if a.shape() != shape {
        return Err(PyValueError::new_err(format!(
            "{arg}: shape {}; allowed: {}",
            shape_text(a.shape()),
            shape_text(shape)
        )));
    }
    if !a.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "{arg}: not C-contiguous; allowed: a C-contiguous array"
        )));
    }
    Ok(a.clone())
}

/// A writeable borrow of the output `a` (argument `arg`).
pub fn readwrite<'py, T: Element>(
    arg: &str,
    a: &Bound<'py, PyArrayDyn<T>>,
) -> PyResult<PyReadwriteArrayDyn<'py, T>> {
    a.try_readwrite().map_err(|_| {
        PyValueError::new_err(format!(
            "{arg}: read-only, or overlaps another argument of this call; allowed: a \
             writeable array of its own"
        ))
    })
}

/// The elements of a borrowed C-contiguous output array, in C order.
pub fn slice_mut<'a, T: Element>(a: &'a mut PyReadwriteArrayDyn<'_, T>) -> &'a mut [T] {
    // Contiguous: checked by `out_array`, or made by `zeros`.
    a.as_slice_mut().unwrap_or(&mut [])
}

/// A result array as returned: a 0-d array becomes a numpy scalar, as
/// numpy's own functions return for scalar input.
pub fn result<'py, T: Element>(a: Bound<'py, PyArrayDyn<T>>) -> PyResult<Bound<'py, PyAny>> {
    if a.ndim() == 0 {
        a.into_any().get_item(())
    } else {
        Ok(a.into_any())
    }
}

/// The three coordinates of a point argument in f64, as given.
pub fn point(arg: &str, obj: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    let (shape, values): (Vec<usize>, Vec<f64>) = match floats(arg, obj)? {
        Floats::F32(v) => (
            v.shape().to_vec(),
            slice(&v).iter().map(|&x| x.into()).collect(),
        ),
        Floats::F64(v) => (v.shape().to_vec(), slice(&v).to_vec()),
    };
    if shape != [3] {
        return Err(PyValueError::new_err(format!(
            "{arg}: shape {}; allowed: (3,), a point x, y, z",
            shape_text(&shape)
        )));
    }
    if let Some((i, v)) = first_non_finite(&values) {
        return Err(PyValueError::new_err(format!(
            "{arg}[{i}] = {} is out of range; allowed: finite coordinates",
            number(v)
        )));
    }
    Ok([values[0], values[1], values[2]])
}

/// A point in precision `F`.
#[inline]
pub fn vec3<F: Real>(a: [f64; 3]) -> F::Vec3 {
    use omnee_core::Vector;
    F::Vec3::new(F::from_f64(a[0]), F::from_f64(a[1]), F::from_f64(a[2]))
}

/// The bits of `x` with `-0.0` as `0.0`, so that equal values hash alike.
pub fn canonical(x: f64) -> u64 {
    if x == 0.0 { 0 } else { x.to_bits() }
}
