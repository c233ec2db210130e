//! Bindings of the association pipeline (`geofeas::association`).

use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::{check_signals, detached, py_err, slice};
use geofeas::association::{
    self, assign, candidates, Alignment, Combine, Coords, Decision, IndexOptions, Inference, Model,
    Options, Reports,
};
use geofeas::error::Error;
use geofeas::score::{self, Score};

/// The `(n, 5)` AOU rows, as `Reports::new` takes them.
pub(super) fn rows5(arr: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; 5]>> {
    Ok(super::flat5("aou", arr)?
        .chunks_exact(5)
        .map(|c| [c[0], c[1], c[2], c[3], c[4]])
        .collect())
}

/// Reports as the bindings take them: any object with the attributes of `geofeas.Reports`
/// (`track`, `source`: uint32 indices; `time`; `aou` `(n, 5)`; `n_tracks`; `coords`,
/// `"planar"` or `"geographic"`).
#[derive(FromPyObject)]
pub(super) struct ReportsArg<'py> {
    track: PyReadonlyArray1<'py, u32>,
    source: PyReadonlyArray1<'py, u32>,
    time: PyReadonlyArray1<'py, f64>,
    aou: PyReadonlyArray2<'py, f64>,
    pub(super) n_tracks: usize,
    coords: String,
}

impl ReportsArg<'_> {
    pub(super) fn coords(&self) -> PyResult<Coords> {
        match self.coords.as_str() {
            "planar" => Ok(Coords::Planar),
            "geographic" => Ok(Coords::Geographic),
            other => Err(py_err(Error::InvalidOption {
                name: "coords",
                reason: format!("expected 'planar' or 'geographic', got {other:?}"),
            })),
        }
    }

    /// The `(n, 5)` AOU rows as given.
    pub(super) fn rows(&self) -> PyResult<Vec<[f64; 5]>> {
        rows5(&self.aou)
    }

    /// The columns `track`, `source`, `time` as slices.
    pub(super) fn columns(&self) -> PyResult<(&[u32], &[u32], &[f64])> {
        Ok((
            slice("track", &self.track)?,
            slice("source", &self.source)?,
            slice("time", &self.time)?,
        ))
    }

    /// The validated, sorted reports.
    pub(super) fn reports(&self) -> PyResult<Reports> {
        let (t, s, tm) = self.columns()?;
        Reports::new(self.coords()?, self.n_tracks, t, s, tm, &self.rows()?).map_err(py_err)
    }
}

/// Operator decisions as the bindings take them: any object with the attributes of
/// `geofeas.Decisions` (`a`, `b`: uint32 track indices; `same`: bool), row `k` of its table
/// being decision `k`.
#[derive(FromPyObject)]
pub(super) struct DecisionsArg<'py> {
    a: PyReadonlyArray1<'py, u32>,
    b: PyReadonlyArray1<'py, u32>,
    same: PyReadonlyArray1<'py, bool>,
}

impl DecisionsArg<'_> {
    /// The decisions as the engine takes them.
    pub(super) fn decisions(&self) -> PyResult<Vec<Decision>> {
        let (a, b, same) = (
            slice("decisions.a", &self.a)?,
            slice("decisions.b", &self.b)?,
            slice("decisions.same", &self.same)?,
        );
        if b.len() != a.len() || same.len() != a.len() {
            return Err(py_err(Error::Invalid(
                "decisions: columns of different lengths".into(),
            )));
        }
        Ok((0..a.len())
            .map(|k| Decision {
                a: a[k],
                b: b[k],
                same: same[k],
                row: k,
            })
            .collect())
    }
}

/// The alignment options of a binding: any mapping with the keys `max_gap`, `horizon`,
/// `process_noise` and `max_still_gap` (the association options are one).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(super) struct AlignmentArgs {
    max_gap: f64,
    horizon: f64,
    process_noise: f64,
    max_still_gap: f64,
}

impl AlignmentArgs {
    pub(super) fn alignment(&self) -> PyResult<Alignment> {
        Alignment {
            max_gap: self.max_gap,
            horizon: self.horizon,
            process_noise: self.process_noise,
            max_still_gap: self.max_still_gap,
        }
        .validated()
        .map_err(py_err)
    }
}

