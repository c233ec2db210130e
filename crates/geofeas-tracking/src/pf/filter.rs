//! One bootstrap particle filter of the bank (seed 003: "four separate PFs rather than a
//! concatenated filter", section I; the predict / weight / resample cycle of its reference 1, Gordon, Salmond and Smith).
//!
//! A filter holds its particles, their normalised weights and its own random stream. Its
//! estimate is the weighted mean and covariance of the posterior cloud (before resampling); the
//! 2-sigma bounds of Figs. 7, 10, 14 and 17 are `2 sqrt(P_xx)`, `2 sqrt(P_yy)`, and the position
//! covariance gives a geofeas [`Ellipse`] (AOU). The measurement residual of Fig. 12 is computed
//! as the paper describes: for each prior particle, the measured minus the modelled intensity in
//! the cell nearest to it, then the weighted mean and standard deviation over the particles.

use rand_xoshiro::Xoshiro256PlusPlus;

use crate::pf::frame::Frame;
use crate::pf::motion::{Ncv, Particles};
use crate::pf::resample::Resampling;
use crate::pf::weights::{normalise, LikelihoodModel};
use geofeas::ellipse::{Ellipse, Gaussian};

/// Weighted mean and covariance of a particle cloud, `(x, y, v_x, v_y)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Mean state.
    pub mean: [f64; 4],
    /// Covariance, row-major 4 x 4.
    pub cov: [[f64; 4]; 4],
}

impl Estimate {
    /// The 2-sigma position bounds `(2 sqrt(P_xx), 2 sqrt(P_yy))`.
    pub fn two_sigma(&self) -> [f64; 2] {
        [2.0 * self.cov[0][0].sqrt(), 2.0 * self.cov[1][1].sqrt()]
    }

    /// The position Gaussian.
    pub fn gaussian(&self) -> Gaussian {
        Gaussian::new(
            [self.mean[0], self.mean[1]],
            [self.cov[0][0], self.cov[0][1], self.cov[1][1]],
        )
    }

    /// The 2-sigma area of uncertainty of the position, in the frame's `(x, y)` coordinates
    /// (for the geofeasibility scores; a degenerate cloud gives zero semi-axes).
    pub fn ellipse(&self) -> Ellipse {
        self.gaussian().to_ellipse()
    }
}

/// One particle filter.
#[derive(Debug, Clone)]
pub struct ParticleFilter {
    /// The particles.
    pub particles: Particles,
    /// Their normalised weights.
    pub weights: Vec<f64>,
    rng: Xoshiro256PlusPlus,
    log_w: Vec<f64>,
    idx: Vec<usize>,
}

impl ParticleFilter {
    /// A filter of `n` particles uniform in `centre +- (xmax, xmax, vmax, vmax)`, equally
    /// weighted, drawing from `rng`.
    pub fn new(
        n: usize,
        centre: [f64; 4],
        xmax: f64,
        vmax: f64,
        mut rng: Xoshiro256PlusPlus,
    ) -> Self {
        let particles = Particles::uniform(n, centre, xmax, vmax, &mut rng);
        Self {
            particles,
            weights: vec![1.0 / n as f64; n],
            rng,
            log_w: vec![0.0; n],
            idx: Vec::with_capacity(n),
        }
    }

    /// Propagates the particles through the motion model.
    pub fn predict(&mut self, model: &Ncv) {
        model.predict(&mut self.particles, &mut self.rng);
    }

    /// Multiplies the weights by `exp(log_l)` computed by `fill` into a scratch buffer and
    /// renormalises; returns `log sum_n w_n l_n` (the log of the filter's marginal likelihood
    /// increment).
    pub fn update(&mut self, fill: impl FnOnce(&Particles, &mut [f64])) -> f64 {
        fill(&self.particles, &mut self.log_w);
        for (l, w) in self.log_w.iter_mut().zip(&self.weights) {
            *l += w.ln();
        }
        let mut w = std::mem::take(&mut self.weights);
        let lse = normalise(&self.log_w, &mut w);
        self.weights = w;
        lse
    }

    /// Effective sample size `1 / sum w^2`.
    pub fn ess(&self) -> f64 {
        1.0 / self.weights.iter().map(|w| w * w).sum::<f64>()
    }

    /// Weighted mean and covariance.
    #[allow(clippy::needless_range_loop)]
    pub fn estimate(&self) -> Estimate {
        let p = &self.particles;
        let cols = [&p.x, &p.y, &p.vx, &p.vy];
        let mut mean = [0.0; 4];
        for (m, c) in mean.iter_mut().zip(cols) {
            *m = c.iter().zip(&self.weights).map(|(v, w)| v * w).sum();
        }
        let mut cov = [[0.0; 4]; 4];
        for n in 0..p.len() {
            let w = self.weights[n];
            let d = [
                p.x[n] - mean[0],
                p.y[n] - mean[1],
                p.vx[n] - mean[2],
                p.vy[n] - mean[3],
            ];
            for a in 0..4 {
                for b in a..4 {
                    cov[a][b] += w * d[a] * d[b];
                }
            }
        }
        for a in 0..4 {
            for b in 0..a {
                cov[a][b] = cov[b][a];
            }
        }
        Estimate { mean, cov }
    }

