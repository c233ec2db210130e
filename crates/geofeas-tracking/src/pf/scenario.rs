//! The four-target focal-plane scenario and its truth model (seed 003: Ohlmeyer and Menon,
//! "Comparison of Two Particle Filter Methods for Image Plane Tracking of Multiple Objects",
//! section II, Figs. 1 and 3).
//!
//! Each target has the Fig. 3 state `(x, y, V, gamma, a_L, a_N)`: position in pixels, speed,
//! heading (counter-clockwise from +x), and longitudinal / normal accelerations with respect to
//! the velocity vector, with `x' = V cos gamma`, `y' = V sin gamma`, `V' = a_L`,
//! `gamma' = a_N / V`. The paper gives "random normal and longitudinal accelerations" whose
//! jerk is "random Gaussian noise with standard deviations sigma_L = 0.5 and sigma_N = 1.0
//! pixels/s^2 at dt = 0.1 s" (Table 1: "target 1-sigma normal / longitudinal accel"), without
//! saying how the accelerations evolve. Three readings are offered:
//! - [`TruthModel::White`] (the default, [`Scenario::paper`]): each step draws new accelerations
//!   `a_L ~ N(0, sigma_L^2)`, `a_N ~ N(0, sigma_N^2)` held over the step, so the jerk is random
//!   and the accelerations have the 1-sigma of Table 1; the same discretisation as the filter's
//!   "sigma_w = 0.5 pixels/s^2 at dt = 0.1 s" (Fig. 4), with twice its normal intensity.
//! - [`TruthModel::Jerk`]: white jerk integrated, `a_{k+1} = a_k + j_k dt`,
//!   `j ~ N(0, sigma^2)` (pixels/s^3), from `a_0 = 0`: random-walk accelerations whose 1-sigma
//!   reaches `sigma` at t = 10 s. They persist, and the paper's filter (sigma_w = 0.5) loses
//!   targets that keep turning above ~1 pixel/s^2 (see `docs/pf-study.md`).
//! - [`TruthModel::GaussMarkov`]: stationary 1-sigma `sigma`, correlation time `tau`.
//!
//! Between steps the accelerations are held and the kinematics are integrated with the midpoint
//! rule.
//!
//! [`Scenario::paper`] starts the four targets near the corners of the 256 x 256 array, heading
//! for points close to the centre (so that they converge and cross) at 22-25 pixels/s, so that
//! they leave toward the opposite edges by t = 10 s (Fig. 1). [`TruthModel::Ncv`] replaces the
//! Fig. 3 model by the filter's own nearly-constant-velocity model (Fig. 4), for consistency
//! tests where the filter's model is exact.

use rand::{Rng, RngExt};
use rand_distr::StandardNormal;

use geofeas::error::{Error, Result};

/// Initial kinematics of one target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetStart {
    /// Position, pixels.
    pub x: f64,
    /// Position, pixels.
    pub y: f64,
    /// Speed, pixels/s.
    pub speed: f64,
    /// Heading, radians counter-clockwise from +x.
    pub heading: f64,
}

/// The truth dynamics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TruthModel {
    /// Fig. 3 with accelerations drawn afresh each step (the default).
    White {
        /// 1-sigma longitudinal acceleration, pixels/s^2 (paper: 0.5).
        sigma_l: f64,
        /// 1-sigma normal acceleration, pixels/s^2 (paper: 1.0).
        sigma_n: f64,
    },
    /// Fig. 3 with accelerations driven by white Gaussian jerk (random walks from 0).
    Jerk {
        /// 1-sigma longitudinal jerk, pixels/s^3.
        sigma_l: f64,
        /// 1-sigma normal jerk, pixels/s^3.
        sigma_n: f64,
    },
    /// Fig. 3 with first-order Gauss-Markov accelerations of stationary 1-sigma `sigma_l`,
    /// `sigma_n` (pixels/s^2) and correlation time `tau` (s), started from their stationary law.
    GaussMarkov {
        /// 1-sigma longitudinal acceleration, pixels/s^2.
        sigma_l: f64,
        /// 1-sigma normal acceleration, pixels/s^2.
        sigma_n: f64,
        /// Correlation time, s.
        tau: f64,
    },
    /// Fig. 4: white x / y accelerations of 1-sigma `sigma_w` held over each step.
    Ncv {
        /// 1-sigma acceleration, pixels/s^2.
        sigma_w: f64,
    },
}

