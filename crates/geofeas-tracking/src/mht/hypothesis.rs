//! Reid's measurement-oriented multiple-hypothesis tracker (seed 004, section 3; Reid 1979).
//!
//! For every detection each parent hypothesis spawns one child that calls the detection a false
//! alarm (factor `beta_FA`, the false-alarm density per unit range x range rate), one that starts
//! a new range-Doppler track (`beta_NT`, the new-target density) and one per track it can update
//! (`P_D` times the association likelihood of [`Track::associate`]). A track can take at most one
//! detection per scan. At the end of a scan every track of a hypothesis that the sensor could have
//! detected but did not update is charged `1 - P_D`. Hypothesis weights are thus Reid's
//! `P_D^N_DT (1 - P_D)^N_miss beta_FA^N_FA beta_NT^N_NT prod N(e; 0, S)`, normalised to sum to one
//! after every detection, and only the `max_hypotheses` most likely survive. Tracks that have not
//! been updated for `max_coast` seconds are closed.
//!
//! With `max_hypotheses = 1` and `scan_cap = Some(k)` the tracker keeps up to `k` hypotheses
//! while a scan is processed and the single best at its end: a global-nearest-neighbour
//! (single-hypothesis) tracker with the same likelihoods, the baseline of the paper.

use std::collections::HashMap;
use std::sync::Arc;

use super::config::MhtConfig;
use super::sensor::{Detection, Sensor};
use super::track::Track;
use geofeas::error::{Error, Result};

/// A closed track, kept for the record in a persistent list.
#[derive(Debug)]
pub struct Closed {
    /// The track as it was last updated.
    pub track: Arc<Track>,
    /// The previously closed track.
    pub prev: Option<Arc<Closed>>,
}

/// One interpretation of all detections so far.
#[derive(Debug, Clone, Default)]
pub struct Hypothesis {
    /// Natural log of the probability (normalised over the kept hypotheses).
    pub log_weight: f64,
    /// Open tracks.
    pub tracks: Vec<Arc<Track>>,
    /// Closed tracks, most recent first.
    pub closed: Option<Arc<Closed>>,
}

impl Hypothesis {
    /// Probability of the hypothesis.
    pub fn probability(&self) -> f64 {
        self.log_weight.exp()
    }

    /// Open and closed tracks.
    pub fn all_tracks(&self) -> Vec<Arc<Track>> {
        let mut out = self.tracks.clone();
        let mut node = self.closed.as_ref();
        while let Some(c) = node {
            out.push(c.track.clone());
            node = c.prev.as_ref();
        }
        out
    }
}

enum Action {
    FalseAlarm,
    NewTrack,
    Update(usize, Arc<Track>),
}

struct Child {
    log_weight: f64,
    parent: usize,
    action: Action,
}

/// The multiple-hypothesis tracker.
#[derive(Debug, Clone)]
pub struct Mht {
    config: MhtConfig,
    sensors: Vec<Sensor>,
    hypotheses: Vec<Hypothesis>,
    time: f64,
    scans: usize,
}

impl Mht {
    /// A tracker for `sensors` (at most 64) with `config`.
    pub fn new(sensors: Vec<Sensor>, config: MhtConfig) -> Result<Self> {
        let config = config.validated()?;
        if sensors.is_empty() || sensors.len() > 64 {
            return Err(Error::InvalidOption {
                name: "sensors",
                reason: format!(
                    "between 1 and 64 sensors are supported, got {}",
                    sensors.len()
                ),
            });
        }
        for (i, s) in sensors.iter().enumerate() {
            s.validated(i)?;
        }
        Ok(Self {
            config,
            sensors,
            hypotheses: vec![Hypothesis::default()],
            time: f64::NEG_INFINITY,
            scans: 0,
        })
    }

    /// The options.
    pub fn config(&self) -> &MhtConfig {
        &self.config
    }

    /// The sensors.
    pub fn sensors(&self) -> &[Sensor] {
        &self.sensors
    }

    /// The kept hypotheses, most likely first; their probabilities sum to one.
    pub fn hypotheses(&self) -> &[Hypothesis] {
        &self.hypotheses
    }

