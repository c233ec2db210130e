//! Bindings of the scores (`geofeas::score`) and the ellipse <-> Gaussian conversions.

use numpy::{
    IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use super::{check_signals, detached, py_err};
use geofeas::ellipse::{Ellipse, Gaussian};
use geofeas::error::Error;
use geofeas::score::{broadcast_len, check_cdist_size, Options, Score};

fn ellipses<'a>(what: &'static str, arr: &'a PyReadonlyArray2<'_, f64>) -> PyResult<&'a [Ellipse]> {
    Ellipse::from_flat(super::flat5(what, arr)?).map_err(py_err)
}

/// The options of every score (the core's `Options`), given by keyword; an option left out
/// takes the core's default. Each score reads the options it uses.
#[pyclass(name = "ScoreOptions", module = "geofeas._core", frozen)]
pub struct ScoreOptions(Options);

#[pymethods]
impl ScoreOptions {
    #[new]
    #[pyo3(signature = (*, threshold=None, method=None, vertices=None, samples=None, seed=None, sampler=None))]
    fn new(
        threshold: Option<bool>,
        method: Option<String>,
        vertices: Option<usize>,
        samples: Option<usize>,
        seed: Option<u64>,
        sampler: Option<String>,
    ) -> Self {
        let d = Options::default();
        Self(Options {
            threshold: threshold.unwrap_or(d.threshold),
            method: method.unwrap_or(d.method),
            vertices: vertices.unwrap_or(d.vertices),
            samples: samples.unwrap_or(d.samples),
            seed: seed.unwrap_or(d.seed),
            sampler: sampler.unwrap_or(d.sampler),
        })
    }

    fn __repr__(&self) -> String {
        let o = &self.0;
        format!(
            "ScoreOptions(threshold={}, method={:?}, vertices={}, samples={}, seed={}, sampler={:?})",
            if o.threshold { "True" } else { "False" },
            o.method,
            o.vertices,
            o.samples,
            o.seed,
            o.sampler
        )
    }
}

/// The score called `score` with `options` (the defaults when `None`).
fn spec(score: &str, options: Option<PyRef<'_, ScoreOptions>>) -> PyResult<Score> {
    Ok(match options {
        Some(o) => Score::from_name(score, &o.0).map_err(py_err)?,
        None => Score::from_name(score, &Options::default()).map_err(py_err)?,
    })
}

/// Elementwise scores of `a[k]` and `b[k]` (a length-1 side broadcasts).
#[pyfunction]
#[pyo3(signature = (a, b, score, options=None))]
fn score_pairs<'py>(
    py: Python<'py>,
    a: PyReadonlyArray2<'py, f64>,
    b: PyReadonlyArray2<'py, f64>,
    score: &str,
    options: Option<PyRef<'py, ScoreOptions>>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let spec = spec(score, options)?;
    let (ea, eb) = (ellipses("a", &a)?, ellipses("b", &b)?);
    let n = broadcast_len(ea.len(), eb.len()).map_err(py_err)?;
    let out = detached(py, || {
        let mut out = vec![0.0; n];
        spec.pairs(ea, eb, &mut out, &mut check_signals)?;
        Ok(out)
    })?;
    Ok(out.into_pyarray(py))
}

/// All-pairs scores, `(n, 5) x (m, 5) -> (n, m)`, refused above `max_bytes` of output.
#[pyfunction]
#[pyo3(signature = (a, b, score, options=None, *, max_bytes))]
fn score_cdist<'py>(
    py: Python<'py>,
    a: PyReadonlyArray2<'py, f64>,
    b: PyReadonlyArray2<'py, f64>,
    score: &str,
    options: Option<PyRef<'py, ScoreOptions>>,
    max_bytes: u128,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = spec(score, options)?;
    let (ea, eb) = (ellipses("a", &a)?, ellipses("b", &b)?);
    let (n, m) = (ea.len(), eb.len());
    check_cdist_size(n, m, max_bytes).map_err(py_err)?;
    let out = detached(py, || {
        let mut out = vec![0.0; n * m];
        spec.cdist(ea, eb, &mut out, &mut check_signals)?;
        Ok(out)
    })?;
    Ok(out.into_pyarray(py).reshape([n, m])?.into_any())
}

/// `(n, 5)` ellipses -> `(n, 2)` means and `(n, 2, 2)` covariances (eqs. 56-59).
#[pyfunction]
fn to_gaussian<'py>(
    py: Python<'py>,
    e: PyReadonlyArray2<'py, f64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let ee = ellipses("e", &e)?;
    let n = ee.len();
    let (mean, cov) = detached(py, || {
        let mut mean = Vec::with_capacity(2 * n);
        let mut cov = Vec::with_capacity(4 * n);
        for (row, e) in ee.iter().enumerate() {
            let g = e
                .validated(row)
                .map_err(|e| e.in_argument("e"))?
                .to_gaussian();
            mean.extend_from_slice(&g.mean);
            cov.extend_from_slice(&[g.cov[0], g.cov[1], g.cov[1], g.cov[2]]);
        }
        Ok((mean, cov))
    })?;
    Ok((
        mean.into_pyarray(py).reshape([n, 2])?.into_any(),
        cov.into_pyarray(py).reshape([n, 2, 2])?.into_any(),
    ))
}

