//! The option sets of the multiple-hypothesis tracker (seed 004), each declared once:
//! [`MhtOptions`], the tracker fed detections (batch or scan by scan); [`MhtRunOptions`], one
//! simulated run of the paper's scenario; [`MhtStudyOptions`], the Monte-Carlo study of Tables
//! 1 and 2; [`MhtBeam`], the beam of a trilateration. Defaults are those of [`MhtConfig`],
//! [`Noise`], [`StudyOptions`] and [`PaperPreset`]. The Python signatures, stubs,
//! command-line flags and docs tables are checked against these declarations.
//!
//! The seven options a run and the study both take (seed, the simulated sensors' detection
//! probability, the recommended tracker's settings) are declared in [`MhtSimOptions`], from
//! which both take them (their field `sim`), each listing them where its signature shows them.
//! A shared set rather than the study taking them from [`MhtRunOptions`]: the study has no
//! targets, sensors, false alarms, tracker or run index of one run, and [`MhtSimOptions`] is
//! what both turn into the core's [`StudyOptions`]. It is not an option group of its own in
//! Python: `mht_options()` shows it inside `run` and `study`.

use super::config::MhtConfig;
use super::sensor::Noise;
use super::study::{PaperPreset, StudyOptions, TrackerKind};
use crate::option_set;
use crate::options::{Named, NamedList};
use geofeas::error::{Error, Result};

/// Most EKF relinearisations per update.
pub const MAX_EKF_ITERATIONS: usize = 100;
/// Most hypotheses kept.
pub const MAX_HYPOTHESES: usize = 100_000;
/// Most targets, sensors and false alarms per scan of a simulated run.
pub const MAX_SCENARIO_COUNT: usize = 1000;

/// Refuses a count option above `max` (a bound on the work and memory of one call, far above
/// the paper's settings).
pub fn at_most(name: &'static str, value: usize, max: usize) -> Result<usize> {
    if value > max {
        return Err(Error::InvalidOption {
            name,
            reason: format!("must be <= {max}, got {value}"),
        });
    }
    Ok(value)
}

option_set! {
    /// The options of the tracker fed detections.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct MhtOptions {
        /// Hypotheses kept after each detection (the paper: 50).
        max_hypotheses: usize = MhtConfig::default().max_hypotheses,
        /// Detection probability assumed by the tracker, in (0, 1).
        pd: f64 = MhtConfig::default().pd,
        /// False-alarm density per (m x m/s) of one scan.
        false_alarm_density: f64 = MhtConfig::default().false_alarm_density,
        /// New-target density per (m x m/s) of one scan.
        new_target_density: f64 = MhtConfig::default().new_target_density,
        /// White-acceleration standard deviation of the motion models, m/s^2 (2 g).
        accel_sigma: f64 = MhtConfig::default().accel_sigma,
        /// Range measurement noise (1-sigma), m.
        sigma_range: f64 = Noise::default().sigma_range,
        /// Range-rate measurement noise (1-sigma), m/s.
        sigma_range_rate: f64 = Noise::default().sigma_range_rate,
        /// Chi-square gate (2 dof) on Kalman innovations.
        gate: f64 = MhtConfig::default().gate,
        /// Tracks not updated for this many seconds are closed.
        max_coast: f64 = MhtConfig::default().max_coast,
        /// Largest target speed, m/s.
        max_speed: f64 = MhtConfig::default().max_speed,
        /// Relinearisations of the Cartesian EKF update (0: the paper's plain EKF).
        ekf_iterations: usize = MhtConfig::default().ekf_iterations,
        /// Run the single-hypothesis (global nearest neighbour) baseline instead.
        single: bool = false,
    }
}

option_set! {
    /// The options of the simulated runs that one run ([`MhtRunOptions`]) and the study
    /// ([`MhtStudyOptions`]) both take: the random streams, the simulated sensors and the
    /// recommended tracker. Not an option group of its own in Python.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct MhtSimOptions {
        /// Seed of the random streams.
        seed: u64 = StudyOptions::default().seed,
        /// Hypotheses kept after each detection (the paper: 50).
        max_hypotheses: usize = StudyOptions::default().max_hypotheses,
        /// mht and single: relinearisations of the Cartesian EKF update (0: plain EKF).
        ekf_iterations: usize = StudyOptions::default().ekf_iterations,
        /// Detection probability of the simulated sensors (the paper: 1).
        detection_probability: f64 = StudyOptions::default().detection_probability,
        /// mht and single: expected new targets per scan in a sensor window.
        new_target_rate: f64 = StudyOptions::default().new_target_rate,
        /// mht and single: probability a track must reach before it counts (0: none).
        confirm_probability: f64 = StudyOptions::default().confirm_probability,
        /// mht and single: white-acceleration standard deviation, m/s^2 (2 g).
        accel_sigma: f64 = StudyOptions::default().accel_sigma,
    }
}