    /// The most likely hypothesis.
    pub fn best(&self) -> &Hypothesis {
        &self.hypotheses[0]
    }

    /// Number of scans processed.
    pub fn scans(&self) -> usize {
        self.scans
    }

    /// Processes one scan of `sensor` at `time`: `detections` are `(index, detection)` pairs,
    /// `index` being the caller's identifier recorded in the tracks' contacts. An empty scan still
    /// charges the missed-detection factor. The `scan` field of the detections is overwritten by
    /// the tracker's own scan counter.
    pub fn process_scan(
        &mut self,
        time: f64,
        sensor: usize,
        detections: &[(usize, Detection)],
    ) -> Result<()> {
        if !time.is_finite() {
            return Err(Error::Invalid(format!(
                "scan {}: time is not finite ({time})",
                self.scans
            )));
        }
        if time < self.time {
            return Err(Error::Invalid(format!(
                "scan {}: time {time} is before the previous scan at {}; scans must be in time order",
                self.scans, self.time
            )));
        }
        if sensor >= self.sensors.len() {
            return Err(Error::Invalid(format!(
                "scan {}: sensor {sensor} does not exist ({} sensors)",
                self.scans,
                self.sensors.len()
            )));
        }
        for (index, d) in detections {
            if d.sensor != sensor || d.time != time {
                return Err(Error::Invalid(format!(
                    "detection {index}: sensor {} at time {} does not belong to the scan of sensor {sensor} at {time}",
                    d.sensor, d.time
                )));
            }
            for (field, value) in [("range", d.range), ("range_rate", d.range_rate)] {
                if !value.is_finite() {
                    return Err(Error::NonFinite {
                        what: "detection",
                        row: *index,
                        field,
                        value,
                    });
                }
            }
            if d.range < 0.0 {
                return Err(Error::Invalid(format!(
                    "detection {index}: negative range {}",
                    d.range
                )));
            }
        }
        let scan = self.scans;
        self.close_coasting(time);
        let cap = self.config.scan_cap.unwrap_or(self.config.max_hypotheses);
        for (index, d) in detections {
            let det = Detection { scan, ..*d };
            self.expand(*index, &det, cap);
        }
        // Missed detections.
        let miss = (1.0 - self.config.pd).ln();
        let s = &self.sensors[sensor];
        for h in &mut self.hypotheses {
            let n = h
                .tracks
                .iter()
                .filter(|t| t.last_scan != scan && t.detectable_by(s))
                .count();
            h.log_weight += n as f64 * miss;
        }
        self.prune(self.config.max_hypotheses);
        self.time = time;
        self.scans += 1;
        Ok(())
    }

    /// Runs the tracker over detections sorted by time and grouped by scan (consecutive
    /// detections with the same `scan` value); `scans` lists every scan `(time, sensor)` in order,
    /// including empty ones, and detection `k` must belong to one of them. Returns the best
    /// hypothesis after each scan through `observe(scan_index, time, tracker)`.
    pub fn run<F: FnMut(usize, f64, &Mht)>(
        &mut self,
        scans: &[(f64, usize)],
        detections: &[Detection],
        mut observe: F,
    ) -> Result<()> {
        let mut k = 0usize;
        let mut batch = Vec::new();
        for (si, &(t, sensor)) in scans.iter().enumerate() {
            batch.clear();
            while k < detections.len() && detections[k].scan == si {
                batch.push((k, detections[k]));
                k += 1;
            }
            self.process_scan(t, sensor, &batch)?;
            observe(si, t, self);
        }
        if k != detections.len() {
            return Err(Error::Invalid(format!(
                "detection {k}: scan {} is not in the scan list or detections are not grouped by scan in order",
                detections[k].scan
            )));
        }
        Ok(())
    }

    fn close_coasting(&mut self, time: f64) {
        let max_coast = self.config.max_coast;
        for h in &mut self.hypotheses {
            if h.tracks.iter().all(|t| time - t.last_time <= max_coast) {
                continue;
            }
            let mut open = Vec::with_capacity(h.tracks.len());
            for t in h.tracks.drain(..) {
                if time - t.last_time <= max_coast {
                    open.push(t);
                } else {
                    h.closed = Some(Arc::new(Closed {
                        track: t,
                        prev: h.closed.take(),
                    }));
                }
            }
            h.tracks = open;
        }
    }

