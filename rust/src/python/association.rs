//! Bindings of the association pipeline (`crate::association`).

use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::{check_signals, detached, slice};
use crate::association::{
    self, assign, candidates, Alignment, Combine, Coords, IndexOptions, Options, Reports,
};
use crate::error::Error;
use crate::score::{self, Score};

/// The `(n, 5)` AOU rows, as `Reports::new` takes them.
fn rows5(arr: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; 5]>> {
    Ok(super::flat5("aou", arr)?
        .chunks_exact(5)
        .map(|c| [c[0], c[1], c[2], c[3], c[4]])
        .collect())
}

pub(super) fn reports(
    track: &PyReadonlyArray1<'_, u32>,
    source: &PyReadonlyArray1<'_, u32>,
    time: &PyReadonlyArray1<'_, f64>,
    aou: &PyReadonlyArray2<'_, f64>,
    n_tracks: usize,
    geographic: bool,
) -> PyResult<Reports> {
    let coords = if geographic {
        Coords::Geographic
    } else {
        Coords::Planar
    };
    Ok(Reports::new(
        coords,
        n_tracks,
        slice("track", track)?,
        slice("source", source)?,
        slice("time", time)?,
        &rows5(aou)?,
    )?)
}

#[allow(clippy::too_many_arguments)]
pub(super) fn options(
    score: &str,
    combine: &str,
    lower: f64,
    upper: Option<f64>,
    max_gap: f64,
    horizon: f64,
    process_noise: f64,
    same_source: bool,
    correlation_time: f64,
    window: f64,
    threshold: bool,
    method: &str,
    vertices: usize,
    samples: usize,
    seed: u64,
    sampler: &str,
    inflation: Option<f64>,
    margin: Option<f64>,
) -> PyResult<Options> {
    let spec = Score::from_name(
        score,
        &score::Options {
            threshold,
            method: method.to_string(),
            vertices,
            samples,
            seed,
            sampler: sampler.to_string(),
        },
    )?;
    Ok(Options {
        score: spec,
        combine: Combine::from_name(combine)?,
        lower,
        upper: upper.unwrap_or_else(association::combine::default_upper),
        align: Alignment {
            max_gap,
            horizon,
            process_noise,
        },
        correlation_time,
        index: IndexOptions {
            window,
            same_source,
        },
        inflation,
        margin,
    }
    .validated()?)
}

/// The whole pipeline on dense track / source ids; returns a dict of arrays.
#[pyfunction]
#[pyo3(signature = (track, source, time, aou, n_tracks, *, geographic, score="glr", combine="chi2",
    lower=0.5, upper=None, max_gap=300.0, horizon=0.0, process_noise=2.0, same_source=false,
    correlation_time=60.0, window=300.0, threshold=false, method="exact", vertices=256,
    samples=500, seed=0, sampler="importance", inflation=None, margin=None))]
#[allow(clippy::too_many_arguments)]
fn associate<'py>(
    py: Python<'py>,
    track: PyReadonlyArray1<'py, u32>,
    source: PyReadonlyArray1<'py, u32>,
    time: PyReadonlyArray1<'py, f64>,
    aou: PyReadonlyArray2<'py, f64>,
    n_tracks: usize,
    geographic: bool,
    score: &str,
    combine: &str,
    lower: f64,
    upper: Option<f64>,
    max_gap: f64,
    horizon: f64,
    process_noise: f64,
    same_source: bool,
    correlation_time: f64,
    window: f64,
    threshold: bool,
    method: &str,
    vertices: usize,
    samples: usize,
    seed: u64,
    sampler: &str,
    inflation: Option<f64>,
    margin: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let o = options(
        score,
        combine,
        lower,
        upper,
        max_gap,
        horizon,
        process_noise,
        same_source,
        correlation_time,
        window,
        threshold,
        method,
        vertices,
        samples,
        seed,
        sampler,
        inflation,
        margin,
    )?;
    let (t, s, tm) = (
        slice("track", &track)?,
        slice("source", &source)?,
        slice("time", &time)?,
    );
    let rows = rows5(&aou)?;
    let coords = if geographic {
        Coords::Geographic
    } else {
        Coords::Planar
    };
    let res = detached(py, || {
        let r = Reports::new(coords, n_tracks, t, s, tm, &rows)?;
        association::associate(&r, &o, &mut check_signals)
    })?;
    let d = PyDict::new(py);
    d.set_item("a", res.a.into_pyarray(py))?;
    d.set_item("b", res.b.into_pyarray(py))?;
    d.set_item("score", res.score.into_pyarray(py))?;
    d.set_item("instants", res.instants.into_pyarray(py))?;
    let class: Vec<u8> = res.class.iter().map(|&c| c as u8).collect();
    d.set_item("class", class.into_pyarray(py))?;
    d.set_item("object", res.object.into_pyarray(py))?;
    d.set_item("candidates", res.candidates)?;
    let (ia, (ib, ic)): (Vec<u32>, (Vec<u32>, Vec<f64>)) =
        res.inflation.iter().map(|&(a, b, c)| (a, (b, c))).unzip();
    d.set_item("inflation_a", ia.into_pyarray(py))?;
    d.set_item("inflation_b", ib.into_pyarray(py))?;
    d.set_item("inflation", ic.into_pyarray(py))?;
    Ok(d)
}

