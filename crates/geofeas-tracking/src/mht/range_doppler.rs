//! Kalman filter in range / range-rate coordinates for single-sensor tracks (seed 004, section 4.2,
//! eqs. 10-18).
//!
//! The state is `(r, r')` of one sensor; the motion model is constant range rate with white
//! range acceleration of standard deviation `accel_sigma` (`F = [[1, dt], [0, 1]]`,
//! `G = (dt^2 / 2, dt)`, eq. 11); the measurement matrix is the identity (eqs. 17-18).

use nalgebra::{Matrix2, Vector2};

use super::innovation;

/// A range / range-rate estimate at `time`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RangeDoppler {
    /// Time of the estimate, seconds.
    pub time: f64,
    /// `(r, r')`.
    pub x: Vector2<f64>,
    /// Covariance of `x`.
    pub p: Matrix2<f64>,
}

impl RangeDoppler {
    /// Prediction to time `t` (eqs. 10-11).
    pub fn predict(&self, t: f64, accel_sigma: f64) -> Self {
        let dt = t - self.time;
        let f = Matrix2::new(1.0, dt, 0.0, 1.0);
        let g = Vector2::new(0.5 * dt * dt, dt);
        let q = accel_sigma * accel_sigma;
        Self {
            time: t,
            x: f * self.x,
            p: f * self.p * f.transpose() + g * g.transpose() * q,
        }
    }

    /// Kalman update with the measurement `z ~ N(x, r)` (eqs. 12-15 with `H = I`). Returns the
    /// updated estimate, the log-likelihood `ln N(e; 0, S)` and the squared Mahalanobis distance
    /// of the innovation; `None` if `S` is not positive definite.
    pub fn update(&self, z: Vector2<f64>, r: &Matrix2<f64>) -> Option<(Self, f64, f64)> {
        let e = z - self.x;
        let s = self.p + r;
        let (sinv, loglik, d2) = innovation(&e, &s)?;
        let k = self.p * sinv;
        let i_k = Matrix2::identity() - k;
        // Joseph form keeps the covariance symmetric positive definite.
        let p = i_k * self.p * i_k.transpose() + k * r * k.transpose();
        Some((
            Self {
                time: self.time,
                x: self.x + k * e,
                p: 0.5 * (p + p.transpose()),
            },
            loglik,
            d2,
        ))
    }
}
