//! Bindings of the multiple-hypothesis trilateration tracker (`geofeas_tracking::mht`).

use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::options::{read_one, schema_py};
use super::{check_signals, detached, py_err};
use geofeas::error::Error;
use geofeas_tracking::mht::{
    bootstrap, group_scans, pool, run_one, study_cells, study_runs, trilaterate_gaussian, Cell,
    Detection, Hypothesis, Metrics, Mht, MhtBeam, MhtOptions, MhtRunOptions, MhtStudyOptions,
    Sensor, TrackerKind,
};

fn matrix<'a>(
    what: &'static str,
    arr: &'a PyReadonlyArray2<'_, f64>,
    cols: usize,
) -> PyResult<&'a [f64]> {
    let shape = arr.shape();
    if shape[1] != cols {
        return Err(py_err(Error::Shape {
            what,
            expected: format!("(n, {cols})"),
            got: format!("{shape:?}"),
        }));
    }
    arr.as_slice()
        .map_err(|e| py_err(Error::Invalid(format!("{what}: {e}"))))
}

fn fixed<const N: usize>(
    what: &'static str,
    arr: &PyReadonlyArray1<'_, f64>,
) -> PyResult<[f64; N]> {
    let s = arr
        .as_slice()
        .map_err(|e| Error::Invalid(format!("{what}: {e}")))
        .map_err(py_err)?;
    <[f64; N]>::try_from(s).map_err(|_| {
        py_err(Error::Shape {
            what,
            expected: format!("({N},)"),
            got: format!("({},)", s.len()),
        })
    })
}

/// Sensors from rows `[x, y, boresight, half_beam, max_range, max_range_rate]`.
fn sensors_from(flat: &[f64]) -> geofeas::Result<Vec<Sensor>> {
    flat.chunks_exact(6)
        .enumerate()
        .map(|(i, r)| {
            Sensor {
                position: [r[0], r[1]],
                boresight: r[2],
                half_beam: r[3],
                period: 1.0,
                offset: 0.0,
                max_range: r[4],
                max_range_rate: r[5],
            }
            .validated(i)
        })
        .collect()
}

/// The tracks of a hypothesis as arrays: Cartesian path rows `[id, time, x, y, vx, vy]`, final
/// 2-sigma ellipses `[id, x0, y0, rx, ry, phi]` of the open Cartesian tracks, and the track id of
/// every detection (-1: not in a track).
fn hypothesis_arrays(best: &Hypothesis, n_detections: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut paths = Vec::new();
    let mut ellipses = Vec::new();
    let mut owner = vec![-1.0; n_detections];
    let mut tracks = best.all_tracks();
    tracks.sort_by_key(|t| t.id);
    for t in &tracks {
        for k in t.detections() {
            if k < n_detections {
                owner[k] = t.id as f64;
            }
        }
        for p in t.path() {
            paths.extend_from_slice(&[t.id as f64, p[0], p[1], p[2], p[3], p[4]]);
        }
    }
    for t in &best.tracks {
        if let Some(e) = t.ellipse() {
            ellipses.extend_from_slice(&[t.id as f64, e.x0, e.y0, e.rx, e.ry, e.phi]);
        }
    }
    (paths, ellipses, owner)
}

fn to_2d<'py>(py: Python<'py>, flat: Vec<f64>, cols: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows = flat.len() / cols;
    flat.into_pyarray(py).reshape([rows, cols])
}

/// A state vector and its covariance.
type StateAndCovariance<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

/// Checks that a row-major 2x2 matrix is a covariance: symmetric (to `1e-12` relative) and
/// positive definite.
fn covariance_2x2(c: &[f64]) -> geofeas::Result<()> {
    let scale = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if (c[1] - c[2]).abs() > 1e-12 * scale {
        return Err(Error::NotPositiveDefinite {
            row: 0,
            reason: format!("not symmetric: [0, 1] = {} != [1, 0] = {}", c[1], c[2]),
        });
    }
    let g = geofeas::ellipse::Gaussian::new([0.0, 0.0], [c[0], 0.5 * (c[1] + c[2]), c[3]]);
    g.validated(0).map(|_| ())
}