/// The index options of a binding: a mapping with the alignment keys and `same_source`,
/// `window`.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(super) struct IndexArgs {
    same_source: bool,
    window: f64,
}

/// The association options from the keyword arguments of the bindings.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(super) struct AssociationArgs {
    score: String,
    combine: String,
    p_match: f64,
    p_reject: f64,
    max_gap: f64,
    horizon: f64,
    process_noise: f64,
    max_still_gap: f64,
    same_source: bool,
    correlation_time: f64,
    window: f64,
    threshold: bool,
    method: String,
    vertices: usize,
    samples: usize,
    seed: u64,
    sampler: String,
    inflation: Option<f64>,
    completeness: f64,
    false_tracks: Vec<f64>,
    density_cell: f64,
    exact_limit: usize,
    chains: usize,
    sweeps: usize,
    posterior_seed: u64,
}

impl AssociationArgs {
    pub(super) fn options(&self) -> PyResult<Options> {
        let spec = Score::from_name(
            &self.score,
            &score::Options {
                threshold: self.threshold,
                method: self.method.clone(),
                vertices: self.vertices,
                samples: self.samples,
                seed: self.seed,
                sampler: self.sampler.clone(),
            },
        )
        .map_err(py_err)?;
        Options {
            score: spec,
            combine: Combine::from_name(&self.combine).map_err(py_err)?,
            p_match: self.p_match,
            p_reject: self.p_reject,
            align: Alignment {
                max_gap: self.max_gap,
                horizon: self.horizon,
                process_noise: self.process_noise,
                max_still_gap: self.max_still_gap,
            },
            correlation_time: self.correlation_time,
            index: IndexOptions {
                window: self.window,
                same_source: self.same_source,
            },
            inflation: self.inflation,
            model: Model {
                completeness: self.completeness,
                false_tracks: self.false_tracks.clone(),
                cell: self.density_cell,
            },
            inference: Inference {
                exact_limit: self.exact_limit,
                chains: self.chains,
                sweeps: self.sweeps,
                seed: self.posterior_seed,
            },
        }
        .validated()
        .map_err(py_err)
    }
}

/// The result of `associate` and `association_finish`: one row per kept pair (`a < b`, dense
/// track ids, sorted), per track and per connected component, and the parts `association_finish`
/// takes back (`time_cover`, `stats`, `counts`: the dicts of `association_track_summary` and
/// `association_pair_stats`).
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct AssociationOutput {
    /// Per pair: the tracks (dense ids), the combined score and its common instants.
    a: Py<PyArray1<u32>>,
    b: Py<PyArray1<u32>>,
    score: Py<PyArray1<f64>>,
    instants: Py<PyArray1<u32>>,
    /// Per pair: log-likelihood ratio, posterior probability of one object and its standard
    /// error (0 where computed exactly).
    llr: Py<PyArray1<f64>>,
    p_same: Py<PyArray1<f64>>,
    std_error: Py<PyArray1<f64>>,
    /// Per pair: 0 match, 1 borderline, 2 non-match.
    pair_class: Py<PyArray1<u8>>,
    /// Per pair: review order (1 first, 0 not borderline), expected probability mass a decision
    /// settles, and how many other pairs each answer takes out of the borderline band.
    review_rank: Py<PyArray1<u32>>,
    review_gain: Py<PyArray1<f64>>,
    settles_same: Py<PyArray1<u32>>,
    settles_different: Py<PyArray1<u32>>,
    /// Per pair: its connected component (`u32::MAX`: none).
    component: Py<PyArray1<u32>>,
    /// Per track: probability of no partner, object id, source and spread.
    p_alone: Py<PyArray1<f64>>,
    object: Py<PyArray1<u32>>,
    track_source: Py<PyArray1<u32>>,
    track_spread: Py<PyArray1<f64>>,
    /// Candidate pairs the index returned, before those without a common instant were dropped.
    candidates: usize,
    /// Per pair of sources: the covariance inflation used.
    inflation_a: Py<PyArray1<u32>>,
    inflation_b: Py<PyArray1<u32>>,
    inflation: Py<PyArray1<f64>>,
    /// Per source: the share of the picture's objects it is estimated to hold.
    coverage: Py<PyArray1<f64>>,
    /// Per source: the odds of a further track of that source in one object.
    track_breaks: Py<PyArray1<f64>>,
    /// Per source: the share of its reports its AOUs leave in the most complete source's cells.
    false_overlap: Py<PyArray1<f64>>,
    /// Per component: tracks, partitions enumerated (0: sampled), method (0 exact, 1 sampled)
    /// and the largest standard error.
    component_tracks: Py<PyArray1<u32>>,
    component_partitions: Py<PyArray1<u64>>,
    component_method: Py<PyArray1<u8>>,
    component_std_error: Py<PyArray1<f64>>,
    /// The tracks' time cover, as `association_track_summary` returns it.
    time_cover: Py<super::fusion::PyTimeCover>,
    /// The pairs' summaries, as `association_pair_stats` returns them.
    stats: Py<super::fusion::PairStats>,
    /// The picture counts, as `association_track_summary` returns them.
    counts: Py<super::fusion::PictureCounts>,
    /// Per component: taken from the memo given to `association_finish`, not computed again.
    component_reused: Py<PyArray1<bool>>,
    /// Every component's posterior, for `association_finish` to reuse.
    memo: Py<PosteriorMemo>,
}

