//! The bank of independent particle filters, one per target, run frame by frame (seed 003,
//! sections III-V).
//!
//! For each frame `k`: every filter propagates its particles (Fig. 4; not on the first frame,
//! where the particles are the uniform initialisation about the truth); the frame's peaks are
//! extracted ([`crate::pf::peaks`]); each filter computes `R_i^j` from its prior
//! particles and prior weights and the peaks are assigned ([`Assignment`]); the weights are
//! multiplied by Method 1's or Method 2's likelihood ([`Method`]) and renormalised; the posterior
//! mean and covariance and the Fig. 12 residual are recorded; the filter resamples when its
//! effective sample size is below `resample_threshold x N` (1: every frame, the paper's SIR).
//! With Method 2 the association is computed and recorded (it is the paper's probability of
//! correct association) but the weights do not use it: the likelihood ratio looks at the pixels
//! about each particle.
//!
//! Filter `i` draws from the stream `(seed, i)`, so the bank's output depends only on the seed,
//! never on the number of threads.

use rayon::prelude::*;

use crate::pf::assignment::{weighted_distances, Assignment};
use crate::pf::filter::{Estimate, ParticleFilter};
use crate::pf::frame::{Frame, Psf};
use crate::pf::motion::{Ncv, Particles};
use crate::pf::peaks::{find_peaks, Peak, PeakOptions};
use crate::pf::resample::Resampling;
use crate::pf::weights::{peak_distance_log_weights, LikelihoodModel};
use geofeas::error::{Error, Result};
use geofeas::rng::stream;

/// How particles are weighted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Method 1 (section IV): `exp(-(r / r1)^2)` to the associated peak.
    PeakDistance,
    /// Method 2 (section V): the track-before-detect likelihood ratio.
    LikelihoodRatio,
}

impl Method {
    /// 1 or 2.
    pub fn from_number(n: u32) -> Result<Self> {
        match n {
            1 => Ok(Self::PeakDistance),
            2 => Ok(Self::LikelihoodRatio),
            other => Err(Error::InvalidOption {
                name: "method",
                reason: format!("expected 1 or 2, got {other}"),
            }),
        }
    }

    /// 1 or 2.
    pub fn number(&self) -> u32 {
        match self {
            Self::PeakDistance => 1,
            Self::LikelihoodRatio => 2,
        }
    }
}

/// Options of the bank.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PfConfig {
    /// Particles per filter (paper: 10,000).
    pub particles: usize,
    /// Weighting method.
    pub method: Method,
    /// Motion model (paper: T = 0.1 s, sigma_w = 0.5 pixels/s^2).
    pub motion: Ncv,
    /// Method 1 distance scale `r_1`, pixels (paper: 1).
    pub r1: f64,
    /// Method 2 measurement model (and the model of the Fig. 12 residuals).
    pub model: LikelihoodModel,
    /// Resampling scheme.
    pub resampling: Resampling,
    /// Resample when ESS < threshold x N (>= 1: every frame).
    pub resample_threshold: f64,
    /// Peak-to-filter association.
    pub association: Assignment,
    /// Peak extraction.
    pub peaks: PeakOptions,
    /// Half-width of the uniform position initialisation, pixels (paper: 3).
    pub xmax: f64,
    /// Half-width of the uniform velocity initialisation, pixels/s (paper: 0.5).
    pub vmax: f64,
    /// Use rayon over filters and particles (off inside parallel Monte-Carlo studies).
    pub parallel: bool,
    /// Compute the Fig. 12 residuals (NaN when off).
    pub residuals: bool,
}

impl PfConfig {
    /// The paper's settings for `method` on frames of true point spread `psf` and noise
    /// `sigma_z` (Table 1).
    pub fn paper(method: Method, psf: &Psf, sigma_z: f64) -> Self {
        Self {
            particles: 10_000,
            method,
            motion: Ncv::default(),
            r1: 1.0,
            model: LikelihoodModel::paper(psf, sigma_z),
            resampling: Resampling::Systematic,
            resample_threshold: 1.0,
            association: Assignment::Nearest,
            peaks: PeakOptions::default(),
            xmax: 3.0,
            vmax: 0.5,
            parallel: true,
            residuals: true,
        }
    }

