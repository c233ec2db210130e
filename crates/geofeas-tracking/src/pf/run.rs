//! One seeded Monte-Carlo run of seed 003's experiment: simulated truth, frames at a given SNR,
//! and one or more filter banks tracking the same frames.
//!
//! A run is identified by `(seed, run)`. The truth draws from the stream `(seed ^ T, run)`, the
//! unit noise of frame `k` from `(seed ^ N ^ mix(run), k)` (scaled by `sigma_Z`, so all SNRs of
//! one run see the same truth and the same noise pattern: common random numbers), and the
//! filters from `(seed ^ F ^ mix(run), i)`, shared by every bank of the run (Methods 1 and 2 start
//! from the same particles). Frames are generated one at a time and dropped after use.

use crate::pf::bank::{Bank, PfConfig, Step};
use crate::pf::frame::{noise_sigma, Frame, Psf};
use crate::pf::peaks::{find_peaks, Peak, PeakOptions};
use crate::pf::scenario::{Scenario, Truth};
use geofeas::error::Result;
use geofeas::rng::{mix64, stream};

const TRUTH: u64 = 0x7472_7574_6800_0001;
const NOISE: u64 = 0x6e6f_6973_6500_0002;
const FILTER: u64 = 0x6669_6c74_6500_0003;

/// The simulated world of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// Scenario and truth model.
    pub scenario: Scenario,
    /// True point spread.
    pub psf: Psf,
    /// Signal-to-noise ratio, dB.
    pub snr_db: f64,
    /// Seed of the study.
    pub seed: u64,
    /// Index of the run.
    pub run: u64,
}

impl RunSpec {
    /// The paper's scenario and point spread at `snr_db`.
    pub fn paper(snr_db: f64, seed: u64, run: u64) -> Self {
        Self {
            scenario: Scenario::paper(),
            psf: Psf::default(),
            snr_db,
            seed,
            run,
        }
    }

    /// `sigma_Z = A / 10^(SNR/20)`.
    pub fn sigma_z(&self) -> f64 {
        noise_sigma(self.snr_db, self.psf.amplitude)
    }

    /// The true trajectories.
    pub fn truth(&self) -> Truth {
        self.scenario
            .simulate(&mut stream(self.seed ^ TRUTH, self.run))
    }

    /// Frame `k` of `truth`.
    pub fn frame(&self, truth: &Truth, k: usize) -> Frame {
        Frame::render(
            self.scenario.width,
            self.scenario.height,
            &truth.positions(k),
            &self.psf,
            self.sigma_z(),
            &mut stream(self.seed ^ NOISE ^ mix64(self.run), k as u64),
        )
    }

    /// The seed of the filter banks of this run.
    pub fn filter_seed(&self) -> u64 {
        self.seed ^ FILTER ^ mix64(self.run)
    }

    /// Checks the scenario and point spread.
    pub fn validated(self) -> Result<Self> {
        let psf = self.psf.validated("psf")?;
        let scenario = self.scenario.validated()?;
        if !self.snr_db.is_finite() {
            return Err(geofeas::error::Error::InvalidOption {
                name: "snr_db",
                reason: format!("must be finite, got {}", self.snr_db),
            });
        }
        Ok(Self {
            psf,
            scenario,
            ..self
        })
    }
}

/// Simulates the run and tracks it with one bank per config, initialised about the true initial
/// states; `observe(bank index, frame index, frame, step, bank)` sees every step, and
/// `interrupt` is polled between frames (true stops with [`crate::Error::Interrupted`]).
pub fn track_run(
    spec: &RunSpec,
    configs: &[PfConfig],
    observe: impl FnMut(usize, usize, &Frame, &Step, &Bank),
    interrupt: &mut dyn FnMut() -> bool,
) -> Result<Truth> {
    let truth = spec.truth();
    track_truth(spec, &truth, configs, observe, interrupt)?;
    Ok(truth)
}

/// [`track_run`] on the run's truth already simulated (`truth` is `spec.truth()`), for callers
/// that read the truth while observing the steps.
pub fn track_truth(
    spec: &RunSpec,
    truth: &Truth,
    configs: &[PfConfig],
    observe: impl FnMut(usize, usize, &Frame, &Step, &Bank),
    interrupt: &mut dyn FnMut() -> bool,
) -> Result<()> {
    let init: Vec<[f64; 4]> = truth.states[0].iter().map(|s| s.xv()).collect();
    let mut banks = configs
        .iter()
        .map(|c| Bank::new(&init, *c, spec.filter_seed()))
        .collect::<Result<Vec<_>>>()?;
    let frames = (0..truth.frames()).map(|k| spec.frame(truth, k));
    track_frames(&mut banks, frames, observe, interrupt)
}

/// The frame loop of every tracking entry point: each frame, in order, goes through every bank;
/// `observe(bank index, frame index, frame, step, bank)` sees every step, and `interrupt` is
/// polled before each frame (true stops with [`crate::Error::Interrupted`]). Banks with the same
/// peak options share one peak extraction per frame.
pub fn track_frames(
    banks: &mut [Bank],
    frames: impl IntoIterator<Item = Frame>,
    mut observe: impl FnMut(usize, usize, &Frame, &Step, &Bank),
    interrupt: &mut dyn FnMut() -> bool,
) -> Result<()> {
    for (k, frame) in frames.into_iter().enumerate() {
        if interrupt() {
            return Err(geofeas::error::Error::Interrupted);
        }
        let mut cache: Option<(PeakOptions, Vec<Peak>)> = None;
        for (b, bank) in banks.iter_mut().enumerate() {
            let opts = bank.config().peaks;
            let peaks = match &cache {
                Some((o, p)) if *o == opts => p.clone(),
                _ => {
                    let p = find_peaks(&frame, &opts);
                    cache = Some((opts, p.clone()));
                    p
                }
            };
            let step = bank.step_with_peaks(&frame, peaks);
            observe(b, k, &frame, &step, bank);
        }
    }
    Ok(())
}