/// Every component's posterior of an association (opaque), which `association_finish` takes
/// back (`memo=`) to recompute only the components that operator decisions changed.
#[pyclass(frozen, module = "geofeas._core")]
pub struct PosteriorMemo(pub(super) association::posterior::Memo);

#[pymethods]
impl PosteriorMemo {
    fn __len__(&self) -> usize {
        self.0.len()
    }

    fn __repr__(&self) -> String {
        format!("PosteriorMemo({} components)", self.0.len())
    }
}

#[pymethods]
impl AssociationOutput {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "AssociationOutput(pairs={}, tracks={}, components={}, candidates={})",
            self.a.bind(py).len(),
            self.object.bind(py).len(),
            self.component_tracks.bind(py).len(),
            self.candidates
        )
    }
}

/// The result as an `AssociationOutput`.
pub(super) fn result_output(
    py: Python<'_>,
    res: association::Association,
) -> PyResult<AssociationOutput> {
    fn arr<T: numpy::Element>(py: Python<'_>, v: Vec<T>) -> Py<PyArray1<T>> {
        v.into_pyarray(py).unbind()
    }
    let (s_same, s_diff): (Vec<u32>, Vec<u32>) = res.settles.iter().copied().unzip();
    let (ia, (ib, ic)): (Vec<u32>, (Vec<u32>, Vec<f64>)) =
        res.inflation.iter().map(|&(a, b, c)| (a, (b, c))).unzip();
    let comps = &res.components;
    Ok(AssociationOutput {
        a: arr(py, res.a),
        b: arr(py, res.b),
        score: arr(py, res.score),
        instants: arr(py, res.instants),
        llr: arr(py, res.llr),
        p_same: arr(py, res.p_same),
        std_error: arr(py, res.std_error),
        pair_class: arr(py, res.class.iter().map(|&c| c as u8).collect()),
        review_rank: arr(py, res.review_rank),
        review_gain: arr(py, res.review_gain),
        settles_same: arr(py, s_same),
        settles_different: arr(py, s_diff),
        component: arr(py, res.component),
        p_alone: arr(py, res.p_alone),
        object: arr(py, res.object),
        track_source: arr(py, res.tracks.iter().map(|t| t.source).collect()),
        track_spread: arr(py, res.tracks.iter().map(|t| t.spread).collect()),
        candidates: res.candidates,
        inflation_a: arr(py, ia),
        inflation_b: arr(py, ib),
        inflation: arr(py, ic),
        coverage: arr(py, res.coverage),
        track_breaks: arr(py, res.track_breaks),
        false_overlap: arr(py, res.false_overlap),
        component_tracks: arr(py, comps.iter().map(|c| c.tracks).collect()),
        component_partitions: arr(py, comps.iter().map(|c| c.partitions).collect()),
        component_method: arr(py, comps.iter().map(|c| c.method as u8).collect()),
        component_std_error: arr(py, comps.iter().map(|c| c.max_std_error).collect()),
        time_cover: Py::new(py, super::fusion::time_cover(py, res.time_cover))?,
        stats: Py::new(py, super::fusion::pair_stats(py, &res.stats))?,
        counts: Py::new(py, super::fusion::picture_counts(py, &res.counts))?,
        component_reused: arr(py, comps.iter().map(|c| c.reused).collect()),
        memo: Py::new(py, PosteriorMemo(res.memo))?,
    })
}

