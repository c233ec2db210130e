//! Bindings of the particle-filter focal-plane tracker (`geofeas_tracking::pf`).

use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyArray4, PyArrayMethods, PyReadonlyArray2,
    PyReadonlyArray3, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::options::{read_one, read_two, schema_py};
use super::{check_signals, detached, py_err};
use geofeas::error::{Error, Result};
use geofeas::rng::stream;
use geofeas_tracking::pf::{
    find_peaks, peak_label, study, track_frames, track_truth, Bank, BankMetrics, Cell, CellResult,
    FilterMetrics, Frame, LikelihoodModel, Method, Particles, PeakOptions, PfOptions, PfRunOptions,
    PfStudyOptions, PfTrackOptions, Psf, RunSpec, Scenario, Step, StudyOptions,
};

/// An `(n, 2)` array of finite points as its flat buffer; errors name the array, row and field.
fn points2<'a>(what: &'static str, arr: &'a PyReadonlyArray2<'_, f64>) -> PyResult<&'a [f64]> {
    let shape = arr.shape();
    if shape[1] != 2 {
        return Err(py_err(Error::Shape {
            what,
            expected: "(n, 2)".into(),
            got: format!("{shape:?}"),
        }));
    }
    let flat = arr
        .as_slice()
        .map_err(|e| Error::Invalid(format!("{what}: {e}")))
        .map_err(py_err)?;
    if let Some(k) = flat.iter().position(|v| !v.is_finite()) {
        return Err(py_err(Error::Invalid(format!(
            "{what} row {}: field '{}' is not finite ({})",
            k / 2,
            ["x", "y"][k % 2],
            flat[k]
        ))));
    }
    Ok(flat)
}

/// The interrupt hook of the frame loop: Ctrl-C is checked every tenth frame.
fn every_tenth_frame() -> impl FnMut() -> bool {
    let mut k = 0usize;
    move || {
        k += 1;
        (k - 1) % 10 == 0 && check_signals()
    }
}

fn frame_from(what: &'static str, arr: &PyReadonlyArray2<'_, f64>) -> Result<Frame> {
    let shape = arr.shape();
    let data = arr
        .as_slice()
        .map_err(|e| Error::Invalid(format!("{what}: {e}")))?;
    Frame::new(shape[1], shape[0], data.to_vec())
}

/// Per-frame outputs of a bank, as flat arrays.
#[derive(Default)]
struct Recorder {
    filters: usize,
    k: usize,
    est: Vec<f64>,
    cov: Vec<f64>,
    peaks: Vec<f64>,
    peak: Vec<i64>,
    dist: Vec<f64>,
    resid: Vec<f64>,
    ess: Vec<f64>,
    frames: usize,
}

impl Recorder {
    fn new(filters: usize, k: usize) -> Self {
        Self {
            filters,
            k,
            ..Self::default()
        }
    }

    fn push(&mut self, step: &Step) {
        self.frames += 1;
        for j in 0..self.k {
            match step.peaks.get(j) {
                Some(p) => self.peaks.extend_from_slice(&[p.x, p.y, p.value]),
                None => self.peaks.extend_from_slice(&[f64::NAN; 3]),
            }
        }
        for r in &step.filters {
            self.est.extend_from_slice(&r.estimate.mean);
            for row in &r.estimate.cov {
                self.cov.extend_from_slice(row);
            }
            self.peak.push(r.peak.map_or(-1, |j| j as i64));
            for j in 0..self.k {
                self.dist
                    .push(r.distances.get(j).copied().unwrap_or(f64::NAN));
            }
            self.resid.extend_from_slice(&r.residual);
            self.ess.push(r.ess);
        }
    }

    fn into_track(self, py: Python<'_>) -> PyResult<PfTrack> {
        let (f, t, k) = (self.frames, self.filters, self.k);
        Ok(PfTrack {
            estimates: self.est.into_pyarray(py).reshape([f, t, 4])?.unbind(),
            covariances: self.cov.into_pyarray(py).reshape([f, t, 4, 4])?.unbind(),
            peaks: self.peaks.into_pyarray(py).reshape([f, k, 3])?.unbind(),
            peak: self.peak.into_pyarray(py).reshape([f, t])?.unbind(),
            distances: self.dist.into_pyarray(py).reshape([f, t, k])?.unbind(),
            residuals: self.resid.into_pyarray(py).reshape([f, t, 2])?.unbind(),
            ess: self.ess.into_pyarray(py).reshape([f, t])?.unbind(),
        })
    }
}

