//! The options of the multiple-hypothesis tracker (seed 004, sections 3-4): Reid's hypothesis
//! weights (`P_D`, `beta_FA`, `beta_NT`), the process and measurement noise of the track filters,
//! gating, coasting and the single-hypothesis baseline. The tracks ([`super::track`]) and the
//! hypotheses ([`super::hypothesis`]) both read them; this module depends on neither.

use super::scenario::{Scenario, G};
use super::sensor::{Noise, Sensor};
use geofeas::error::{Error, Result};

/// Options of the tracker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MhtConfig {
    /// Hypotheses kept after each detection (paper: 50).
    pub max_hypotheses: usize,
    /// If set, hypotheses kept while a scan is processed; pruning to `max_hypotheses` then
    /// happens only at the end of the scan.
    pub scan_cap: Option<usize>,
    /// Detection probability assumed by the tracker, in (0, 1).
    pub pd: f64,
    /// False-alarm density, per (metre x metre per second) of one scan.
    pub false_alarm_density: f64,
    /// New-target density, per (metre x metre per second) of one scan.
    pub new_target_density: f64,
    /// Process noise: white acceleration standard deviation, m/s^2 (default 2 g; the paper sets
    /// `Q = 4 g` in eq. 11, i.e. `sqrt(4 g) = 6.26` if `Q` is read as a covariance).
    pub accel_sigma: f64,
    /// Measurement noise.
    pub noise: Noise,
    /// Chi-square gate on the squared Mahalanobis distance of Kalman innovations (2 dof).
    pub gate: f64,
    /// A track not updated for this many seconds is closed.
    pub max_coast: f64,
    /// Largest target speed, m/s.
    pub max_speed: f64,
    /// Smallest |sin| of the angle between the lines of sight of a trilateration.
    pub min_sin_angle: f64,
    /// Whether a detection may be explained as a false alarm. A single-hypothesis tracker turns
    /// this off: it can never revisit the decision, so every detection it does not assign to a
    /// track starts a tentative track, which is closed if nothing else joins it.
    pub false_alarm_hypotheses: bool,
    /// Relinearisations of the Cartesian (iterated) EKF update; 0 is the plain EKF of the paper,
    /// the default 2 keeps tracks through the 4 g turns far more often.
    pub ekf_iterations: usize,
}

impl Default for MhtConfig {
    fn default() -> Self {
        let volume = 100.0 * 30.0;
        Self {
            max_hypotheses: 50,
            scan_cap: None,
            pd: 0.9,
            false_alarm_density: 1.0 / volume,
            new_target_density: 0.02 / volume,
            accel_sigma: 2.0 * G,
            noise: Noise::default(),
            gate: 16.0,
            max_coast: 1.0,
            max_speed: 15.0,
            min_sin_angle: 0.05,
            false_alarm_hypotheses: true,
            ekf_iterations: 2,
        }
    }
}

impl MhtConfig {
    /// The configuration for a scenario: its noise, `beta_FA = max(n_FA, 0.1) / V` and
    /// `beta_NT = 0.02 / V` with `V` the range / range-rate window of the first sensor.
    pub fn for_scenario(scenario: &Scenario) -> Self {
        let volume = scenario
            .sensors
            .first()
            .map_or(3000.0, Sensor::window_volume);
        Self {
            false_alarm_density: (scenario.false_alarms as f64).max(0.1) / volume,
            new_target_density: 0.02 / volume,
            noise: scenario.noise,
            max_speed: scenario.sensors.first().map_or(15.0, |s| s.max_range_rate),
            ..Self::default()
        }
    }

    /// The single-hypothesis (global nearest neighbour) variant of this configuration.
    pub fn single_hypothesis(self) -> Self {
        Self {
            max_hypotheses: 1,
            scan_cap: Some(64),
            false_alarm_hypotheses: false,
            ..self
        }
    }

    /// Checks every option.
    pub fn validated(self) -> Result<Self> {
        let bad = |name: &'static str, reason: String| Err(Error::InvalidOption { name, reason });
        if self.max_hypotheses == 0 {
            return bad("max_hypotheses", "must be >= 1".into());
        }
        if self.scan_cap == Some(0) {
            return bad("scan_cap", "must be >= 1".into());
        }
        if !(self.pd > 0.0 && self.pd < 1.0) {
            return bad("pd", format!("must be in (0, 1), got {}", self.pd));
        }
        for (name, v) in [
            ("false_alarm_density", self.false_alarm_density),
            ("new_target_density", self.new_target_density),
            ("accel_sigma", self.accel_sigma),
            ("gate", self.gate),
            ("max_coast", self.max_coast),
            ("max_speed", self.max_speed),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(name, format!("must be finite and > 0, got {v}"));
            }
        }
        if !(self.min_sin_angle.is_finite() && (0.0..1.0).contains(&self.min_sin_angle)) {
            return bad(
                "min_sin_angle",
                format!("must be in [0, 1), got {}", self.min_sin_angle),
            );
        }
        self.noise.validated()?;
        Ok(self)
    }
}