/// The whole pipeline on `reports` (see `ReportsArg`) with operator `decisions` (see
/// `DecisionsArg`); returns an `AssociationOutput`. `options` holds the keyword arguments of
/// `geofeas.associate` as resolved in Python.
#[pyfunction]
#[pyo3(signature = (reports, decisions, *, options))]
fn associate<'py>(
    py: Python<'py>,
    reports: ReportsArg<'py>,
    decisions: DecisionsArg<'py>,
    options: AssociationArgs,
) -> PyResult<AssociationOutput> {
    let o = options.options()?;
    let dec = decisions.decisions()?;
    let (t, s, tm) = reports.columns()?;
    let (coords, rows, n) = (reports.coords()?, reports.rows()?, reports.n_tracks);
    let res = detached(py, || {
        let r = Reports::new(coords, n, t, s, tm, &rows)?;
        association::associate(&r, &o, &dec, &mut check_signals)
    })?;
    result_output(py, res)
}

/// Candidate pairs `(a, b)` from the R-tree, or by testing every pair of chunks.
#[pyfunction]
#[pyo3(signature = (reports, *, options, brute_force=false))]
fn association_candidates<'py>(
    py: Python<'py>,
    reports: ReportsArg<'py>,
    options: Bound<'py, PyAny>,
    brute_force: bool,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let r = reports.reports()?;
    let align = options.extract::<AlignmentArgs>()?.alignment()?;
    let IndexArgs {
        same_source,
        window,
    } = options.extract()?;
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
    let rule = Combine::from_name(rule).map_err(py_err)?;
    let (g, m, t, off) = (
        slice("g", &g)?,
        slice("m", &m)?,
        slice("time", &time)?,
        slice("offsets", &offsets)?,
    );
    if m.len() != g.len() || t.len() != g.len() {
        return Err(py_err(Error::Invalid(
            "g, m and time must have the same length".into(),
        )));
    }
    for w in off.windows(2) {
        if w[0] > w[1] || w[1] as usize > g.len() {
            return Err(py_err(Error::Invalid(format!(
                "offsets must be non-decreasing and <= {}",
                g.len()
            ))));
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
        return Err(py_err(Error::Invalid(
            "a, b and score must have the same length".into(),
        )));
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

/// The common instants of tracks `a` and `b` (dense ids) as the association aligns them: the
/// times, the squared Mahalanobis distance `d^T S^-1 d` of each instant (`S = R_a + R_b`, before
/// inflation) and both aligned states as `(n, 5)` rows `pos0, pos1, cov_xx, cov_xy, cov_yy`
/// (positions as given: metres or `lat, lon` degrees; covariances in m^2, x east, y north).
#[pyfunction]
#[pyo3(signature = (reports, a, b, *, alignment))]
fn association_pair_instants<'py>(
    py: Python<'py>,
    reports: ReportsArg<'py>,
    a: usize,
    b: usize,
    alignment: AlignmentArgs,
) -> PyResult<PairInstants> {
    let n_tracks = reports.n_tracks;
    for (what, k) in [("a", a), ("b", b)] {
        if k >= n_tracks {
            return Err(py_err(Error::Invalid(format!(
                "{what}: track index {k} is not below n_tracks = {n_tracks}"
            ))));
        }
    }
    let r = reports.reports()?;
    let align = alignment.alignment()?;
    let (t, m, sa, sb) = py.detach(|| {
        let inst = association::align::common_instants(&r, a, b, &align);
        let n = inst.len();
        let (mut t, mut m) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut sa, mut sb) = (Vec::with_capacity(5 * n), Vec::with_capacity(5 * n));
        for i in &inst {
            t.push(i.time);
            m.push(association::gaussian_instant(r.coords, &i.a, &i.b)[0]);
            for (out, s) in [(&mut sa, &i.a), (&mut sb, &i.b)] {
                out.extend_from_slice(&[s.pos[0], s.pos[1], s.cov[0], s.cov[1], s.cov[2]]);
            }
        }
        (t, m, sa, sb)
    });
    let n = t.len();
    Ok(PairInstants {
        time: t.into_pyarray(py).unbind(),
        m: m.into_pyarray(py).unbind(),
        state_a: sa.into_pyarray(py).reshape([n, 5])?.unbind(),
        state_b: sb.into_pyarray(py).reshape([n, 5])?.unbind(),
    })
}

