//! Track performance metrics of seed 004, section 5.2, and standard multi-target measures.
//!
//! After every scan the tracker output is the most likely hypothesis; of its open tracks only the
//! Cartesian ones with at least `min_contacts` contacts from at least `min_sensors` sensors count
//! and, if `confirm_probability > 0`, only once the track is *confirmed*: the summed probability
//! of the kept hypotheses that contain it has reached `confirm_probability` at some output (the
//! paper's M6T counts a track only from its "confirmed" stage, whose rule the paper does not
//! give). Such a track is *true* when more than half of its contacts come from one target, else
//! *false* (ghosts included). Then
//! - `T_PD`: time during which a target is held by a true track, over the time it is present
//!   (the output of scan k holds until scan k + 1);
//! - `T_FAR`: false tracks summed over all outputs, divided by the scenario duration (tracks/s;
//!   it grows with the output rate, as the paper notes);
//! - `pos_err`, `vel_err`: mean Euclidean error of the true tracks' position and velocity
//!   against the ground truth at the time of their estimate; `vel_err_axis` is the mean absolute
//!   error per axis (`(|dvx| + |dvy|) / 2`) and `speed_err` the mean absolute error of the speed
//!   `| |v| - |v_true| |`, the two other readings of the paper's "average of the absolute error";
//! - `gospa` (cut-off `gospa_cutoff`, order 2, alpha 2; [`crate::gospa`]) between the
//!   targets' positions and the output tracks' positions predicted to the output time, averaged
//!   over outputs, with its localisation part (root of the summed squared errors of assigned
//!   pairs) and the mean numbers of missed and false targets;
//! - `id_switches`: per run, times the true track holding a target changes identity;
//!   `fragmentations`: per run, times a target's track resumes after an interruption.

use std::collections::{HashMap, HashSet};

use super::hypothesis::Hypothesis;
use super::scenario::Trajectory;
use super::sensor::Detection;
use crate::gospa::gospa;

/// Which tracks count as tracker output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    /// Smallest number of contacts (paper: 3).
    pub min_contacts: usize,
    /// Smallest number of distinct sensors (paper: 2).
    pub min_sensors: u32,
    /// Probability over the kept hypotheses a track must reach once before it counts (0: every
    /// track of the best hypothesis counts at once).
    pub confirm_probability: f64,
    /// GOSPA cut-off distance, m.
    pub gospa_cutoff: f64,
}

impl Default for Evaluation {
    fn default() -> Self {
        Self {
            min_contacts: 3,
            min_sensors: 2,
            confirm_probability: 0.0,
            gospa_cutoff: 5.0,
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
    /// Sum of per-axis absolute velocity errors `(|dvx| + |dvy|) / 2` of true tracks.
    pub vel_axis_sum: f64,
    /// Sum of absolute speed errors of true tracks.
    pub speed_sum: f64,
    /// Number of outputs (scans).
    pub outputs: f64,
    /// Sum of GOSPA distances over outputs.
    pub gospa_sum: f64,
    /// Sum over outputs of the localisation part `(sum d^2)^(1/2)`.
    pub gospa_loc_sum: f64,
    /// Missed targets summed over outputs.
    pub gospa_missed_sum: f64,
    /// False targets summed over outputs.
    pub gospa_false_sum: f64,
    /// Identity switches.
    pub id_switches: f64,
    /// Track fragmentations.
    pub fragmentations: f64,
    /// Number of runs pooled.
    pub runs: f64,
}

/// The metrics of section 5.2 and the standard multi-target measures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Track probability of detection.
    pub t_pd: f64,
    /// False track rate, tracks/s.
    pub t_far: f64,
    /// Mean position error of true tracks, m (NaN without true tracks).
    pub pos_err: f64,
    /// Mean velocity error (Euclidean) of true tracks, m/s (NaN without true tracks).
    pub vel_err: f64,
    /// Mean per-axis absolute velocity error of true tracks, m/s.
    pub vel_err_axis: f64,
    /// Mean absolute speed error of true tracks, m/s.
    pub speed_err: f64,
    /// Mean GOSPA distance per output, m.
    pub gospa: f64,
    /// Mean localisation part of GOSPA per output, m.
    pub gospa_loc: f64,
    /// Mean missed targets per output.
    pub gospa_missed: f64,
    /// Mean false targets per output.
    pub gospa_false: f64,
    /// Identity switches per run.
    pub id_switches: f64,
    /// Fragmentations per run.
    pub fragmentations: f64,
}

impl Metrics {
    /// Names of the fields, in the order of [`Metrics::values`] (the study's table columns).
    pub const NAMES: [&'static str; 12] = [
        "t_pd",
        "t_far",
        "pos_err",
        "vel_err",
        "vel_err_axis",
        "speed_err",
        "gospa",
        "gospa_loc",
        "gospa_missed",
        "gospa_false",
        "id_switches",
        "fragmentations",
    ];