/// What a bank of filters did on each of `F` frames: `T` filters, `K` peaks per frame.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PfTrack {
    /// `(F, T, 4)`: each filter's posterior mean `x, y, vx, vy`.
    estimates: Py<PyArray3<f64>>,
    /// `(F, T, 4, 4)`: each filter's posterior covariance.
    covariances: Py<PyArray4<f64>>,
    /// `(F, K, 3)`: the frame's peaks `x, y, intensity`, NaN rows when fewer.
    peaks: Py<PyArray3<f64>>,
    /// `(F, T)`: the peak each filter took, -1 for none.
    peak: Py<PyArray2<i64>>,
    /// `(F, T, K)`: distance of each filter to each peak (`R_i^j`).
    distances: Py<PyArray3<f64>>,
    /// `(F, T, 2)`: each filter's residual (Fig. 12 mean and sd).
    residuals: Py<PyArray3<f64>>,
    /// `(F, T)`: each filter's effective sample size.
    ess: Py<PyArray2<f64>>,
}

#[pymethods]
impl PfTrack {
    fn __repr__(&self, py: Python<'_>) -> String {
        let s = self.distances.bind(py).shape();
        format!("PfTrack(frames={}, filters={}, peaks={})", s[0], s[1], s[2])
    }
}

/// One simulated run of the paper's scenario and its track: `F` frames, `T` targets.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PfRun {
    /// What the filters did on the run's frames.
    track: Py<PfTrack>,
    /// `(F, T, 8)`: each target's `x, y, vx, vy, speed, heading, a_L, a_N`.
    truth: Py<PyArray3<f64>>,
    /// `(F, T)`: the peak a filter took is nearest to its own target.
    correct: Py<PyArray2<bool>>,
    /// `(n, 4)` rows `[frame, filter, x, y]`: resampled particles at the snapshot frames.
    snapshots: Py<PyArray2<f64>>,
    /// `(len(keep_frames), H, W)`: the kept frames' images.
    frames: Py<PyArray3<f64>>,
    /// The sensor's noise 1-sigma.
    sigma_z: f64,
    /// Seconds between frames.
    dt: f64,
    /// The seed of the filters' particles (`pf_track` with it reproduces the run).
    filter_seed: u64,
}

#[pymethods]
impl PfRun {
    fn __repr__(&self, py: Python<'_>) -> String {
        let s = self.truth.bind(py).shape();
        format!(
            "PfRun(frames={}, targets={}, snapshots={}, kept_frames={})",
            s[0],
            s[1],
            self.snapshots.bind(py).shape()[0],
            self.frames.bind(py).shape()[0]
        )
    }
}