/// The common instants of two tracks as the association aligns them.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PairInstants {
    /// The instants' times.
    time: Py<PyArray1<f64>>,
    /// The squared Mahalanobis distance of each instant.
    m: Py<PyArray1<f64>>,
    /// `(n, 5)`: the aligned states of both tracks, `pos0, pos1, cov_xx, cov_xy, cov_yy`.
    state_a: Py<PyArray2<f64>>,
    state_b: Py<PyArray2<f64>>,
}

#[pymethods]
impl PairInstants {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("PairInstants(instants={})", self.time.bind(py).len())
    }
}

/// The states of every track at the sorted instants `times` at which the engine's alignment
/// gives it one (`geofeas::association::align::states_at`): arrays `track` (dense id), `index`
/// (into `times`) and `state` `(m, 5)` rows `pos0, pos1, cov_xx, cov_xy, cov_yy`, track by
/// track in time order.
#[pyfunction]
#[pyo3(signature = (reports, times, *, alignment))]
fn association_states_at<'py>(
    py: Python<'py>,
    reports: ReportsArg<'py>,
    times: PyReadonlyArray1<'py, f64>,
    alignment: AlignmentArgs,
) -> PyResult<StatesAt> {
    let n_tracks = reports.n_tracks;
    let r = reports.reports()?;
    let align = alignment.alignment()?;
    let grid = slice("times", &times)?;
    if let Some(k) = grid.iter().position(|t| !t.is_finite()) {
        return Err(py_err(
            Error::NonFinite {
                what: "times",
                row: k,
                field: "time",
                value: grid[k],
            }
            .in_argument("times"),
        ));
    }
    if let Some(k) = grid.windows(2).position(|w| w[0] >= w[1]) {
        return Err(py_err(Error::Invalid(format!(
            "argument 'times': must be strictly increasing, got {} then {} at index {}",
            grid[k],
            grid[k + 1],
            k + 1
        ))));
    }
    let per_track: Vec<Vec<(usize, association::State)>> = py.detach(|| {
        use rayon::prelude::*;
        (0..n_tracks)
            .into_par_iter()
            .map(|t| association::align::states_at(&r, t, grid, &align))
            .collect()
    });
    let m: usize = per_track.iter().map(Vec::len).sum();
    let (mut tr, mut ix, mut st) = (
        Vec::with_capacity(m),
        Vec::with_capacity(m),
        Vec::with_capacity(5 * m),
    );
    for (t, states) in per_track.iter().enumerate() {
        for (k, s) in states {
            tr.push(t as u32);
            ix.push(*k as u64);
            st.extend_from_slice(&[s.pos[0], s.pos[1], s.cov[0], s.cov[1], s.cov[2]]);
        }
    }
    Ok(StatesAt {
        track: tr.into_pyarray(py).unbind(),
        index: ix.into_pyarray(py).unbind(),
        state: st.into_pyarray(py).reshape([m, 5])?.unbind(),
    })
}

