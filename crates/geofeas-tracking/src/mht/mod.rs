//! Multiple-hypothesis trilateration and tracking with distributed radars (seed 004: van Kleef,
//! Bergmans, Kester, Groen, "Multiple-Hypothesis Trilateration and Tracking with Distributed
//! Radars").
//!
//! - [`sensor`]: range / range-rate radars at arbitrary positions, `h_i` and its Jacobian (eqs. 20-21).
//! - [`scenario`]: the seeded simulator of section 5.1 (M-shaped trajectories, asynchronous scans,
//!   false alarms uniform in range-Doppler).
//! - [`trilateration`]: two detections to a Cartesian state and its covariance (eqs. 1-9).
//! - [`range_doppler`]: Kalman filter of single-sensor tracks (section 4.2).
//! - [`cartesian`]: extended Kalman filter of multi-sensor tracks (section 4.3).
//! - [`config`]: the tracker's options ([`MhtConfig`]), read by tracks and hypotheses alike.
//! - [`track`]: flexible-state tracks and the three association types (section 3).
//! - [`hypothesis`]: Reid's measurement-oriented MHT and the single-hypothesis baseline; it
//!   holds tracks, tracks never see hypotheses (`config` <- `track` <- `hypothesis`).
//! - [`options`](mod@options): the option sets of the tracker, a run, the study and a
//!   trilateration's beam.
//! - [`metrics`]: T_PD, T_FAR, position and velocity errors (section 5.2), GOSPA, identity
//!   switches and fragmentation.
//! - [`study`]: the Monte-Carlo reproduction of Tables 1 and 2.
//!
//! A Cartesian track's position covariance is a geofeas [`geofeas::Ellipse`]
//! ([`track::Track::ellipse`]), so tracks of two radar networks can be scored with the
//! geofeasibility scores.
//!
//! ```
//! use geofeas::rng::stream;
//! use geofeas_tracking::mht::{Mht, MhtConfig, Scenario};
//!
//! // The paper's two-target scenario with two false alarms per sensor per scan.
//! let scenario = Scenario::paper(2, 3, 2).unwrap();
//! let detections = scenario.simulate(&mut stream(7, 0));
//! let mut mht = Mht::new(scenario.sensors.clone(), MhtConfig::for_scenario(&scenario)).unwrap();
//! mht.run(&scenario.scan_times(), &detections, |_, _, _| {}).unwrap();
//! // Probabilities of the kept hypotheses sum to one; the best holds Cartesian tracks with AOUs.
//! let total: f64 = mht.hypotheses().iter().map(|h| h.probability()).sum();
//! assert!((total - 1.0).abs() < 1e-9);
//! let ellipses: Vec<_> = mht.best().tracks.iter().filter_map(|t| t.ellipse()).collect();
//! assert!(ellipses.len() >= 2);
//! ```

pub mod cartesian;
pub mod config;
pub mod hypothesis;
pub mod metrics;
pub mod options;
pub mod range_doppler;
pub mod scenario;
pub mod sensor;
pub mod study;
pub mod track;
pub mod trilateration;

use nalgebra::{Matrix2, Vector2};

pub use config::MhtConfig;
pub use hypothesis::{group_scans, Hypothesis, Mht};
pub use metrics::{Evaluation, Metrics, Scorer, Tally};
pub use options::{MhtBeam, MhtOptions, MhtRunOptions, MhtSimOptions, MhtStudyOptions};
pub use scenario::{Scenario, Trajectory};
pub use sensor::{Detection, Noise, Sensor};
pub use study::{
    bootstrap, evaluation, paper_cells, pool, run_one, run_one_with, study, study_cells,
    study_runs, study_with_interrupt, Cell, PaperPreset, StudyOptions, TrackerKind,
    EXTENDED_ONE_TARGET, EXTENDED_TWO_TARGETS,
};
pub use track::Track;
pub use trilateration::{trilaterate, trilaterate_gaussian, Trilateration};

/// For an innovation `e` with covariance `s`: `(S^-1, ln N(e; 0, S), e^T S^-1 e)`, or `None` if
/// `s` is not positive definite.
pub(crate) fn innovation(e: &Vector2<f64>, s: &Matrix2<f64>) -> Option<(Matrix2<f64>, f64, f64)> {
    let det = s[(0, 0)] * s[(1, 1)] - s[(0, 1)] * s[(1, 0)];
    if !(det > 0.0 && s[(0, 0)] > 0.0 && det.is_finite()) {
        return None;
    }
    let sinv = Matrix2::new(s[(1, 1)], -s[(0, 1)], -s[(1, 0)], s[(0, 0)]) / det;
    let d2 = (e.transpose() * sinv * e)[(0, 0)];
    let loglik = -0.5 * d2 - (2.0 * std::f64::consts::PI).ln() - 0.5 * det.ln();
    Some((sinv, loglik, d2))
}