/// Trilaterates two detections `(r, r')` of sensors at `pos_a`, `pos_b` (beams of half-width
/// `half_beam` along `boresight`); returns the state `(x, y, vx, vy)` and its covariance (eq. 8).
/// Keyword options: those of `mht_options()["beam"]`.
#[pyfunction]
#[pyo3(signature = (pos_a, z_a, cov_a, pos_b, z_b, cov_b, **options))]
fn mht_trilaterate<'py>(
    pos_a: PyReadonlyArray1<'py, f64>,
    z_a: PyReadonlyArray1<'py, f64>,
    cov_a: PyReadonlyArray2<'py, f64>,
    pos_b: PyReadonlyArray1<'py, f64>,
    z_b: PyReadonlyArray1<'py, f64>,
    cov_b: PyReadonlyArray2<'py, f64>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<StateAndCovariance<'py>> {
    let py = pos_a.py();
    let MhtBeam {
        boresight,
        half_beam,
    } = read_one::<MhtBeam>(options)?;
    let sensor = |p: [f64; 2], row| {
        Sensor {
            position: p,
            boresight,
            half_beam,
            ..Sensor::paper(0.0, 1.0)
        }
        .validated(row)
    };
    let a = sensor(fixed::<2>("pos_a", &pos_a)?, 0).map_err(py_err)?;
    let b = sensor(fixed::<2>("pos_b", &pos_b)?, 1).map_err(py_err)?;
    let za = fixed::<2>("z_a", &z_a)?;
    let zb = fixed::<2>("z_b", &z_b)?;
    let ca = matrix("cov_a", &cov_a, 2)?;
    let cb = matrix("cov_b", &cov_b, 2)?;
    if ca.len() != 4 || cb.len() != 4 {
        return Err(py_err(Error::Shape {
            what: "cov_a / cov_b",
            expected: "(2, 2)".into(),
            got: format!("{:?} / {:?}", cov_a.shape(), cov_b.shape()),
        }));
    }
    for (what, v) in [
        ("z_a", &za[..]),
        ("z_b", &zb[..]),
        ("cov_a", ca),
        ("cov_b", cb),
    ] {
        if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(py_err(
                Error::NonFinite {
                    what: "value",
                    row: i,
                    field: what,
                    value: *x,
                }
                .in_argument(what),
            ));
        }
    }
    for (what, c) in [("cov_a", ca), ("cov_b", cb)] {
        covariance_2x2(c)
            .map_err(|e| e.in_argument(what))
            .map_err(py_err)?;
    }
    let m = |c: &[f64]| nalgebra::Matrix2::new(c[0], c[1], c[2], c[3]);
    let (x, p) = trilaterate_gaussian(&a, za.into(), &m(ca), &b, zb.into(), &m(cb))
        .ok_or_else(|| {
            Error::Invalid(
                "no trilateration: the range circles do not intersect in front of both sensors, \
                 or the lines of sight are parallel"
                    .into(),
            )
        })
        .map_err(py_err)?;
    let state = x.as_slice().to_vec().into_pyarray(py);
    // nalgebra is column-major; the covariance is symmetric, transpose for clarity anyway.
    let cov = to_2d(py, p.transpose().as_slice().to_vec(), 4)?;
    Ok((state, cov))
}

