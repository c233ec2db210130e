//! Bindings for distributed association (`geofeas.integrations.dask`): the per-pair summaries a tile
//! computes (`geofeas::association::score_pairs`), the mergeable picture counts of a partition of
//! whole tracks (`evidence::Counts`), and the global step run once on the gathered pairs and
//! components (`geofeas::association::finish`, the very function `associate` ends with).

use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::association::{
    AlignmentArgs, AssociationArgs, AssociationOutput, DecisionsArg, ReportsArg,
};
use super::{check_signals, detached, py_err, slice};
use geofeas::association::align::TimeCover;
use geofeas::association::candidates::{TrackPartial, PARTIAL_WIDTH};
use geofeas::association::evidence::Counts;
use geofeas::association::{self, posterior, PairStat, Picture};
use geofeas::error::Error;

/// The fields of a [`PairStat`], in the order the bindings exchange them.
const STAT_FIELDS: [&str; 10] = [
    "score",
    "instants",
    "sum_m",
    "k_eff",
    "mean_mg",
    "mean_ln_det",
    "mean_trace_over_det",
    "mean_inv_det",
    "evidence_k_eff",
    "pos",
];

/// Per pair `(a, b)` of a tile: the summary of its common instants.
#[pyfunction]
#[pyo3(signature = (reports, a, b, *, options, stream_ids=None))]
fn association_pair_stats<'py>(
    py: Python<'py>,
    reports: ReportsArg<'py>,
    a: PyReadonlyArray1<'py, u32>,
    b: PyReadonlyArray1<'py, u32>,
    options: AssociationArgs,
    stream_ids: Option<PyReadonlyArray1<'py, u32>>,
) -> PyResult<PairStats> {
    let n_tracks = reports.n_tracks;
    let r = reports.reports()?;
    let r = match &stream_ids {
        Some(ids) => r
            .with_stream_ids(slice("stream_ids", ids)?)
            .map_err(py_err)?,
        None => r,
    };
    let o = options.options()?;
    let (sa, sb) = (slice("a", &a)?, slice("b", &b)?);
    if sa.len() != sb.len() {
        return Err(py_err(Error::LengthMismatch {
            left: sa.len(),
            right: sb.len(),
        }));
    }
    for (row, (&x, &y)) in sa.iter().zip(sb).enumerate() {
        if x as usize >= n_tracks || y as usize >= n_tracks {
            return Err(py_err(Error::Invalid(format!(
                "pair row {row}: track index out of range 0..{n_tracks}"
            ))));
        }
    }
    let pairs: Vec<(u32, u32)> = sa.iter().copied().zip(sb.iter().copied()).collect();
    let out = detached(py, || {
        association::score_pairs(&r, &pairs, &o, &mut check_signals)
    })?;
    Ok(pair_stats(py, &out))
}

/// The summaries of pairs' common instants, one row per pair (the fields of `PairStat`, `pos`
/// as `pos_0`, `pos_1`): what `association_finish` takes back, as a mapping, with the pairs.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PairStats {
    score: Py<PyArray1<f64>>,
    instants: Py<PyArray1<u32>>,
    sum_m: Py<PyArray1<f64>>,
    k_eff: Py<PyArray1<f64>>,
    mean_mg: Py<PyArray1<f64>>,
    mean_ln_det: Py<PyArray1<f64>>,
    mean_trace_over_det: Py<PyArray1<f64>>,
    mean_inv_det: Py<PyArray1<f64>>,
    evidence_k_eff: Py<PyArray1<f64>>,
    pos_0: Py<PyArray1<f64>>,
    pos_1: Py<PyArray1<f64>>,
}

#[pymethods]
impl PairStats {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("PairStats(pairs={})", self.score.bind(py).len())
    }
}

