//! Seeded simulator of the paper's experiments (seed 004, section 5.1).
//!
//! Targets fly constant-speed trajectories made of straight legs joined by coordinated turns at a
//! fixed lateral acceleration (the paper: 10 m/s, 4 g, an "M" shape, 20 s). Each sensor scans
//! asynchronously with its own period; at every scan it detects every target inside its beam and
//! range window with probability `pd`, adds Gaussian range and range-rate noise, and adds a fixed
//! number of false alarms drawn uniformly in its range / range-rate window. Detections are returned
//! in time order, grouped by scan, shuffled within a scan.

use rand::RngExt;
use rand_distr::StandardNormal;

use super::sensor::{paper_sensors, Detection, Noise, Sensor};
use geofeas::error::{Error, Result};

/// Standard gravity, m/s^2.
pub const G: f64 = 9.80665;

/// One piece of a trajectory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Leg {
    /// Fly straight for this many seconds.
    Straight(f64),
    /// Turn by this many radians (counter-clockwise positive) at the trajectory's lateral acceleration.
    Turn(f64),
}

/// A constant-speed trajectory: start, initial heading, legs.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Position at t = 0.
    pub start: [f64; 2],
    /// Heading at t = 0, radians counter-clockwise from +x.
    pub heading: f64,
    /// Speed, m/s.
    pub speed: f64,
    /// Lateral acceleration in turns, m/s^2.
    pub turn_acceleration: f64,
    /// The legs, flown in order; after the last one the target flies straight on.
    pub legs: Vec<Leg>,
}

impl Trajectory {
    /// The "M" of the paper: four strokes (up, down to the middle, up, down) joined by 4 g turns,
    /// lasting `duration` seconds at `speed`; `rotation` turns the whole figure (0: the upright M
    /// flown left to right, the "horizontal" trajectory).
    pub fn m_shape(
        start: [f64; 2],
        rotation: f64,
        speed: f64,
        turn_acceleration: f64,
        duration: f64,
    ) -> Self {
        let d = std::f64::consts::PI / 180.0;
        let turns = [-150.0 * d, 120.0 * d, -150.0 * d];
        let omega = turn_acceleration / speed;
        let turning: f64 = turns.iter().map(|a: &f64| a.abs() / omega).sum();
        // Outer strokes of length a, inner strokes of a / (2 sin 60) so the middle vertex is at half height.
        let ratio = 1.0 / (2.0 * (60.0 * d).sin());
        let t_outer = ((duration - turning) / (2.0 + 2.0 * ratio)).max(0.0);
        let t_inner = t_outer * ratio;
        Self {
            start,
            heading: 90.0 * d + rotation,
            speed,
            turn_acceleration,
            legs: vec![
                Leg::Straight(t_outer),
                Leg::Turn(turns[0]),
                Leg::Straight(t_inner),
                Leg::Turn(turns[1]),
                Leg::Straight(t_inner),
                Leg::Turn(turns[2]),
                Leg::Straight(t_outer),
            ],
        }
    }

    /// Cartesian state `(x, y, vx, vy)` at time `t` (clamped below at 0).
    pub fn state(&self, t: f64) -> [f64; 4] {
        let mut t = t.max(0.0);
        let [mut x, mut y] = self.start;
        let mut h = self.heading;
        let v = self.speed;
        let omega = self.turn_acceleration / v;
        for leg in &self.legs {
            let dur = match *leg {
                Leg::Straight(s) => s,
                Leg::Turn(a) => a.abs() / omega,
            };
            let step = t.min(dur);
            match *leg {
                Leg::Straight(_) => {
                    x += v * step * h.cos();
                    y += v * step * h.sin();
                }
                Leg::Turn(a) => {
                    let w = omega * a.signum();
                    let h1 = h + w * step;
                    x += v / w * (h1.sin() - h.sin());
                    y += v / w * (h.cos() - h1.cos());
                    h = h1;
                }
            }
            t -= step;
            if t <= 0.0 {
                return [x, y, v * h.cos(), v * h.sin()];
            }
        }
        x += v * t * h.cos();
        y += v * t * h.sin();
        [x, y, v * h.cos(), v * h.sin()]
    }
}

/// A simulated experiment: sensors, targets, detection probability and false alarms.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The radars.
    pub sensors: Vec<Sensor>,
    /// The targets' trajectories.
    pub targets: Vec<Trajectory>,
    /// Simulated time, seconds.
    pub duration: f64,
    /// Probability of detecting a target inside the beam at a scan (paper: 1).
    pub pd: f64,
    /// False alarms per sensor per scan (a fixed count, as in the paper).
    pub false_alarms: usize,
    /// Measurement noise.
    pub noise: Noise,
}

