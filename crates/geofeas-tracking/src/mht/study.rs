//! Monte-Carlo reproduction of Tables 1 and 2 of seed 004 (section 5).
//!
//! A [`Cell`] is one column of a table: number of targets, number of sensors, tracker (the MHT in
//! the project's recommended configuration, the MHT in the paper-faithful configuration, or the
//! single-hypothesis baseline) and false alarms per sensor per scan. Each of
//! `runs` runs simulates the scenario with its own random stream derived from
//! `(seed, targets, sensors, false alarms, run)` (the same data for both trackers, whatever the
//! number of threads), tracks it, scores the best hypothesis after every scan ([`Tally`]), and
//! the tallies of all runs are pooled. Runs are spread over threads with rayon. [`bootstrap`]
//! gives percentile confidence intervals of every metric by resampling runs.
//!
//! The two MHT configurations differ only where the paper is silent or where the project departs
//! from it on purpose ([`StudyOptions`] vs [`PaperPreset`]): the recommended one uses an iterated
//! EKF (2 relinearisations), a new-target density of 0.02 per window and no confirmation stage;
//! the paper-faithful one uses the paper's plain EKF, the paper's `Q = 4 g` read as a covariance
//! and a new-target density 2 x 10^6 times lower.

use rayon::prelude::*;

use super::config::MhtConfig;
use super::hypothesis::{Hypothesis, Mht};
use super::metrics::{Evaluation, Metrics, Scorer, Tally};
use super::scenario::Scenario;
use super::scenario::G;
use super::sensor::Detection;
use geofeas::error::{Error, Result};
use geofeas::rng::{mix64, stream};

/// The tracker of a study cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TrackerKind {
    /// Multiple hypotheses, the project's recommended configuration ([`StudyOptions`]).
    Mht,
    /// Multiple hypotheses, the paper-faithful configuration ([`StudyOptions::paper`]).
    MhtPaper,
    /// Single hypothesis (global nearest neighbour), with the recommended filter.
    Single,
}

impl TrackerKind {
    /// Every tracker of the study.
    pub const ALL: [TrackerKind; 3] =
        [TrackerKind::Mht, TrackerKind::MhtPaper, TrackerKind::Single];

    /// `"mht"`, `"mht-paper"` or `"single"`.
    pub fn name(&self) -> &'static str {
        match self {
            TrackerKind::Mht => "mht",
            TrackerKind::MhtPaper => "mht-paper",
            TrackerKind::Single => "single",
        }
    }

    /// The tracker of a name given by [`TrackerKind::name`].
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|k| k.name() == name)
            .ok_or_else(|| Error::InvalidOption {
                name: "tracker",
                reason: format!("expected one of 'mht', 'mht-paper', 'single', got '{name}'"),
            })
    }
}

/// The paper-faithful MHT configuration: what the paper states (plain EKF, 50 hypotheses,
/// `Q = 4 g` in eq. 11, Cartesian output tracks of three contacts from two sensors) plus the
/// choice it leaves open that drives its T_PD trend, the new-target density, set so that the
/// true track competes with "hypotheses interpreting the true contacts as false alarms" as the
/// paper describes (see `docs/mht-study.md` for the sweep).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperPreset {
    /// Relinearisations of the Cartesian EKF (the paper: 0, plain EKF).
    pub ekf_iterations: usize,
    /// Expected new targets per scan in a sensor's window (not given by the paper).
    pub new_target_rate: f64,
    /// Confirmation stage: probability over the kept hypotheses a track must reach before it
    /// counts (M6T's "confirmed" stage; its rule is not given by the paper). 0: none.
    pub confirm_probability: f64,
    /// White-acceleration standard deviation, m/s^2. Eq. 11 adds `G Q G^T` with `Q` a
    /// covariance, and the paper sets "the Q value" to 4 g: `Q = 39.2 (m/s^2)^2`, i.e.
    /// `sqrt(4 g) = 6.26 m/s^2`.
    pub accel_sigma: f64,
}

