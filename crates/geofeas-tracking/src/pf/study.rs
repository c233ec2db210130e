//! Monte-Carlo reproduction of seed 003's studies: tracking errors at 2, 6 and 15 dB
//! (Figs. 7, 10, 14, 17), the probability of correct association against SNR for both methods
//! (Fig. 19) and the sensitivity of Method 2 to the initial uncertainty at 2 dB (Fig. 20).
//!
//! A [`Cell`] is one (method, SNR, `X_max`, `V_max`) configuration. Cells that share SNR and
//! initialisation are run together on the same frames ([`crate::pf::run`]: common
//! truth, noise and initial particles for every SNR and method of a run). Runs are spread over
//! threads with rayon (the filters inside a run then stay sequential); tallies are merged in run
//! order, so the results do not depend on the thread count.

use rayon::prelude::*;

use crate::pf::assignment::Assignment;
use crate::pf::bank::{Method, PfConfig};
use crate::pf::metrics::{pooled, BankMetrics, BankTally, FilterMetrics, FilterTally};
use crate::pf::peaks::PeakOptions;
use crate::pf::resample::Resampling;
use crate::pf::run::{track_truth, RunSpec};
use crate::pf::scenario::Scenario;
use crate::pf::weights::LikelihoodModel;
use geofeas::error::{Error, Result};

/// One configuration of the study.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Weighting method.
    pub method: Method,
    /// SNR, dB.
    pub snr_db: f64,
    /// Position initialisation half-width, pixels.
    pub xmax: f64,
    /// Velocity initialisation half-width, pixels/s.
    pub vmax: f64,
}

/// Options shared by every cell.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyOptions {
    /// Monte-Carlo runs per cell.
    pub runs: usize,
    /// Seed.
    pub seed: u64,
    /// Particles per filter (paper: 10,000).
    pub particles: usize,
    /// Assignment rule.
    pub association: Assignment,
    /// Resampling scheme.
    pub resampling: Resampling,
    /// Peak extraction.
    pub peaks: PeakOptions,
    /// Method 2 model factors `[amplitude, blur, sigma]` (paper: 0.8, 1.5, 1.5).
    pub model_factors: [f64; 3],
    /// Filter process noise, pixels/s^2 (paper: 0.5).
    pub sigma_w: f64,
    /// The scenario.
    pub scenario: Scenario,
}

impl Default for StudyOptions {
    fn default() -> Self {
        Self {
            runs: 10,
            seed: 0,
            particles: 10_000,
            association: Assignment::Nearest,
            resampling: Resampling::Systematic,
            peaks: PeakOptions::default(),
            model_factors: [0.8, 1.5, 1.5],
            sigma_w: 0.5,
            scenario: Scenario::paper(),
        }
    }
}

/// The results of one cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellResult {
    /// The cell.
    pub cell: Cell,
    /// Pooled over the filters.
    pub all: FilterMetrics,
    /// Per filter.
    pub filters: Vec<FilterMetrics>,
    /// Lower end of the 95 % percentile-bootstrap interval of `all` over runs.
    pub lo: FilterMetrics,
    /// Upper end of the same interval.
    pub hi: FilterMetrics,
    /// GOSPA and identity measures of the bank.
    pub bank: BankMetrics,
}

/// Resamples drawn by [`bootstrap`] in [`study`].
pub const BOOTSTRAP_RESAMPLES: usize = 1000;