pub(super) fn pair_stats(py: Python<'_>, out: &[PairStat]) -> PairStats {
    let col = |f: fn(&PairStat) -> f64| -> Py<PyArray1<f64>> {
        out.iter()
            .map(f)
            .collect::<Vec<f64>>()
            .into_pyarray(py)
            .unbind()
    };
    let instants: Vec<u32> = out.iter().map(|p| p.instants).collect();
    PairStats {
        score: col(|p| p.score),
        instants: instants.into_pyarray(py).unbind(),
        sum_m: col(|p| p.sum_m),
        k_eff: col(|p| p.k_eff),
        mean_mg: col(|p| p.mean_mg),
        mean_ln_det: col(|p| p.mean_ln_det),
        mean_trace_over_det: col(|p| p.mean_trace_over_det),
        mean_inv_det: col(|p| p.mean_inv_det),
        evidence_k_eff: col(|p| p.evidence_k_eff),
        pos_0: col(|p| p.pos[0]),
        pos_1: col(|p| p.pos[1]),
    }
}

/// What the global step needs of the tracks of a partition holding whole tracks, from one
/// reading of their reports: the picture counts and when each track has a state.
#[pyfunction]
#[pyo3(signature = (reports, *, options))]
fn association_track_summary<'py>(
    py: Python<'py>,
    reports: ReportsArg<'py>,
    options: AssociationArgs,
) -> PyResult<(PictureCounts, PyTimeCover)> {
    let r = reports.reports()?;
    let o = options.options()?;
    let (counts, cover) = py.detach(|| {
        (
            Counts::of(&r, o.model.cell, o.align.max_gap),
            TimeCover::of(&r, &o.align),
        )
    });
    Ok((picture_counts(py, &counts), time_cover(py, cover)))
}

/// When each track has a state (`align::TimeCover`): the chains of track `t` are
/// `cover_offsets[t]..cover_offsets[t + 1]` of `cover_start`, `cover_end` and
/// `cover_reports` (the number of reports in each).
#[pyclass(name = "TimeCover", frozen, get_all, module = "geofeas._core")]
pub struct PyTimeCover {
    cover_offsets: Py<PyArray1<u32>>,
    cover_start: Py<PyArray1<f64>>,
    cover_end: Py<PyArray1<f64>>,
    cover_reports: Py<PyArray1<u32>>,
}

#[pymethods]
impl PyTimeCover {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "TimeCover(tracks={}, chains={})",
            self.cover_offsets.bind(py).len().saturating_sub(1),
            self.cover_start.bind(py).len()
        )
    }
}

pub(super) fn time_cover(py: Python<'_>, c: TimeCover) -> PyTimeCover {
    let (s, e): (Vec<f64>, Vec<f64>) = c.spans.iter().map(|x| (x[0], x[1])).unzip();
    PyTimeCover {
        cover_offsets: c.offsets.into_pyarray(py).unbind(),
        cover_start: s.into_pyarray(py).unbind(),
        cover_end: e.into_pyarray(py).unbind(),
        cover_reports: c.reports.into_pyarray(py).unbind(),
    }
}

/// The picture counts of some tracks: per-source track-microseconds `micros`, summed AOU
/// reach `reach` (metres) and `reports`, the occupied cells `cell_source, cell_row, cell_col,
/// cell_micros` and the time range `time`.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PictureCounts {
    micros: Py<PyArray1<u64>>,
    reach: Py<PyArray1<u64>>,
    reports: Py<PyArray1<u64>>,
    cell_source: Py<PyArray1<u32>>,
    cell_row: Py<PyArray1<i64>>,
    cell_col: Py<PyArray1<i64>>,
    cell_micros: Py<PyArray1<u64>>,
    time: (f64, f64),
}

#[pymethods]
impl PictureCounts {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "PictureCounts(sources={}, cells={})",
            self.micros.bind(py).len(),
            self.cell_source.bind(py).len()
        )
    }
}