option_set! {
    /// The options of one simulated run of the paper's scenario (section 5.1).
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct MhtRunOptions {
        /// Targets of the scenario.
        targets: usize = 2,
        /// Sensors of the scenario (2 or 3).
        sensors: usize = 3,
        /// False alarms per sensor per scan.
        false_alarms: usize = 2,
        /// Tracker: mht (recommended), mht-paper (paper-faithful) or single (baseline).
        tracker: TrackerKind = TrackerKind::Mht,
        /// Index of the run.
        run: usize = 0,
        /// The options of the simulated runs, shared with the study.
        sim: MhtSimOptions {
            seed,
            max_hypotheses,
            ekf_iterations,
            detection_probability,
            new_target_rate,
            confirm_probability,
            accel_sigma,
        },
    }
}

option_set! {
    /// The options of the Monte-Carlo study of Tables 1 and 2.
    #[derive(Debug, Clone, PartialEq)]
    pub struct MhtStudyOptions {
        /// Monte-Carlo runs per column.
        runs: usize = StudyOptions::default().runs,
        /// The options of the simulated runs, shared with one run.
        sim: MhtSimOptions {
            seed,
            max_hypotheses,
            ekf_iterations,
            new_target_rate,
            detection_probability,
            confirm_probability,
            accel_sigma,
        },
        /// mht-paper: relinearisations of the Cartesian EKF update (0: the paper's EKF).
        paper_ekf_iterations: usize = PaperPreset::default().ekf_iterations,
        /// mht-paper: expected new targets per scan in a sensor window.
        paper_new_target_rate: f64 = PaperPreset::default().new_target_rate,
        /// mht-paper: probability a track must reach before it counts (0: none).
        paper_confirm_probability: f64 = PaperPreset::default().confirm_probability,
        /// mht-paper: white-acceleration sigma, m/s^2 (sqrt(4 g): the paper's Q = 4 g).
        paper_accel_sigma: f64 = PaperPreset::default().accel_sigma,
        /// Trackers compared: mht (recommended), mht-paper (paper-faithful), single (baseline).
        trackers: NamedList<TrackerKind> = NamedList(TrackerKind::ALL.to_vec()),
        /// False alarms per sensor per scan of the one-target columns.
        one_target: Vec<usize> = vec![0, 1, 2, 4, 6, 7, 8],
        /// False alarms per sensor per scan of the two-target columns.
        two_targets: Vec<usize> = vec![0, 1, 2, 3, 4, 6, 8],
        /// Bootstrap resamples of the intervals.
        resamples: usize = 1000,
        /// Confidence level of the intervals, in (0, 1).
        level: f64 = 0.95,
    }
}

option_set! {
    /// The beam of both sensors of a trilateration.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct MhtBeam {
        /// Beam direction, radians counter-clockwise from +x.
        boresight: f64 = std::f64::consts::FRAC_PI_2,
        /// Half-width of the beam, radians.
        half_beam: f64 = std::f64::consts::FRAC_PI_2,
    }
}

impl MhtOptions {
    /// The checked tracker configuration.
    pub fn config(&self) -> Result<MhtConfig> {
        at_most("ekf_iterations", self.ekf_iterations, MAX_EKF_ITERATIONS)?;
        at_most("max_hypotheses", self.max_hypotheses, MAX_HYPOTHESES)?;
        let config = MhtConfig {
            max_hypotheses: self.max_hypotheses,
            pd: self.pd,
            false_alarm_density: self.false_alarm_density,
            new_target_density: self.new_target_density,
            accel_sigma: self.accel_sigma,
            noise: Noise {
                sigma_range: self.sigma_range,
                sigma_range_rate: self.sigma_range_rate,
            },
            gate: self.gate,
            max_coast: self.max_coast,
            max_speed: self.max_speed,
            ekf_iterations: self.ekf_iterations,
            ..MhtConfig::default()
        };
        Ok(if self.single {
            config.single_hypothesis()
        } else {
            config
        })
    }
}

