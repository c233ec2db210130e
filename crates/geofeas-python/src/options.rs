//! Keyword options read into the trackers' described option sets
//! ([`geofeas_tracking::options::OptionSet`]), and the sets' schemas as Python values: the one
//! definition of every option lives in the tracking crate, the bindings only convert.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString, PyTuple};

use super::py_err;
use geofeas::error::Error;
use geofeas_tracking::options::{OptionKind, OptionSet, OptionSpec, OptionValue};

fn bad(name: &'static str, reason: String) -> PyErr {
    py_err(Error::InvalidOption { name, reason })
}

fn shown(obj: &Bound<'_, PyAny>) -> String {
    obj.repr().map_or_else(|_| "?".into(), |r| r.to_string())
}

fn int(name: &'static str, obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    if obj.is_instance_of::<PyBool>() {
        return Err(bad(
            name,
            format!("expected an integer, got {}", shown(obj)),
        ));
    }
    if let Ok(u) = obj.extract::<u64>() {
        return Ok(u);
    }
    match obj.extract::<i64>() {
        Ok(i) => Err(bad(name, format!("must be >= 0, got {i}"))),
        Err(_) => Err(bad(
            name,
            format!("expected an integer, got {}", shown(obj)),
        )),
    }
}

fn float(name: &'static str, obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    if obj.is_instance_of::<PyString>() {
        return Err(bad(name, format!("expected a number, got {}", shown(obj))));
    }
    obj.extract()
        .map_err(|_| bad(name, format!("expected a number, got {}", shown(obj))))
}

fn text(name: &'static str, obj: &Bound<'_, PyAny>) -> PyResult<String> {
    obj.extract()
        .map_err(|_| bad(name, format!("expected a name, got {}", shown(obj))))
}

/// The items of a sequence (not a string), each read by `item`.
fn items<T>(
    name: &'static str,
    obj: &Bound<'_, PyAny>,
    item: impl Fn(&'static str, &Bound<'_, PyAny>) -> PyResult<T>,
) -> PyResult<Vec<T>> {
    let not_seq = || bad(name, format!("expected a sequence, got {}", shown(obj)));
    if obj.is_instance_of::<PyString>() {
        return Err(not_seq());
    }
    obj.try_iter()
        .map_err(|_| not_seq())?
        .map(|x| item(name, &x?))
        .collect()
}

/// The value of `obj` as an option of `spec`'s kind; errors name the option.
fn value_of(spec: &OptionSpec, obj: &Bound<'_, PyAny>) -> PyResult<OptionValue> {
    let name = spec.name;
    Ok(match spec.kind {
        OptionKind::Bool => OptionValue::Bool(
            obj.extract()
                .map_err(|_| bad(name, format!("expected True or False, got {}", shown(obj))))?,
        ),
        OptionKind::Int => OptionValue::Int(int(name, obj)?),
        OptionKind::Float => OptionValue::Float(float(name, obj)?),
        OptionKind::Choice(_) => OptionValue::Text(text(name, obj)?),
        OptionKind::Floats(_) => OptionValue::Floats(items(name, obj, float)?),
        OptionKind::Ints => OptionValue::Ints(items(name, obj, int)?),
        OptionKind::Choices(_) => OptionValue::Texts(items(name, obj, text)?),
        OptionKind::OptionalFloats if obj.is_none() => OptionValue::None,
        OptionKind::OptionalFloats => OptionValue::Floats(items(name, obj, float)?),
    })
}

/// Reads keyword options into two option sets (each keyword belongs to the first set that
/// declares it); an undeclared keyword is refused with the list of the declared ones.
pub(crate) fn read_two<A: OptionSet, B: OptionSet>(
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<(A, B)> {
    let (mut a, mut b) = (A::default(), B::default());
    let (sa, sb) = (A::schema(), B::schema());
    for (k, v) in kwargs.into_iter().flat_map(|d| d.iter()) {
        let key: String = k.extract()?;
        if let Some(s) = sa.iter().find(|s| s.name == key) {
            a.set(&key, value_of(s, &v)?).map_err(py_err)?;
        } else if let Some(s) = sb.iter().find(|s| s.name == key) {
            b.set(&key, value_of(s, &v)?).map_err(py_err)?;
        } else {
            let names: Vec<_> = sa.iter().chain(&sb).map(|s| s.name).collect();
            return Err(bad(
                "options",
                format!(
                    "unexpected keyword '{key}' (expected one of {})",
                    names.join(", ")
                ),
            ));
        }
    }
    Ok((a, b))
}

/// Reads keyword options into one option set.
pub(crate) fn read_one<A: OptionSet>(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<A> {
    Ok(read_two::<A, NoOptions>(kwargs)?.0)
}

/// The empty option set.
#[derive(Default)]
pub(crate) struct NoOptions;

impl OptionSet for NoOptions {
    fn schema() -> Vec<OptionSpec> {
        Vec::new()
    }
    fn set(&mut self, name: &str, _: OptionValue) -> geofeas::Result<()> {
        Err(Error::Invalid(format!("unexpected option '{name}'")))
    }
}

fn value_py<'py>(py: Python<'py>, v: &OptionValue) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        OptionValue::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        OptionValue::Int(i) => i.into_pyobject(py)?.into_any(),
        OptionValue::Float(x) => x.into_pyobject(py)?.into_any(),
        OptionValue::Text(s) => PyString::new(py, s).into_any(),
        OptionValue::Floats(v) => PyTuple::new(py, v)?.into_any(),
        OptionValue::Ints(v) => PyTuple::new(py, v)?.into_any(),
        OptionValue::Texts(v) => PyTuple::new(py, v)?.into_any(),
        OptionValue::None => py.None().into_bound(py),
    })
}

/// The schema of a set as a list of `(name, kind, default, doc, choices)`: `kind` one of
/// `bool`, `int`, `float`, `choice`, `floats`, `ints`, `choices`, `floats or None`; list
/// defaults as tuples; `choices` the accepted names (empty unless a choice).
pub(crate) fn schema_py<'py, A: OptionSet>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let rows = A::schema()
        .iter()
        .map(|s| {
            let (kind, choices): (&str, &[&str]) = match s.kind {
                OptionKind::Bool => ("bool", &[]),
                OptionKind::Int => ("int", &[]),
                OptionKind::Float => ("float", &[]),
                OptionKind::Choice(c) => ("choice", c),
                OptionKind::Floats(_) => ("floats", &[]),
                OptionKind::Ints => ("ints", &[]),
                OptionKind::Choices(c) => ("choices", c),
                OptionKind::OptionalFloats => ("floats or None", &[]),
            };
            PyTuple::new(
                py,
                [
                    PyString::new(py, s.name).into_any(),
                    PyString::new(py, kind).into_any(),
                    value_py(py, &s.default)?,
                    PyString::new(py, s.doc).into_any(),
                    PyTuple::new(py, choices)?.into_any(),
                ],
            )
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, rows)
}