impl Default for PaperPreset {
    fn default() -> Self {
        Self {
            ekf_iterations: 0,
            new_target_rate: 1e-8,
            confirm_probability: 0.0,
            accel_sigma: (4.0 * G).sqrt(),
        }
    }
}

/// One column of Table 1 or 2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Cell {
    /// 1 or 2 targets.
    pub targets: usize,
    /// 2 or 3 sensors.
    pub sensors: usize,
    /// The tracker.
    pub tracker: TrackerKind,
    /// False alarms per sensor per scan.
    pub false_alarms: usize,
}

/// Study options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudyOptions {
    /// Monte-Carlo runs per cell.
    pub runs: usize,
    /// Seed of the random streams.
    pub seed: u64,
    /// Hypotheses kept by the MHT (paper: 50).
    pub max_hypotheses: usize,
    /// Relinearisations of the Cartesian EKF update (0: the paper's plain EKF).
    pub ekf_iterations: usize,
    /// Expected new targets per scan in a sensor's range / range-rate window: the new-target
    /// density is this over the window's volume (the paper does not give it).
    pub new_target_rate: f64,
    /// Detection probability of the simulated sensors (paper: 1).
    pub detection_probability: f64,
    /// Confirmation stage of the recommended MHT (0: none), see [`Evaluation`].
    pub confirm_probability: f64,
    /// Process noise of the recommended MHT and the baseline: white acceleration standard
    /// deviation, m/s^2 (2 g; see [`PaperPreset::accel_sigma`] for the paper's).
    pub accel_sigma: f64,
    /// The paper-faithful MHT configuration ([`TrackerKind::MhtPaper`]).
    pub paper: PaperPreset,
}

impl Default for StudyOptions {
    fn default() -> Self {
        Self {
            runs: 20,
            seed: 0,
            max_hypotheses: 50,
            ekf_iterations: 2,
            new_target_rate: 0.02,
            detection_probability: 1.0,
            confirm_probability: 0.0,
            accel_sigma: 2.0 * G,
            paper: PaperPreset::default(),
        }
    }
}

impl StudyOptions {
    /// Checks every option.
    pub fn validated(&self) -> Result<()> {
        if self.runs == 0 {
            return Err(Error::InvalidOption {
                name: "runs",
                reason: "must be >= 1".into(),
            });
        }
        for (name, v) in [
            ("new_target_rate", self.new_target_rate),
            ("paper_new_target_rate", self.paper.new_target_rate),
            ("accel_sigma", self.accel_sigma),
            ("paper_accel_sigma", self.paper.accel_sigma),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::InvalidOption {
                    name,
                    reason: format!("must be finite and > 0, got {v}"),
                });
            }
        }
        for (name, v) in [
            ("confirm_probability", self.confirm_probability),
            ("paper_confirm_probability", self.paper.confirm_probability),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(Error::InvalidOption {
                    name,
                    reason: format!("must be in [0, 1], got {v}"),
                });
            }
        }
        if self.max_hypotheses == 0 {
            return Err(Error::InvalidOption {
                name: "max_hypotheses",
                reason: "must be >= 1".into(),
            });
        }
        Ok(())
    }
}

/// The output of one run.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// The simulated scenario.
    pub scenario: Scenario,
    /// Scan times `(time, sensor)`.
    pub scans: Vec<(f64, usize)>,
    /// All detections, in processing order.
    pub detections: Vec<Detection>,
    /// The most likely hypothesis at the end.
    pub best: Hypothesis,
    /// The metric sums of this run.
    pub tally: Tally,
}

/// Every cell of the paper's tables: one target with 0, 1, 2, 4, 6 and two targets with 0-4
/// false alarms per sensor per scan, three and two sensors, MHT and single hypothesis.
pub fn paper_cells() -> Vec<Cell> {
    study_cells(
        &[TrackerKind::Mht, TrackerKind::Single],
        &[0, 1, 2, 4, 6],
        &[0, 1, 2, 3, 4],
    )
}

