//! PyO3 bindings: the `geofeas._core` extension module. Thin: arrays in as views, the work done by
//! the core with the GIL released, arrays out without copies, core errors mapped to exceptions.

use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;

mod association;
mod fusion;
mod mht;
mod options;
mod pf;
mod scores;

pyo3::create_exception!(
    geofeas,
    GeofeasError,
    PyValueError,
    "Invalid input or options for a geofeas computation (a ValueError)."
);

/// A core error as a Python exception: a [`GeofeasError`] carrying the message and, as
/// attributes, the argument, row and field at fault (`None` when the error does not concern
/// one); Ctrl-C becomes `KeyboardInterrupt`. A function, not `From<geofeas::Error> for PyErr`:
/// both types are foreign to this crate, and the core has no pyo3.
pub(crate) fn py_err(err: geofeas::Error) -> PyErr {
    if err == geofeas::Error::Interrupted {
        return PyKeyboardInterrupt::new_err("interrupted");
    }
    let py_err = GeofeasError::new_err(err.to_string());
    Python::attach(|py| {
        let value = py_err.value(py);
        // setting an attribute on a fresh exception instance cannot fail
        let _ = value.setattr("argument", err.argument());
        let _ = value.setattr("row", err.row());
        let _ = value.setattr("field", err.field());
        let (rows, reason) = err
            .rows()
            .map_or((None, None), |(r, why)| (Some(r.to_vec()), Some(why)));
        let _ = value.setattr("rows", rows);
        let _ = value.setattr("reason", reason);
    });
    py_err
}

/// The interrupt hook handed to the core's drivers: between chunks, briefly re-take the GIL and
/// let Python handle pending signals (Ctrl-C). Must run on the thread that called into Rust.
pub(crate) fn check_signals() -> bool {
    Python::attach(|py| py.check_signals().is_err())
}

/// A 1-D array as a slice (it must be contiguous); errors name the array.
pub(crate) fn slice<'a, T: numpy::Element>(
    what: &'static str,
    arr: &'a numpy::PyReadonlyArray1<'_, T>,
) -> PyResult<&'a [T]> {
    arr.as_slice()
        .map_err(|e| py_err(geofeas::Error::Invalid(format!("{what}: {e}"))))
}

/// An `(n, 5)` float64 array (ellipses or AOU rows) as its contiguous flat buffer; errors name
/// the array.
pub(crate) fn flat5<'a>(
    what: &'static str,
    arr: &'a numpy::PyReadonlyArray2<'_, f64>,
) -> PyResult<&'a [f64]> {
    use numpy::PyUntypedArrayMethods;
    let shape = arr.shape();
    if shape[1] != 5 {
        return Err(py_err(geofeas::Error::Shape {
            what,
            expected: "(n, 5)".into(),
            got: format!("{shape:?}"),
        }));
    }
    arr.as_slice()
        .map_err(|e| py_err(geofeas::Error::Invalid(format!("{what}: {e}"))))
}

/// Runs `f` with the GIL released, converting a core error into a Python exception.
pub(crate) fn detached<T, F>(py: Python<'_>, f: F) -> PyResult<T>
where
    T: Send,
    F: Send + FnOnce() -> geofeas::Result<T>,
{
    py.detach(f).map_err(py_err)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    let error_type = m.py().get_type::<GeofeasError>();
    for attribute in ["argument", "row", "field"] {
        error_type.setattr(attribute, m.py().None())?;
    }
    m.add("GeofeasError", error_type)?;
    scores::register(m)?;
    mht::register(m)?;
    pf::register(m)?;
    association::register(m)?;
    fusion::register(m)?;
    Ok(())
}