    /// The fields in the order of [`Metrics::NAMES`].
    pub fn values(&self) -> [f64; 12] {
        [
            self.t_pd,
            self.t_far,
            self.pos_err,
            self.vel_err,
            self.vel_err_axis,
            self.speed_err,
            self.gospa,
            self.gospa_loc,
            self.gospa_missed,
            self.gospa_false,
            self.id_switches,
            self.fragmentations,
        ]
    }
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
        self.vel_axis_sum += o.vel_axis_sum;
        self.speed_sum += o.speed_sum;
        self.outputs += o.outputs;
        self.gospa_sum += o.gospa_sum;
        self.gospa_loc_sum += o.gospa_loc_sum;
        self.gospa_missed_sum += o.gospa_missed_sum;
        self.gospa_false_sum += o.gospa_false_sum;
        self.id_switches += o.id_switches;
        self.fragmentations += o.fragmentations;
        self.runs += o.runs;
    }

    /// The metrics.
    pub fn metrics(&self) -> Metrics {
        let div = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
        Metrics {
            t_pd: div(self.in_track, self.present),
            t_far: div(self.false_tracks, self.duration),
            pos_err: div(self.pos_sum, self.true_outputs),
            vel_err: div(self.vel_sum, self.true_outputs),
            vel_err_axis: div(self.vel_axis_sum, self.true_outputs),
            speed_err: div(self.speed_sum, self.true_outputs),
            gospa: div(self.gospa_sum, self.outputs),
            gospa_loc: div(self.gospa_loc_sum, self.outputs),
            gospa_missed: div(self.gospa_missed_sum, self.outputs),
            gospa_false: div(self.gospa_false_sum, self.outputs),
            id_switches: div(self.id_switches, self.runs),
            fragmentations: div(self.fragmentations, self.runs),
        }
    }
}

/// Scores the outputs of one run in order: keeps the confirmed tracks and, per target, the
/// identity of the track that last held it.
#[derive(Debug, Clone)]
pub struct Scorer {
    eval: Evaluation,
    confirmed: HashSet<usize>,
    holder: Vec<Option<usize>>,
    held_before: Vec<bool>,
    started: bool,
}

impl Scorer {
    /// A scorer for one run.
    pub fn new(eval: Evaluation) -> Self {
        Self {
            eval,
            confirmed: HashSet::new(),
            holder: Vec::new(),
            held_before: Vec::new(),
            started: false,
        }
    }

    /// Track ids of the best hypothesis (the first of `hypotheses`, most likely first) that
    /// count as output at this scan; updates the confirmed set.
    fn output_ids(&mut self, hypotheses: &[Hypothesis]) -> Vec<usize> {
        let best = &hypotheses[0];
        let eligible: Vec<usize> = best
            .tracks
            .iter()
            .filter(|t| {
                t.is_cartesian()
                    && t.contacts >= self.eval.min_contacts
                    && t.sensor_count() >= self.eval.min_sensors
            })
            .map(|t| t.id)
            .collect();
        if self.eval.confirm_probability <= 0.0 {
            return eligible;
        }
        let pending: HashSet<usize> = eligible
            .iter()
            .copied()
            .filter(|id| !self.confirmed.contains(id))
            .collect();
        if !pending.is_empty() {
            let mut mass: HashMap<usize, f64> = HashMap::new();
            for h in hypotheses {
                let p = h.probability();
                for t in &h.tracks {
                    if pending.contains(&t.id) {
                        *mass.entry(t.id).or_default() += p;
                    }
                }
            }
            for (id, m) in mass {
                if m >= self.eval.confirm_probability {
                    self.confirmed.insert(id);
                }
            }
        }
        eligible
            .into_iter()
            .filter(|id| self.confirmed.contains(id))
            .collect()
    }

