//! Bindings of the particle-filter focal-plane tracker (`geofeas_tracking::pf`).

use numpy::{
    IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::options::{read_one, read_two, schema_py};
use super::{check_signals, detached, py_err};
use geofeas::error::{Error, Result};
use geofeas::rng::stream;
use geofeas_tracking::pf::{
    find_peaks, peak_label, study, track_frames, track_truth, Bank, Cell, Frame, LikelihoodModel,
    Method, Particles, PeakOptions, PfOptions, PfRunOptions, PfStudyOptions, PfTrackOptions, Psf,
    RunSpec, Scenario, Step, StudyOptions,
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

    fn into_dict<'py>(self, py: Python<'py>, out: &Bound<'py, PyDict>) -> PyResult<()> {
        let (f, t, k) = (self.frames, self.filters, self.k);
        out.set_item("estimates", self.est.into_pyarray(py).reshape([f, t, 4])?)?;
        out.set_item(
            "covariances",
            self.cov.into_pyarray(py).reshape([f, t, 4, 4])?,
        )?;
        out.set_item("peaks", self.peaks.into_pyarray(py).reshape([f, k, 3])?)?;
        out.set_item("peak", self.peak.into_pyarray(py).reshape([f, t])?)?;
        out.set_item("distances", self.dist.into_pyarray(py).reshape([f, t, k])?)?;
        out.set_item("residuals", self.resid.into_pyarray(py).reshape([f, t, 2])?)?;
        out.set_item("ess", self.ess.into_pyarray(py).reshape([f, t])?)?;
        Ok(())
    }
}

/// Simulates one run of the paper's scenario and tracks it; keyword options are those of
/// `pf_options()["run"]` and `pf_options()["filter"]`.
#[pyfunction]
#[pyo3(signature = (**options))]
fn pf_simulate_run<'py>(
    py: Python<'py>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
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
    let out = PyDict::new(py);
    let f = rec.frames;
    rec.into_dict(py, &out)?;
    out.set_item(
        "truth",
        truth_rows.into_pyarray(py).reshape([f, targets, 8])?,
    )?;
    out.set_item("correct", correct.into_pyarray(py).reshape([f, targets])?)?;
    let ns = snaps.len() / 4;
    out.set_item("snapshots", snaps.into_pyarray(py).reshape([ns, 4])?)?;
    let nk = kept.len() / (width * height);
    out.set_item(
        "frames",
        kept.into_pyarray(py).reshape([nk, height, width])?,
    )?;
    out.set_item("sigma_z", sigma_z)?;
    out.set_item("dt", dt)?;
    out.set_item("filter_seed", filter_seed)?;
    Ok(out)
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
) -> PyResult<Bound<'py, PyDict>> {
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
    let out = PyDict::new(py);
    rec.into_dict(py, &out)?;
    Ok(out)
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
) -> PyResult<Bound<'py, PyDict>> {
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
        particles: o.particles,
        association: o.association,
        resampling: o.resampling,
        peaks: PeakOptions {
            count: o.peaks,
            min_separation: o.min_separation,
            smoothing: o.smoothing,
        }
        .validated()
        .map_err(py_err)?,
        model_factors: o.model_factors,
        sigma_w: o.sigma_w,
        scenario: Scenario {
            model: o.truth.model(),
            ..Scenario::paper()
        },
    };
    let rows = detached(py, || study(&cells, &opts, &mut check_signals))?;
    let n = rows.len();
    let t = opts.scenario.starts.len();
    let col = |f: &dyn Fn(&geofeas_tracking::pf::CellResult) -> f64| -> Vec<f64> {
        rows.iter().map(f).collect()
    };
    let out = PyDict::new(py);
    out.set_item(
        "method",
        rows.iter()
            .map(|r| r.cell.method.number() as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    out.set_item("snr_db", col(&|r| r.cell.snr_db).into_pyarray(py))?;
    out.set_item("xmax", col(&|r| r.cell.xmax).into_pyarray(py))?;
    out.set_item("vmax", col(&|r| r.cell.vmax).into_pyarray(py))?;
    out.set_item("pca", col(&|r| r.all.pca).into_pyarray(py))?;
    out.set_item("hit", col(&|r| r.all.hit).into_pyarray(py))?;
    out.set_item("rmse_px", col(&|r| r.all.rmse).into_pyarray(py))?;
    out.set_item("coverage", col(&|r| r.all.coverage).into_pyarray(py))?;
    out.set_item("held", col(&|r| r.all.held).into_pyarray(py))?;
    for (name, f) in [
        (
            "gospa",
            (|m| m.gospa) as fn(&geofeas_tracking::pf::BankMetrics) -> f64,
        ),
        ("gospa_loc", |m| m.gospa_loc),
        ("gospa_missed", |m| m.gospa_missed),
        ("gospa_false", |m| m.gospa_false),
        ("id_switches", |m| m.id_switches),
        ("fragmentations", |m| m.fragmentations),
    ] {
        out.set_item(name, col(&|r| f(&r.bank)).into_pyarray(py))?;
    }
    for (name, f) in [
        (
            "pca",
            (|m| m.pca) as fn(&geofeas_tracking::pf::FilterMetrics) -> f64,
        ),
        ("hit", |m| m.hit),
        ("rmse_px", |m| m.rmse),
        ("coverage", |m| m.coverage),
        ("held", |m| m.held),
    ] {
        out.set_item(format!("{name}_lo"), col(&|r| f(&r.lo)).into_pyarray(py))?;
        out.set_item(format!("{name}_hi"), col(&|r| f(&r.hi)).into_pyarray(py))?;
    }
    let per = |f: &dyn Fn(&geofeas_tracking::pf::FilterMetrics) -> f64| -> Vec<f64> {
        rows.iter().flat_map(|r| r.filters.iter().map(f)).collect()
    };
    out.set_item(
        "filter_pca",
        per(&|m| m.pca).into_pyarray(py).reshape([n, t])?,
    )?;
    out.set_item(
        "filter_rmse_px",
        per(&|m| m.rmse).into_pyarray(py).reshape([n, t])?,
    )?;
    Ok(out)
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
    Ok(())
}
