//! Bindings for distributed association (`geofeas.dask`): the per-pair summaries a tile
//! computes (`crate::association::score_pairs`), and the global steps run once on the gathered
//! pairs — the covariance inflation of the chi-square rules estimated per pair of sources
//! (`combine::estimate_inflation`) and the triage and grouping (`assign::group`) — exactly as
//! the tail of `crate::association::associate` does them.

use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::{check_signals, detached, slice};
use crate::association::assign::{self, TrackInfo};
use crate::association::{self, combine, Combine, IndexOptions};
use crate::error::Error;

/// Classes (`0` match, `1` borderline, `2` non-match) of the pairs `(a, b)` with `score`, and
/// the object of every track, from the tracks' sources and time spans: the same triage and
/// grouping as the last step of `associate`.
#[pyfunction]
#[pyo3(signature = (source, start, end, a, b, score, *, lower, upper, spread=None))]
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
    spread: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let spread = spread.as_ref().map(|s| slice("spread", s)).transpose()?;
    let (sa, sb, ss) = (slice("a", &a)?, slice("b", &b)?, slice("score", &score)?);
    if sb.len() != sa.len() || ss.len() != sa.len() {
        return Err(Error::Invalid("a, b and score must have the same length".into()).into());
    }
    let pairs: Vec<(u32, u32)> = sa.iter().copied().zip(sb.iter().copied()).collect();
    let (class, object) = group_checked(
        py,
        slice("source", &source)?,
        slice("start", &start)?,
        slice("end", &end)?,
        &pairs,
        ss,
        lower,
        upper,
        spread,
    )?;
    Ok((
        class.into_pyarray(py).into_any(),
        object.into_pyarray(py).into_any(),
    ))
}

/// `assign::group` after checking lengths, indices and thresholds; classes as `u8`.
#[allow(clippy::too_many_arguments)]
fn group_checked(
    py: Python<'_>,
    src: &[u32],
    t0: &[f64],
    t1: &[f64],
    pairs: &[(u32, u32)],
    scores: &[f64],
    lower: f64,
    upper: f64,
    spread: Option<&[f64]>,
) -> PyResult<(Vec<u8>, Vec<u32>)> {
    if t0.len() != src.len()
        || t1.len() != src.len()
        || spread.is_some_and(|s| s.len() != src.len())
    {
        return Err(Error::Invalid(
            "source, start, end (and spread) must have the same length".into(),
        )
        .into());
    }
    let n = src.len();
    for (row, &(x, y)) in pairs.iter().enumerate() {
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
            spread: spread.map_or(0.0, |s| s[t]),
        })
        .collect();
    let (class, object) = py.detach(|| assign::group(&tracks, pairs, scores, lower, upper));
    Ok((class.iter().map(|&c| c as u8).collect(), object))
}

/// Per pair `(a, b)`: the combined score (with `inflation`, 1 when `None`), the number of
/// instants, the summed squared distances and the effective number of instants.
#[pyfunction]
#[pyo3(signature = (track, source, time, aou, n_tracks, a, b, *, geographic, score="glr",
    combine="chi2", max_gap=300.0, horizon=0.0, process_noise=2.0, correlation_time=60.0,
    threshold=false, method="exact", vertices=256, samples=500, seed=0, sampler="importance",
    inflation=None, stream_ids=None))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn association_pair_stats<'py>(
    py: Python<'py>,
    track: PyReadonlyArray1<'py, u32>,
    source: PyReadonlyArray1<'py, u32>,
    time: PyReadonlyArray1<'py, f64>,
    aou: PyReadonlyArray2<'py, f64>,
    n_tracks: usize,
    a: PyReadonlyArray1<'py, u32>,
    b: PyReadonlyArray1<'py, u32>,
    geographic: bool,
    score: &str,
    combine: &str,
    max_gap: f64,
    horizon: f64,
    process_noise: f64,
    correlation_time: f64,
    threshold: bool,
    method: &str,
    vertices: usize,
    samples: usize,
    seed: u64,
    sampler: &str,
    inflation: Option<f64>,
    stream_ids: Option<PyReadonlyArray1<'py, u32>>,
) -> PyResult<(
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
)> {
    let r = super::association::reports(&track, &source, &time, &aou, n_tracks, geographic)?;
    let r = match &stream_ids {
        Some(ids) => r.with_stream_ids(slice("stream_ids", ids)?)?,
        None => r,
    };
    let index = IndexOptions::default();
    let o = super::association::options(
        score,
        combine,
        0.5,
        None,
        max_gap,
        horizon,
        process_noise,
        index.same_source,
        correlation_time,
        index.window,
        threshold,
        method,
        vertices,
        samples,
        seed,
        sampler,
        inflation,
        None,
    )?;
    let (sa, sb) = (slice("a", &a)?, slice("b", &b)?);
    if sa.len() != sb.len() {
        return Err(Error::LengthMismatch {
            left: sa.len(),
            right: sb.len(),
        }
        .into());
    }
    for (row, (&x, &y)) in sa.iter().zip(sb).enumerate() {
        if x as usize >= n_tracks || y as usize >= n_tracks {
            return Err(Error::Invalid(format!(
                "pair row {row}: track index out of range 0..{n_tracks}"
            ))
            .into());
        }
    }
    let pairs: Vec<(u32, u32)> = sa.iter().copied().zip(sb.iter().copied()).collect();
    let out = detached(py, || {
        association::score_pairs(&r, &pairs, &o, &mut check_signals)
    })?;
    let score: Vec<f64> = out.iter().map(|p| p.score).collect();
    let instants: Vec<u32> = out.iter().map(|p| p.instants).collect();
    let sum_m: Vec<f64> = out.iter().map(|p| p.sum_m).collect();
    let k_eff: Vec<f64> = out.iter().map(|p| p.k_eff).collect();
    Ok((
        score.into_pyarray(py).into_any(),
        instants.into_pyarray(py).into_any(),
        sum_m.into_pyarray(py).into_any(),
        k_eff.into_pyarray(py).into_any(),
    ))
}