/// The states of the tracks at given instants, track by track in time order.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct StatesAt {
    /// The track (dense id) of each state.
    track: Py<PyArray1<u32>>,
    /// The index into the instants of each state.
    index: Py<PyArray1<u64>>,
    /// `(m, 5)`: the states, `pos0, pos1, cov_xx, cov_xy, cov_yy`.
    state: Py<PyArray2<f64>>,
}

#[pymethods]
impl StatesAt {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("StatesAt(states={})", self.track.bind(py).len())
    }
}

/// Whether operator decisions are possible together (`association::posterior::check_decisions`):
/// the tracks by `source` code and time span `start`, `end`; decision `k` joins tracks `a[k]`
/// and `b[k]` (`same[k]`) or separates them. `None` if they are, else the decisions involved
/// (indices into `a`: the shortest chain of "same" decisions, then the "different" one) and
/// what is wrong with them.
#[pyfunction]
#[pyo3(signature = (source, start, end, a, b, same))]
fn decisions_contradiction<'py>(
    source: PyReadonlyArray1<'py, u32>,
    start: PyReadonlyArray1<'py, f64>,
    end: PyReadonlyArray1<'py, f64>,
    a: PyReadonlyArray1<'py, u32>,
    b: PyReadonlyArray1<'py, u32>,
    same: PyReadonlyArray1<'py, bool>,
) -> PyResult<Option<(Vec<usize>, String)>> {
    let (src, t0, t1) = (
        slice("source", &source)?,
        slice("start", &start)?,
        slice("end", &end)?,
    );
    let (sa, sb, ss) = (slice("a", &a)?, slice("b", &b)?, slice("same", &same)?);
    if t0.len() != src.len()
        || t1.len() != src.len()
        || sb.len() != sa.len()
        || ss.len() != sa.len()
    {
        return Err(py_err(Error::Invalid(
            "decisions_contradiction: source, start, end must have one row per track and a, b, \
             same one per decision"
                .into(),
        )));
    }
    let tracks: Vec<association::posterior::Track> = (0..src.len())
        .map(|t| association::posterior::Track {
            source: src[t],
            start: t0[t],
            end: t1[t],
            spread: 1.0,
            further: 0.0,
        })
        .collect();
    let decisions: Vec<Decision> = (0..sa.len())
        .map(|k| Decision {
            a: sa[k],
            b: sb[k],
            same: ss[k],
            row: k,
        })
        .collect();
    match association::posterior::check_decisions(&tracks, &decisions) {
        Ok(()) => Ok(None),
        Err(Error::Decisions { rows, reason }) => Ok(Some((rows, reason))),
        Err(e) => Err(py_err(e)),
    }
}

/// Geographic AOU rows `(n, 5)` `lat, lon, rx, ry, bearing` (degrees, metres, degrees clockwise
/// from north) as planar rows `x, y, rx, ry, phi` in the azimuthal-equidistant frame of
/// `origin = (lat, lon)` (`geofeas::association::geodesy::project_aeqd`).
#[pyfunction]
#[pyo3(signature = (aou, origin))]
fn project_aeqd<'py>(
    py: Python<'py>,
    aou: PyReadonlyArray2<'py, f64>,
    origin: (f64, f64),
) -> PyResult<Bound<'py, PyAny>> {
    let rows = rows5(&aou)?;
    let n = rows.len();
    let out = detached(py, || {
        association::geodesy::project_aeqd([origin.0, origin.1], &rows)
            .map_err(|e| e.in_argument("reports"))
    })?;
    let flat: Vec<f64> = out.into_iter().flatten().collect();
    Ok(flat.into_pyarray(py).reshape([n, 5])?.into_any())
}

/// The geodesics (WGS84) from `(lat1, lon1)` to `(lat2, lon2)`, row by row: lengths `s12` (m)
/// and azimuths `azi1` at the first points, `azi2` (forward) at the second (degrees clockwise
/// from north) (`geofeas::association::geodesy::inverse_rows`).
#[pyfunction]
fn geodesic_inverse<'py>(
    py: Python<'py>,
    lat1: PyReadonlyArray1<'py, f64>,
    lon1: PyReadonlyArray1<'py, f64>,
    lat2: PyReadonlyArray1<'py, f64>,
    lon2: PyReadonlyArray1<'py, f64>,
) -> PyResult<GeodesicColumns<'py>> {
    let (a, b, c, d) = (
        slice("lat1", &lat1)?,
        slice("lon1", &lon1)?,
        slice("lat2", &lat2)?,
        slice("lon2", &lon2)?,
    );
    let rows = detached(py, || association::geodesy::inverse_rows(a, b, c, d))?;
    Ok(columns3(py, rows))
}