impl MhtSimOptions {
    /// The checked study options of `runs` runs per cell, with the paper-faithful tracker
    /// `paper`.
    pub fn study_options(&self, runs: usize, paper: PaperPreset) -> Result<StudyOptions> {
        at_most("ekf_iterations", self.ekf_iterations, MAX_EKF_ITERATIONS)?;
        at_most("max_hypotheses", self.max_hypotheses, MAX_HYPOTHESES)?;
        Ok(StudyOptions {
            runs,
            seed: self.seed,
            max_hypotheses: self.max_hypotheses,
            ekf_iterations: self.ekf_iterations,
            detection_probability: self.detection_probability,
            new_target_rate: self.new_target_rate,
            confirm_probability: self.confirm_probability,
            accel_sigma: self.accel_sigma,
            paper,
        })
    }
}

impl MhtRunOptions {
    /// The study options of the run's tracker.
    pub fn study_options(&self) -> Result<StudyOptions> {
        let opts = self.sim.study_options(1, PaperPreset::default())?;
        for (name, v) in [
            ("targets", self.targets),
            ("sensors", self.sensors),
            ("false_alarms", self.false_alarms),
        ] {
            at_most(name, v, MAX_SCENARIO_COUNT)?;
        }
        Ok(opts)
    }
}

impl MhtStudyOptions {
    /// The core study options.
    pub fn study_options(&self) -> Result<StudyOptions> {
        let opts = self.sim.study_options(
            self.runs,
            PaperPreset {
                ekf_iterations: self.paper_ekf_iterations,
                new_target_rate: self.paper_new_target_rate,
                confirm_probability: self.paper_confirm_probability,
                accel_sigma: self.paper_accel_sigma,
            },
        )?;
        if !(self.level > 0.0 && self.level < 1.0) {
            return Err(Error::InvalidOption {
                name: "level",
                reason: format!("must be in (0, 1), got {}", self.level),
            });
        }
        Ok(opts)
    }
}

impl Named for TrackerKind {
    const NAMES: &'static [&'static str] = &["mht", "mht-paper", "single"];
    fn name(&self) -> &'static str {
        TrackerKind::name(self)
    }
    fn from_name(name: &str) -> Result<Self> {
        TrackerKind::from_name(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::{OptionSet, OptionValue};

    #[test]
    fn defaults_are_the_cores() {
        assert_eq!(
            MhtOptions::default().config().unwrap(),
            MhtConfig::default()
        );
        assert_eq!(
            MhtStudyOptions::default().study_options().unwrap(),
            StudyOptions::default()
        );
        let single = MhtOptions {
            single: true,
            ..MhtOptions::default()
        };
        assert_eq!(
            single.config().unwrap(),
            MhtConfig::default().single_hypothesis()
        );
        for (i, n) in TrackerKind::NAMES.iter().enumerate() {
            assert_eq!(TrackerKind::ALL[i].name(), *n);
        }
    }

    #[test]
    fn run_and_study_take_every_shared_option() {
        let shared = MhtSimOptions::schema();
        for (set, schema) in [
            ("run", MhtRunOptions::schema()),
            ("study", MhtStudyOptions::schema()),
        ] {
            for o in &shared {
                assert_eq!(schema.iter().find(|s| s.name == o.name), Some(o), "{set}");
            }
        }
        assert_eq!(
            MhtRunOptions::default().study_options().unwrap(),
            StudyOptions {
                runs: 1,
                ..StudyOptions::default()
            }
        );
        let mut r = MhtRunOptions::default();
        r.set("seed", OptionValue::Int(7)).unwrap();
        r.set("accel_sigma", OptionValue::Float(3.0)).unwrap();
        let opts = r.study_options().unwrap();
        assert_eq!((opts.seed, opts.accel_sigma), (7, 3.0));
        let mut s = MhtStudyOptions::default();
        s.set("max_hypotheses", OptionValue::Int(100_001)).unwrap();
        assert!(s
            .study_options()
            .unwrap_err()
            .to_string()
            .contains("max_hypotheses"));
    }

    #[test]
    fn bounds_are_enforced() {
        let mut o = MhtOptions::default();
        o.set("ekf_iterations", OptionValue::Int(101)).unwrap();
        assert!(o
            .config()
            .unwrap_err()
            .to_string()
            .contains("ekf_iterations"));
        let mut s = MhtStudyOptions::default();
        s.set("level", OptionValue::Float(1.0)).unwrap();
        assert!(s.study_options().unwrap_err().to_string().contains("level"));
        let err = s
            .set("trackers", OptionValue::Texts(vec!["kalman".into()]))
            .unwrap_err();
        assert!(err.to_string().contains("kalman"), "{err}");
    }
}