/// The global steps of `associate` on gathered pairs `(a, b)` (sorted, `a < b`, each with at
/// least one instant): for the chi-square rules the inflation per pair of sources (given, or
/// estimated when `inflation` is `None`, then every score recomputed from its summary), then
/// the triage and grouping. Returns a dict: `score`, `class`, `object`, `inflation_a`,
/// `inflation_b`, `inflation`.
#[pyfunction]
#[pyo3(signature = (source, start, end, a, b, score, instants, sum_m, k_eff, *, combine,
    inflation, lower, upper, spread=None))]
#[allow(clippy::too_many_arguments)]
fn association_finish<'py>(
    py: Python<'py>,
    source: PyReadonlyArray1<'py, u32>,
    start: PyReadonlyArray1<'py, f64>,
    end: PyReadonlyArray1<'py, f64>,
    a: PyReadonlyArray1<'py, u32>,
    b: PyReadonlyArray1<'py, u32>,
    score: PyReadonlyArray1<'py, f64>,
    instants: PyReadonlyArray1<'py, u32>,
    sum_m: PyReadonlyArray1<'py, f64>,
    k_eff: PyReadonlyArray1<'py, f64>,
    combine: &str,
    inflation: Option<f64>,
    lower: f64,
    upper: f64,
    spread: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let spread = spread.as_ref().map(|s| slice("spread", s)).transpose()?;
    let rule = Combine::from_name(combine)?;
    let src = slice("source", &source)?;
    let (sa, sb) = (slice("a", &a)?, slice("b", &b)?);
    let (ss, sk, sm, se) = (
        slice("score", &score)?,
        slice("instants", &instants)?,
        slice("sum_m", &sum_m)?,
        slice("k_eff", &k_eff)?,
    );
    let n = sa.len();
    if [sb.len(), ss.len(), sk.len(), sm.len(), se.len()]
        .iter()
        .any(|&l| l != n)
    {
        return Err(Error::Invalid(
            "a, b, score, instants, sum_m and k_eff must have the same length".into(),
        )
        .into());
    }
    for (row, (&x, &y)) in sa.iter().zip(sb).enumerate() {
        if x as usize >= src.len() || y as usize >= src.len() {
            return Err(Error::Invalid(format!(
                "pair row {row}: track index out of range 0..{}",
                src.len()
            ))
            .into());
        }
    }
    let kept: Vec<(u32, u32)> = sa.iter().copied().zip(sb.iter().copied()).collect();
    let stats: Vec<(f64, f64, f64)> = (0..n).map(|i| (sm[i], sk[i] as f64, se[i])).collect();
    let mut scores = ss.to_vec();
    let mut groups: Vec<(u32, u32, f64)> = Vec::new();
    if rule.is_chi2() {
        groups = match inflation {
            Some(c) => {
                let mut g: Vec<(u32, u32, f64)> = kept
                    .iter()
                    .map(|&(x, y)| {
                        let (p, q) = (src[x as usize], src[y as usize]);
                        (p.min(q), p.max(q), c)
                    })
                    .collect();
                g.sort_by_key(|x| (x.0, x.1));
                g.dedup_by(|x, y| (x.0, x.1) == (y.0, y.1));
                g
            }
            None => {
                let est = combine::estimate_inflation(&kept, src, &stats);
                for (i, &(x, y)) in kept.iter().enumerate() {
                    let (p, q) = (src[x as usize], src[y as usize]);
                    let key = (p.min(q), p.max(q));
                    let c = est
                        .binary_search_by(|e| (e.0, e.1).cmp(&key))
                        .map_or(1.0, |j| est[j].2);
                    let (m, k, ke) = stats[i];
                    scores[i] = rule.from_summary(m / c, k, ke);
                }
                est
            }
        };
    }
    let d = association_group_dict(py, source, start, end, &kept, &scores, lower, upper, spread)?;
    let (ga, (gb, gc)): (Vec<u32>, (Vec<u32>, Vec<f64>)) =
        groups.iter().map(|&(x, y, c)| (x, (y, c))).unzip();
    d.set_item("score", scores.into_pyarray(py))?;
    d.set_item("inflation_a", ga.into_pyarray(py))?;
    d.set_item("inflation_b", gb.into_pyarray(py))?;
    d.set_item("inflation", gc.into_pyarray(py))?;
    Ok(d)
}

#[allow(clippy::too_many_arguments)]
fn association_group_dict<'py>(
    py: Python<'py>,
    source: PyReadonlyArray1<'py, u32>,
    start: PyReadonlyArray1<'py, f64>,
    end: PyReadonlyArray1<'py, f64>,
    pairs: &[(u32, u32)],
    scores: &[f64],
    lower: f64,
    upper: f64,
    spread: Option<&[f64]>,
) -> PyResult<Bound<'py, PyDict>> {
    let (class, object) = group_checked(
        py,
        slice("source", &source)?,
        slice("start", &start)?,
        slice("end", &end)?,
        pairs,
        scores,
        lower,
        upper,
        spread,
    )?;
    let d = PyDict::new(py);
    d.set_item("class", class.into_pyarray(py))?;
    d.set_item("object", object.into_pyarray(py))?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(association_group, m)?)?;
    m.add_function(wrap_pyfunction!(association_pair_stats, m)?)?;
    m.add_function(wrap_pyfunction!(association_finish, m)?)?;
    Ok(())
}