/// The ends `(lat2, lon2)` (longitude in `[-180, 180)`) of the geodesics (WGS84) of lengths `s12`
/// (m) leaving `(lat1, lon1)` at azimuths `azi1` (degrees clockwise from north), and their forward
/// azimuths `azi2` there (`geofeas::association::geodesy::direct_rows`).
#[pyfunction]
fn geodesic_direct<'py>(
    py: Python<'py>,
    lat1: PyReadonlyArray1<'py, f64>,
    lon1: PyReadonlyArray1<'py, f64>,
    azi1: PyReadonlyArray1<'py, f64>,
    s12: PyReadonlyArray1<'py, f64>,
) -> PyResult<GeodesicColumns<'py>> {
    let (a, b, c, d) = (
        slice("lat1", &lat1)?,
        slice("lon1", &lon1)?,
        slice("azi1", &azi1)?,
        slice("s12", &s12)?,
    );
    let rows = detached(py, || association::geodesy::direct_rows(a, b, c, d))?;
    Ok(columns3(py, rows))
}

type GeodesicColumns<'py> = (
    Bound<'py, numpy::PyArray1<f64>>,
    Bound<'py, numpy::PyArray1<f64>>,
    Bound<'py, numpy::PyArray1<f64>>,
);

fn columns3(py: Python<'_>, rows: Vec<[f64; 3]>) -> GeodesicColumns<'_> {
    let column = |k: usize| rows.iter().map(|r| r[k]).collect::<Vec<f64>>();
    (
        column(0).into_pyarray(py),
        column(1).into_pyarray(py),
        column(2).into_pyarray(py),
    )
}

/// The options of `geofeas.associate`, defined once in the core (`association::schema`): a
/// list of dicts `name`, `default`, `choices`, `help`, in signature order.
#[pyfunction]
fn association_options(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    use geofeas::association::schema::{options, Value};
    options()
        .into_iter()
        .map(|o| {
            let d = PyDict::new(py);
            d.set_item("name", o.name)?;
            match o.default {
                Value::Float(v) => d.set_item("default", v)?,
                Value::Int(v) => d.set_item("default", v)?,
                Value::Bool(v) => d.set_item("default", v)?,
                Value::Text(v) => d.set_item("default", v)?,
            }
            d.set_item("choices", o.choices)?;
            d.set_item("help", o.help)?;
            Ok(d)
        })
        .collect()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(association_options, m)?)?;
    m.add_function(wrap_pyfunction!(associate, m)?)?;
    m.add_class::<AssociationOutput>()?;
    m.add_class::<PosteriorMemo>()?;
    m.add_class::<PairInstants>()?;
    m.add_class::<StatesAt>()?;
    m.add_function(wrap_pyfunction!(association_candidates, m)?)?;
    m.add_function(wrap_pyfunction!(combine_instants, m)?)?;
    m.add_function(wrap_pyfunction!(assign_one_to_one, m)?)?;
    m.add_function(wrap_pyfunction!(association_default_upper, m)?)?;
    m.add_function(wrap_pyfunction!(association_pair_instants, m)?)?;
    m.add_function(wrap_pyfunction!(association_states_at, m)?)?;
    m.add_function(wrap_pyfunction!(project_aeqd, m)?)?;
    m.add_function(wrap_pyfunction!(decisions_contradiction, m)?)?;
    m.add_function(wrap_pyfunction!(geodesic_inverse, m)?)?;
    m.add_function(wrap_pyfunction!(geodesic_direct, m)?)?;
    m.add("WGS84_A", association::geodesy::WGS84_A)?;
    m.add("WGS84_F", association::geodesy::WGS84_F)?;
    Ok(())
}
