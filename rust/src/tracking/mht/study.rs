//! Monte-Carlo reproduction of Tables 1 and 2 of seed 004 (section 5).
//!
//! A [`Cell`] is one column of a table: number of targets, number of sensors, tracker (MHT with
//! 50 hypotheses or the single-hypothesis baseline) and false alarms per sensor per scan. Each of
//! `runs` runs simulates the scenario with its own random stream derived from
//! `(seed, targets, sensors, false alarms, run)` (the same data for both trackers, whatever the
//! number of threads), tracks it, scores the best hypothesis after every scan ([`Tally`]), and
//! the tallies of all runs are pooled. Runs are spread over threads with rayon.

use rayon::prelude::*;

use super::hypothesis::{Hypothesis, Mht, MhtConfig};
use super::metrics::{Evaluation, Metrics, Tally};
use super::scenario::Scenario;
use super::sensor::Detection;
use crate::error::{Error, Result};
use crate::score::monte_carlo::{mix64, stream};

/// The tracker of a study cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TrackerKind {
    /// Multiple hypotheses (paper: 50).
    Mht,
    /// Single hypothesis (global nearest neighbour).
    Single,
}

impl TrackerKind {
    /// `"mht"` or `"single"`.
    pub fn name(&self) -> &'static str {
        match self {
            TrackerKind::Mht => "mht",
            TrackerKind::Single => "single",
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
        }
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
    let mut cells = Vec::new();
    for tracker in [TrackerKind::Mht, TrackerKind::Single] {
        for sensors in [3, 2] {
            for (targets, fas) in [(1usize, vec![0usize, 1, 2, 4, 6]), (2, vec![0, 1, 2, 3, 4])] {
                for false_alarms in fas {
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
    let base = MhtConfig {
        max_hypotheses: opts.max_hypotheses,
        ekf_iterations: opts.ekf_iterations,
        ..MhtConfig::for_scenario(scenario)
    };
    let volume = scenario
        .sensors
        .first()
        .map_or(3000.0, |s| s.window_volume());
    let base = MhtConfig {
        new_target_density: opts.new_target_rate / volume,
        ..base
    };
    match cell.tracker {
        TrackerKind::Mht => base,
        TrackerKind::Single => base.single_hypothesis(),
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
    let eval = Evaluation::default();
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
        tally.observe(
            &eval,
            m.best(),
            &detections[..done],
            &scenario.targets,
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
    if opts.runs == 0 {
        return Err(Error::InvalidOption {
            name: "runs",
            reason: "must be >= 1".into(),
        });
    }
    if !(opts.new_target_rate.is_finite() && opts.new_target_rate > 0.0) {
        return Err(Error::InvalidOption {
            name: "new_target_rate",
            reason: format!("must be finite and > 0, got {}", opts.new_target_rate),
        });
    }
    if opts.max_hypotheses == 0 {
        return Err(Error::InvalidOption {
            name: "max_hypotheses",
            reason: "must be >= 1".into(),
        });
    }
    let jobs: Vec<(usize, usize)> = (0..cells.len())
        .flat_map(|c| (0..opts.runs).map(move |r| (c, r)))
        .collect();
    let batch = 8 * rayon::current_num_threads();
    let mut pooled = vec![Tally::default(); cells.len()];
    for chunk in jobs.chunks(batch) {
        if interrupt() {
            return Err(Error::Interrupted);
        }
        let tallies: Vec<Tally> = chunk
            .par_iter()
            .map(|&(c, r)| run_one(&cells[c], opts, r).map(|o| o.tally))
            .collect::<Result<_>>()?;
        // Merged in job order, so the sums do not depend on the thread count.
        for (&(c, _), t) in chunk.iter().zip(&tallies) {
            pooled[c].merge(t);
        }
    }
    Ok(cells
        .iter()
        .copied()
        .zip(pooled.iter().map(Tally::metrics))
        .collect())
}