pub(super) fn picture_counts(py: Python<'_>, c: &Counts) -> PictureCounts {
    let s: Vec<u32> = c.grid.keys().map(|k| k.0).collect();
    let row: Vec<i64> = c.grid.keys().map(|k| k.1).collect();
    let col: Vec<i64> = c.grid.keys().map(|k| k.2).collect();
    let v: Vec<u64> = c.grid.values().copied().collect();
    PictureCounts {
        micros: c.micros.clone().into_pyarray(py).unbind(),
        reach: c.reach.clone().into_pyarray(py).unbind(),
        reports: c.reports.clone().into_pyarray(py).unbind(),
        cell_source: s.into_pyarray(py).unbind(),
        cell_row: row.into_pyarray(py).unbind(),
        cell_col: col.into_pyarray(py).unbind(),
        cell_micros: v.into_pyarray(py).unbind(),
        time: c.time,
    }
}

/// The tracks of the global step: a mapping of arrays with one row per track, `source` and
/// `spread`, and the chains of every track (`cover_offsets`, one more, and `cover_start`,
/// `cover_end`, `cover_reports`, one per chain), as `association_track_summary` returns them.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct TracksArg<'py> {
    source: PyReadonlyArray1<'py, u32>,
    spread: PyReadonlyArray1<'py, f64>,
    cover_offsets: PyReadonlyArray1<'py, u32>,
    cover_start: PyReadonlyArray1<'py, f64>,
    cover_end: PyReadonlyArray1<'py, f64>,
    cover_reports: PyReadonlyArray1<'py, u32>,
}

