//! Bindings for distributed association (`geofeas.dask`): the global triage and grouping step
//! (`crate::association::assign::group`) on pairs scored elsewhere, e.g. tile by tile.

use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::association::assign::{self, TrackInfo};
use crate::error::Error;

fn slice<'a, T: numpy::Element>(
    what: &'static str,
    arr: &'a PyReadonlyArray1<'_, T>,
) -> PyResult<&'a [T]> {
    Ok(arr
        .as_slice()
        .map_err(|e| Error::Invalid(format!("{what}: {e}")))?)
}

/// Classes (`0` match, `1` borderline, `2` non-match) of the pairs `(a, b)` with `score`, and
/// the object of every track, from the tracks' sources and time spans: the same triage and
/// grouping as the last step of `associate`.
#[pyfunction]
#[pyo3(signature = (source, start, end, a, b, score, *, lower, upper))]
#[allow(clippy::too_many_arguments)]
fn association_group<'py>(
    py: Python<'py>,
    source: PyReadonlyArray1<'py, u32>,
    start: PyReadonlyArray1<'py, f64>,
    end: PyReadonlyArray1<'py, f64>,
    a: PyReadonlyArray1<'py, u32>,
    b: PyReadonlyArray1<'py, u32>,
    score: PyReadonlyArray1<'py, f64>,
    lower: f64,
    upper: f64,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let (src, t0, t1) = (
        slice("source", &source)?,
        slice("start", &start)?,
        slice("end", &end)?,
    );
    let (sa, sb, ss) = (slice("a", &a)?, slice("b", &b)?, slice("score", &score)?);
    if t0.len() != src.len() || t1.len() != src.len() {
        return Err(
            Error::Invalid("source, start and end must have the same length".into()).into(),
        );
    }
    if sb.len() != sa.len() || ss.len() != sa.len() {
        return Err(Error::Invalid("a, b and score must have the same length".into()).into());
    }
    let n = src.len();
    for (row, (&x, &y)) in sa.iter().zip(sb).enumerate() {
        if x as usize >= n || y as usize >= n || x == y {
            return Err(Error::Invalid(format!(
                "pair row {row}: tracks ({x}, {y}) must be two distinct indices in 0..{n}"
            ))
            .into());
        }
    }
    if !(0.0..=1.0).contains(&lower) || !(lower..=1.0).contains(&upper) {
        return Err(Error::Invalid(format!(
            "lower, upper must satisfy 0 <= lower <= upper <= 1, got {lower}, {upper}"
        ))
        .into());
    }
    let tracks: Vec<TrackInfo> = (0..n)
        .map(|t| TrackInfo {
            source: src[t],
            start: t0[t],
            end: t1[t],
        })
        .collect();
    let pairs: Vec<(u32, u32)> = sa.iter().copied().zip(sb.iter().copied()).collect();
    let (class, object) = py.detach(|| assign::group(&tracks, &pairs, ss, lower, upper));
    let class: Vec<u8> = class.iter().map(|&c| c as u8).collect();
    Ok((
        class.into_pyarray(py).into_any(),
        object.into_pyarray(py).into_any(),
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(association_group, m)?)?;
    Ok(())
}
