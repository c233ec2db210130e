//! Extended Kalman filter in Cartesian coordinates for multi-sensor tracks (seed 004, section 4.3,
//! eqs. 10-15 and 19-21).
//!
//! The state is `(x, y, vx, vy)`; the motion model is nearly constant velocity with white
//! acceleration of standard deviation `accel_sigma` on each axis (eq. 11 with
//! `G = [[dt^2/2, 0], [0, dt^2/2], [dt, 0], [0, dt]]`); a detection of sensor `i` is compared with
//! `h_i(x)` (eq. 20) through the Jacobian `H_i` (eq. 21, see [`Sensor::jacobian`]).

use nalgebra::{Matrix2, Matrix4, Matrix4x2, Vector2, Vector4};

use super::innovation;
use super::sensor::Sensor;

/// A Cartesian estimate at `time`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cartesian {
    /// Time of the estimate, seconds.
    pub time: f64,
    /// `(x, y, vx, vy)`.
    pub x: Vector4<f64>,
    /// Covariance of `x`.
    pub p: Matrix4<f64>,
}

impl Cartesian {
    /// Prediction to time `t` (eqs. 10-11).
    pub fn predict(&self, t: f64, accel_sigma: f64) -> Self {
        let dt = t - self.time;
        let mut f = Matrix4::identity();
        f[(0, 2)] = dt;
        f[(1, 3)] = dt;
        let h = 0.5 * dt * dt;
        let g = Matrix4x2::new(h, 0.0, 0.0, h, dt, 0.0, 0.0, dt);
        let q = accel_sigma * accel_sigma;
        Self {
            time: t,
            x: f * self.x,
            p: f * self.p * f.transpose() + g * g.transpose() * q,
        }
    }

    /// Position `(x, y)`.
    pub fn position(&self) -> [f64; 2] {
        [self.x[0], self.x[1]]
    }

    /// Predicted measurement `h_i(x)` and innovation covariance `S = H P H^T + R` for `sensor`.
    pub fn innovation_covariance(
        &self,
        sensor: &Sensor,
        r: &Matrix2<f64>,
    ) -> (Vector2<f64>, Matrix2<f64>) {
        let h = sensor.jacobian(&self.x);
        (sensor.measure(&self.x), h * self.p * h.transpose() + r)
    }

    /// EKF update with the detection `z ~ N(h_i(x), r)` of `sensor` (eqs. 12-15). Returns the
    /// updated estimate, `ln N(e; 0, S)` and the squared Mahalanobis distance; `None` if the
    /// predicted position is on the sensor or `S` is not positive definite.
    pub fn update(
        &self,
        sensor: &Sensor,
        z: Vector2<f64>,
        r: &Matrix2<f64>,
    ) -> Option<(Self, f64, f64)> {
        self.update_iterated(sensor, z, r, 0)
    }

    /// [`Cartesian::update`] relinearising `h_i` at the updated estimate `iterations` times
    /// (iterated EKF, a Gauss-Newton step on the posterior each); the likelihood and gate use the
    /// linearisation at the prediction.
    pub fn update_iterated(
        &self,
        sensor: &Sensor,
        z: Vector2<f64>,
        r: &Matrix2<f64>,
        iterations: usize,
    ) -> Option<(Self, f64, f64)> {
        let dx = self.x[0] - sensor.position[0];
        let dy = self.x[1] - sensor.position[1];
        if dx.hypot(dy) <= 1e-9 {
            return None;
        }
        let h = sensor.jacobian(&self.x);
        let e = z - sensor.measure(&self.x);
        let s = h * self.p * h.transpose() + r;
        let (sinv, loglik, d2) = innovation(&e, &s)?;
        let mut k = self.p * h.transpose() * sinv;
        let mut x = self.x + k * e;
        let mut h = h;
        // Iterated EKF (Gauss-Newton on the posterior): relinearise h_i at the new estimate.
        for _ in 0..iterations {
            let d =
                ((x[0] - sensor.position[0]).powi(2) + (x[1] - sensor.position[1]).powi(2)).sqrt();
            if d <= 1e-9 {
                break;
            }
            h = sensor.jacobian(&x);
            let si = h * self.p * h.transpose() + r;
            let Some(si_inv) = si.try_inverse() else {
                break;
            };
            k = self.p * h.transpose() * si_inv;
            x = self.x + k * (z - sensor.measure(&x) - h * (self.x - x));
        }
        let i_kh = Matrix4::identity() - k * h;
        let p = i_kh * self.p * i_kh.transpose() + k * r * k.transpose();
        Some((
            Self {
                time: self.time,
                x,
                p: 0.5 * (p + p.transpose()),
            },
            loglik,
            d2,
        ))
    }
}