impl Scenario {
    /// The paper's scenario: `targets` (1 or 2) M-shaped trajectories at 10 m/s with 4 g turns for
    /// 20 s, `sensors` = 3 (x = -10, 0, 10 m) or 2 (x = -10 and 10 m), detection probability 1,
    /// `false_alarms` per sensor per scan, noise 5 cm and 2 cm/s.
    pub fn paper(targets: usize, sensors: usize, false_alarms: usize) -> Result<Self> {
        let all = paper_sensors();
        let sensors = match sensors {
            3 => all,
            2 => vec![all[0], all[2]],
            n => {
                return Err(Error::InvalidOption {
                    name: "sensors",
                    reason: format!("the paper's layouts have 2 or 3 sensors, got {n}"),
                })
            }
        };
        let (v, a, dur) = (10.0, 4.0 * G, 20.0);
        let horizontal = Trajectory::m_shape([-17.5, 12.0], 0.0, v, a, dur);
        let vertical = Trajectory::m_shape([30.0, 22.0], std::f64::consts::FRAC_PI_2, v, a, dur);
        let targets = match targets {
            1 => vec![horizontal],
            2 => vec![horizontal, vertical],
            n => {
                return Err(Error::InvalidOption {
                    name: "targets",
                    reason: format!("the paper's scenarios have 1 or 2 targets, got {n}"),
                })
            }
        };
        Ok(Self {
            sensors,
            targets,
            duration: dur,
            pd: 1.0,
            false_alarms,
            noise: Noise::default(),
        })
    }

    /// Checks sensors, noise, duration and `pd`.
    pub fn validated(self) -> Result<Self> {
        for (i, s) in self.sensors.iter().enumerate() {
            s.validated(i)?;
        }
        self.noise.validated()?;
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return Err(Error::InvalidOption {
                name: "duration",
                reason: format!("must be finite and > 0, got {}", self.duration),
            });
        }
        if !(0.0..=1.0).contains(&self.pd) {
            return Err(Error::InvalidOption {
                name: "pd",
                reason: format!("must be in [0, 1], got {}", self.pd),
            });
        }
        if self.sensors.is_empty() {
            return Err(Error::InvalidOption {
                name: "sensors",
                reason: "at least one sensor is needed".into(),
            });
        }
        Ok(self)
    }

    /// Scan times `(time, sensor)` of all sensors in `[0, duration]`, in time order (ties by sensor).
    pub fn scan_times(&self) -> Vec<(f64, usize)> {
        let mut scans = Vec::new();
        for (i, s) in self.sensors.iter().enumerate() {
            let mut k = 0usize;
            loop {
                let t = s.offset + k as f64 * s.period;
                if t > self.duration + 1e-9 {
                    break;
                }
                if t >= 0.0 {
                    scans.push((t, i));
                }
                k += 1;
            }
        }
        scans.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        scans
    }

    /// Simulates all detections with the random stream `rng`.
    pub fn simulate<R: rand::Rng>(&self, rng: &mut R) -> Vec<Detection> {
        let mut out = Vec::new();
        for (scan, (t, i)) in self.scan_times().into_iter().enumerate() {
            let s = &self.sensors[i];
            let first = out.len();
            for (k, target) in self.targets.iter().enumerate() {
                let x = target.state(t);
                if !s.sees([x[0], x[1]]) || rng.random::<f64>() >= self.pd {
                    continue;
                }
                let z = s.measure(&x.into());
                let nr: f64 = rng.sample(StandardNormal);
                let nv: f64 = rng.sample(StandardNormal);
                out.push(Detection {
                    time: t,
                    sensor: i,
                    scan,
                    range: z[0] + self.noise.sigma_range * nr,
                    range_rate: z[1] + self.noise.sigma_range_rate * nv,
                    target: Some(k),
                });
            }
            for _ in 0..self.false_alarms {
                let r = s.max_range * rng.random::<f64>();
                let rr = s.max_range_rate * (2.0 * rng.random::<f64>() - 1.0);
                out.push(Detection {
                    time: t,
                    sensor: i,
                    scan,
                    range: r,
                    range_rate: rr,
                    target: None,
                });
            }
            // Fisher-Yates within the scan so that target contacts are not always first.
            let n = out.len() - first;
            for j in (1..n).rev() {
                let k = rng.random_range(0..=j);
                out.swap(first + j, first + k);
            }
        }
        out
    }
}
