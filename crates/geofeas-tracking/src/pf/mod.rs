//! Particle-filter tracking of multiple objects on a focal-plane image (seed 003: Ohlmeyer and
//! Menon, "Comparison of Two Particle Filter Methods for Image Plane Tracking of Multiple
//! Objects").
//!
//! - [`scenario`]: the four-target scenario and the Fig. 3 truth model (seeded).
//! - [`frame`]: frames of Gaussian point spreads plus white noise, `sigma_Z = A / 10^(SNR/20)`.
//! - [`peaks`]: the measurement peaks (local maxima, strongest first).
//! - [`motion`]: particle clouds and the nearly-constant-velocity model of Fig. 4.
//! - [`weights`]: Method 1 (distance to the associated peak) and Method 2 (the
//!   track-before-detect likelihood ratio, separable point spread, log domain).
//! - [`resample`]: systematic, stratified, multinomial and residual resampling.
//! - [`assignment`]: which peak each filter takes: the weighted-nearest-neighbour rule
//!   `R_i^j = sum_n w_i^n r_ij^n` and a one-to-one variant.
//! - [`filter`]: one particle filter: update, estimate and 2-sigma bounds, Fig. 12 residuals.
//! - [`bank`]: the bank of filters, frame by frame.
//! - [`options`](mod@options): the option sets of the bank, a run, given frames and the study.
//! - [`run`]: the frame loop ([`track_frames`]) and one seeded run (truth, frames, banks).
//! - [`metrics`]: errors, probability of correct association, 2-sigma coverage, held tracks.
//! - [`study`](mod@study): the Monte-Carlo reproduction of Figs. 7-20.
//!
//! A filter's position covariance is a geofeas [`geofeas::Ellipse`]
//! ([`filter::Estimate::ellipse`]), so its estimates can be scored with the geofeasibility scores.
//!
//! ```
//! use geofeas_tracking::pf::{track_run, Method, PfConfig, RunSpec};
//!
//! // The paper's scenario at 15 dB, tracked by Method 2 with 1000 particles per filter.
//! let spec = RunSpec::paper(15.0, 7, 0);
//! let cfg = PfConfig {
//!     particles: 1000,
//!     ..PfConfig::paper(Method::LikelihoodRatio, &spec.psf, spec.sigma_z())
//! };
//! let mut last = Vec::new();
//! let truth = track_run(&spec, &[cfg], |_, _, _, step, _| last = step.filters.clone(), &mut || false)
//!     .unwrap();
//! let end = truth.states.last().unwrap();
//! for (rec, s) in last.iter().zip(end) {
//!     let e = rec.estimate.mean;
//!     assert!((e[0] - s.x).hypot(e[1] - s.y) < 1.0);
//!     assert!(rec.estimate.ellipse().rx > 0.0);
//! }
//! ```

pub mod assignment;
pub mod bank;
pub mod filter;
pub mod frame;
pub mod metrics;
pub mod motion;
pub mod options;
pub mod peaks;
pub mod resample;
pub mod run;
pub mod scenario;
pub mod study;
pub mod weights;

pub use assignment::{weighted_distances, Assignment};

/// The former name of [`Assignment`].
#[deprecated(note = "renamed `Assignment` (module `assignment`)")]
pub type Association = Assignment;
pub use bank::{Bank, Method, PfConfig, Step, StepRecord};
pub use filter::{Estimate, ParticleFilter};
pub use frame::{noise_sigma, Frame, Psf};
pub use metrics::{peak_label, BankMetrics, BankTally, FilterMetrics, FilterTally};
pub use motion::{Ncv, Particles};
pub use options::{PfOptions, PfRunOptions, PfStudyOptions, PfTrackOptions, TruthKind};
pub use peaks::{find_peaks, Peak, PeakOptions};
pub use resample::Resampling;
pub use run::{track_frames, track_run, track_truth, RunSpec};
pub use scenario::{Scenario, TargetStart, Truth, TruthModel, TruthState};
pub use study::{bootstrap, paper_cells, study, Cell, CellResult, StudyOptions};
pub use weights::LikelihoodModel;