/// `(n, 2)` means and `(n, 2, 2)` covariances -> `(n, 5)` ellipses.
#[pyfunction]
fn from_gaussian<'py>(
    py: Python<'py>,
    mean: PyReadonlyArray2<'py, f64>,
    cov: PyReadonlyArray3<'py, f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let (ms, cs) = (mean.shape(), cov.shape());
    if ms[1] != 2 || cs[1] != 2 || cs[2] != 2 || ms[0] != cs[0] {
        return Err(py_err(Error::Shape {
            what: "mean, cov",
            expected: "(n, 2) and (n, 2, 2)".into(),
            got: format!("{ms:?} and {cs:?}"),
        }));
    }
    let m = mean
        .as_slice()
        .map_err(|e| Error::Invalid(format!("mean: {e}")))
        .map_err(py_err)?;
    let c = cov
        .as_slice()
        .map_err(|e| Error::Invalid(format!("cov: {e}")))
        .map_err(py_err)?;
    let n = ms[0];
    let out = detached(py, || {
        let mut out = Vec::with_capacity(5 * n);
        for row in 0..n {
            let cc = &c[4 * row..4 * row + 4];
            let scale = cc[1]
                .abs()
                .max(cc[2].abs())
                .max(cc[0].abs())
                .max(cc[3].abs());
            if (cc[1] - cc[2]).abs() > 1e-12 * scale {
                return Err(Error::NotPositiveDefinite {
                    row,
                    reason: format!(
                        "not symmetric: cov[0, 1] = {} != cov[1, 0] = {}",
                        cc[1], cc[2]
                    ),
                }
                .in_argument("cov"));
            }
            let g = Gaussian::new(
                [m[2 * row], m[2 * row + 1]],
                [cc[0], 0.5 * (cc[1] + cc[2]), cc[3]],
            )
            .validated(row)
            .map_err(|e| {
                let argument = if e.field().is_some_and(|f| f.starts_with("mean")) {
                    "mean"
                } else {
                    "cov"
                };
                e.in_argument(argument)
            })?;
            out.extend_from_slice(&g.to_ellipse().to_row());
        }
        Ok(out)
    })?;
    Ok(out.into_pyarray(py).reshape([n, 5])?.into_any())
}

/// Validates `(n, 5)` ellipses, raising on the first bad row.
#[pyfunction]
fn validate_ellipses(py: Python<'_>, e: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
    let ee = ellipses("e", &e)?;
    detached(py, || {
        geofeas::score::validate(ee).map_err(|e| e.in_argument("e"))
    })
}

/// The documented polygon-overlap error bound for `vertices` and area ratio `A_max / A_min`.
#[pyfunction]
fn polygon_error_bound(vertices: usize, ratio: f64) -> f64 {
    geofeas::score::Polygon::new(vertices).error_bound(ratio)
}

/// Elementwise intersection areas of `a[k]` and `b[k]` (a length-1 side broadcasts).
#[pyfunction]
fn intersection_area<'py>(
    py: Python<'py>,
    a: PyReadonlyArray2<'py, f64>,
    b: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (ea, eb) = (ellipses("a", &a)?, ellipses("b", &b)?);
    let n = broadcast_len(ea.len(), eb.len()).map_err(py_err)?;
    let out = detached(py, || {
        let mut out = vec![0.0; n];
        geofeas::score::score_pairs(
            &geofeas::score::IntersectionArea,
            ea,
            eb,
            &mut out,
            &mut check_signals,
        )?;
        Ok(out)
    })?;
    Ok(out.into_pyarray(py))
}

/// The names of the scores (`geofeas::score::schema::score_names`).
#[pyfunction]
fn score_names() -> Vec<&'static str> {
    geofeas::score::schema::score_names()
}

/// The options of the scores, defined once in the core (`geofeas::score::schema`): a list of dicts
/// `name`, `default`, `kind`, `choices`, `range` (`(min, max)` or `None`), `help`, `scores`.
#[pyfunction]
fn score_options(py: Python<'_>) -> PyResult<Vec<Bound<'_, pyo3::types::PyDict>>> {
    use geofeas::score::schema::{options, Value};
    options()
        .into_iter()
        .map(|o| {
            let d = pyo3::types::PyDict::new(py);
            d.set_item("name", o.name)?;
            d.set_item("kind", o.default.kind())?;
            match o.default {
                Value::Bool(v) => d.set_item("default", v)?,
                Value::Int(v) => d.set_item("default", v)?,
                Value::Text(v) => d.set_item("default", v)?,
            }
            d.set_item("choices", o.choices)?;
            d.set_item("range", o.range)?;
            d.set_item("help", o.help)?;
            d.set_item("scores", o.scores)?;
            Ok(d)
        })
        .collect()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<ScoreOptions>()?;
    m.add_function(wrap_pyfunction!(score_names, m)?)?;
    m.add_function(wrap_pyfunction!(score_options, m)?)?;
    m.add_function(wrap_pyfunction!(intersection_area, m)?)?;
    m.add_function(wrap_pyfunction!(score_pairs, m)?)?;
    m.add_function(wrap_pyfunction!(score_cdist, m)?)?;
    m.add_function(wrap_pyfunction!(to_gaussian, m)?)?;
    m.add_function(wrap_pyfunction!(from_gaussian, m)?)?;
    m.add_function(wrap_pyfunction!(validate_ellipses, m)?)?;
    m.add_function(wrap_pyfunction!(polygon_error_bound, m)?)?;
    Ok(())
}