    /// Fig. 12 residual `(weighted mean, weighted sd)` of `z - h` in the cell nearest to each
    /// particle, with the filter's model; particles off the frame are left out (NaN if all are).
    pub fn residual(&self, frame: &Frame, model: &LikelihoodModel) -> [f64; 2] {
        let p = &self.particles;
        let (mut sw, mut s1, mut s2) = (0.0, 0.0, 0.0);
        let (wmax, hmax) = (frame.width as f64 - 1.0, frame.height as f64 - 1.0);
        for n in 0..p.len() {
            let (i, j) = ((p.x[n] + 0.5).floor(), (p.y[n] + 0.5).floor());
            if !(i >= 0.0 && j >= 0.0 && i <= wmax && j <= hmax) {
                continue;
            }
            let r = frame.at(i as usize, j as usize) - model.intensity(i, j, p.x[n], p.y[n]);
            let w = self.weights[n];
            sw += w;
            s1 += w * r;
            s2 += w * r * r;
        }
        if sw <= 0.0 {
            return [f64::NAN; 2];
        }
        let m = s1 / sw;
        [m, (s2 / sw - m * m).max(0.0).sqrt()]
    }

    /// Resamples with `scheme` and resets the weights to `1/N`.
    pub fn resample(&mut self, scheme: Resampling) {
        scheme.resample(&self.weights, &mut self.rng, &mut self.idx);
        self.particles = self.particles.select(&self.idx);
        let u = 1.0 / self.weights.len() as f64;
        self.weights.iter_mut().for_each(|w| *w = u);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geofeas::rng::stream;

    #[test]
    fn estimate_of_a_uniform_cloud() {
        let f = ParticleFilter::new(100_000, [10.0, 20.0, 1.0, -1.0], 3.0, 0.5, stream(1, 0));
        let e = f.estimate();
        assert!((e.mean[0] - 10.0).abs() < 0.03 && (e.mean[3] + 1.0).abs() < 0.005);
        assert!((e.cov[0][0] - 3.0).abs() < 0.05); // (2 * 3)^2 / 12
        assert!((e.cov[2][2] - 1.0 / 12.0).abs() < 0.002);
        assert!(e.cov[0][1].abs() < 0.05);
        let el = e.ellipse();
        assert!((el.rx - 2.0 * 3f64.sqrt()).abs() < 0.05);
        assert!((f.ess() - 100_000.0).abs() < 1e-6);
    }

    #[test]
    fn residuals_vanish_with_the_exact_model_and_match_the_noise() {
        use crate::pf::frame::Psf;
        let psf = Psf::default();
        let model = LikelihoodModel::scaled(&psf, 0.1, [1.0, 1.0, 1.0]);
        let at = ParticleFilter::new(100, [40.3, 30.6, 0.0, 0.0], 0.0, 0.0, stream(3, 0));
        let mut clean = Frame::zeros(80, 60);
        clean.add_psf(40.3, 30.6, &psf);
        // Particles on the target with the true model explain the noise-free frame exactly.
        let [m, sd] = at.residual(&clean, &model);
        assert!(m.abs() < 1e-12 && sd < 1e-6, "{m} {sd}");
        let f = ParticleFilter::new(5000, [40.3, 30.6, 0.0, 0.0], 1.0, 0.0, stream(3, 0));
        // Pure noise of sigma 0.5 and no target: mean ~0, sd ~0.5 (cells shared by particles).
        let noise = Frame::render(80, 60, &[], &psf, 0.5, &mut stream(3, 1));
        let far = LikelihoodModel {
            amplitude: 1e-12,
            ..model
        };
        let [m, sd] = f.residual(&noise, &far);
        assert!(m.abs() < 0.5 && (0.2..0.8).contains(&sd), "{m} {sd}");
    }

    #[test]
    fn update_is_bayes_and_resampling_resets() {
        let mut f = ParticleFilter::new(4, [0.0; 4], 1.0, 1.0, stream(2, 0));
        let lse = f.update(|_, out| out.copy_from_slice(&[0.0, 1.0f64.ln(), 3.0f64.ln(), -1e9]));
        assert!((lse - (5.0f64 / 4.0).ln()).abs() < 1e-12);
        assert!((f.weights[2] - 0.6).abs() < 1e-12 && f.weights[3] == 0.0);
        assert!((f.ess() - 1.0 / (0.04 + 0.04 + 0.36)).abs() < 1e-9);
        f.resample(Resampling::Systematic);
        assert!(f.weights.iter().all(|&w| w == 0.25));
    }
}