    /// Checks every option.
    pub fn validated(self) -> Result<Self> {
        if self.particles == 0 || self.particles > 10_000_000 {
            return Err(Error::InvalidOption {
                name: "particles",
                reason: format!("must be in 1..=10000000, got {}", self.particles),
            });
        }
        let pos = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::InvalidOption {
                    name,
                    reason: format!("must be finite and > 0, got {v}"),
                })
            }
        };
        let nonneg = |name: &'static str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(Error::InvalidOption {
                    name,
                    reason: format!("must be finite and >= 0, got {v}"),
                })
            }
        };
        pos("dt", self.motion.dt)?;
        nonneg("sigma_w", self.motion.sigma_w)?;
        pos("r1", self.r1)?;
        nonneg("xmax", self.xmax)?;
        nonneg("vmax", self.vmax)?;
        nonneg("resample_threshold", self.resample_threshold)?;
        self.model.validated()?;
        self.peaks.validated()?;
        Ok(self)
    }
}

/// What one filter did on one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// Posterior estimate.
    pub estimate: Estimate,
    /// The peak the filter took (index into the frame's peaks).
    pub peak: Option<usize>,
    /// `R_i^j` to every peak.
    pub distances: Vec<f64>,
    /// Fig. 12 residual `(mean, sd)`.
    pub residual: [f64; 2],
    /// Effective sample size after the update.
    pub ess: f64,
}

/// One frame's output: the peaks and each filter's record.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// The frame's peaks, strongest first.
    pub peaks: Vec<Peak>,
    /// One record per filter.
    pub filters: Vec<StepRecord>,
}

/// The bank of filters.
#[derive(Debug, Clone)]
pub struct Bank {
    config: PfConfig,
    filters: Vec<ParticleFilter>,
    frames_seen: usize,
}

impl Bank {
    /// One filter per row of `init` (`x, y, v_x, v_y`: the centre of the uniform
    /// initialisation); filter `i` draws from the stream `(seed, i)`.
    pub fn new(init: &[[f64; 4]], config: PfConfig, seed: u64) -> Result<Self> {
        let config = config.validated()?;
        for (row, s) in init.iter().enumerate() {
            for (field, &value) in ["x", "y", "vx", "vy"].iter().zip(s) {
                if !value.is_finite() {
                    return Err(Error::NonFinite {
                        what: "initial state",
                        row,
                        field,
                        value,
                    });
                }
            }
        }
        let filters = init
            .iter()
            .enumerate()
            .map(|(i, c)| {
                ParticleFilter::new(
                    config.particles,
                    *c,
                    config.xmax,
                    config.vmax,
                    stream(seed, i as u64),
                )
            })
            .collect();
        Ok(Self {
            config,
            filters,
            frames_seen: 0,
        })
    }

    /// The options.
    pub fn config(&self) -> &PfConfig {
        &self.config
    }

    /// The particles of filter `i` (after the last resampling).
    pub fn particles(&self, i: usize) -> &Particles {
        &self.filters[i].particles
    }

    /// The filters.
    pub fn filters(&self) -> &[ParticleFilter] {
        &self.filters
    }

    /// Processes the next frame.
    pub fn step(&mut self, frame: &Frame) -> Step {
        let peaks = find_peaks(frame, &self.config.peaks);
        self.step_with_peaks(frame, peaks)
    }

