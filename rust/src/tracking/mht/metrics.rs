//! Track performance metrics of seed 004, section 5.2.
//!
//! After every scan the tracker output is the most likely hypothesis; of its open tracks only the
//! Cartesian ones with at least `min_contacts` contacts from at least `min_sensors` sensors count.
//! Such a track is *true* when more than half of its contacts come from one target, else *false*
//! (ghosts included). Then
//! - `T_PD`: time during which a target is held by a true track, over the time it is present
//!   (the output of scan k holds until scan k + 1);
//! - `T_FAR`: false tracks summed over all outputs, divided by the scenario duration (tracks/s;
//!   it grows with the output rate, as the paper notes);
//! - `pos_err`, `vel_err`: mean Euclidean error of the true tracks' position and velocity
//!   against the ground truth at the time of their estimate.

use super::hypothesis::Hypothesis;
use super::scenario::Trajectory;
use super::sensor::Detection;

/// Which tracks count as tracker output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Evaluation {
    /// Smallest number of contacts (paper: 3).
    pub min_contacts: usize,
    /// Smallest number of distinct sensors (paper: 2).
    pub min_sensors: u32,
}

impl Default for Evaluation {
    fn default() -> Self {
        Self {
            min_contacts: 3,
            min_sensors: 2,
        }
    }
}

/// Sums from which the metrics are computed; add the sums of several runs with [`Tally::merge`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tally {
    /// Time targets were in track, summed over targets.
    pub in_track: f64,
    /// Time targets were present, summed over targets.
    pub present: f64,
    /// False tracks summed over the outputs.
    pub false_tracks: f64,
    /// Scenario time.
    pub duration: f64,
    /// Sum of position errors of true tracks.
    pub pos_sum: f64,
    /// Sum of velocity errors of true tracks.
    pub vel_sum: f64,
    /// Number of true-track outputs.
    pub true_outputs: f64,
}

/// The four metrics of section 5.2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Track probability of detection.
    pub t_pd: f64,
    /// False track rate, tracks/s.
    pub t_far: f64,
    /// Mean position error of true tracks, m (NaN without true tracks).
    pub pos_err: f64,
    /// Mean velocity error of true tracks, m/s (NaN without true tracks).
    pub vel_err: f64,
}

impl Tally {
    /// Adds another tally.
    pub fn merge(&mut self, o: &Tally) {
        self.in_track += o.in_track;
        self.present += o.present;
        self.false_tracks += o.false_tracks;
        self.duration += o.duration;
        self.pos_sum += o.pos_sum;
        self.vel_sum += o.vel_sum;
        self.true_outputs += o.true_outputs;
    }

    /// The metrics.
    pub fn metrics(&self) -> Metrics {
        let div = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
        Metrics {
            t_pd: div(self.in_track, self.present),
            t_far: div(self.false_tracks, self.duration),
            pos_err: div(self.pos_sum, self.true_outputs),
            vel_err: div(self.vel_sum, self.true_outputs),
        }
    }

    /// Scores the output `best` valid for `dt` seconds, given the processed `detections` (their
    /// `target` labels are the ground truth) and the targets' trajectories.
    pub fn observe(
        &mut self,
        eval: &Evaluation,
        best: &Hypothesis,
        detections: &[Detection],
        truth: &[Trajectory],
        dt: f64,
    ) {
        let mut held = vec![false; truth.len()];
        let mut counts = vec![0usize; truth.len()];
        for t in &best.tracks {
            let Some(c) = t.cartesian() else { continue };
            if t.contacts < eval.min_contacts || t.sensor_count() < eval.min_sensors {
                continue;
            }
            counts.iter_mut().for_each(|c| *c = 0);
            let ids = t.detections();
            for &k in &ids {
                if let Some(target) = detections[k].target {
                    if target < counts.len() {
                        counts[target] += 1;
                    }
                }
            }
            let owner = counts
                .iter()
                .enumerate()
                .find(|(_, &n)| 2 * n > ids.len())
                .map(|(k, _)| k);
            match owner {
                Some(k) => {
                    held[k] = true;
                    let g = truth[k].state(c.time);
                    self.pos_sum += (c.x[0] - g[0]).hypot(c.x[1] - g[1]);
                    self.vel_sum += (c.x[2] - g[2]).hypot(c.x[3] - g[3]);
                    self.true_outputs += 1.0;
                }
                None => self.false_tracks += 1.0,
            }
        }
        self.present += dt * truth.len() as f64;
        self.in_track += dt * held.iter().filter(|&&h| h).count() as f64;
    }
}