/// The global step of `associate` on gathered `pairs` (a mapping: `a`, `b`, sorted, `a < b`,
/// each with at least one instant; their summaries as `association_pair_stats` returns them;
/// `candidates`, the number of candidate pairs before those without instants were dropped),
/// the `tracks` (see `TracksArg`), the picture `counts` of parts that together hold every
/// track once (a list of the counts `association_track_summary` returns; merged here) and
/// operator `decisions`. Returns an `AssociationOutput`, as `associate` does. With `memo` (an
/// earlier `AssociationOutput`'s, from the same tracks, pairs, counts and options), the
/// components it holds unchanged are taken from it: only those the decisions change are
/// computed, with the same result.
#[pyfunction]
#[pyo3(signature = (tracks, pairs, counts, decisions, *, geographic, options, memo=None))]
#[allow(clippy::too_many_arguments)]
fn association_finish<'py>(
    py: Python<'py>,
    tracks: TracksArg<'py>,
    pairs: Bound<'py, PyDict>,
    counts: Vec<Bound<'py, PyDict>>,
    decisions: DecisionsArg<'py>,
    geographic: bool,
    options: AssociationArgs,
    memo: Option<PyRef<'py, super::association::PosteriorMemo>>,
) -> PyResult<AssociationOutput> {
    let o = options.options()?;
    let dec = decisions.decisions()?;
    let (src, sp) = (
        slice("source", &tracks.source)?,
        slice("spread", &tracks.spread)?,
    );
    let (c0, c1) = (
        slice("cover_start", &tracks.cover_start)?,
        slice("cover_end", &tracks.cover_end)?,
    );
    let offsets = slice("cover_offsets", &tracks.cover_offsets)?;
    let n_reports = slice("cover_reports", &tracks.cover_reports)?;
    if sp.len() != src.len()
        || offsets.len() != src.len() + 1
        || c0.len() != c1.len()
        || n_reports.len() != c0.len()
    {
        return Err(py_err(Error::Invalid(
            "tracks: source and spread must have one row per track, cover_offsets one more, \
             and cover_start, cover_end and cover_reports the same length"
                .into(),
        )));
    }
    let cover = TimeCover::from_parts(
        offsets.to_vec(),
        c0.iter().zip(c1).map(|(&x, &y)| [x, y]).collect(),
        n_reports.to_vec(),
        o.align.horizon,
    )
    .map_err(py_err)?;
    let tracks: Vec<posterior::Track> = (0..src.len())
        .map(|t| {
            let (start, end) = cover.span(t);
            posterior::Track {
                source: src[t],
                start,
                end,
                spread: sp[t],
                further: 0.0,
            }
        })
        .collect();
    let item = |name: &'static str| -> PyResult<Bound<'py, PyAny>> {
        pairs
            .get_item(name)?
            .ok_or_else(|| py_err(Error::Invalid(format!("pairs: missing '{name}'"))))
    };
    let (a, b): (PyReadonlyArray1<'_, u32>, PyReadonlyArray1<'_, u32>) =
        (item("a")?.extract()?, item("b")?.extract()?);
    let candidates: usize = item("candidates")?.extract()?;
    let (sa, sb) = (slice("a", &a)?, slice("b", &b)?);
    let get = |name: &'static str| -> PyResult<Vec<f64>> {
        let v = item(name)?;
        let arr: PyReadonlyArray1<'_, f64> = v.extract()?;
        let s = slice(name, &arr)?.to_vec();
        if s.len() != sa.len() {
            return Err(py_err(Error::Invalid(format!(
                "pairs: '{name}' has {} rows for {} pairs",
                s.len(),
                sa.len()
            ))));
        }
        Ok(s)
    };
    let cols: Vec<Vec<f64>> = STAT_FIELDS
        .iter()
        .filter(|&&f| f != "instants" && f != "pos")
        .map(|f| get(f))
        .collect::<PyResult<_>>()?;
    let (p0, p1) = (get("pos_0")?, get("pos_1")?);
    let instants: PyReadonlyArray1<'_, u32> = item("instants")?.extract()?;
    let instants = slice("instants", &instants)?;
    if sb.len() != sa.len() || instants.len() != sa.len() {
        return Err(py_err(Error::Invalid(
            "pairs: a, b and instants must have the same length".into(),
        )));
    }
    let kept: Vec<((u32, u32), PairStat)> = (0..sa.len())
        .map(|i| {
            (
                (sa[i], sb[i]),
                PairStat {
                    score: cols[0][i],
                    instants: instants[i],
                    sum_m: cols[1][i],
                    k_eff: cols[2][i],
                    mean_mg: cols[3][i],
                    mean_ln_det: cols[4][i],
                    mean_trace_over_det: cols[5][i],
                    mean_inv_det: cols[6][i],
                    evidence_k_eff: cols[7][i],
                    pos: [p0[i], p1[i]],
                },
            )
        })
        .collect();
    let mut merged = Counts {
        cell: o.model.cell,
        geographic,
        time: (f64::INFINITY, f64::NEG_INFINITY),
        ..Counts::default()
    };
    for (k, part) in counts.iter().enumerate() {
        merged.merge(&counts_of(k, part, geographic, o.model.cell)?);
    }
    let counts = merged;
    let memo = memo.as_deref().map(|m| &m.0);
    let res = detached(py, || {
        let picture = Picture::from_counts(counts.clone(), &o.model);
        let mut res = association::finish(
            &tracks,
            &cover,
            &picture,
            &o,
            &kept,
            &dec,
            memo,
            &mut check_signals,
        )?;
        res.candidates = candidates;
        res.counts = counts;
        Ok(res)
    })?;
    super::association::result_output(py, res)
}