/// False alarms per sensor per scan of the extended study: the paper's columns and beyond, up
/// to 8 (the paper states "no tracks at 7 or more").
pub const EXTENDED_ONE_TARGET: [usize; 7] = [0, 1, 2, 4, 6, 7, 8];
/// As [`EXTENDED_ONE_TARGET`], for two targets.
pub const EXTENDED_TWO_TARGETS: [usize; 7] = [0, 1, 2, 3, 4, 6, 8];

/// The cells of `trackers` x {3, 2 sensors} x (one target with `one_target` false alarms, two
/// targets with `two_targets`).
pub fn study_cells(
    trackers: &[TrackerKind],
    one_target: &[usize],
    two_targets: &[usize],
) -> Vec<Cell> {
    let mut cells = Vec::new();
    for &tracker in trackers {
        for sensors in [3, 2] {
            for (targets, fas) in [(1usize, one_target), (2, two_targets)] {
                for &false_alarms in fas {
                    cells.push(Cell {
                        targets,
                        sensors,
                        tracker,
                        false_alarms,
                    });
                }
            }
        }
    }
    cells
}

/// The tracker configuration of a cell.
pub fn tracker_config(cell: &Cell, scenario: &Scenario, opts: &StudyOptions) -> MhtConfig {
    let volume = scenario
        .sensors
        .first()
        .map_or(3000.0, |s| s.window_volume());
    let (iterations, rate, accel) = match cell.tracker {
        TrackerKind::MhtPaper => (
            opts.paper.ekf_iterations,
            opts.paper.new_target_rate,
            opts.paper.accel_sigma,
        ),
        _ => (opts.ekf_iterations, opts.new_target_rate, opts.accel_sigma),
    };
    let base = MhtConfig {
        max_hypotheses: opts.max_hypotheses,
        ekf_iterations: iterations,
        new_target_density: rate / volume,
        accel_sigma: accel,
        ..MhtConfig::for_scenario(scenario)
    };
    match cell.tracker {
        TrackerKind::Mht | TrackerKind::MhtPaper => base,
        TrackerKind::Single => base.single_hypothesis(),
    }
}

/// Which tracks of a cell count as output.
pub fn evaluation(cell: &Cell, opts: &StudyOptions) -> Evaluation {
    Evaluation {
        confirm_probability: match cell.tracker {
            TrackerKind::MhtPaper => opts.paper.confirm_probability,
            _ => opts.confirm_probability,
        },
        ..Evaluation::default()
    }
}

/// Simulates and tracks run `run` of `cell`.
pub fn run_one(cell: &Cell, opts: &StudyOptions, run: usize) -> Result<RunOutput> {
    run_one_with(cell, opts, run, |c| c)
}

/// [`run_one`] with the tracker configuration passed through `adjust`.
pub fn run_one_with<F: Fn(MhtConfig) -> MhtConfig>(
    cell: &Cell,
    opts: &StudyOptions,
    run: usize,
    adjust: F,
) -> Result<RunOutput> {
    opts.validated()?;
    let scenario = Scenario {
        pd: opts.detection_probability,
        ..Scenario::paper(cell.targets, cell.sensors, cell.false_alarms)?
    }
    .validated()?;
    let key = (cell.targets as u64) << 40 | (cell.sensors as u64) << 32 | cell.false_alarms as u64;
    let mut rng = stream(opts.seed ^ mix64(key), run as u64);
    let detections = scenario.simulate(&mut rng);
    let scans = scenario.scan_times();
    let mut mht = Mht::new(
        scenario.sensors.clone(),
        adjust(tracker_config(cell, &scenario, opts)),
    )?;
    let mut scorer = Scorer::new(evaluation(cell, opts));
    let mut tally = Tally {
        duration: scenario.duration,
        ..Tally::default()
    };
    let mut done = 0usize;
    mht.run(&scans, &detections, |si, t, m| {
        while done < detections.len() && detections[done].scan <= si {
            done += 1;
        }
        let next = scans.get(si + 1).map_or(scenario.duration, |s| s.0);
        scorer.observe(
            &mut tally,
            m.hypotheses(),
            &detections[..done],
            &scenario.targets,
            t,
            next - t,
        );
    })?;
    Ok(RunOutput {
        best: mht.best().clone(),
        scenario,
        scans,
        detections,
        tally,
    })
}

