//! Tracks with a flexible state and the three association types (seed 004, sections 3-4).
//!
//! A track is either a single-sensor range / range-rate track ([`RangeDoppler`], section 4.2) or
//! a Cartesian track ([`Cartesian`], section 4.3). A detection `M_i` joins a track by one of:
//!
//! 1. `M_i + T(r, r')_i -> T(r, r')_i`: Kalman update in range-Doppler coordinates;
//! 2. `M_i + T(r, r')_j -> T(x, y, vx, vy)`: the track is predicted to the detection time and
//!    trilaterated with it (eqs. 1-8);
//! 3. `M_i + T(x, y, vx, vy) -> T(x, y, vx, vy)`: extended Kalman update (eqs. 19-21).
//!
//! Each association returns the log-likelihood of the detection given the track. Types 1 and 3
//! use the Gaussian innovation density `N(e; 0, S)` with a chi-square gate. Type 2 has no
//! Gaussian prediction of the other sensor's measurement (the track's bearing is unknown); the
//! paper does not give its likelihood, so we use the uniform density of the detection over what
//! the track allows: range in `[|r_j - d|, r_j + d]` (width `2 min(r_j, d)`, `d` the baseline)
//! and range rate in `[-v_max, v_max]`, and reject trilaterations with nearly parallel lines of
//! sight or a speed beyond `v_max` plus three standard deviations.
//!
//! The contacts of a track form a persistent list shared between hypotheses, so a hypothesis
//! clone copies pointers, not histories.

use std::sync::Arc;

use nalgebra::{Matrix2, Vector2};

use super::cartesian::Cartesian;
use super::config::MhtConfig;
use super::range_doppler::RangeDoppler;
use super::sensor::{Detection, Sensor};
use super::trilateration::trilaterate_gaussian;
use geofeas::ellipse::{Ellipse, Gaussian};

/// The state of a track in the coordinates it currently lives in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Estimate {
    /// Single-sensor track in range / range-rate coordinates of `sensor`.
    RangeDoppler { sensor: usize, est: RangeDoppler },
    /// Multi-sensor track in Cartesian coordinates.
    Cartesian(Cartesian),
}

/// One contact of a track: the detection index, its time, and the Cartesian state after the
/// update if the track was Cartesian then.
#[derive(Debug)]
pub struct Contact {
    /// Index of the detection in the processed sequence.
    pub detection: usize,
    /// Time of the detection.
    pub time: f64,
    /// `(x, y, vx, vy)` after the update, for Cartesian tracks.
    pub state: Option<[f64; 4]>,
    /// The previous contact.
    pub prev: Option<Arc<Contact>>,
}

/// A track of one hypothesis.
#[derive(Debug, Clone)]
pub struct Track {
    /// Identifier: the index of the detection that started the track (the same in every
    /// hypothesis that contains the track).
    pub id: usize,
    /// Current estimate.
    pub estimate: Estimate,
    /// Global scan index of the last update.
    pub last_scan: usize,
    /// Time of the last update.
    pub last_time: f64,
    /// Number of contacts (the first detection included).
    pub contacts: usize,
    /// Bit mask of the sensors that contributed.
    pub sensor_mask: u64,
    /// Most recent contact.
    pub history: Arc<Contact>,
}

impl Track {
    /// A new range-Doppler track started by detection `index` with covariance `r`.
    pub fn start(index: usize, det: &Detection, r: &Matrix2<f64>) -> Self {
        Self {
            id: index,
            estimate: Estimate::RangeDoppler {
                sensor: det.sensor,
                est: RangeDoppler {
                    time: det.time,
                    x: det.z(),
                    p: *r,
                },
            },
            last_scan: det.scan,
            last_time: det.time,
            contacts: 1,
            sensor_mask: 1u64 << det.sensor,
            history: Arc::new(Contact {
                detection: index,
                time: det.time,
                state: None,
                prev: None,
            }),
        }
    }

    /// Whether the track is Cartesian.
    pub fn is_cartesian(&self) -> bool {
        matches!(self.estimate, Estimate::Cartesian(_))
    }

    /// Number of distinct sensors that contributed.
    pub fn sensor_count(&self) -> u32 {
        self.sensor_mask.count_ones()
    }

    /// The Cartesian estimate, if any.
    pub fn cartesian(&self) -> Option<&Cartesian> {
        match &self.estimate {
            Estimate::Cartesian(c) => Some(c),
            Estimate::RangeDoppler { .. } => None,
        }
    }

    /// Indices of the detections of this track, oldest first.
    pub fn detections(&self) -> Vec<usize> {
        let mut out = Vec::with_capacity(self.contacts);
        let mut node = Some(&self.history);
        while let Some(c) = node {
            out.push(c.detection);
            node = c.prev.as_ref();
        }
        out.reverse();
        out
    }