/// Tracks detection rows `[time, sensor, range, range_rate]` (sorted by time) from sensors rows
/// `[x, y, boresight, half_beam, max_range, max_range_rate]`.
/// Keyword options: those of `mht_options()["tracker"]`.
#[pyfunction]
#[pyo3(signature = (detections, sensors, **options))]
fn mht_track<'py>(
    py: Python<'py>,
    detections: PyReadonlyArray2<'py, f64>,
    sensors: PyReadonlyArray2<'py, f64>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<MhtTrack> {
    let config = read_one::<MhtOptions>(options)?.config().map_err(py_err)?;
    let flat = matrix("detections", &detections, 4)?;
    let sens = sensors_from(matrix("sensors", &sensors, 6)?).map_err(py_err)?;
    let mut dets = Vec::with_capacity(flat.len() / 4);
    for (row, r) in flat.chunks_exact(4).enumerate() {
        let s = r[1];
        if !(s.is_finite() && s >= 0.0 && s.fract() == 0.0 && (s as usize) < sens.len()) {
            return Err(py_err(Error::Invalid(format!(
                "detection row {row}: sensor {s} is not an index of the {} sensors",
                sens.len()
            ))));
        }
        dets.push(Detection {
            time: r[0],
            sensor: s as usize,
            scan: 0,
            range: r[2],
            range_rate: r[3],
            target: None,
        });
    }
    let n = dets.len();
    let (best, probability) = detached(py, move || {
        let scans = group_scans(&mut dets)?;
        let mut mht = Mht::new(sens, config)?;
        mht.run(&scans, &dets, |_, _, _| {})?;
        let best = mht.best().clone();
        Ok((best.clone(), best.probability()))
    })?;
    let (paths, ellipses, owner) = hypothesis_arrays(&best, n);
    Ok(MhtTrack {
        tracks: to_2d(py, paths, 6)?.unbind(),
        ellipses: to_2d(py, ellipses, 6)?.unbind(),
        track_of_detection: owner.into_pyarray(py).unbind(),
        probability,
    })
}

/// The tracks of the most likely hypothesis after a stream of detections.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct MhtTrack {
    /// Rows `[id, time, x, y, vx, vy]`: every Cartesian update of every track.
    tracks: Py<PyArray2<f64>>,
    /// Rows `[id, x0, y0, rx, ry, phi]`: 2-sigma AOU of the open Cartesian tracks.
    ellipses: Py<PyArray2<f64>>,
    /// The track id of every detection, -1 for none.
    track_of_detection: Py<PyArray1<f64>>,
    /// Probability of the hypothesis among those kept.
    probability: f64,
}

#[pymethods]
impl MhtTrack {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "MhtTrack(updates={}, ellipses={}, detections={}, probability={})",
            self.tracks.bind(py).shape()[0],
            self.ellipses.bind(py).shape()[0],
            self.track_of_detection.bind(py).len(),
            self.probability
        )
    }
}

/// One simulated and tracked run of a paper scenario.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct MhtRun {
    /// Rows `[time, sensor, range, range_rate, target, track]` (target -1: false alarm; track
    /// -1: in no track of the final most likely hypothesis).
    detections: Py<PyArray2<f64>>,
    /// As in `MhtTrack`.
    tracks: Py<PyArray2<f64>>,
    ellipses: Py<PyArray2<f64>>,
    /// Rows `[target, time, x, y, vx, vy]` every 0.05 s.
    truth: Py<PyArray2<f64>>,
    /// Rows `[x, y]`: the sensors' positions.
    sensors: Py<PyArray2<f64>>,
    /// `(metrics,)`: the run's metrics in the order of `mht_metric_names()`.
    metrics: Py<PyArray1<f64>>,
    /// Seconds simulated.
    duration: f64,
}

#[pymethods]
impl MhtRun {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "MhtRun(detections={}, updates={}, sensors={}, duration={})",
            self.detections.bind(py).shape()[0],
            self.tracks.bind(py).shape()[0],
            self.sensors.bind(py).shape()[0],
            self.duration
        )
    }
}

/// The Monte-Carlo study of Tables 1 and 2: one row per cell, every metric pooled over the
/// cell's runs with its percentile-bootstrap interval.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct MhtStudy {
    /// The cells: tracker name, sensors, targets and false alarms per sensor per scan.
    tracker: Vec<&'static str>,
    sensors: Py<PyArray1<i64>>,
    targets: Py<PyArray1<i64>>,
    false_alarms: Py<PyArray1<i64>>,
    /// `(rows, metrics)`: columns in the order of `mht_metric_names()`.
    metrics: Py<PyArray2<f64>>,
    /// `(rows, metrics)`: the intervals' lower and upper bounds.
    metrics_lo: Py<PyArray2<f64>>,
    metrics_hi: Py<PyArray2<f64>>,
}