fn counts_of(k: usize, d: &Bound<'_, PyDict>, geographic: bool, cell: f64) -> PyResult<Counts> {
    let item = |name: &str| {
        d.get_item(name)?
            .ok_or_else(|| py_err(Error::Invalid(format!("counts[{k}]: missing '{name}'"))))
    };
    let micros: Vec<u64> = item("micros")?.extract()?;
    let reach: Vec<u64> = item("reach")?.extract()?;
    let reports: Vec<u64> = item("reports")?.extract()?;
    if reach.len() != micros.len() || reports.len() != micros.len() {
        return Err(py_err(Error::Invalid(format!(
            "counts[{k}]: micros, reach and reports must have one entry per source"
        ))));
    }
    let s: Vec<u32> = item("cell_source")?.extract()?;
    let row: Vec<i64> = item("cell_row")?.extract()?;
    let col: Vec<i64> = item("cell_col")?.extract()?;
    let v: Vec<u64> = item("cell_micros")?.extract()?;
    let time: (f64, f64) = item("time")?.extract()?;
    if row.len() != s.len() || col.len() != s.len() || v.len() != s.len() {
        return Err(py_err(Error::Invalid(format!(
            "counts[{k}]: cell columns of different lengths"
        ))));
    }
    let mut grid = std::collections::BTreeMap::new();
    for i in 0..s.len() {
        let c: &mut u64 = grid.entry((s[i], row[i], col[i])).or_insert(0);
        *c = c.saturating_add(v[i]);
    }
    Ok(Counts {
        cell,
        geographic,
        micros,
        grid,
        time,
        reach,
        reports,
    })
}

/// The mergeable partial of every track of some reports (`candidates::TrackPartial`): an
/// `(n_tracks, PARTIAL_WIDTH)` array, one opaque row per track, for
/// `association_track_boxes`.
#[pyfunction]
#[pyo3(signature = (reports,))]
fn association_track_partials<'py>(
    py: Python<'py>,
    reports: ReportsArg<'py>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (r, rows, n_tracks) = (reports.reports()?, reports.rows()?, reports.n_tracks);
    let flat: Vec<f64> = py.detach(|| {
        TrackPartial::of(&r, &rows)
            .iter()
            .flat_map(|p| p.to_row())
            .collect()
    });
    Ok(
        numpy::ndarray::Array2::from_shape_vec((n_tracks, PARTIAL_WIDTH), flat)
            .map_err(|e| Error::Invalid(e.to_string()))
            .map_err(py_err)?
            .into_pyarray(py),
    )
}