    /// Scores the output at `time` (the best of `hypotheses`, valid for `dt` seconds) into
    /// `tally`.
    pub fn observe(
        &mut self,
        tally: &mut Tally,
        hypotheses: &[Hypothesis],
        detections: &[Detection],
        truth: &[Trajectory],
        time: f64,
        dt: f64,
    ) {
        if !self.started {
            self.started = true;
            tally.runs += 1.0;
            self.holder = vec![None; truth.len()];
            self.held_before = vec![false; truth.len()];
        }
        let ids: HashSet<usize> = self.output_ids(hypotheses).into_iter().collect();
        let best = &hypotheses[0];
        // Per target: the true track with the most contacts holding it.
        let mut held: Vec<Option<(usize, usize)>> = vec![None; truth.len()];
        let mut counts = vec![0usize; truth.len()];
        let mut estimates = Vec::new();
        for t in &best.tracks {
            if !ids.contains(&t.id) {
                continue;
            }
            let Some(c) = t.cartesian() else { continue };
            let lag = time - c.time;
            estimates.push([c.x[0] + c.x[2] * lag, c.x[1] + c.x[3] * lag]);
            counts.iter_mut().for_each(|c| *c = 0);
            let dets = t.detections();
            for &k in &dets {
                if let Some(target) = detections.get(k).and_then(|d| d.target) {
                    if target < counts.len() {
                        counts[target] += 1;
                    }
                }
            }
            let owner = counts
                .iter()
                .enumerate()
                .find(|(_, &n)| 2 * n > dets.len())
                .map(|(k, _)| k);
            match owner {
                Some(k) => {
                    let g = truth[k].state(c.time);
                    let (dvx, dvy) = (c.x[2] - g[2], c.x[3] - g[3]);
                    tally.pos_sum += (c.x[0] - g[0]).hypot(c.x[1] - g[1]);
                    tally.vel_sum += dvx.hypot(dvy);
                    tally.vel_axis_sum += 0.5 * (dvx.abs() + dvy.abs());
                    tally.speed_sum += (c.x[2].hypot(c.x[3]) - g[2].hypot(g[3])).abs();
                    tally.true_outputs += 1.0;
                    let better = match held[k] {
                        None => true,
                        Some((id, n)) => t.contacts > n || (t.contacts == n && t.id < id),
                    };
                    if better {
                        held[k] = Some((t.id, t.contacts));
                    }
                }
                None => tally.false_tracks += 1.0,
            }
        }
        for (k, h) in held.iter().enumerate() {
            match h {
                Some((id, _)) => {
                    if let Some(last) = self.holder[k] {
                        if last != *id {
                            tally.id_switches += 1.0;
                        }
                        if !self.held_before[k] {
                            tally.fragmentations += 1.0;
                        }
                    }
                    self.holder[k] = Some(*id);
                    self.held_before[k] = true;
                }
                None => self.held_before[k] = false,
            }
        }
        let positions: Vec<[f64; 2]> = truth
            .iter()
            .map(|tr| {
                let s = tr.state(time);
                [s[0], s[1]]
            })
            .collect();
        let g = gospa(&positions, &estimates, self.eval.gospa_cutoff, 2.0);
        tally.outputs += 1.0;
        tally.gospa_sum += g.distance;
        tally.gospa_loc_sum += g.localisation.sqrt();
        tally.gospa_missed_sum += g.missed as f64;
        tally.gospa_false_sum += g.false_targets as f64;
        tally.present += dt * truth.len() as f64;
        tally.in_track += dt * held.iter().filter(|h| h.is_some()).count() as f64;
    }
}