#[pymethods]
impl MhtStudy {
    fn __repr__(&self, py: Python<'_>) -> String {
        let s = self.metrics.bind(py).shape();
        format!("MhtStudy(rows={}, metrics={})", s[0], s[1])
    }
}

/// Simulates and tracks one run of a paper scenario; returns detections, tracks, ellipses, truth
/// and metrics.
/// Keyword options: those of `mht_options()["run"]`.
#[pyfunction]
#[pyo3(signature = (**options))]
fn mht_simulate_run<'py>(
    py: Python<'py>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<MhtRun> {
    let r = read_one::<MhtRunOptions>(options)?;
    let opts = r.study_options().map_err(py_err)?;
    let cell = Cell {
        targets: r.targets,
        sensors: r.sensors,
        tracker: r.tracker,
        false_alarms: r.false_alarms,
    };
    let run = r.run;
    let o = detached(py, move || run_one(&cell, &opts, run))?;
    let n = o.detections.len();
    let (paths, ellipses, owner) = hypothesis_arrays(&o.best, n);
    let mut det_rows = Vec::with_capacity(n * 6);
    for (d, own) in o.detections.iter().zip(&owner) {
        det_rows.extend_from_slice(&[
            d.time,
            d.sensor as f64,
            d.range,
            d.range_rate,
            d.target.map_or(-1.0, |t| t as f64),
            *own,
        ]);
    }
    let mut truth = Vec::new();
    let steps = (o.scenario.duration / 0.05).round() as usize;
    for (k, tr) in o.scenario.targets.iter().enumerate() {
        for i in 0..=steps {
            let t = i as f64 * 0.05;
            let s = tr.state(t);
            truth.extend_from_slice(&[k as f64, t, s[0], s[1], s[2], s[3]]);
        }
    }
    let sens: Vec<f64> = o
        .scenario
        .sensors
        .iter()
        .flat_map(|s| [s.position[0], s.position[1]])
        .collect();
    let metrics = o
        .tally
        .metrics()
        .values()
        .to_vec()
        .into_pyarray(py)
        .unbind();
    Ok(MhtRun {
        detections: to_2d(py, det_rows, 6)?.unbind(),
        tracks: to_2d(py, paths, 6)?.unbind(),
        ellipses: to_2d(py, ellipses, 6)?.unbind(),
        truth: to_2d(py, truth, 6)?.unbind(),
        sensors: to_2d(py, sens, 2)?.unbind(),
        metrics,
        duration: o.scenario.duration,
    })
}