/// Candidate pairs `(a, b)` from the R-tree, or by testing every pair of chunks.
#[pyfunction]
#[pyo3(signature = (track, source, time, aou, n_tracks, *, geographic, brute_force=false,
    max_gap=300.0, horizon=0.0, process_noise=2.0, same_source=false, window=300.0))]
#[allow(clippy::too_many_arguments)]
fn association_candidates<'py>(
    py: Python<'py>,
    track: PyReadonlyArray1<'py, u32>,
    source: PyReadonlyArray1<'py, u32>,
    time: PyReadonlyArray1<'py, f64>,
    aou: PyReadonlyArray2<'py, f64>,
    n_tracks: usize,
    geographic: bool,
    brute_force: bool,
    max_gap: f64,
    horizon: f64,
    process_noise: f64,
    same_source: bool,
    window: f64,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let r = reports(&track, &source, &time, &aou, n_tracks, geographic)?;
    let align = Alignment {
        max_gap,
        horizon,
        process_noise,
    }
    .validated()?;
    let index = IndexOptions {
        window,
        same_source,
    };
    let pairs = detached(py, || {
        let chunks = candidates::chunks(&r, &align, &index);
        Ok(if brute_force {
            candidates::brute_force_pairs(&r, &chunks, &index)
        } else {
            candidates::candidate_pairs(&r, &chunks, &index)
        })
    })?;
    let (a, b): (Vec<u32>, Vec<u32>) = pairs.into_iter().unzip();
    Ok((a.into_pyarray(py).into_any(), b.into_pyarray(py).into_any()))
}

/// Combines groups of per-instant scores: group `j` is `offsets[j]..offsets[j + 1]`.
#[pyfunction]
#[pyo3(signature = (g, m, time, offsets, rule, *, correlation_time=0.0))]
fn combine_instants<'py>(
    py: Python<'py>,
    g: PyReadonlyArray1<'py, f64>,
    m: PyReadonlyArray1<'py, f64>,
    time: PyReadonlyArray1<'py, f64>,
    offsets: PyReadonlyArray1<'py, u64>,
    rule: &str,
    correlation_time: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let rule = Combine::from_name(rule)?;
    let (g, m, t, off) = (
        slice("g", &g)?,
        slice("m", &m)?,
        slice("time", &time)?,
        slice("offsets", &offsets)?,
    );
    if m.len() != g.len() || t.len() != g.len() {
        return Err(Error::Invalid("g, m and time must have the same length".into()).into());
    }
    for w in off.windows(2) {
        if w[0] > w[1] || w[1] as usize > g.len() {
            return Err(Error::Invalid(format!(
                "offsets must be non-decreasing and <= {}",
                g.len()
            ))
            .into());
        }
    }
    let out: Vec<f64> = py.detach(|| {
        use rayon::prelude::*;
        off.par_windows(2)
            .map(|w| {
                let (s, e) = (w[0] as usize, w[1] as usize);
                rule.combine(&g[s..e], &m[s..e], &t[s..e], correlation_time)
            })
            .collect()
    });
    Ok(out.into_pyarray(py).into_any())
}

/// One-to-one assignment maximising the total score: indices of the chosen pairs.
#[pyfunction]
#[pyo3(signature = (a, b, score, *, min_score=0.0))]
fn assign_one_to_one<'py>(
    py: Python<'py>,
    a: PyReadonlyArray1<'py, u32>,
    b: PyReadonlyArray1<'py, u32>,
    score: PyReadonlyArray1<'py, f64>,
    min_score: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let (sa, sb, ss) = (slice("a", &a)?, slice("b", &b)?, slice("score", &score)?);
    if sa.len() != sb.len() || sa.len() != ss.len() {
        return Err(Error::Invalid("a, b and score must have the same length".into()).into());
    }
    let pairs: Vec<(u32, u32)> = sa.iter().copied().zip(sb.iter().copied()).collect();
    let chosen: Vec<u64> = py
        .detach(|| assign::assign_one_to_one(&pairs, ss, min_score))
        .into_iter()
        .map(|k| k as u64)
        .collect();
    Ok(chosen.into_pyarray(py).into_any())
}

/// The default upper (match) threshold of the calibrated combination.
#[pyfunction]
fn association_default_upper() -> f64 {
    association::combine::default_upper()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(associate, m)?)?;
    m.add_function(wrap_pyfunction!(association_candidates, m)?)?;
    m.add_function(wrap_pyfunction!(combine_instants, m)?)?;
    m.add_function(wrap_pyfunction!(assign_one_to_one, m)?)?;
    m.add_function(wrap_pyfunction!(association_default_upper, m)?)?;
    Ok(())
}