/// 95 % percentile bootstrap of the pooled metrics over runs: `runs[r]` is run `r`'s tally
/// pooled over the filters; `resamples` resamples of the runs with replacement drawn from
/// `seed`. Returns the 2.5 % and 97.5 % quantiles of every metric.
pub fn bootstrap(
    runs: &[FilterTally],
    resamples: usize,
    seed: u64,
) -> (FilterMetrics, FilterMetrics) {
    use rand::RngExt;
    let all = pooled(runs).metrics();
    if runs.len() < 2 || resamples == 0 {
        return (all, all);
    }
    let mut rng = geofeas::rng::stream(seed ^ 0x9f_b007, runs.len() as u64);
    let mut draws: Vec<[f64; 5]> = Vec::with_capacity(resamples);
    for _ in 0..resamples {
        let mut t = FilterTally::default();
        for _ in 0..runs.len() {
            t.merge(&runs[rng.random_range(0..runs.len())]);
        }
        let m = t.metrics();
        draws.push([m.pca, m.hit, m.rmse, m.coverage, m.held]);
    }
    let mut q = [[0.0; 5]; 2];
    for k in 0..5 {
        let mut v: Vec<f64> = draws.iter().map(|d| d[k]).collect();
        v.sort_by(f64::total_cmp);
        let at = |p: f64| v[((p * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
        q[0][k] = at(0.025);
        q[1][k] = at(0.975);
    }
    let m = |a: [f64; 5]| FilterMetrics {
        pca: a[0],
        hit: a[1],
        rmse: a[2],
        coverage: a[3],
        held: a[4],
    };
    (m(q[0]), m(q[1]))
}

/// The paper's cells: both methods at 0, 1, ..., 20 dB with `X_max = 3`, `V_max = 0.5`, and
/// Method 2 at 2 dB for `(X_max, V_max)` in `ic`.
pub fn paper_cells(ic: &[(f64, f64)]) -> Vec<Cell> {
    let mut cells = Vec::new();
    for method in [Method::PeakDistance, Method::LikelihoodRatio] {
        for snr in 0..=20 {
            cells.push(Cell {
                method,
                snr_db: snr as f64,
                xmax: 3.0,
                vmax: 0.5,
            });
        }
    }
    for &(xmax, vmax) in ic {
        cells.push(Cell {
            method: Method::LikelihoodRatio,
            snr_db: 2.0,
            xmax,
            vmax,
        });
    }
    cells
}

/// The bank configuration of `cell`.
pub fn cell_config(cell: &Cell, spec: &RunSpec, opts: &StudyOptions) -> PfConfig {
    let base = PfConfig::paper(cell.method, &spec.psf, spec.sigma_z());
    PfConfig {
        particles: opts.particles,
        association: opts.association,
        resampling: opts.resampling,
        peaks: opts.peaks,
        model: LikelihoodModel::scaled(&spec.psf, spec.sigma_z(), opts.model_factors),
        xmax: cell.xmax,
        vmax: cell.vmax,
        motion: crate::pf::motion::Ncv {
            sigma_w: opts.sigma_w,
            ..base.motion
        },
        parallel: false,
        residuals: false,
        ..base
    }
}

/// Runs the study and returns one result per cell, in the order of `cells`; `interrupt` is
/// polled between batches of runs.
pub fn study(
    cells: &[Cell],
    opts: &StudyOptions,
    interrupt: &mut dyn FnMut() -> bool,
) -> Result<Vec<CellResult>> {
    if opts.runs == 0 {
        return Err(Error::InvalidOption {
            name: "runs",
            reason: "must be >= 1".into(),
        });
    }
    let targets = opts.scenario.starts.len();
    // Cells sharing (snr, xmax, vmax) run on the same frames.
    let mut groups: Vec<(f64, f64, f64, Vec<usize>)> = Vec::new();
    for (c, cell) in cells.iter().enumerate() {
        for (name, v) in [
            ("snr_db", cell.snr_db),
            ("xmax", cell.xmax),
            ("vmax", cell.vmax),
        ] {
            if !v.is_finite() {
                return Err(Error::InvalidOption {
                    name,
                    reason: format!("cell {c}: must be finite, got {v}"),
                });
            }
        }
        let key = (cell.snr_db, cell.xmax, cell.vmax);
        match groups.iter_mut().find(|g| (g.0, g.1, g.2) == key) {
            Some(g) => g.3.push(c),
            None => groups.push((key.0, key.1, key.2, vec![c])),
        }
    }
    // Validate every configuration once, up front.
    for g in &groups {
        let spec = RunSpec {
            scenario: opts.scenario.clone(),
            ..RunSpec::paper(g.0, opts.seed, 0)
        }
        .validated()?;
        for &c in &g.3 {
            cell_config(&cells[c], &spec, opts).validated()?;
        }
    }
    let jobs: Vec<(usize, usize)> = (0..opts.runs)
        .flat_map(|r| (0..groups.len()).map(move |g| (g, r)))
        .collect();
    let mut tallies = vec![vec![FilterTally::default(); targets]; cells.len()];
    // Per cell, each run's tally pooled over the filters, in run order.
    let mut per_run: Vec<Vec<FilterTally>> = vec![Vec::with_capacity(opts.runs); cells.len()];
    let mut banks = vec![BankTally::default(); cells.len()];
    let batch = 4 * rayon::current_num_threads();
    for chunk in jobs.chunks(batch) {
        if interrupt() {
            return Err(Error::Interrupted);
        }
        let out: Vec<(Vec<Vec<FilterTally>>, Vec<BankTally>)> = chunk
            .par_iter()
            .map(|&(g, r)| {
                let (snr, _, _, ref members) = groups[g];
                let spec = RunSpec {
                    scenario: opts.scenario.clone(),
                    ..RunSpec::paper(snr, opts.seed, r as u64)
                };
                let configs: Vec<PfConfig> = members
                    .iter()
                    .map(|&c| cell_config(&cells[c], &spec, opts))
                    .collect();
                let mut t = vec![vec![FilterTally::default(); targets]; members.len()];
                let mut bt = vec![BankTally::default(); members.len()];
                let truth_states = spec.truth();
                track_truth(
                    &spec,
                    &truth_states,
                    &configs,
                    |b, k, _, step, _| {
                        for (i, ti) in t[b].iter_mut().enumerate() {
                            ti.observe(i, step, &truth_states.states[k]);
                        }
                        bt[b].observe(step, &truth_states.states[k]);
                    },
                    &mut || false,
                )?;
                for tb in &mut t {
                    tb.iter_mut().for_each(FilterTally::finish_run);
                }
                bt.iter_mut().for_each(BankTally::finish_run);
                Ok((t, bt))
            })
            .collect::<Result<_>>()?;
        for (&(g, _), (t, bt)) in chunk.iter().zip(out) {
            for (&c, b) in groups[g].3.iter().zip(&bt) {
                banks[c].merge(b);
            }
            for (&c, tc) in groups[g].3.iter().zip(t) {
                for (acc, x) in tallies[c].iter_mut().zip(&tc) {
                    acc.merge(x);
                }
                per_run[c].push(pooled(&tc));
            }
        }
    }
    Ok(cells
        .iter()
        .zip(&tallies)
        .zip(&per_run)
        .enumerate()
        .map(|(c, ((cell, t), runs))| {
            let bank = banks[c].metrics();
            let (lo, hi) = bootstrap(runs, BOOTSTRAP_RESAMPLES, opts.seed ^ c as u64);
            CellResult {
                cell: *cell,
                all: pooled(t).metrics(),
                filters: t.iter().map(FilterTally::metrics).collect(),
                lo,
                hi,
                bank,
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_study_is_reproducible_and_ordered() {
        let opts = StudyOptions {
            runs: 2,
            particles: 300,
            scenario: Scenario {
                duration: 1.0,
                ..Scenario::paper()
            },
            ..StudyOptions::default()
        };
        let cells = [
            Cell {
                method: Method::LikelihoodRatio,
                snr_db: 15.0,
                xmax: 3.0,
                vmax: 0.5,
            },
            Cell {
                method: Method::PeakDistance,
                snr_db: 15.0,
                xmax: 3.0,
                vmax: 0.5,
            },
        ];
        let a = study(&cells, &opts, &mut || false).unwrap();
        let b = study(&cells, &opts, &mut || false).unwrap();
        assert_eq!(a, b);
        assert_eq!(a[1].cell.method, Method::PeakDistance);
        assert!(a[0].all.rmse < 1.5 && a[0].all.pca > 0.8, "{:?}", a[0].all);
        assert!(study(&cells, &opts, &mut || true).is_err());
        assert!(study(&cells, &StudyOptions { runs: 0, ..opts }, &mut || false).is_err());
    }
}