    /// Processes the next frame whose peaks (by this bank's [`PeakOptions`]) are already known.
    pub fn step_with_peaks(&mut self, frame: &Frame, peaks: Vec<Peak>) -> Step {
        let cfg = self.config;
        let first = self.frames_seen == 0;
        self.frames_seen += 1;
        let predict = |f: &mut ParticleFilter| {
            if !first {
                f.predict(&cfg.motion);
            }
            weighted_distances(&f.particles, &f.weights, &peaks)
        };
        let distances: Vec<Vec<f64>> = if cfg.parallel {
            self.filters.par_iter_mut().map(predict).collect()
        } else {
            self.filters.iter_mut().map(predict).collect()
        };
        let assigned = cfg.association.assign(&distances);
        let update = |(f, (peak, dist)): (&mut ParticleFilter, (Option<usize>, Vec<f64>))| {
            match cfg.method {
                Method::PeakDistance => {
                    if let Some(j) = peak {
                        f.update(|p, out| peak_distance_log_weights(p, &peaks[j], cfg.r1, out));
                    }
                }
                Method::LikelihoodRatio => {
                    f.update(|p, out| cfg.model.log_weights(frame, p, out, cfg.parallel));
                }
            }
            let estimate = f.estimate();
            let residual = if cfg.residuals {
                f.residual(frame, &cfg.model)
            } else {
                [f64::NAN; 2]
            };
            let ess = f.ess();
            if cfg.resample_threshold >= 1.0
                || ess < cfg.resample_threshold * f.weights.len() as f64
            {
                f.resample(cfg.resampling);
            }
            StepRecord {
                estimate,
                peak,
                distances: dist,
                residual,
                ess,
            }
        };
        let jobs = assigned.into_iter().zip(distances);
        let filters: Vec<StepRecord> = if cfg.parallel {
            self.filters
                .par_iter_mut()
                .zip(jobs.collect::<Vec<_>>())
                .map(update)
                .collect()
        } else {
            self.filters.iter_mut().zip(jobs).map(update).collect()
        };
        Step { peaks, filters }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pf::frame::noise_sigma;

    fn frames(pos: &[[f64; 2]], v: [f64; 2], n: usize, sigma: f64) -> Vec<Frame> {
        (0..n)
            .map(|k| {
                let t = k as f64 * 0.1;
                let p: Vec<[f64; 2]> = pos
                    .iter()
                    .map(|q| [q[0] + v[0] * t, q[1] + v[1] * t])
                    .collect();
                Frame::render(
                    128,
                    128,
                    &p,
                    &Psf::default(),
                    sigma,
                    &mut stream(77, k as u64),
                )
            })
            .collect()
    }

    #[test]
    fn both_methods_track_constant_velocity_targets() {
        let sigma = noise_sigma(15.0, 1.0);
        let pos = [[30.0, 30.0], [90.0, 40.0]];
        let fr = frames(&pos, [10.0, 5.0], 30, sigma);
        for method in [Method::PeakDistance, Method::LikelihoodRatio] {
            let cfg = PfConfig {
                particles: 2000,
                ..PfConfig::paper(method, &Psf::default(), sigma)
            };
            let init = [[31.0, 29.0, 10.3, 5.2], [89.0, 41.0, 9.8, 4.7]];
            let mut bank = Bank::new(&init, cfg, 3).unwrap();
            let mut last = None;
            for f in &fr {
                last = Some(bank.step(f));
            }
            let last = last.unwrap();
            for (i, r) in last.filters.iter().enumerate() {
                let t = 2.9;
                let (x, y) = (pos[i][0] + 10.0 * t, pos[i][1] + 5.0 * t);
                let e = (r.estimate.mean[0] - x).hypot(r.estimate.mean[1] - y);
                assert!(e < 1.0, "method {} filter {i}: error {e}", method.number());
                assert_eq!(r.peak.map(|j| last.peaks[j].x), Some(x.round()));
            }
        }
    }

    #[test]
    fn same_seed_same_output_parallel_or_not() {
        let sigma = noise_sigma(6.0, 1.0);
        let fr = frames(&[[40.0, 40.0]], [5.0, 0.0], 5, sigma);
        let run = |parallel| {
            let cfg = PfConfig {
                particles: 3000,
                parallel,
                ..PfConfig::paper(Method::LikelihoodRatio, &Psf::default(), sigma)
            };
            let mut bank = Bank::new(&[[40.0, 40.0, 5.0, 0.0]], cfg, 9).unwrap();
            fr.iter().map(|f| bank.step(f)).collect::<Vec<_>>()
        };
        assert_eq!(run(true), run(false));
    }

    #[test]
    fn bad_options_are_rejected() {
        let cfg = PfConfig::paper(Method::PeakDistance, &Psf::default(), 0.1);
        assert!(Bank::new(
            &[[0.0; 4]],
            PfConfig {
                particles: 0,
                ..cfg
            },
            0
        )
        .is_err());
        assert!(Bank::new(&[[0.0; 4]], PfConfig { r1: -1.0, ..cfg }, 0).is_err());
        let e = Bank::new(&[[0.0; 4], [0.0, f64::NAN, 0.0, 0.0]], cfg, 0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("row 1") && e.contains("'y'"), "{e}");
        assert!(Method::from_number(3).is_err());
    }
}