/// Simulates one run of the paper's scenario and tracks it; keyword options are those of
/// `pf_options()["run"]` and `pf_options()["filter"]`.
#[pyfunction]
#[pyo3(signature = (**options))]
fn pf_simulate_run<'py>(py: Python<'py>, options: Option<&Bound<'py, PyDict>>) -> PyResult<PfRun> {
    let (run, filter) = read_two::<PfRunOptions, PfOptions>(options)?;
    if run.snapshot_particles == 0 {
        return Err(py_err(Error::InvalidOption {
            name: "snapshot_particles",
            reason: "must be >= 1".into(),
        }));
    }
    let spec = RunSpec {
        scenario: Scenario {
            model: run.truth.model(),
            ..Scenario::paper()
        },
        ..RunSpec::paper(run.snr_db, run.seed, run.run)
    }
    .validated()
    .map_err(py_err)?;
    let cfg = filter
        .config(run.method, &spec.psf, spec.sigma_z(), spec.scenario.dt)
        .map_err(py_err)?;
    let PfRunOptions {
        snapshot_frames,
        snapshot_particles,
        keep_frames,
        ..
    } = run;
    let n_frames = spec.scenario.frames();
    for &k in snapshot_frames.iter().chain(&keep_frames) {
        if k >= n_frames {
            return Err(py_err(Error::InvalidOption {
                name: "snapshot_frames / keep_frames",
                reason: format!("frame {k} is not in 0..{n_frames}"),
            }));
        }
    }
    let targets = spec.scenario.starts.len();
    let (width, height, dt, sigma_z, filter_seed) = (
        spec.scenario.width,
        spec.scenario.height,
        spec.scenario.dt,
        spec.sigma_z(),
        spec.filter_seed(),
    );
    let (rec, truth_rows, correct, snaps, kept) = detached(py, move || {
        let truth = spec.truth();
        let mut rec = Recorder::new(targets, cfg.peaks.count);
        let mut correct = Vec::with_capacity(n_frames * targets);
        let mut snaps = Vec::new();
        let mut kept = Vec::new();
        track_truth(
            &spec,
            &truth,
            &[cfg],
            |_, k, frame, step, bank| {
                for (i, r) in step.filters.iter().enumerate() {
                    let ok = r
                        .peak
                        .is_some_and(|j| peak_label(&step.peaks[j], &truth.states[k]) == Some(i));
                    correct.push(ok);
                }
                rec.push(step);
                // The cloud after this frame's resampling: the equally weighted posterior.
                if snapshot_frames.contains(&k) {
                    for i in 0..targets {
                        let p: &Particles = bank.particles(i);
                        let m = snapshot_particles.min(p.len()).max(1);
                        let stride = (p.len() / m).max(1);
                        for n in (0..p.len()).step_by(stride).take(m) {
                            snaps.extend_from_slice(&[k as f64, i as f64, p.x[n], p.y[n]]);
                        }
                    }
                }
                if keep_frames.contains(&k) {
                    kept.extend_from_slice(&frame.data);
                }
            },
            &mut every_tenth_frame(),
        )?;
        let mut rows = Vec::with_capacity(n_frames * targets * 8);
        for row in &truth.states {
            for s in row {
                rows.extend_from_slice(&[s.x, s.y, s.vx, s.vy, s.speed, s.heading, s.a_l, s.a_n]);
            }
        }
        Ok((rec, rows, correct, snaps, kept))
    })?;
    let f = rec.frames;
    let ns = snaps.len() / 4;
    let nk = kept.len() / (width * height);
    Ok(PfRun {
        track: Py::new(py, rec.into_track(py)?)?,
        truth: truth_rows
            .into_pyarray(py)
            .reshape([f, targets, 8])?
            .unbind(),
        correct: correct.into_pyarray(py).reshape([f, targets])?.unbind(),
        snapshots: snaps.into_pyarray(py).reshape([ns, 4])?.unbind(),
        frames: kept.into_pyarray(py).reshape([nk, height, width])?.unbind(),
        sigma_z,
        dt,
        filter_seed,
    })
}

/// Tracks user frames `(F, H, W)` with one filter per row of `init` (`x, y, vx, vy`); keyword
/// options are those of `pf_options()["track"]` and `pf_options()["filter"]`.
#[pyfunction]
#[pyo3(signature = (frames, init, *, sigma_z, **options))]
fn pf_track<'py>(
    py: Python<'py>,
    frames: PyReadonlyArray3<'py, f64>,
    init: PyReadonlyArray2<'py, f64>,
    sigma_z: f64,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<PfTrack> {
    let (opts, filter) = read_two::<PfTrackOptions, PfOptions>(options)?;
    let PfTrackOptions {
        method,
        amplitude,
        blur,
        dt,
        seed,
    } = opts;
    let psf = Psf { amplitude, blur }.validated("psf").map_err(py_err)?;
    if !(sigma_z.is_finite() && sigma_z > 0.0) {
        return Err(py_err(Error::InvalidOption {
            name: "sigma_z",
            reason: format!("must be finite and > 0, got {sigma_z}"),
        }));
    }
    let cfg = filter.config(method, &psf, sigma_z, dt).map_err(py_err)?;
    let shape = frames.shape().to_vec();
    let (h, w) = (shape[1], shape[2]);
    if h == 0 || w == 0 {
        return Err(py_err(Error::Shape {
            what: "frames",
            expected: "(F, H, W) with H, W >= 1".into(),
            got: format!("{shape:?}"),
        }));
    }
    let data = frames
        .as_slice()
        .map_err(|e| Error::Invalid(format!("frames: {e}")))
        .map_err(py_err)?;
    if let Some(k) = data.iter().position(|v| !v.is_finite()) {
        return Err(py_err(Error::Invalid(format!(
            "frames: value at frame {} row {} column {} is not finite ({})",
            k / (h * w),
            (k / w) % h,
            k % w,
            data[k]
        ))));
    }
    let ishape = init.shape();
    if ishape[1] != 4 {
        return Err(py_err(Error::Shape {
            what: "init",
            expected: "(n, 4) with columns x, y, vx, vy".into(),
            got: format!("{ishape:?}"),
        }));
    }
    let flat = init
        .as_slice()
        .map_err(|e| Error::Invalid(format!("init: {e}")))
        .map_err(py_err)?;
    let init: Vec<[f64; 4]> = flat
        .chunks_exact(4)
        .map(|r| [r[0], r[1], r[2], r[3]])
        .collect();
    let targets = init.len();
    let rec = detached(py, move || {
        let mut rec = Recorder::new(targets, cfg.peaks.count);
        let frames = data.chunks_exact(h * w).map(|chunk| Frame {
            width: w,
            height: h,
            data: chunk.to_vec(),
        });
        track_frames(
            &mut [Bank::new(&init, cfg, seed)?],
            frames,
            |_, _, _, step, _| rec.push(step),
            &mut every_tenth_frame(),
        )?;
        Ok(rec)
    })?;
    rec.into_track(py)
}