/// The Monte-Carlo study of Tables 1 and 2: one row per cell (tracker x sensors x targets x
/// false alarms), every metric with its percentile-bootstrap confidence interval over runs.
/// Keyword options: those of `mht_options()["study"]`.
#[pyfunction]
#[pyo3(signature = (**options))]
fn mht_study<'py>(py: Python<'py>, options: Option<&Bound<'py, PyDict>>) -> PyResult<MhtStudy> {
    let o = read_one::<MhtStudyOptions>(options)?;
    let opts = o.study_options().map_err(py_err)?;
    let (seed, resamples, level) = (o.sim.seed, o.resamples, o.level);
    let kinds = o.trackers.0;
    let (one_target, two_targets) = (o.one_target, o.two_targets);
    let cells = study_cells(&kinds, &one_target, &two_targets);
    let rows = detached(py, || {
        let per_cell = study_runs(&cells, &opts, &mut check_signals)?;
        Ok::<_, Error>(
            per_cell
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let (lo, hi) = bootstrap(r, resamples, level, seed ^ i as u64);
                    (pool(r).metrics().values(), lo, hi)
                })
                .collect::<Vec<_>>(),
        )
    })?;
    let n = rows.len();
    let ints = |f: fn(&Cell) -> usize| -> Py<PyArray1<i64>> {
        cells
            .iter()
            .map(|c| f(c) as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .unbind()
    };
    type Row = ([f64; 12], [f64; 12], [f64; 12]);
    let table = |pick: fn(&Row) -> &[f64; 12]| -> PyResult<Py<PyArray2<f64>>> {
        let flat: Vec<f64> = rows.iter().flat_map(|r| *pick(r)).collect();
        Ok(flat
            .into_pyarray(py)
            .reshape([n, Metrics::NAMES.len()])?
            .unbind())
    };
    Ok(MhtStudy {
        tracker: cells.iter().map(|c| c.tracker.name()).collect(),
        sensors: ints(|c| c.sensors),
        targets: ints(|c| c.targets),
        false_alarms: ints(|c| c.false_alarms),
        metrics: table(|r| &r.0)?,
        metrics_lo: table(|r| &r.1)?,
        metrics_hi: table(|r| &r.2)?,
    })
}

/// Names of the study's trackers.
#[pyfunction]
fn mht_tracker_names() -> Vec<&'static str> {
    TrackerKind::ALL.iter().map(TrackerKind::name).collect()
}

/// Names of the study's metrics, in table order.
#[pyfunction]
fn mht_metric_names() -> Vec<&'static str> {
    Metrics::NAMES.to_vec()
}

/// Rows `[id, time, x, y, vx, vy, P upper triangle (10, row by row), contacts, sensors]` of the
/// Cartesian open tracks of `h`, by track id.
fn estimate_rows(h: &Hypothesis) -> Vec<f64> {
    let mut tracks: Vec<_> = h.tracks.iter().filter(|t| t.is_cartesian()).collect();
    tracks.sort_by_key(|t| t.id);
    let mut rows = Vec::with_capacity(tracks.len() * ESTIMATE_COLUMNS);
    for t in tracks {
        if let Some(c) = t.cartesian() {
            rows.extend_from_slice(&[t.id as f64, c.time, c.x[0], c.x[1], c.x[2], c.x[3]]);
            for i in 0..4 {
                for j in i..4 {
                    rows.push(0.5 * (c.p[(i, j)] + c.p[(j, i)]));
                }
            }
            rows.extend_from_slice(&[t.contacts as f64, t.sensor_count() as f64]);
        }
    }
    rows
}

const ESTIMATE_COLUMNS: usize = 18;

/// A multiple-hypothesis trilateration tracker fed one scan at a time (seed 004, Reid's
/// measurement-oriented MHT). Sensors are rows `[x, y, boresight, half_beam, max_range,
/// max_range_rate]`; options as in `mht_track`.
#[pyclass(name = "MhtTracker", module = "geofeas._core")]
pub struct PyMhtTracker {
    mht: Mht,
    detections: usize,
}

#[pymethods]
impl PyMhtTracker {
    /// Keyword options: those of `mht_options()["tracker"]`.
    #[new]
    #[pyo3(signature = (sensors, **options))]
    fn new(
        sensors: PyReadonlyArray2<'_, f64>,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let config = read_one::<MhtOptions>(options)?.config().map_err(py_err)?;
        let sens = sensors_from(matrix("sensors", &sensors, 6)?).map_err(py_err)?;
        Ok(Self {
            mht: Mht::new(sens, config).map_err(py_err)?,
            detections: 0,
        })
    }