/// One target's true state at one frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TruthState {
    /// Position, pixels.
    pub x: f64,
    /// Position, pixels.
    pub y: f64,
    /// Velocity, pixels/s.
    pub vx: f64,
    /// Velocity, pixels/s.
    pub vy: f64,
    /// Speed `V`, pixels/s.
    pub speed: f64,
    /// Heading `gamma`, radians.
    pub heading: f64,
    /// Longitudinal acceleration, pixels/s^2.
    pub a_l: f64,
    /// Normal acceleration, pixels/s^2.
    pub a_n: f64,
}

impl TruthState {
    /// `(x, y, vx, vy)`.
    pub fn xv(&self) -> [f64; 4] {
        [self.x, self.y, self.vx, self.vy]
    }
}

/// True states of all targets at every frame: `states[k][t]` is target `t` at `k dt`.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// Frame interval, s.
    pub dt: f64,
    /// `states[frame][target]`.
    pub states: Vec<Vec<TruthState>>,
}

impl Truth {
    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.states.len()
    }

    /// Number of targets.
    pub fn targets(&self) -> usize {
        self.states.first().map_or(0, Vec::len)
    }

    /// Positions of all targets at frame `k`.
    pub fn positions(&self, k: usize) -> Vec<[f64; 2]> {
        self.states[k].iter().map(|s| [s.x, s.y]).collect()
    }
}

/// Scenario geometry, duration and truth model.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// Array width (x), pixels.
    pub width: usize,
    /// Array height (y), pixels.
    pub height: usize,
    /// Duration, s; frames at `0, dt, ..., duration`.
    pub duration: f64,
    /// Frame interval, s.
    pub dt: f64,
    /// The targets' initial kinematics.
    pub starts: Vec<TargetStart>,
    /// The truth dynamics.
    pub model: TruthModel,
}

impl Scenario {
    /// The paper's scenario: four targets on 256 x 256 pixels for 10 s at 0.1 s (Fig. 1), Fig. 3
    /// truth model with `sigma_L = 0.5`, `sigma_N = 1.0` pixels/s^2.
    pub fn paper() -> Self {
        let start = |x: f64, y: f64, ax: f64, ay: f64, speed: f64| TargetStart {
            x,
            y,
            speed,
            heading: (ay - y).atan2(ax - x),
        };
        Self {
            width: 256,
            height: 256,
            duration: 10.0,
            dt: 0.1,
            starts: vec![
                start(30.0, 30.0, 128.0, 140.0, 23.0),
                start(226.0, 30.0, 116.0, 128.0, 24.0),
                start(226.0, 226.0, 128.0, 116.0, 22.0),
                start(30.0, 226.0, 140.0, 128.0, 25.0),
            ],
            model: TruthModel::White {
                sigma_l: 0.5,
                sigma_n: 1.0,
            },
        }
    }

    /// Number of frames, `round(duration / dt) + 1`.
    pub fn frames(&self) -> usize {
        (self.duration / self.dt).round() as usize + 1
    }

