//! Range / range-rate radars at arbitrary planar positions (seed 004, section 2 and eq. 20).
//!
//! A [`Sensor`] sits at `position`, looks along `boresight` (radians counter-clockwise from +x)
//! with a beam of half-width `half_beam`, and measures the range `r = |p - s|` and range rate
//! `r' = (p - s) . v / r` of a target with Cartesian state `(x, y, vx, vy)` (eq. 20, generalised
//! from sensors on the x axis to any position). [`Sensor::jacobian`] is the derivative of that map;
//! eq. 21 of the paper prints the element `d r' / d x` as `y (x' - x y') / r^3`, which is a typo
//! for `dy (dy x' - dx y') / r^3` (checked against finite differences in the tests).

use nalgebra::{Matrix2, Matrix2x4, Vector2, Vector4};

use geofeas::error::{Error, Result};

/// A radar measuring range and range rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensor {
    /// Position `(x, y)` in metres.
    pub position: [f64; 2],
    /// Pointing direction, radians counter-clockwise from +x (`pi / 2` faces +y).
    pub boresight: f64,
    /// Half of the beam width, radians (`pi / 2` for the paper's 180 degrees).
    pub half_beam: f64,
    /// Scan period, seconds.
    pub period: f64,
    /// Time of the first scan, seconds.
    pub offset: f64,
    /// Largest range reported; false alarms are uniform in `[0, max_range]`.
    pub max_range: f64,
    /// Largest |range rate| reported; false alarms are uniform in `[-max_range_rate, max_range_rate]`.
    pub max_range_rate: f64,
}

impl Sensor {
    /// A sensor of the paper (section 5.1): at `(x, 0)`, 180-degree beam facing +y, 100 m range
    /// window and +-15 m/s range-rate window for the false alarms.
    pub fn paper(x: f64, period: f64) -> Self {
        Self {
            position: [x, 0.0],
            boresight: std::f64::consts::FRAC_PI_2,
            half_beam: std::f64::consts::FRAC_PI_2,
            period,
            offset: 0.0,
            max_range: 100.0,
            max_range_rate: 15.0,
        }
    }

    /// Checks finiteness and ranges of every field; `row` is reported in the error.
    pub fn validated(self, row: usize) -> Result<Self> {
        let fields = [
            ("x", self.position[0]),
            ("y", self.position[1]),
            ("boresight", self.boresight),
            ("half_beam", self.half_beam),
            ("period", self.period),
            ("offset", self.offset),
            ("max_range", self.max_range),
            ("max_range_rate", self.max_range_rate),
        ];
        for (field, value) in fields {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    what: "sensor",
                    row,
                    field,
                    value,
                });
            }
        }
        for (field, value) in [
            ("half_beam", self.half_beam),
            ("period", self.period),
            ("max_range", self.max_range),
            ("max_range_rate", self.max_range_rate),
        ] {
            if value <= 0.0 {
                return Err(Error::NonPositive {
                    what: "sensor",
                    row,
                    field,
                    value,
                });
            }
        }
        if self.half_beam > std::f64::consts::PI {
            return Err(Error::Invalid(format!(
                "sensor row {row}: half_beam {} exceeds pi",
                self.half_beam
            )));
        }
        Ok(self)
    }

    /// Whether the point `p` lies inside the beam (range not limited).
    pub fn in_beam(&self, p: [f64; 2]) -> bool {
        let (dx, dy) = (p[0] - self.position[0], p[1] - self.position[1]);
        let r = dx.hypot(dy);
        if r == 0.0 {
            return false;
        }
        let (s, c) = self.boresight.sin_cos();
        (dx * c + dy * s) / r >= self.half_beam.cos() - 1e-12
    }

    /// Whether the sensor can detect a target at `p`: inside the beam and the range window.
    pub fn sees(&self, p: [f64; 2]) -> bool {
        self.in_beam(p)
            && (p[0] - self.position[0]).hypot(p[1] - self.position[1]) <= self.max_range
    }

    /// The measurement function `h_i(x) = (r, r')` of eq. 20.
    pub fn measure(&self, x: &Vector4<f64>) -> Vector2<f64> {
        let (dx, dy) = (x[0] - self.position[0], x[1] - self.position[1]);
        let r = dx.hypot(dy);
        Vector2::new(r, (dx * x[2] + dy * x[3]) / r)
    }

    /// The Jacobian `H_i` of [`Sensor::measure`] at `x` (eq. 21, corrected).
    pub fn jacobian(&self, x: &Vector4<f64>) -> Matrix2x4<f64> {
        let (dx, dy) = (x[0] - self.position[0], x[1] - self.position[1]);
        let r = dx.hypot(dy);
        let r3 = r * r * r;
        let cross = dy * x[2] - dx * x[3];
        Matrix2x4::new(
            dx / r,
            dy / r,
            0.0,
            0.0,
            dy * cross / r3,
            -dx * cross / r3,
            dx / r,
            dy / r,
        )
    }

    /// Volume of the range / range-rate window, `max_range * 2 max_range_rate`.
    pub fn window_volume(&self) -> f64 {
        self.max_range * 2.0 * self.max_range_rate
    }
}

/// The paper's three sensors (section 5.1): x = -10, 0, 10 m, scan periods 0.5, 0.6, 0.7 s.
pub fn paper_sensors() -> Vec<Sensor> {
    vec![
        Sensor::paper(-10.0, 0.5),
        Sensor::paper(0.0, 0.6),
        Sensor::paper(10.0, 0.7),
    ]
}

/// Measurement noise of a radar: standard deviations of range and range rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    /// Range standard deviation, metres (paper: 0.05).
    pub sigma_range: f64,
    /// Range-rate standard deviation, m/s (paper: 0.02).
    pub sigma_range_rate: f64,
}

impl Default for Noise {
    fn default() -> Self {
        Self {
            sigma_range: 0.05,
            sigma_range_rate: 0.02,
        }
    }
}

impl Noise {
    /// The measurement covariance `R`.
    pub fn covariance(&self) -> Matrix2<f64> {
        Matrix2::new(
            self.sigma_range * self.sigma_range,
            0.0,
            0.0,
            self.sigma_range_rate * self.sigma_range_rate,
        )
    }

    /// Checks both deviations are finite and > 0.
    pub fn validated(self) -> Result<Self> {
        for (name, v) in [
            ("sigma_range", self.sigma_range),
            ("sigma_range_rate", self.sigma_range_rate),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::InvalidOption {
                    name,
                    reason: format!("must be finite and > 0, got {v}"),
                });
            }
        }
        Ok(self)
    }
}

/// One detection: a range / range-rate contact of one sensor at one scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detection {
    /// Time of the scan, seconds.
    pub time: f64,
    /// Index of the sensor.
    pub sensor: usize,
    /// Global scan index: detections with the same `scan` come from one sweep of one sensor.
    pub scan: usize,
    /// Measured range, metres.
    pub range: f64,
    /// Measured range rate, m/s.
    pub range_rate: f64,
    /// Ground truth: the target that caused it, `None` for a false alarm (simulation only).
    pub target: Option<usize>,
}

impl Detection {
    /// The measurement vector `z = (r, r')`.
    pub fn z(&self) -> Vector2<f64> {
        Vector2::new(self.range, self.range_rate)
    }
}