    /// Cartesian states `(time, x, y, vx, vy)` after each Cartesian update, oldest first.
    pub fn path(&self) -> Vec<[f64; 5]> {
        let mut out = Vec::new();
        let mut node = Some(&self.history);
        while let Some(c) = node {
            if let Some(s) = c.state {
                out.push([c.time, s[0], s[1], s[2], s[3]]);
            }
            node = c.prev.as_ref();
        }
        out.reverse();
        out
    }

    /// Whether `sensor` could detect the track: a Cartesian track inside its beam and range,
    /// any range-Doppler track (its bearing is unknown; in the paper's layout every beam covers
    /// the same half plane).
    pub fn detectable_by(&self, sensor: &Sensor) -> bool {
        match &self.estimate {
            Estimate::Cartesian(c) => sensor.sees(c.position()),
            Estimate::RangeDoppler { .. } => true,
        }
    }

    /// The 2-sigma area of uncertainty of a Cartesian track's position as a geofeas
    /// [`Ellipse`] (seed 000, eqs. 56-59), for scoring with the geofeasibility scores.
    pub fn ellipse(&self) -> Option<Ellipse> {
        let c = self.cartesian()?;
        Some(
            Gaussian::new(
                [c.x[0], c.x[1]],
                [c.p[(0, 0)], 0.5 * (c.p[(0, 1)] + c.p[(1, 0)]), c.p[(1, 1)]],
            )
            .to_ellipse(),
        )
    }

    fn extended(&self, index: usize, det: &Detection, estimate: Estimate) -> Self {
        let state = match &estimate {
            Estimate::Cartesian(c) => Some([c.x[0], c.x[1], c.x[2], c.x[3]]),
            Estimate::RangeDoppler { .. } => None,
        };
        Self {
            id: self.id,
            estimate,
            last_scan: det.scan,
            last_time: det.time,
            contacts: self.contacts + 1,
            sensor_mask: self.sensor_mask | (1u64 << det.sensor),
            history: Arc::new(Contact {
                detection: index,
                time: det.time,
                state,
                prev: Some(self.history.clone()),
            }),
        }
    }

    /// Associates detection `index` to this track with one of the three association types.
    /// Returns the updated track and the log-likelihood of the detection, or `None` if the
    /// association is impossible (outside the gate, no trilateration, not detectable).
    pub fn associate(
        &self,
        index: usize,
        det: &Detection,
        sensors: &[Sensor],
        cfg: &MhtConfig,
    ) -> Option<(Self, f64)> {
        let r = cfg.noise.covariance();
        let si = &sensors[det.sensor];
        match &self.estimate {
            Estimate::RangeDoppler { sensor, est } if *sensor == det.sensor => {
                let pred = est.predict(det.time, cfg.accel_sigma);
                let (upd, loglik, d2) = pred.update(det.z(), &r)?;
                if d2 > cfg.gate {
                    return None;
                }
                let e = Estimate::RangeDoppler {
                    sensor: *sensor,
                    est: upd,
                };
                Some((self.extended(index, det, e), loglik))
            }
            Estimate::RangeDoppler { sensor, est } => {
                let sj = &sensors[*sensor];
                let pred = est.predict(det.time, cfg.accel_sigma);
                let (x, p) = trilaterate_gaussian(sj, pred.x, &pred.p, si, det.z(), &r)?;
                let rel = Vector2::new(x[0], x[1]);
                let a = (rel - Vector2::from(sj.position)).normalize();
                let b = (rel - Vector2::from(si.position)).normalize();
                if (a[0] * b[1] - a[1] * b[0]).abs() < cfg.min_sin_angle {
                    return None;
                }
                let speed = x[2].hypot(x[3]);
                let speed_sd = (p[(2, 2)] + p[(3, 3)]).max(0.0).sqrt();
                if speed > cfg.max_speed + 3.0 * speed_sd || det.range_rate.abs() > cfg.max_speed {
                    return None;
                }
                let d = (Vector2::from(si.position) - Vector2::from(sj.position)).norm();
                let width = 2.0 * pred.x[0].max(0.0).min(d);
                if width.is_nan() || width <= 0.0 {
                    return None;
                }
                let loglik = -(width * 2.0 * cfg.max_speed).ln();
                let e = Estimate::Cartesian(Cartesian {
                    time: det.time,
                    x,
                    p,
                });
                Some((self.extended(index, det, e), loglik))
            }
            Estimate::Cartesian(c) => {
                let pred = c.predict(det.time, cfg.accel_sigma);
                if !si.sees(pred.position()) {
                    return None;
                }
                let (upd, loglik, d2) =
                    pred.update_iterated(si, det.z(), &r, cfg.ekf_iterations)?;
                // The updated track must stay in front of the sensor: with collinear sensors the
                // mirror image behind them explains the detections equally well.
                if d2 > cfg.gate || !si.in_beam(upd.position()) {
                    return None;
                }
                Some((self.extended(index, det, Estimate::Cartesian(upd)), loglik))
            }
        }
    }
}
