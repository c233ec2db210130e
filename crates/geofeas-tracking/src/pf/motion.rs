//! Particle clouds and the filter's nearly-constant-velocity model (seed 003, Fig. 4).
//!
//! `X_{k+1} = Phi X_k + Gamma w_k` with `X = (x, y, v_x, v_y)`,
//! `Phi = [[I, T I], [0, I]]`, `Gamma = [T^2/2 I, T I]` and `w_k ~ N(0, sigma_w^2 I)` (paper:
//! `sigma_w = 0.5` pixels/s^2 at `T = 0.1` s). Particles are stored as four columns; the process
//! noise is drawn in particle order from the filter's own stream, so a seed gives the same cloud
//! whatever the number of threads.

use rand::{Rng, RngExt};
use rand_distr::StandardNormal;

/// `N` particles as columns `x, y, v_x, v_y`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Particles {
    /// Positions, pixels.
    pub x: Vec<f64>,
    /// Positions, pixels.
    pub y: Vec<f64>,
    /// Velocities, pixels/s.
    pub vx: Vec<f64>,
    /// Velocities, pixels/s.
    pub vy: Vec<f64>,
}

impl Particles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// `n` particles uniform in `centre +- (xmax, xmax, vmax, vmax)` (the paper's
    /// initialisation, section V).
    pub fn uniform<R: Rng>(n: usize, centre: [f64; 4], xmax: f64, vmax: f64, rng: &mut R) -> Self {
        let mut p = Self {
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            vx: Vec::with_capacity(n),
            vy: Vec::with_capacity(n),
        };
        let mut u = |c: f64, h: f64| c + h * (2.0 * rng.random::<f64>() - 1.0);
        for _ in 0..n {
            p.x.push(u(centre[0], xmax));
            p.y.push(u(centre[1], xmax));
            p.vx.push(u(centre[2], vmax));
            p.vy.push(u(centre[3], vmax));
        }
        p
    }

    /// The particles at indices `idx` (resampling).
    pub fn select(&self, idx: &[usize]) -> Self {
        let pick = |v: &Vec<f64>| idx.iter().map(|&i| v[i]).collect();
        Self {
            x: pick(&self.x),
            y: pick(&self.y),
            vx: pick(&self.vx),
            vy: pick(&self.vy),
        }
    }
}

/// The nearly-constant-velocity model of Fig. 4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ncv {
    /// Time step `T`, s (paper: 0.1).
    pub dt: f64,
    /// 1-sigma of the x / y accelerations, pixels/s^2 (paper: 0.5).
    pub sigma_w: f64,
}

impl Default for Ncv {
    fn default() -> Self {
        Self {
            dt: 0.1,
            sigma_w: 0.5,
        }
    }
}

impl Ncv {
    /// Propagates every particle one step.
    pub fn predict<R: Rng>(&self, p: &mut Particles, rng: &mut R) {
        let (t, h) = (self.dt, 0.5 * self.dt * self.dt);
        for n in 0..p.len() {
            let wx = self.sigma_w * rng.sample::<f64, _>(StandardNormal);
            let wy = self.sigma_w * rng.sample::<f64, _>(StandardNormal);
            p.x[n] += t * p.vx[n] + h * wx;
            p.y[n] += t * p.vy[n] + h * wy;
            p.vx[n] += t * wx;
            p.vy[n] += t * wy;
        }
    }

    /// The covariance `Gamma Gamma^T sigma_w^2` added per step to `(x, v_x)` (same for y):
    /// `[[T^4/4, T^3/2], [T^3/2, T^2]] sigma_w^2`.
    pub fn process_covariance(&self) -> [[f64; 2]; 2] {
        let (t, q) = (self.dt, self.sigma_w * self.sigma_w);
        [
            [t.powi(4) / 4.0 * q, t.powi(3) / 2.0 * q],
            [t.powi(3) / 2.0 * q, t * t * q],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geofeas::rng::stream;

    #[test]
    fn prediction_moments_match_phi_and_gamma() {
        let mut p = Particles::uniform(
            200_000,
            [10.0, 20.0, 3.0, -2.0],
            0.0,
            0.0,
            &mut stream(1, 0),
        );
        let m = Ncv {
            dt: 0.1,
            sigma_w: 2.0,
        };
        m.predict(&mut p, &mut stream(1, 1));
        let n = p.len() as f64;
        let mean = |v: &Vec<f64>| v.iter().sum::<f64>() / n;
        let (mx, mvx) = (mean(&p.x), mean(&p.vx));
        assert!((mx - 10.3).abs() < 1e-3 && (mean(&p.y) - 19.8).abs() < 1e-3);
        let cxx = p.x.iter().map(|v| (v - mx).powi(2)).sum::<f64>() / n;
        let cxv =
            p.x.iter()
                .zip(&p.vx)
                .map(|(a, b)| (a - mx) * (b - mvx))
                .sum::<f64>()
                / n;
        let cvv = p.vx.iter().map(|v| (v - mvx).powi(2)).sum::<f64>() / n;
        let q = m.process_covariance();
        assert!((cxx / q[0][0] - 1.0).abs() < 0.02);
        assert!((cxv / q[0][1] - 1.0).abs() < 0.02);
        assert!((cvv / q[1][1] - 1.0).abs() < 0.02);
    }

    #[test]
    fn uniform_initialisation_bounds() {
        let p = Particles::uniform(10_000, [5.0, 6.0, 1.0, 2.0], 3.0, 0.5, &mut stream(2, 0));
        assert!(p.x.iter().all(|v| (2.0..=8.0).contains(v)));
        assert!(p.vy.iter().all(|v| (1.5..=2.5).contains(v)));
        let var = p.x.iter().map(|v| (v - 5.0).powi(2)).sum::<f64>() / 10_000.0;
        assert!((var - 3.0).abs() < 0.15, "{var}"); // (2 * 3)^2 / 12
    }
}