    /// Checks every field.
    pub fn validated(self) -> Result<Self> {
        let opt = |name: &'static str, ok: bool, v: f64| {
            if ok {
                Ok(())
            } else {
                Err(Error::InvalidOption {
                    name,
                    reason: format!("must be finite and > 0, got {v}"),
                })
            }
        };
        let pos = |v: f64| v.is_finite() && v > 0.0;
        opt("dt", pos(self.dt), self.dt)?;
        opt("duration", pos(self.duration), self.duration)?;
        if self.width < 3 || self.height < 3 {
            return Err(Error::InvalidOption {
                name: "width / height",
                reason: format!("must be >= 3, got {} x {}", self.width, self.height),
            });
        }
        if self.frames() > 1_000_000 {
            return Err(Error::InvalidOption {
                name: "duration",
                reason: format!("{} frames is too many", self.frames()),
            });
        }
        match self.model {
            TruthModel::White { sigma_l, sigma_n }
            | TruthModel::Jerk { sigma_l, sigma_n }
            | TruthModel::GaussMarkov {
                sigma_l, sigma_n, ..
            } => {
                let nn = |v: f64| v.is_finite() && v >= 0.0;
                if !(nn(sigma_l) && nn(sigma_n)) {
                    return Err(Error::InvalidOption {
                        name: "sigma_l / sigma_n",
                        reason: format!("must be finite and >= 0, got {sigma_l}, {sigma_n}"),
                    });
                }
                if let TruthModel::GaussMarkov { tau, .. } = self.model {
                    opt("tau", pos(tau), tau)?;
                }
            }
            TruthModel::Ncv { sigma_w } => {
                if !(sigma_w.is_finite() && sigma_w >= 0.0) {
                    return Err(Error::InvalidOption {
                        name: "sigma_w",
                        reason: format!("must be finite and >= 0, got {sigma_w}"),
                    });
                }
            }
        }
        for (row, s) in self.starts.iter().enumerate() {
            for (field, value) in [
                ("x", s.x),
                ("y", s.y),
                ("speed", s.speed),
                ("heading", s.heading),
            ] {
                if !value.is_finite() {
                    return Err(Error::NonFinite {
                        what: "target",
                        row,
                        field,
                        value,
                    });
                }
            }
            if s.speed <= 0.0 {
                return Err(Error::NonPositive {
                    what: "target",
                    row,
                    field: "speed",
                    value: s.speed,
                });
            }
        }
        Ok(self)
    }

    /// Simulates the true states at every frame with the random stream `rng`.
    pub fn simulate<R: Rng>(&self, rng: &mut R) -> Truth {
        let n = self.frames();
        let dt = self.dt;
        let mut states = vec![Vec::with_capacity(self.starts.len()); n];
        for s0 in &self.starts {
            let mut v = s0.speed;
            let mut g = s0.heading;
            let (mut x, mut y) = (s0.x, s0.y);
            let (mut al, mut an) = match self.model {
                TruthModel::White { sigma_l, sigma_n }
                | TruthModel::GaussMarkov {
                    sigma_l, sigma_n, ..
                } => (
                    sigma_l * rng.sample::<f64, _>(StandardNormal),
                    sigma_n * rng.sample::<f64, _>(StandardNormal),
                ),
                TruthModel::Jerk { .. } | TruthModel::Ncv { .. } => (0.0, 0.0),
            };
            let (mut vx, mut vy) = (v * g.cos(), v * g.sin());
            for (k, row) in states.iter_mut().enumerate() {
                row.push(TruthState {
                    x,
                    y,
                    vx,
                    vy,
                    speed: v,
                    heading: g,
                    a_l: al,
                    a_n: an,
                });
                if k + 1 == n {
                    break;
                }
                match self.model {
                    TruthModel::White { .. }
                    | TruthModel::Jerk { .. }
                    | TruthModel::GaussMarkov { .. } => {
                        let vm = (v + 0.5 * al * dt).max(1e-6);
                        let gm = g + 0.5 * an / vm * dt;
                        x += vm * gm.cos() * dt;
                        y += vm * gm.sin() * dt;
                        g += an / vm * dt;
                        v = (v + al * dt).max(1e-6);
                        vx = v * g.cos();
                        vy = v * g.sin();
                        let (el, en): (f64, f64) =
                            (rng.sample(StandardNormal), rng.sample(StandardNormal));
                        match self.model {
                            TruthModel::White { sigma_l, sigma_n } => {
                                al = sigma_l * el;
                                an = sigma_n * en;
                            }
                            TruthModel::Jerk { sigma_l, sigma_n } => {
                                al += sigma_l * dt * el;
                                an += sigma_n * dt * en;
                            }
                            TruthModel::GaussMarkov {
                                sigma_l,
                                sigma_n,
                                tau,
                            } => {
                                let rho = (-dt / tau).exp();
                                let q = (1.0 - rho * rho).sqrt();
                                al = rho * al + sigma_l * q * el;
                                an = rho * an + sigma_n * q * en;
                            }
                            TruthModel::Ncv { .. } => unreachable!(),
                        }
                    }
                    TruthModel::Ncv { sigma_w } => {
                        let wx = sigma_w * rng.sample::<f64, _>(StandardNormal);
                        let wy = sigma_w * rng.sample::<f64, _>(StandardNormal);
                        x += vx * dt + 0.5 * dt * dt * wx;
                        y += vy * dt + 0.5 * dt * dt * wy;
                        vx += dt * wx;
                        vy += dt * wy;
                        v = vx.hypot(vy);
                        g = vy.atan2(vx);
                        // Accelerations of the next step along / across the velocity.
                        let (s, c) = g.sin_cos();
                        al = wx * c + wy * s;
                        an = -wx * s + wy * c;
                    }
                }
            }
        }
        Truth { dt, states }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geofeas::rng::stream;

    #[test]
    fn paper_targets_converge_cross_and_stay_in_the_array() {
        let sc = Scenario::paper().validated().unwrap();
        assert_eq!(sc.frames(), 101);
        for run in 0..20 {
            let truth = sc.simulate(&mut stream(5, run));
            assert_eq!(truth.frames(), 101);
            assert_eq!(truth.targets(), 4);
            let centre = |s: &TruthState| (s.x - 128.0).hypot(s.y - 128.0);
            for t in 0..4 {
                let d0 = centre(&truth.states[0][t]);
                let dmin = (0..101)
                    .map(|k| centre(&truth.states[k][t]))
                    .fold(f64::INFINITY, f64::min);
                let d1 = centre(&truth.states[100][t]);
                assert!(dmin < 0.3 * d0, "target {t} run {run} does not converge");
                assert!(d1 > 2.0 * dmin, "target {t} run {run} does not leave");
                for k in 0..101 {
                    let s = truth.states[k][t];
                    assert!((0.0..256.0).contains(&s.x) && (0.0..256.0).contains(&s.y));
                }
            }
        }
    }

    #[test]
    fn gauss_markov_accelerations_have_their_sigma() {
        let sc = Scenario {
            duration: 2000.0,
            model: TruthModel::GaussMarkov {
                sigma_l: 0.5,
                sigma_n: 1.0,
                tau: 1.0,
            },
            starts: vec![TargetStart {
                x: 0.0,
                y: 0.0,
                speed: 1e6,
                heading: 0.0,
            }],
            ..Scenario::paper()
        };
        let truth = sc.simulate(&mut stream(1, 0));
        let n = truth.frames() as f64;
        let (mut sl, mut sn) = (0.0, 0.0);
        for row in &truth.states {
            sl += row[0].a_l * row[0].a_l;
            sn += row[0].a_n * row[0].a_n;
        }
        // 20000 steps with tau = 10 steps: ~1000 independent samples, 1-sigma of the estimate ~5%.
        assert!(((sl / n).sqrt() - 0.5).abs() < 0.1, "{}", (sl / n).sqrt());
        assert!(((sn / n).sqrt() - 1.0).abs() < 0.2, "{}", (sn / n).sqrt());
    }

    #[test]
    fn jerk_random_walk_reaches_sigma_at_ten_seconds() {
        let sc = Scenario {
            model: TruthModel::Jerk {
                sigma_l: 0.5,
                sigma_n: 1.0,
            },
            ..Scenario::paper()
        };
        let (mut sl, mut sn, runs) = (0.0, 0.0, 2000);
        for r in 0..runs {
            let truth = sc.simulate(&mut stream(8, r));
            assert_eq!(truth.states[0][0].a_l, 0.0);
            let s = truth.states[100][1];
            sl += s.a_l * s.a_l;
            sn += s.a_n * s.a_n;
        }
        // 2000 runs: the sample sd is within ~1.6% (1 sigma) of the truth.
        let (sl, sn) = ((sl / runs as f64).sqrt(), (sn / runs as f64).sqrt());
        assert!(
            (sl - 0.5).abs() < 0.03 && (sn - 1.0).abs() < 0.06,
            "{sl} {sn}"
        );
    }

    #[test]
    fn white_accelerations_have_the_table_sigma() {
        let truth = Scenario::paper().simulate(&mut stream(3, 0));
        let (mut sl, mut sn, mut n) = (0.0, 0.0, 0.0);
        for row in &truth.states {
            for s in row {
                sl += s.a_l * s.a_l;
                sn += s.a_n * s.a_n;
                n += 1.0;
            }
        }
        // 404 draws: the sample sd is within ~3.5% (1 sigma).
        let (sl, sn) = ((sl / n).sqrt(), (sn / n).sqrt());
        assert!(
            (sl - 0.5).abs() < 0.06 && (sn - 1.0).abs() < 0.12,
            "{sl} {sn}"
        );
    }

    #[test]
    fn kinematics_are_consistent() {
        let sc = Scenario::paper();
        let truth = sc.simulate(&mut stream(2, 0));
        for t in 0..4 {
            for k in 0..100 {
                let (a, b) = (truth.states[k][t], truth.states[k + 1][t]);
                let dx = (b.x - a.x) / 0.1;
                let dy = (b.y - a.y) / 0.1;
                // Mean velocity over the step lies between the velocities at its ends.
                assert!((dx - 0.5 * (a.vx + b.vx)).abs() < 0.05);
                assert!((dy - 0.5 * (a.vy + b.vy)).abs() < 0.05);
            }
        }
    }

    #[test]
    fn bad_options_are_rejected() {
        assert!(Scenario {
            dt: 0.0,
            ..Scenario::paper()
        }
        .validated()
        .is_err());
        let mut s = Scenario::paper();
        s.starts[2].speed = f64::NAN;
        let e = s.validated().unwrap_err().to_string();
        assert!(e.contains("row 2") && e.contains("speed"), "{e}");
    }
}