/// Method 2 log weights of particles `xy` `(N, 2)` on `frame` `(H, W)` with the filter model
/// `(amplitude, blur, sigma, half_box)`.
#[pyfunction]
#[pyo3(signature = (frame, xy, *, amplitude, blur, sigma, half_box=10))]
fn pf_log_weights<'py>(
    py: Python<'py>,
    frame: PyReadonlyArray2<'py, f64>,
    xy: PyReadonlyArray2<'py, f64>,
    amplitude: f64,
    blur: f64,
    sigma: f64,
    half_box: usize,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let f = frame_from("frame", &frame).map_err(py_err)?;
    let model = LikelihoodModel {
        amplitude,
        blur,
        sigma,
        half_box,
    }
    .validated()
    .map_err(py_err)?;
    let flat = points2("xy", &xy)?;
    let p = Particles {
        x: flat.iter().step_by(2).copied().collect(),
        y: flat.iter().skip(1).step_by(2).copied().collect(),
        vx: vec![0.0; flat.len() / 2],
        vy: vec![0.0; flat.len() / 2],
    };
    let out = detached(py, move || {
        let mut out = vec![0.0; p.len()];
        model.log_weights(&f, &p, &mut out, true);
        Ok(out)
    })?;
    Ok(out.into_pyarray(py))
}

/// Peaks `(K, 3)` rows `[x, y, value]` of `frame`, strongest first.
#[pyfunction]
#[pyo3(signature = (frame, *, count=4, min_separation=3.0, smoothing=0.0))]
fn pf_peaks<'py>(
    py: Python<'py>,
    frame: PyReadonlyArray2<'py, f64>,
    count: usize,
    min_separation: f64,
    smoothing: f64,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let f = frame_from("frame", &frame).map_err(py_err)?;
    let opts = PeakOptions {
        count,
        min_separation,
        smoothing,
    }
    .validated()
    .map_err(py_err)?;
    let peaks = detached(py, move || Ok(find_peaks(&f, &opts)))?;
    let flat: Vec<f64> = peaks.iter().flat_map(|p| [p.x, p.y, p.value]).collect();
    flat.into_pyarray(py).reshape([peaks.len(), 3])
}

/// A simulated frame `(height, width)` of point spreads at `positions` `(T, 2)` plus noise.
#[pyfunction]
#[pyo3(signature = (positions, *, width=256, height=256, amplitude=1.0, blur=2.0, sigma=0.1, seed=0))]
fn pf_render<'py>(
    positions: PyReadonlyArray2<'py, f64>,
    width: usize,
    height: usize,
    amplitude: f64,
    blur: f64,
    sigma: f64,
    seed: u64,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let psf = Psf { amplitude, blur }.validated("psf").map_err(py_err)?;
    if !(sigma.is_finite() && sigma >= 0.0) {
        return Err(py_err(Error::InvalidOption {
            name: "sigma",
            reason: format!("must be finite and >= 0, got {sigma}"),
        }));
    }
    if width == 0 || height == 0 || width.checked_mul(height).map_or(true, |n| n > 1 << 26) {
        return Err(py_err(Error::InvalidOption {
            name: "width / height",
            reason: format!("must be >= 1 and at most 2^26 cells, got {width} x {height}"),
        }));
    }
    let flat = points2("positions", &positions)?;
    let pos: Vec<[f64; 2]> = flat.chunks_exact(2).map(|r| [r[0], r[1]]).collect();
    let py = positions.py();
    let f = detached(py, move || {
        Ok(Frame::render(
            width,
            height,
            &pos,
            &psf,
            sigma,
            &mut stream(seed, 0),
        ))
    })?;
    f.data.into_pyarray(py).reshape([height, width])
}