    /// Processes the scan of `sensor` at `time` with detection rows `[range, range_rate]` (an
    /// empty `(0, 2)` array for a scan without detections: every track the sensor could see is
    /// then charged `1 - P_D`). Returns the index of the scan's first detection in the stream.
    fn process_scan(
        &mut self,
        py: Python<'_>,
        time: f64,
        sensor: usize,
        detections: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<usize> {
        let flat = matrix("detections", &detections, 2)?;
        let first = self.detections;
        let batch: Vec<(usize, Detection)> = flat
            .chunks_exact(2)
            .enumerate()
            .map(|(k, r)| {
                (
                    first + k,
                    Detection {
                        time,
                        sensor,
                        scan: 0,
                        range: r[0],
                        range_rate: r[1],
                        target: None,
                    },
                )
            })
            .collect();
        let n = batch.len();
        let mht = &mut self.mht;
        detached(py, move || mht.process_scan(time, sensor, &batch))?;
        self.detections += n;
        Ok(first)
    }

    /// Number of scans processed.
    #[getter]
    fn scans(&self) -> usize {
        self.mht.scans()
    }

    /// Number of detections processed.
    #[getter]
    fn detections(&self) -> usize {
        self.detections
    }

    /// Cartesian tracks of the hypothesis of rank `rank` (0: the most likely), rows
    /// `[id, time, x, y, vx, vy, P upper triangle (10), contacts, sensors]`.
    #[pyo3(signature = (rank=0))]
    fn estimates<'py>(&self, py: Python<'py>, rank: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let h = self
            .mht
            .hypotheses()
            .get(rank)
            .ok_or_else(|| Error::InvalidOption {
                name: "rank",
                reason: format!(
                    "{rank} is not below the {} kept hypotheses",
                    self.mht.hypotheses().len()
                ),
            })
            .map_err(py_err)?;
        to_2d(py, estimate_rows(h), ESTIMATE_COLUMNS)
    }

    /// The `top` most likely hypotheses: `(probability, estimates, open track ids)` each, with
    /// the estimates as in `estimates` and the ids of all open tracks (range-Doppler included).
    #[pyo3(signature = (top=5))]
    #[allow(clippy::type_complexity)]
    fn hypotheses<'py>(
        &self,
        py: Python<'py>,
        top: usize,
    ) -> PyResult<Vec<(f64, Bound<'py, PyArray2<f64>>, Vec<usize>)>> {
        self.mht
            .hypotheses()
            .iter()
            .take(top)
            .map(|h| {
                let mut ids: Vec<usize> = h.tracks.iter().map(|t| t.id).collect();
                ids.sort_unstable();
                Ok((
                    h.probability(),
                    to_2d(py, estimate_rows(h), ESTIMATE_COLUMNS)?,
                    ids,
                ))
            })
            .collect()
    }

    /// The track id of every detection processed so far in the most likely hypothesis (-1: not
    /// in a track, i.e. a false alarm there).
    fn track_of_detection<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let (_, _, owner) = hypothesis_arrays(self.mht.best(), self.detections);
        owner.into_pyarray(py)
    }
}

/// The option sets of the MHT: `{"tracker", "run", "study", "beam"}` to lists of
/// `(name, kind, default, doc, choices)`, in declaration order.
#[pyfunction]
fn mht_options(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("tracker", schema_py::<MhtOptions>(py)?)?;
    out.set_item("run", schema_py::<MhtRunOptions>(py)?)?;
    out.set_item("study", schema_py::<MhtStudyOptions>(py)?)?;
    out.set_item("beam", schema_py::<MhtBeam>(py)?)?;
    Ok(out)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(mht_options, m)?)?;
    m.add_function(wrap_pyfunction!(mht_trilaterate, m)?)?;
    m.add_function(wrap_pyfunction!(mht_track, m)?)?;
    m.add_function(wrap_pyfunction!(mht_simulate_run, m)?)?;
    m.add_function(wrap_pyfunction!(mht_study, m)?)?;
    m.add_function(wrap_pyfunction!(mht_metric_names, m)?)?;
    m.add_function(wrap_pyfunction!(mht_tracker_names, m)?)?;
    m.add_class::<PyMhtTracker>()?;
    m.add_class::<MhtTrack>()?;
    m.add_class::<MhtRun>()?;
    m.add_class::<MhtStudy>()?;
    Ok(())
}