    fn expand(&mut self, index: usize, det: &Detection, cap: usize) {
        let cfg = self.config;
        let ln_fa = cfg.false_alarm_density.ln();
        let ln_nt = cfg.new_target_density.ln();
        let ln_pd = cfg.pd.ln();
        let mut cache: HashMap<*const Track, Option<(Arc<Track>, f64)>> = HashMap::new();
        let mut children = Vec::new();
        for (pi, h) in self.hypotheses.iter().enumerate() {
            if cfg.false_alarm_hypotheses {
                children.push(Child {
                    log_weight: h.log_weight + ln_fa,
                    parent: pi,
                    action: Action::FalseAlarm,
                });
            }
            children.push(Child {
                log_weight: h.log_weight + ln_nt,
                parent: pi,
                action: Action::NewTrack,
            });
            for (slot, t) in h.tracks.iter().enumerate() {
                if t.last_scan == det.scan {
                    continue;
                }
                let entry = cache.entry(Arc::as_ptr(t)).or_insert_with(|| {
                    t.associate(index, det, &self.sensors, &cfg)
                        .map(|(nt, ll)| (Arc::new(nt), ll))
                });
                if let Some((nt, ll)) = entry {
                    children.push(Child {
                        log_weight: h.log_weight + ln_pd + *ll,
                        parent: pi,
                        action: Action::Update(slot, nt.clone()),
                    });
                }
            }
        }
        let by_weight = |a: &Child, b: &Child| {
            b.log_weight
                .total_cmp(&a.log_weight)
                .then(a.parent.cmp(&b.parent))
        };
        if children.len() > cap {
            children.select_nth_unstable_by(cap - 1, by_weight);
            children.truncate(cap);
        }
        let new_track = Arc::new(Track::start(index, det, &cfg.noise.covariance()));
        let mut next = Vec::with_capacity(children.len());
        for c in children {
            let parent = &self.hypotheses[c.parent];
            let mut tracks = parent.tracks.clone();
            match c.action {
                Action::FalseAlarm => {}
                Action::NewTrack => tracks.push(new_track.clone()),
                Action::Update(slot, t) => tracks[slot] = t,
            }
            next.push(Hypothesis {
                log_weight: c.log_weight,
                tracks,
                closed: parent.closed.clone(),
            });
        }
        self.hypotheses = next;
        self.prune(cap);
    }

    /// Keeps the `n` most likely hypotheses, sorted, with probabilities normalised to one.
    fn prune(&mut self, n: usize) {
        self.hypotheses
            .sort_by(|a, b| b.log_weight.total_cmp(&a.log_weight));
        self.hypotheses.truncate(n);
        let top = self.hypotheses[0].log_weight;
        let sum: f64 = self
            .hypotheses
            .iter()
            .map(|h| (h.log_weight - top).exp())
            .sum();
        let norm = top + sum.ln();
        for h in &mut self.hypotheses {
            h.log_weight -= norm;
        }
    }
}

/// Groups time-ordered detections into scans: consecutive detections with the same time and
/// sensor form one scan. Sets each detection's `scan` and returns the scans `(time, sensor)`.
/// Errors name the first detection out of time order or with a non-finite time.
pub fn group_scans(detections: &mut [Detection]) -> Result<Vec<(f64, usize)>> {
    let mut scans: Vec<(f64, usize)> = Vec::new();
    for (row, d) in detections.iter_mut().enumerate() {
        if !d.time.is_finite() {
            return Err(Error::NonFinite {
                what: "detection",
                row,
                field: "time",
                value: d.time,
            });
        }
        match scans.last() {
            Some(&(t, s)) if t == d.time && s == d.sensor => {}
            Some(&(t, _)) if d.time < t => {
                return Err(Error::Invalid(format!(
                    "detection row {row}: time {} is before the previous detection at {t}; sort detections by time",
                    d.time
                )))
            }
            _ => scans.push((d.time, d.sensor)),
        }
        d.scan = scans.len() - 1;
    }
    Ok(scans)
}