/// The Monte-Carlo study: PCA / errors against SNR for both methods, and Method 2's
/// initial-condition sensitivity for the `(xmax, vmax)` rows of `ic`; keyword options are those
/// of `pf_options()["study"]`.
#[pyfunction]
#[pyo3(signature = (ic, **options))]
fn pf_study<'py>(
    py: Python<'py>,
    ic: PyReadonlyArray2<'py, f64>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<PfStudy> {
    let o = read_one::<PfStudyOptions>(options)?;
    let shape = ic.shape();
    if shape[1] != 2 {
        return Err(py_err(Error::Shape {
            what: "ic",
            expected: "(n, 2) with columns xmax, vmax".into(),
            got: format!("{shape:?}"),
        }));
    }
    let flat = ic
        .as_slice()
        .map_err(|e| Error::Invalid(format!("ic: {e}")))
        .map_err(py_err)?;
    let ic: Vec<(f64, f64)> = flat.chunks_exact(2).map(|r| (r[0], r[1])).collect();
    let grid = o.snrs.unwrap_or_else(|| (0..=20).map(f64::from).collect());
    let mut cells: Vec<Cell> = Vec::new();
    for method in [Method::PeakDistance, Method::LikelihoodRatio] {
        for &snr_db in &grid {
            cells.push(Cell {
                method,
                snr_db,
                xmax: 3.0,
                vmax: 0.5,
            });
        }
    }
    for &(xmax, vmax) in &ic {
        cells.push(Cell {
            method: Method::LikelihoodRatio,
            snr_db: o.ic_snr,
            xmax,
            vmax,
        });
    }
    let opts = StudyOptions {
        runs: o.runs,
        seed: o.seed,
        particles: o.filter.particles,
        association: o.filter.association,
        resampling: o.filter.resampling,
        peaks: o.filter.peak_options().map_err(py_err)?,
        model_factors: o.filter.model_factors,
        sigma_w: o.filter.sigma_w,
        scenario: Scenario {
            model: o.truth.model(),
            ..Scenario::paper()
        },
    };
    let rows = detached(py, || study(&cells, &opts, &mut check_signals))?;
    let n = rows.len();
    let t = opts.scenario.starts.len();
    let col = |f: &dyn Fn(&CellResult) -> f64| -> Vec<f64> { rows.iter().map(f).collect() };
    let filter_metrics = |pick: fn(&CellResult) -> &FilterMetrics| -> PyResult<Py<PfMetrics>> {
        let c = |f: fn(&FilterMetrics) -> f64| -> Py<PyArray1<f64>> {
            rows.iter()
                .map(|r| f(pick(r)))
                .collect::<Vec<_>>()
                .into_pyarray(py)
                .unbind()
        };
        Py::new(
            py,
            PfMetrics {
                pca: c(|m| m.pca),
                hit: c(|m| m.hit),
                rmse_px: c(|m| m.rmse),
                coverage: c(|m| m.coverage),
                held: c(|m| m.held),
            },
        )
    };
    let bank = |f: fn(&BankMetrics) -> f64| -> Py<PyArray1<f64>> {
        col(&|r| f(&r.bank)).into_pyarray(py).unbind()
    };
    let per = |f: &dyn Fn(&FilterMetrics) -> f64| -> Vec<f64> {
        rows.iter().flat_map(|r| r.filters.iter().map(f)).collect()
    };
    Ok(PfStudy {
        method: rows
            .iter()
            .map(|r| r.cell.method.number() as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .unbind(),
        snr_db: col(&|r| r.cell.snr_db).into_pyarray(py).unbind(),
        xmax: col(&|r| r.cell.xmax).into_pyarray(py).unbind(),
        vmax: col(&|r| r.cell.vmax).into_pyarray(py).unbind(),
        all: filter_metrics(|r| &r.all)?,
        lo: filter_metrics(|r| &r.lo)?,
        hi: filter_metrics(|r| &r.hi)?,
        bank: Py::new(
            py,
            PfBankMetrics {
                gospa: bank(|m| m.gospa),
                gospa_loc: bank(|m| m.gospa_loc),
                gospa_missed: bank(|m| m.gospa_missed),
                gospa_false: bank(|m| m.gospa_false),
                id_switches: bank(|m| m.id_switches),
                fragmentations: bank(|m| m.fragmentations),
            },
        )?,
        filter_pca: per(&|m| m.pca).into_pyarray(py).reshape([n, t])?.unbind(),
        filter_rmse_px: per(&|m| m.rmse).into_pyarray(py).reshape([n, t])?.unbind(),
    })
}