/// The partials of `association_track_partials` (rows of any partitions), merged per track
/// (`track`: each row's track, `0..n_tracks`, every track at least once), and each track's
/// halo box: a dict of `reports`, `start`, `end`, `spread` (the posterior's AOU size of the
/// track), `halo` (the spatial growth, m), `lo` and `hi` (`(n, 4)`: x, y, z, t), `first_time`
/// and `first_aou` (`(n, 5)`, the earliest report as given).
#[pyfunction]
#[pyo3(signature = (partials, track, n_tracks, *, geographic, alignment, halo=0.0))]
fn association_track_boxes<'py>(
    py: Python<'py>,
    partials: PyReadonlyArray2<'py, f64>,
    track: PyReadonlyArray1<'py, u32>,
    n_tracks: usize,
    geographic: bool,
    alignment: AlignmentArgs,
    halo: f64,
) -> PyResult<TrackBoxes> {
    let align = alignment.alignment()?;
    if !(halo.is_finite() && halo >= 0.0) {
        return Err(py_err(Error::InvalidOption {
            name: "halo",
            reason: format!("must be a finite number >= 0, got {halo}"),
        }));
    }
    let rows = partials.as_array();
    let t = slice("track", &track)?;
    if rows.ncols() != PARTIAL_WIDTH || rows.nrows() != t.len() {
        return Err(py_err(Error::Shape {
            what: "partials",
            expected: format!("({}, {PARTIAL_WIDTH})", t.len()),
            got: format!("{:?}", rows.shape()),
        }));
    }
    // one contiguous view (a copy only for a strided input), read row by row
    let rows = rows.as_standard_layout();
    let flat = rows.as_slice().expect("standard layout is contiguous");
    let mut merged: Vec<Option<TrackPartial>> = vec![None; n_tracks];
    for (row, (&k, v)) in t.iter().zip(flat.chunks_exact(PARTIAL_WIDTH)).enumerate() {
        let slot = merged
            .get_mut(k as usize)
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "track row {row}: {k} is not below n_tracks = {n_tracks}"
                ))
            })
            .map_err(py_err)?;
        let p = TrackPartial::from_row(v, row).map_err(py_err)?;
        match slot {
            Some(m) => m.merge(&p),
            None => *slot = Some(p),
        }
    }
    let merged: Vec<TrackPartial> = merged
        .into_iter()
        .enumerate()
        .map(|(k, p)| p.ok_or_else(|| Error::Invalid(format!("track {k} has no partial"))))
        .collect::<Result<_, _>>()
        .map_err(py_err)?;
    let n = merged.len();
    let (mut lo, mut hi, mut first, mut growth) = (
        Vec::with_capacity(4 * n),
        Vec::with_capacity(4 * n),
        Vec::with_capacity(5 * n),
        Vec::with_capacity(n),
    );
    for p in &merged {
        let g = p.growth(&align, geographic, halo);
        let (l, h) = p.box_grown_by(&align, geographic, g);
        lo.extend_from_slice(&l);
        hi.extend_from_slice(&h);
        first.extend_from_slice(&p.ends[0].aou);
        growth.push(g);
    }
    let shaped = |v: Vec<f64>, k: usize| {
        numpy::ndarray::Array2::from_shape_vec((n, k), v).map_err(|e| Error::Invalid(e.to_string()))
    };
    let col = |f: fn(&TrackPartial) -> f64| -> Py<PyArray1<f64>> {
        merged
            .iter()
            .map(f)
            .collect::<Vec<f64>>()
            .into_pyarray(py)
            .unbind()
    };
    let reports: Vec<u64> = merged.iter().map(|p| p.reports).collect();
    Ok(TrackBoxes {
        reports: reports.into_pyarray(py).unbind(),
        start: col(|p| p.t_min),
        end: col(|p| p.t_max),
        spread: col(|p| posterior::Track::spread_of(p.area_min, p.area_max)),
        halo: growth.into_pyarray(py).unbind(),
        lo: shaped(lo, 4).map_err(py_err)?.into_pyarray(py).unbind(),
        hi: shaped(hi, 4).map_err(py_err)?.into_pyarray(py).unbind(),
        first_time: col(|p| p.ends[0].time),
        first_aou: shaped(first, 5).map_err(py_err)?.into_pyarray(py).unbind(),
    })
}

/// The merged partials of every track: one row per track.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct TrackBoxes {
    /// Reports of the track.
    reports: Py<PyArray1<u64>>,
    /// First and last report times.
    start: Py<PyArray1<f64>>,
    end: Py<PyArray1<f64>>,
    /// The track's AOU spread (as the posterior's tracks have it).
    spread: Py<PyArray1<f64>>,
    /// The spatial growth of the box, m.
    halo: Py<PyArray1<f64>>,
    /// `(n, 4)`: the grown box's corners, x, y, z, t.
    lo: Py<PyArray2<f64>>,
    hi: Py<PyArray2<f64>>,
    /// The earliest report: its time and `(n, 5)` AOU as given.
    first_time: Py<PyArray1<f64>>,
    first_aou: Py<PyArray2<f64>>,
}

#[pymethods]
impl TrackBoxes {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("TrackBoxes(tracks={})", self.start.bind(py).len())
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<TrackBoxes>()?;
    m.add_class::<PairStats>()?;
    m.add_class::<PyTimeCover>()?;
    m.add_class::<PictureCounts>()?;
    m.add_function(wrap_pyfunction!(association_track_partials, m)?)?;
    m.add_function(wrap_pyfunction!(association_track_boxes, m)?)?;
    m.add_function(wrap_pyfunction!(association_pair_stats, m)?)?;
    m.add_function(wrap_pyfunction!(association_finish, m)?)?;
    m.add_function(wrap_pyfunction!(association_track_summary, m)?)?;
    Ok(())
}