/// Runs `opts.runs` Monte-Carlo runs of every cell in parallel and returns the pooled metrics,
/// in the order of `cells`.
pub fn study(cells: &[Cell], opts: &StudyOptions) -> Result<Vec<(Cell, Metrics)>> {
    study_with_interrupt(cells, opts, &mut || false)
}

/// [`study`] calling `interrupt` on the calling thread between batches of runs; if it returns
/// true the study stops with [`Error::Interrupted`].
pub fn study_with_interrupt(
    cells: &[Cell],
    opts: &StudyOptions,
    interrupt: &mut dyn FnMut() -> bool,
) -> Result<Vec<(Cell, Metrics)>> {
    let runs = study_runs(cells, opts, interrupt)?;
    Ok(cells
        .iter()
        .copied()
        .zip(runs.iter().map(|r| pool(r).metrics()))
        .collect())
}

/// The tallies of all runs pooled, in order.
pub fn pool(runs: &[Tally]) -> Tally {
    let mut out = Tally::default();
    for t in runs {
        out.merge(t);
    }
    out
}

/// Percentile bootstrap of the pooled metrics over runs: `resamples` resamples of the runs with
/// replacement (seeded), returning the `(1 - level) / 2` and `(1 + level) / 2` quantiles of
/// every metric in the order of [`Metrics::NAMES`] (NaN where a resample has no value).
pub fn bootstrap(
    runs: &[Tally],
    resamples: usize,
    level: f64,
    seed: u64,
) -> ([f64; 12], [f64; 12]) {
    use rand::RngExt;
    let nan = [f64::NAN; 12];
    if runs.is_empty() || resamples == 0 {
        return (nan, nan);
    }
    let mut rng = stream(seed ^ 0xb007_57a9, runs.len() as u64);
    let mut draws: Vec<[f64; 12]> = Vec::with_capacity(resamples);
    for _ in 0..resamples {
        let mut t = Tally::default();
        for _ in 0..runs.len() {
            t.merge(&runs[rng.random_range(0..runs.len())]);
        }
        draws.push(t.metrics().values());
    }
    let (mut lo, mut hi) = (nan, nan);
    for k in 0..12 {
        let mut v: Vec<f64> = draws.iter().map(|d| d[k]).filter(|x| !x.is_nan()).collect();
        if v.is_empty() {
            continue;
        }
        v.sort_by(f64::total_cmp);
        let q = |p: f64| v[((p * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
        lo[k] = q(0.5 * (1.0 - level));
        hi[k] = q(0.5 * (1.0 + level));
    }
    (lo, hi)
}

/// Runs `opts.runs` Monte-Carlo runs of every cell and returns each run's tally, per cell in the
/// order of `cells` (run order within a cell), calling `interrupt` between batches.
pub fn study_runs(
    cells: &[Cell],
    opts: &StudyOptions,
    interrupt: &mut dyn FnMut() -> bool,
) -> Result<Vec<Vec<Tally>>> {
    opts.validated()?;
    let jobs: Vec<(usize, usize)> = (0..cells.len())
        .flat_map(|c| (0..opts.runs).map(move |r| (c, r)))
        .collect();
    let batch = 8 * rayon::current_num_threads();
    let mut per_cell = vec![Vec::with_capacity(opts.runs); cells.len()];
    for chunk in jobs.chunks(batch) {
        if interrupt() {
            return Err(Error::Interrupted);
        }
        let tallies: Vec<Tally> = chunk
            .par_iter()
            .map(|&(c, r)| run_one(&cells[c], opts, r).map(|o| o.tally))
            .collect::<Result<_>>()?;
        // Kept in job order, so the sums do not depend on the thread count.
        for (&(c, _), t) in chunk.iter().zip(tallies) {
            per_cell[c].push(t);
        }
    }
    Ok(per_cell)
}