/// Per-filter metrics of the study's rows, pooled over the filters and runs of each row (one
/// array element per row).
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PfMetrics {
    /// Probability of correct association: the peak taken is nearer the filter's own target
    /// than any other.
    pca: Py<PyArray1<f64>>,
    /// The peak taken is also within 3 px of that target.
    hit: Py<PyArray1<f64>>,
    /// Position RMSE, pixels.
    rmse_px: Py<PyArray1<f64>>,
    /// Fraction of errors inside the filters' 2-sigma bounds, per axis.
    coverage: Py<PyArray1<f64>>,
    /// Fraction of tracks whose error stays below 5 px over the last second.
    held: Py<PyArray1<f64>>,
}

#[pymethods]
impl PfMetrics {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("PfMetrics(rows={})", self.pca.bind(py).len())
    }
}

/// Metrics of the whole bank of filters of the study's rows (one array element per row).
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PfBankMetrics {
    /// GOSPA and its localisation, missed and false parts.
    gospa: Py<PyArray1<f64>>,
    gospa_loc: Py<PyArray1<f64>>,
    gospa_missed: Py<PyArray1<f64>>,
    gospa_false: Py<PyArray1<f64>>,
    /// Identity switches and track fragmentations.
    id_switches: Py<PyArray1<f64>>,
    fragmentations: Py<PyArray1<f64>>,
}

#[pymethods]
impl PfBankMetrics {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("PfBankMetrics(rows={})", self.gospa.bind(py).len())
    }
}

/// The Monte-Carlo study of the particle filter: one row per cell (method, SNR, initial
/// spread), the metrics pooled over its runs with their confidence interval bounds.
#[pyclass(frozen, get_all, module = "geofeas._core")]
pub struct PfStudy {
    /// The cells: method (1 or 2), SNR in dB, initial position and velocity spreads.
    method: Py<PyArray1<i64>>,
    snr_db: Py<PyArray1<f64>>,
    xmax: Py<PyArray1<f64>>,
    vmax: Py<PyArray1<f64>>,
    /// The per-filter metrics, and their interval's lower and upper bounds.
    all: Py<PfMetrics>,
    lo: Py<PfMetrics>,
    hi: Py<PfMetrics>,
    /// The bank metrics.
    bank: Py<PfBankMetrics>,
    /// `(rows, T)`: probability of correct association and RMSE of each filter.
    filter_pca: Py<PyArray2<f64>>,
    filter_rmse_px: Py<PyArray2<f64>>,
}

#[pymethods]
impl PfStudy {
    fn __repr__(&self, py: Python<'_>) -> String {
        let s = self.filter_pca.bind(py).shape();
        format!("PfStudy(rows={}, filters={})", s[0], s[1])
    }
}

/// The option sets of the particle filter: `{"filter", "run", "track", "study"}` to lists of
/// `(name, kind, default, doc, choices)`, in declaration order.
#[pyfunction]
fn pf_options(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("filter", schema_py::<PfOptions>(py)?)?;
    out.set_item("run", schema_py::<PfRunOptions>(py)?)?;
    out.set_item("track", schema_py::<PfTrackOptions>(py)?)?;
    out.set_item("study", schema_py::<PfStudyOptions>(py)?)?;
    Ok(out)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(pf_options, m)?)?;
    m.add_function(wrap_pyfunction!(pf_simulate_run, m)?)?;
    m.add_function(wrap_pyfunction!(pf_track, m)?)?;
    m.add_function(wrap_pyfunction!(pf_log_weights, m)?)?;
    m.add_function(wrap_pyfunction!(pf_peaks, m)?)?;
    m.add_function(wrap_pyfunction!(pf_render, m)?)?;
    m.add_function(wrap_pyfunction!(pf_study, m)?)?;
    m.add_class::<PfTrack>()?;
    m.add_class::<PfRun>()?;
    m.add_class::<PfStudy>()?;
    m.add_class::<PfMetrics>()?;
    m.add_class::<PfBankMetrics>()?;
    Ok(())
}
