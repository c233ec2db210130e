//! The evidence of one track pair for the joint model ([`crate::association::posterior`]): the
//! log-likelihood ratio `L` of "one object" against "two objects", and the picture-wide
//! quantities it needs, estimated from the picture itself (`docs/association.md`, "The joint
//! model", gives the derivation and every assumption).
//!
//! Per common instant `t` the two AOUs are Gaussians (seed 000, eqs. 56-59); under "one object"
//! the difference of the centres is `N(0, S_t)` with `S_t = c (R_a + R_b)` (`c` the covariance
//! inflation of the pair's sources), whose log-density, normaliser included, is
//! `l_t = -m_t / 2 - ln(2 pi sqrt(det S_t))`. Under "two objects" the second track follows some
//! other object: at the first instant it is anywhere the picture's objects are, with the local
//! object density `mu` (objects per m^2); at every later *independent* instant it is where its
//! own motion puts it, a density whose expected log is `h_t = -1 - ln(2 pi sqrt(det(S_t + Q)))`
//! with `Q = 2 q tau I` the spread of straight-line motion over one correlation time (`q` the
//! process noise, `tau` the correlation time), less what its own earlier instants leave
//! unknown: at the `j`-th later instant its position is known from the `j` before with the
//! covariance `S_t / j` of their mean, so the instant's density is that of `S_t (1 + 1/j) + Q`,
//! and the sum `Lambda = sum_j ln sqrt(det(S (1 + 1/j) + Q) / det(S + Q))` ([`own_prediction`];
//! `ln k_eff` when `Q << S`) is added to `L`. With means over the instants that count every
//! report's error once, worth `k_eff` independent instants
//! ([`crate::association::combine::pair_instant_counts`]),
//!
//! `L = (mean l - ln mu) + (k_eff - 1) (mean l - mean h) + Lambda + ln kappa + ln(1 - F_a) + ln(1 - F_b)`
//!
//! where `kappa = 1 / prod_s (1 - P_s)` is the prior odds of one merge under independent
//! per-source coverage `P_s` (an object of a Poisson picture seen by every source with its own
//! probability), and `F_s` is the probability that a track of source `s` is false were it
//! alone ([`Picture::ln_not_false`]): a lone track is an object no other source sees (density
//! `mu P_s prod_{s' != s} (1 - P_s')`) or a false track (density `phi_s`, from the share `f_s`
//! of the source's tracks that are false, spread as the source's reports are: over the cells
//! where the objects are, the share `rho_s` of them that its AOUs leave there,
//! [`Picture::overlap`]), so
//! `F_s = r / (r + (mu / mu_bar) prod_{s' != s} (1 - P_s'))` with `r = rho_s f_s / (1 - f_s)`. The
//! posterior counts each track's `ln(1 - F)` once per object ([`PairEvidence::own`]).
//!
//! `kappa` is the prior odds of merging two objects seen by different sources. An object seen
//! by source `s` may get several tracks of it (a tracker's break, another pass of a patrol
//! aircraft), with odds `g_s` of a further one ([`track_breaks`]); merging two objects both
//! seen by `s` then has `g_s / P_s` for `s` where `kappa` has `1 / (1 - P_s)`, so the posterior
//! weighs every further track of a source in one object by `g_s (1 - P_s) / P_s`.
//!
//! **Estimates from the picture.** `mu` is the time-averaged number of tracks of the most
//! complete source (the one with the most track-seconds) per area, on a grid of
//! [`Model::cell`]-metre cells smoothed over the 3 x 3 neighbourhood, divided by that source's
//! completeness ([`Model::completeness`]), and never below a twentieth of the picture-wide
//! density. `P_s` is the completeness times the ratio of source `s`'s track-seconds to the most
//! complete source's, clamped to `[0.001, 0.999]`. `g_s` comes from the number of tracks of
//! `s` per object it sees, `P_s` times the picture's objects ([`track_breaks`]).

use super::reports::{Coords, Reports};
use super::PairStat;
use crate::error::{Error, Result};

/// Parameters of the pair evidence (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// Fraction of the picture's objects the most complete source holds a track of.
    pub completeness: f64,
    /// Fraction of each source's tracks that are false (by source index); sources beyond the
    /// vector take [`Model::DEFAULT_FALSE_TRACKS`].
    pub false_tracks: Vec<f64>,
    /// Side of the density grid's cells (m).
    pub cell: f64,
}

impl Default for Model {
    fn default() -> Self {
        Self {
            completeness: 0.95,
            false_tracks: Vec::new(),
            cell: 2_000.0,
        }
    }
}

impl Model {
    /// The false-track fraction of a source without one given.
    pub const DEFAULT_FALSE_TRACKS: f64 = 0.05;

    /// Checks the parameters.
    pub fn validated(self) -> Result<Self> {
        let bad = |name: &'static str, reason: String| Err(Error::InvalidOption { name, reason });
        if !(self.completeness > 0.0 && self.completeness < 1.0) {
            return bad(
                "completeness",
                format!("must be in (0, 1), got {}", self.completeness),
            );
        }
        if let Some((s, f)) = self
            .false_tracks
            .iter()
            .enumerate()
            .find(|(_, f)| !(**f >= 0.0 && **f < 1.0))
        {
            return bad(
                "false_tracks",
                format!("source {s}: must be in [0, 1), got {f}"),
            );
        }
        if !(self.cell.is_finite() && self.cell > 0.0) {
            return bad(
                "density_cell",
                format!("must be finite and > 0, got {}", self.cell),
            );
        }
        Ok(self)
    }

    fn false_fraction(&self, source: u32) -> f64 {
        self.false_tracks
            .get(source as usize)
            .copied()
            .unwrap_or(Self::DEFAULT_FALSE_TRACKS)
    }
}

/// Track-seconds per source and per grid cell: the mergeable summary of a picture (or of any
/// part of it holding whole tracks) from which [`Picture`] is built. Cells are anchored at
/// absolute indices (planar: `floor(x / cell)`; geographic: rows of `cell` metres of latitude,
/// columns of `cell` metres of longitude at the row's centre), and durations are whole
/// microseconds (integers, so sums do not depend on their order): the counts of several parts
/// add up to those of the whole, bit for bit.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Counts {
    /// Cell side (m).
    pub cell: f64,
    /// Whether positions are `(lat, lon)` degrees.
    pub geographic: bool,
    /// Track-microseconds per source.
    pub micros: Vec<u64>,
    /// Track-microseconds per `(source, row, column)`.
    pub grid: std::collections::BTreeMap<(u32, i64, i64), u64>,
    /// Earliest and latest report time.
    pub time: (f64, f64),
    /// Per source: the sum over its reports of `sqrt(rx ry)`, the geometric mean of their
    /// 2-sigma semi-axes, in whole metres (over [`Counts::reports`], the source's typical AOU).
    pub reach: Vec<u64>,
    /// Reports per source.
    pub reports: Vec<u64>,
}

const EARTH_RADIUS: f64 = 6_371_008.8;

impl Counts {
    fn metres_per_degree() -> f64 {
        EARTH_RADIUS * std::f64::consts::PI / 180.0
    }

    /// A duration (s) as whole microseconds (rounded; saturating, `NaN` as 0).
    pub fn to_micros(seconds: f64) -> u64 {
        (seconds * 1e6).round() as u64
    }

    /// Microseconds as seconds.
    pub fn seconds(micros: u64) -> f64 {
        micros as f64 * 1e-6
    }

    /// The cell `(row, column)` of a position.
    fn cell_of(&self, pos: [f64; 2]) -> (i64, i64) {
        let clamp = |v: f64| v.clamp(-1e15, 1e15) as i64;
        if self.geographic {
            let m = Self::metres_per_degree();
            let row = (pos[0] * m / self.cell).floor();
            let centre = ((row + 0.5) * self.cell / m).clamp(-90.0, 90.0);
            let col = (pos[1] * m * centre.to_radians().cos().max(1e-3) / self.cell).floor();
            (clamp(row), clamp(col))
        } else {
            (
                clamp((pos[1] / self.cell).floor()),
                clamp((pos[0] / self.cell).floor()),
            )
        }
    }

    /// The counts of `r` (reports stand for the time to the next report of their track, at
    /// most `max_gap` seconds; a track's last report for the gap before it, a lone report for
    /// `min(max_gap, 60)`).
    pub fn of(r: &Reports, cell: f64, max_gap: f64) -> Self {
        let mut out = Self {
            cell,
            geographic: r.coords == Coords::Geographic,
            micros: Vec::new(),
            grid: Default::default(),
            time: (f64::INFINITY, f64::NEG_INFINITY),
            reach: Vec::new(),
            reports: Vec::new(),
        };
        for t in 0..r.n_tracks {
            let range = r.range(t);
            let times = &r.time[range.clone()];
            let s = r.source[t];
            if out.micros.len() <= s as usize {
                out.micros.resize(s as usize + 1, 0);
                out.reach.resize(s as usize + 1, 0);
                out.reports.resize(s as usize + 1, 0);
            }
            for (k, i) in range.enumerate() {
                let next = times.get(k + 1).map(|&x| x - times[k]);
                let prev = (k > 0).then(|| times[k] - times[k - 1]);
                let dt = match (next, prev) {
                    (Some(a), _) => a.min(max_gap),
                    (None, Some(b)) => b.min(max_gap),
                    (None, None) => max_gap.min(60.0),
                };
                let us = Self::to_micros(dt);
                out.micros[s as usize] = out.micros[s as usize].saturating_add(us);
                let reach = r.area[i].max(0.0).sqrt().round() as u64;
                out.reach[s as usize] = out.reach[s as usize].saturating_add(reach);
                out.reports[s as usize] = out.reports[s as usize].saturating_add(1);
                let (row, col) = out.cell_of(r.state[i].pos);
                let cell = out.grid.entry((s, row, col)).or_insert(0);
                *cell = cell.saturating_add(us);
                out.time = (out.time.0.min(times[k]), out.time.1.max(times[k]));
            }
        }
        out
    }

    /// Adds the counts of another part of the picture.
    pub fn merge(&mut self, other: &Counts) {
        if self.micros.len() < other.micros.len() {
            self.micros.resize(other.micros.len(), 0);
        }
        for (s, v) in other.micros.iter().enumerate() {
            self.micros[s] = self.micros[s].saturating_add(*v);
        }
        for (mine, theirs) in [
            (&mut self.reach, &other.reach),
            (&mut self.reports, &other.reports),
        ] {
            if mine.len() < theirs.len() {
                mine.resize(theirs.len(), 0);
            }
            for (s, v) in theirs.iter().enumerate() {
                mine[s] = mine[s].saturating_add(*v);
            }
        }
        for (k, v) in &other.grid {
            let cell = self.grid.entry(*k).or_insert(0);
            *cell = cell.saturating_add(*v);
        }
        self.time = (self.time.0.min(other.time.0), self.time.1.max(other.time.1));
    }
}

/// What the picture says about itself: the object density grid and per-source coverage.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    counts: Counts,
    /// Objects per m^2 per occupied cell of the reference source (3 x 3 smoothed).
    density: std::collections::BTreeMap<(i64, i64), f64>,
    /// Picture-wide density floor (objects per m^2).
    floor: f64,
    /// Picture-wide density: the reference source's objects over the cells it occupies.
    mean: f64,
    /// Coverage `P_s` per source.
    pub coverage: Vec<f64>,
    /// Per source, the share `rho_s` of its reports that fall in the cells the reference source
    /// occupies ([`blurred_share`]), at least [`MIN_OVERLAP`]: its false tracks are spread as
    /// its reports are, so over those cells their density is `rho_s` times the picture-wide
    /// rate.
    pub overlap: Vec<f64>,
    /// `ln kappa = -sum_s ln(1 - P_s)`.
    pub ln_kappa: f64,
    /// The most complete source.
    pub reference: u32,
}

impl Picture {
    /// Estimates the density grid and the coverages from `r` (reports interpolated across gaps
    /// up to `max_gap` seconds).
    pub fn estimate(r: &Reports, model: &Model, max_gap: f64) -> Self {
        Self::from_counts(Counts::of(r, model.cell, max_gap), model)
    }

    /// The picture of merged [`Counts`].
    pub fn from_counts(counts: Counts, model: &Model) -> Self {
        let secs: Vec<f64> = counts.micros.iter().map(|&u| Counts::seconds(u)).collect();
        let reference = (0..secs.len())
            .max_by(|&a, &b| secs[a].total_cmp(&secs[b]).then(b.cmp(&a)))
            .unwrap_or(0) as u32;
        let span = (counts.time.1 - counts.time.0).max(1.0);
        let cell_area = counts.cell * counts.cell;
        let total = secs.get(reference as usize).copied().unwrap_or(0.0);
        let own: std::collections::BTreeMap<(i64, i64), f64> = counts
            .grid
            .iter()
            .filter(|(k, _)| k.0 == reference)
            .map(|(k, v)| ((k.1, k.2), Counts::seconds(*v)))
            .collect();
        // picture-wide: the reference source's objects over the cells it occupies
        let occupied = own.len().max(1) as f64;
        let mean = (total / span / (occupied * cell_area) / model.completeness)
            .max(20.0 * f64::MIN_POSITIVE);
        let floor = mean / 20.0;
        let mut density = std::collections::BTreeMap::new();
        for &(row, col) in own.keys() {
            let mut sum = 0.0;
            for dr in -1..=1 {
                for dc in -1..=1 {
                    sum += own.get(&(row + dr, col + dc)).copied().unwrap_or(0.0);
                }
            }
            let mu = sum / span / (9.0 * cell_area) / model.completeness;
            density.insert((row, col), mu.max(floor));
        }
        let coverage: Vec<f64> = secs
            .iter()
            .map(|&s| {
                if total > 0.0 {
                    (model.completeness * s / total).clamp(0.001, 0.999)
                } else {
                    0.5
                }
            })
            .collect();
        let ln_kappa = -coverage.iter().map(|p| (1.0 - p).ln()).sum::<f64>();
        // the typical 1-sigma reach of each source's reports beyond the reference's own
        let sigma = |s: usize| {
            let n = counts.reports.get(s).copied().unwrap_or(0);
            (n > 0).then(|| counts.reach[s] as f64 / n as f64 / 2.0)
        };
        let own_sigma = sigma(reference as usize).unwrap_or(0.0);
        let overlap = (0..secs.len())
            .map(|s| match sigma(s) {
                Some(x) => {
                    let extra = (x * x - own_sigma * own_sigma).max(0.0).sqrt();
                    blurred_share(&own, extra / counts.cell).clamp(MIN_OVERLAP, 1.0)
                }
                None => 1.0,
            })
            .collect();
        Self {
            counts,
            density,
            floor,
            mean,
            coverage,
            overlap,
            ln_kappa,
            reference,
        }
    }

    /// Object density (per m^2) at `pos`: the smoothed density of its cell, or of the nearest
    /// occupied cell among its eight neighbours, or the floor.
    pub fn density_at(&self, pos: [f64; 2]) -> f64 {
        let (row, col) = self.counts.cell_of(pos);
        if let Some(&d) = self.density.get(&(row, col)) {
            return d;
        }
        let mut best = self.floor;
        for dr in -1..=1 {
            for dc in -1..=1 {
                if let Some(&d) = self.density.get(&(row + dr, col + dc)) {
                    best = best.max(d);
                }
            }
        }
        best
    }
}

impl Picture {
    /// `ln(1 - F_s)`: the log of the odds that a track of source `s` where the object density is
    /// `mu` is a real object's and not a false track, were it alone (see the module docs).
    pub fn ln_not_false(&self, model: &Model, source: u32, mu: f64) -> f64 {
        let f = model.false_fraction(source);
        if f <= 0.0 {
            return 0.0;
        }
        let rho = self.overlap.get(source as usize).copied().unwrap_or(1.0);
        let r = f / (1.0 - f) * rho;
        let p = self.coverage.get(source as usize).copied().unwrap_or(0.5);
        // mu / mean * prod over the other sources of (1 - P)
        let q = (mu / self.mean) * (-self.ln_kappa).exp() / (1.0 - p);
        q.ln() - (r + q).ln()
    }
}

/// The share of the reference source's track-time that stays in its own cells when every
/// position is displaced by an isotropic Gaussian of standard deviation `sigma` cells: each
/// occupied cell's time, at the cell's centre, spread over the cells by the Gaussian's mass in
/// each, and summed over the occupied ones, weighed by the cells' time. A source whose reports
/// scatter about the objects `sigma` cells further than the reference's (its AOUs wider) has
/// this share of its reports where the objects are. Exactly 1 at `sigma = 0`. The Gaussian is
/// separable, so the sum is two passes of a one-dimensional kernel over the occupied cells and
/// their neighbours, `O(cells x reach)`, the kernel cut at 6 sigma (and at the occupied
/// extent).
pub fn blurred_share(cells: &std::collections::BTreeMap<(i64, i64), f64>, sigma: f64) -> f64 {
    let total: f64 = cells.values().sum();
    // no time, or no displacement (a NaN reach included): everything stays
    if total.is_nan() || total <= 0.0 || sigma.is_nan() || sigma <= 0.0 {
        return 1.0;
    }
    let (mut lo, mut hi) = ((i64::MAX, i64::MAX), (i64::MIN, i64::MIN));
    for &(r, c) in cells.keys() {
        lo = (lo.0.min(r), lo.1.min(c));
        hi = (hi.0.max(r), hi.1.max(c));
    }
    let extent = (hi.0 - lo.0).max(hi.1 - lo.1);
    let reach = ((6.0 * sigma).ceil() as i64).min(extent).max(0);
    let kernel: Vec<f64> = (-reach..=reach).map(|d| cell_mass(d, sigma)).collect();
    // pass 1: along columns, at every cell within `reach` columns of an occupied one
    let mut along: std::collections::HashMap<(i64, i64), f64> = Default::default();
    for (&(r, c), &w) in cells {
        for (j, k) in kernel.iter().enumerate() {
            *along.entry((r, c + j as i64 - reach)).or_insert(0.0) += w * k;
        }
    }
    // pass 2: along rows, read at the occupied cells only
    let mut kept = 0.0;
    for &(r, c) in cells.keys() {
        for (j, k) in kernel.iter().enumerate() {
            if let Some(v) = along.get(&(r + j as i64 - reach, c)) {
                kept += v * k;
            }
        }
    }
    kept / total
}

/// The mass of a centred Gaussian of standard deviation `sigma` (in cells, `> 0`) in the cell
/// `d` cells from its centre's, along one axis.
pub fn cell_mass(d: i64, sigma: f64) -> f64 {
    let phi = |x: f64| 0.5 * (1.0 + statrs::function::erf::erf(x / std::f64::consts::SQRT_2));
    phi((d as f64 + 0.5) / sigma) - phi((d as f64 - 0.5) / sigma)
}

/// The smallest share `rho_s` of a source's reports in the reference source's cells
/// ([`Picture::overlap`]): a twentieth, as the density's floor is of its mean, so a source whose
/// AOUs dwarf the picture still has false tracks where the objects are.
pub const MIN_OVERLAP: f64 = 0.05;

/// The smallest `g_s` of [`track_breaks`]: that of the most complete source, which the model
/// takes to give each object it sees one track (as the density estimate does), and of a source
/// that shows no break.
pub const MIN_TRACK_BREAK: f64 = 0.05;

/// Per source, `g_s`: the odds that an object source `s` sees gets a further track of that
/// source (a track break, another pass of a patrol aircraft), `P(n + 1 tracks) / P(n tracks)`
/// for an object seen by `s`, from `m_s`, its tracks per object it sees, of a geometric count:
/// `g_s = 1 - 1 / m_s`, clamped to `[MIN_TRACK_BREAK, 0.99]`. The objects `s` sees are
/// `P_s` (`coverage`) times the picture's objects, which are the real tracks of the most
/// complete source (`reference`, one per object) over the completeness; the real tracks of a
/// source are its tracks less the false share `f_s`. So
/// `m_s = N_s (1 - f_s) c / (P_s N_ref (1 - f_ref))`, with `N` the numbers of tracks and `c` the
/// completeness: `1` for the reference source.
pub fn track_breaks(
    track_source: &[u32],
    coverage: &[f64],
    reference: u32,
    model: &Model,
) -> Vec<f64> {
    let mut tracks = vec![0usize; coverage.len()];
    for &s in track_source {
        if let Some(n) = tracks.get_mut(s as usize) {
            *n += 1;
        }
    }
    let real = |s: usize| tracks[s] as f64 * (1.0 - model.false_fraction(s as u32));
    let objects = tracks
        .get(reference as usize)
        .map_or(0.0, |_| real(reference as usize))
        / model.completeness;
    (0..coverage.len())
        .map(|s| {
            if s as u32 == reference || tracks[s] == 0 || objects <= 0.0 {
                return MIN_TRACK_BREAK;
            }
            let m = real(s) / (coverage[s] * objects);
            (1.0 - 1.0 / m).clamp(MIN_TRACK_BREAK, 0.99)
        })
        .collect()
}

/// The term of the `j`-th later independent instant in [`own_prediction`],
/// `ln sqrt(det(S (1 + 1/j) + Q) / det(S + Q))`.
fn own_term(a: f64, b: f64) -> impl Fn(f64) -> f64 {
    let base = (1.0 + a + b).ln();
    move |j: f64| {
        let x = 1.0 + 1.0 / j;
        0.5 * ((x * x + x * a + b).ln() - base)
    }
}

/// The part of `L` that the second track's own earlier instants leave unexplained under "two
/// objects": at its `j`-th later independent instant the track's position is known from its
/// `j` earlier ones with the covariance `S / j` of their mean, so the density of the instant
/// is that of `S + S / j + Q`, not of `S + Q`. Summed over the `k - 1` later instants (the
/// last one weighed by the fraction of `k`), `sum_j ln sqrt(det(S (1 + 1/j) + Q) / det(S + Q))`,
/// from `det(x S + q I) / det S = x^2 + x a + b` with `a = q tr S / det S` and
/// `b = q^2 / det S` (`Q = q I`; the means over the instants, as for `h`). For `Q << S` it is
/// `ln k`: `k` fixes of a still emitter pin it `sqrt k` times more tightly than one, which the
/// density of one fix against the next misses.
fn own_prediction(k: f64, a: f64, b: f64) -> f64 {
    if k.is_nan() || k <= 1.0 {
        return 0.0;
    }
    let term = own_term(a, b);
    let whole = (k - 1.0).floor();
    let mut sum = 0.0;
    let mut j = 1.0;
    while j <= whole {
        sum += term(j);
        j += 1.0;
    }
    let rest = k - 1.0 - whole;
    if rest > 0.0 {
        sum += rest * term(whole + 1.0);
    }
    sum
}

/// `own_prediction(k1, a, b) - own_prediction(k0, a, b)` for `k1 >= k0`, summing only the
/// instants between the two.
pub(crate) fn own_prediction_between(k0: f64, k1: f64, a: f64, b: f64) -> f64 {
    let (k0, k1) = (k0.max(1.0), k1.max(1.0));
    if k0.is_nan() || k1.is_nan() || k1 <= k0 {
        return 0.0;
    }
    let term = own_term(a, b);
    // own_prediction(k) = sum of term(j) for j = 1..=w, plus r term(w + 1), w = floor(k - 1)
    let (w0, w1) = ((k0 - 1.0).floor(), (k1 - 1.0).floor());
    let (r0, r1) = (k0 - 1.0 - w0, k1 - 1.0 - w1);
    let mut sum = r1 * term(w1 + 1.0) - r0 * term(w0 + 1.0);
    let mut j = w0 + 1.0;
    while j <= w1 {
        sum += term(j);
        j += 1.0;
    }
    sum
}

/// A pair's `L` (see the module docs) and the terms `ln(1 - F)` of each of its tracks in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairEvidence {
    pub llr: f64,
    pub own: (f64, f64),
    /// Independent instants of the pair (`k_eff`).
    pub k_eff: f64,
    /// What one more independent instant adds to `llr`: `mean l - mean h` (the slope of `L` in
    /// `k_eff`; 0 when the pair has no instant).
    pub fit: f64,
    /// The spread of straight-line motion against the pair's AOUs, `(a, b)` of
    /// [`own_prediction`]: its term `Lambda` in `llr` is `own_prediction(k_eff, a, b)`.
    pub motion: (f64, f64),
}

/// `L` of a scored pair (see the module docs): `stat` from [`super::pair_stat`], `c` the
/// covariance inflation of its sources, `q` the process noise (m^2/s) and `tau` the correlation
/// time (s).
pub fn log_likelihood_ratio(
    stat: &PairStat,
    c: f64,
    sources: (u32, u32),
    picture: &Picture,
    model: &Model,
    q: f64,
    tau: f64,
) -> PairEvidence {
    let k = stat.instants;
    let none = PairEvidence {
        llr: f64::NEG_INFINITY,
        own: (0.0, 0.0),
        k_eff: 0.0,
        fit: 0.0,
        motion: (0.0, 0.0),
    };
    if k == 0 {
        return none;
    }
    let two_pi_ln = (2.0 * std::f64::consts::PI).ln();
    // mean l: -m/(2c) - ln(2 pi) - ln c - ln det S / 2
    let mean_l = -0.5 * stat.mean_mg / c - two_pi_ln - c.ln() - 0.5 * stat.mean_ln_det;
    // mean h - mean l's normaliser part: ln det(cS + Q) - ln det(cS) = ln(1 + Q u / c + Q^2 v / c^2)
    let qq = 2.0 * q * tau;
    // det(cS + Q) / det(cS) = 1 + a + b
    let (a, b) = (
        qq * stat.mean_trace_over_det / c,
        qq * qq * stat.mean_inv_det / (c * c),
    );
    let widen = 0.5 * (1.0 + a + b).ln();
    // mean l - mean h = -m/(2c) + 1 + widen
    let fit = -0.5 * stat.mean_mg / c + 1.0 + widen;
    let learn = own_prediction(stat.evidence_k_eff, a, b);
    let mu = picture.density_at(stat.pos);
    let own = (
        picture.ln_not_false(model, sources.0, mu),
        picture.ln_not_false(model, sources.1, mu),
    );
    let prior = picture.ln_kappa + own.0 + own.1;
    let l = (mean_l - mu.ln()) + (stat.evidence_k_eff - 1.0).max(0.0) * fit + learn + prior;
    if l.is_nan() || own.0.is_nan() || own.1.is_nan() {
        none
    } else {
        PairEvidence {
            llr: l,
            own,
            k_eff: stat.evidence_k_eff,
            fit,
            motion: (a, b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `own_prediction` is `sum_j ln sqrt(det(S (1 + 1/j) + Q) / det(S + Q))` over the later
    /// instants: `ln k` when the prediction is exact (`Q = 0`), and the determinants' ratio
    /// from the matrices themselves for an elongated, rotated `S` and `Q = 2 q tau I`.
    #[test]
    fn own_prediction_by_hand_and_by_determinants() {
        for k in 1..12 {
            let got = own_prediction(k as f64, 0.0, 0.0);
            assert!((got - (k as f64).ln()).abs() < 1e-12, "k {k}: {got}");
        }
        // 2.5 instants: the first later one whole, the second by half
        let want = 2f64.ln() + 0.5 * 1.5f64.ln();
        assert!((own_prediction(2.5, 0.0, 0.0) - want).abs() < 1e-12);
        let (s1, s2, th) = (4.0e6_f64, 9.0e4_f64, 0.6_f64);
        let (c, sn) = (th.cos(), th.sin());
        // S = rotation diag(s1, s2) rotation^T, entries written out
        let (sxx, sxy, syy) = (
            s1 * c * c + s2 * sn * sn,
            (s1 - s2) * c * sn,
            s1 * sn * sn + s2 * c * c,
        );
        let det = |x: f64, q: f64| (x * sxx + q) * (x * syy + q) - x * x * sxy * sxy;
        let qq = 2.0 * 2.0 * 60.0 * 1000.0; // a large diffusion, to weigh the cross terms
        let want: f64 = (1..7)
            .map(|j| 0.5 * (det(1.0 + 1.0 / j as f64, qq) / det(1.0, qq)).ln())
            .sum();
        let (tr, dt) = (sxx + syy, det(1.0, 0.0));
        let got = own_prediction(7.0, qq * tr / dt, qq * qq / dt);
        assert!((got - want).abs() < 1e-10, "{got} {want}");
    }

    /// The difference of `own_prediction` between two counts, summed over the instants
    /// between them only, is the difference of the whole sums (whole and fractional counts,
    /// below one, equal, and a wide `Q`).
    #[test]
    fn own_prediction_between_two_counts_is_their_difference() {
        for (a, b) in [(0.0, 0.0), (0.3, 0.02), (5.0, 7.0)] {
            for (k0, k1) in [
                (1.0, 5.0),
                (2.5, 2.75),
                (0.4, 3.2),
                (3.5, 17.25),
                (4.0, 4.0),
            ] {
                let want = own_prediction(k1, a, b) - own_prediction(k0, a, b);
                let got = own_prediction_between(k0, k1, a, b);
                assert!(
                    (got - want).abs() < 1e-12,
                    "{k0} {k1} {a} {b}: {got} {want}"
                );
            }
        }
    }

    /// `L` of a still emitter's `k` fixes (covariance `R`, 9 x 1.5 km) against a still ship
    /// with a state at each, against the exact marginal likelihood ratio: "one object" is
    /// `prod_i N(z_i; s, R)`; "two objects" is the emitter anywhere at density `mu`,
    /// `mu * integral prod_i N(z_i; x, R) dx`, the integral by brute-force quadrature on a grid.
    /// The model replaces the scatter of the fixes about their mean, `W = sum_i (z_i -
    /// mean)^T R^-1 (z_i - mean)`, by its expectation `2 (k - 1)` (its `h` has the expected
    /// density of an instant): so the two agree when `W = 2 (k - 1)`, and differ by `(k - 1) -
    /// W / 2` otherwise. Without the term of the emitter's own earlier fixes
    /// (`own_prediction`) they differ by `ln k`.
    #[test]
    fn a_still_emitter_s_fixes_against_the_exact_marginal_likelihood() {
        let (s1, s2) = (9000.0_f64 * 9000.0, 1500.0_f64 * 1500.0);
        let inv = |d: [f64; 2]| d[0] * d[0] / s1 + d[1] * d[1] / s2;
        let ln_n =
            |d: [f64; 2]| -0.5 * inv(d) - (2.0 * std::f64::consts::PI).ln() - 0.5 * (s1 * s2).ln();
        let mu = 3.0e-8;
        let picture = Picture {
            counts: Counts::default(),
            density: Default::default(),
            floor: mu,
            mean: mu,
            coverage: vec![0.5, 0.5],
            overlap: vec![1.0, 1.0],
            ln_kappa: 0.0,
            reference: 0,
        };
        let model = Model {
            false_tracks: vec![0.0, 0.0],
            ..Model::default()
        };
        let ship = [2000.0, -300.0];
        // offsets about the fixes' mean, scaled so that W = 2 (k - 1) with `scale = 1`
        let unit: [[f64; 2]; 5] = [
            [1.0, 0.0],
            [-1.0, 0.5],
            [0.3, -1.0],
            [-0.5, 0.2],
            [0.2, 0.3],
        ];
        for k in [2usize, 3, 5] {
            for scale in [1.0, 0.6, 1.7] {
                let raw: Vec<[f64; 2]> = unit[..k].to_vec();
                let m = [
                    raw.iter().map(|u| u[0]).sum::<f64>() / k as f64,
                    raw.iter().map(|u| u[1]).sum::<f64>() / k as f64,
                ];
                let cen: Vec<[f64; 2]> = raw
                    .iter()
                    .map(|u| [(u[0] - m[0]) * s1.sqrt(), (u[1] - m[1]) * s2.sqrt()])
                    .collect();
                let w0: f64 = cen.iter().map(|&d| inv(d)).sum();
                let a = (2.0 * (k as f64 - 1.0) / w0).sqrt() * scale;
                let fixes: Vec<[f64; 2]> = cen.iter().map(|d| [d[0] * a, d[1] * a]).collect();
                let w: f64 = fixes.iter().map(|&d| inv(d)).sum();
                // one object: every fix against the ship
                let rel: Vec<[f64; 2]> = fixes
                    .iter()
                    .map(|d| [d[0] - ship[0], d[1] - ship[1]])
                    .collect();
                let one: f64 = rel.iter().map(|&d| ln_n(d)).sum();
                // two objects: the emitter anywhere, by quadrature over +-8 sigma
                let (n, half) = (801usize, 8.0);
                let (hx, hy) = (
                    2.0 * half * s1.sqrt() / (n - 1) as f64,
                    2.0 * half * s2.sqrt() / (n - 1) as f64,
                );
                let mut logs = Vec::with_capacity(n * n);
                for i in 0..n {
                    for j in 0..n {
                        let x = [
                            -half * s1.sqrt() + i as f64 * hx,
                            -half * s2.sqrt() + j as f64 * hy,
                        ];
                        logs.push(
                            fixes
                                .iter()
                                .map(|f| ln_n([f[0] - x[0], f[1] - x[1]]))
                                .sum::<f64>(),
                        );
                    }
                }
                let top = logs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                let integral =
                    top + (logs.iter().map(|l| (l - top).exp()).sum::<f64>() * hx * hy).ln();
                let exact = one - mu.ln() - integral;
                let stat = PairStat {
                    instants: k as u32,
                    mean_mg: rel.iter().map(|&d| inv(d)).sum::<f64>() / k as f64,
                    mean_ln_det: (s1 * s2).ln(),
                    mean_trace_over_det: (s1 + s2) / (s1 * s2),
                    mean_inv_det: 1.0 / (s1 * s2),
                    evidence_k_eff: k as f64,
                    pos: [0.0, 0.0],
                    ..PairStat::EMPTY
                };
                let got = log_likelihood_ratio(&stat, 1.0, (0, 1), &picture, &model, 0.0, 60.0).llr;
                let want = exact + (k as f64 - 1.0) - w / 2.0;
                assert!(
                    (got - want).abs() < 1e-6,
                    "k {k}, W {w:.3}: L {got:.6}, exact {exact:.6} + (k - 1) - W / 2 = {want:.6}"
                );
            }
        }
    }

    /// `g_s` by hand: 40 reference tracks with completeness 0.95 stand for 40 objects (one
    /// false in twenty); source 1 (coverage 0.5, false share 0.1) has 60 tracks, 54 real, for
    /// 20 seen objects, `m = 2.7`; source 2 fewer tracks than objects it sees, source 3 none,
    /// and the reference source take the floor.
    #[test]
    fn track_breaks_by_hand() {
        let mut source = vec![0u32; 40];
        source.extend([1u32; 60]);
        source.extend([2u32; 3]);
        let model = Model {
            false_tracks: vec![0.05, 0.1, 0.05, 0.05],
            ..Model::default()
        };
        let g = track_breaks(&source, &[0.95, 0.5, 0.2, 0.3], 0, &model);
        // 54 real tracks for 0.5 x 40 = 20 seen objects: m = 2.7, g = 1 - 1 / 2.7 = 17 / 27
        assert!((g[1] - 17.0 / 27.0).abs() < 1e-12, "{g:?}");
        assert_eq!(g[0], MIN_TRACK_BREAK);
        assert_eq!(g[2], MIN_TRACK_BREAK);
        assert_eq!(g[3], MIN_TRACK_BREAK);
    }

    /// Reports of `tracks` tracks (sources 0..3) wandering over a few cells with irregular,
    /// non-representable time steps.
    fn picture(coords: Coords, tracks: u32) -> (Vec<u32>, Vec<u32>, Vec<f64>, Vec<[f64; 5]>) {
        let (mut track, mut source, mut time, mut aou) = (vec![], vec![], vec![], vec![]);
        let mut z = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            z ^= z << 13;
            z ^= z >> 7;
            z ^= z << 17;
            (z >> 11) as f64 / (1u64 << 53) as f64
        };
        for t in 0..tracks {
            let mut clock = 1.7e9 + 1000.0 * next();
            let (mut x, mut y) = (9000.0 * next(), 9000.0 * next());
            for _ in 0..(3 + (next() * 40.0) as usize) {
                track.push(t);
                source.push(t % 3);
                time.push(clock);
                let pos = match coords {
                    Coords::Planar => [x, y],
                    Coords::Geographic => [50.0 + y / 111_000.0, -1.0 + x / 70_000.0],
                };
                aou.push([pos[0], pos[1], 50.0, 20.0, 0.3]);
                clock += 0.1 + 400.0 * next();
                x += 300.0 * (next() - 0.5);
                y += 300.0 * (next() - 0.5);
            }
        }
        (track, source, time, aou)
    }

    #[test]
    fn counts_of_any_split_of_the_tracks_add_up_to_the_whole_exactly() {
        for coords in [Coords::Planar, Coords::Geographic] {
            let n = 60;
            let (track, source, time, aou) = picture(coords, n);
            let whole = Reports::new(coords, n as usize, &track, &source, &time, &aou).unwrap();
            let all = Counts::of(&whole, 2_000.0, 300.0);
            assert!(all.grid.len() > 10, "the tracks visit many cells");
            // three parts holding every track once, in an order unlike the whole's
            let mut merged = Counts {
                cell: 2_000.0,
                geographic: coords == Coords::Geographic,
                time: (f64::INFINITY, f64::NEG_INFINITY),
                ..Counts::default()
            };
            for part in [2, 0, 1] {
                let keep: Vec<usize> = (0..track.len())
                    .filter(|&i| (track[i] / 4) % 3 == part)
                    .collect();
                let mut ids: Vec<u32> = keep.iter().map(|&i| track[i]).collect();
                ids.dedup();
                let local: Vec<u32> = keep
                    .iter()
                    .map(|&i| ids.iter().position(|&t| t == track[i]).unwrap() as u32)
                    .collect();
                let r = Reports::new(
                    coords,
                    ids.len(),
                    &local,
                    &keep.iter().map(|&i| source[i]).collect::<Vec<_>>(),
                    &keep.iter().map(|&i| time[i]).collect::<Vec<_>>(),
                    &keep.iter().map(|&i| aou[i]).collect::<Vec<_>>(),
                )
                .unwrap();
                merged.merge(&Counts::of(&r, 2_000.0, 300.0));
            }
            assert_eq!(merged, all);
            let model = Model::default();
            assert_eq!(
                Picture::from_counts(merged, &model),
                Picture::from_counts(all, &model)
            );
        }
    }

    /// `blurred_share` against the double sum over every pair of occupied cells, on random
    /// sparse pictures (the two passes and the kernel's cut against no cut), and by hand from
    /// `erf`: one cell keeps `(2 Phi(1 / (2 sigma)) - 1)^2`, which also checks `cell_mass`;
    /// nothing is lost at `sigma = 0`.
    #[test]
    fn blurred_share_against_the_double_sum() {
        let one: std::collections::BTreeMap<(i64, i64), f64> = [((3, -4), 7.0)].into();
        for sigma in [0.1, 0.5, 1.0, 3.0] {
            let want = (2.0
                * (0.5
                    * (1.0 + statrs::function::erf::erf(0.5 / sigma / std::f64::consts::SQRT_2)))
                - 1.0)
                .powi(2);
            assert!((blurred_share(&one, sigma) - want).abs() < 1e-12, "{sigma}");
        }
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..30 {
            let mut cells = std::collections::BTreeMap::new();
            let n = 1 + (next() * 60.0) as usize;
            let span = 2.0 + next() * 40.0;
            for _ in 0..n {
                let key = ((next() * span) as i64 - 5, (next() * span) as i64 + 2);
                *cells.entry(key).or_insert(0.0) += 0.5 + next() * 100.0;
            }
            let sigma = [0.0, 0.05, 0.7, 2.5, 9.0][case % 5] * (0.5 + next());
            let total: f64 = cells.values().sum();
            let mut kept = 0.0;
            for (&(r, c), &w) in &cells {
                for &(r2, c2) in cells.keys() {
                    kept += if sigma > 0.0 {
                        w * cell_mass(r2 - r, sigma) * cell_mass(c2 - c, sigma)
                    } else {
                        w * f64::from(u8::from((r, c) == (r2, c2)))
                    };
                }
            }
            let got = blurred_share(&cells, sigma);
            assert!(
                (got - kept / total).abs() < 1e-9,
                "case {case}: {got} against {}",
                kept / total
            );
        }
        assert_eq!(blurred_share(&one, 0.0), 1.0);
    }

    /// `rho_s` and `F_s` by hand. The reference source (0) holds 400 s in cell (0, 0) and 200 s
    /// in (0, 1), its reports' `sqrt(rx ry)` 20 m (`sigma` 10 m); source 1's are 2 km
    /// (`sigma` 1 km, `sqrt(1000^2 - 10^2)` beyond the reference's, half a 2 km cell); source
    /// 2's are 200 km, whose share is below the floor; source 3 has no report. With `f = 0.05`
    /// (`r = 1 / 19`) and `mu = mu_bar`, `ln(1 - F_s) = ln q - ln(r rho_s + q)` with
    /// `q = prod_{s' != s} (1 - P_s')`.
    #[test]
    fn false_tracks_are_spread_as_their_source_s_reports_are() {
        let mut counts = Counts {
            cell: 2_000.0,
            geographic: false,
            micros: vec![600_000_000, 120_000_000, 10_000_000, 0],
            time: (0.0, 600.0),
            reach: vec![20 * 50, 2_000 * 4, 200_000, 0],
            reports: vec![50, 4, 1, 0],
            ..Counts::default()
        };
        for (k, v) in [
            ((0, 0, 0), 400_000_000),
            ((0, 0, 1), 200_000_000),
            ((1, 0, 0), 30_000_000),
            ((1, 3, 7), 90_000_000),
            ((2, 9, 9), 10_000_000),
        ] {
            counts.grid.insert(k, v);
        }
        let model = Model::default();
        let picture = Picture::from_counts(counts, &model);
        // source 1: each cell keeps its row's mass at d = 0 and the two cells share columns
        let s1 = (1_000.0_f64.powi(2) - 10.0_f64.powi(2)).sqrt() / 2_000.0;
        let rows = cell_mass(0, s1);
        let cols = (400.0 * (cell_mass(0, s1) + cell_mass(1, s1))
            + 200.0 * (cell_mass(0, s1) + cell_mass(-1, s1)))
            / 600.0;
        let rho1 = rows * cols;
        assert_eq!(picture.overlap[0], 1.0);
        assert!((picture.overlap[1] - rho1).abs() < 1e-12);
        assert_eq!(picture.overlap[2], MIN_OVERLAP);
        assert_eq!(picture.overlap[3], 1.0);
        let p: Vec<f64> = [600.0, 120.0, 10.0, 0.0]
            .iter()
            .map(|s| (0.95 * s / 600.0_f64).clamp(0.001, 0.999))
            .collect();
        assert_eq!(picture.coverage, p);
        let r = 0.05 / 0.95;
        for (source, rho) in [(0usize, 1.0), (1, rho1), (2, MIN_OVERLAP), (3, 1.0)] {
            let q: f64 = (0..4)
                .filter(|&x| x != source)
                .map(|x| 1.0 - p[x])
                .product();
            let by_hand = q.ln() - (r * rho + q).ln();
            let got = picture.ln_not_false(&model, source as u32, picture.mean);
            assert!(
                (got - by_hand).abs() < 1e-12,
                "source {source}: {got} against {by_hand}"
            );
        }
    }

    #[test]
    fn counts_are_the_reports_durations() {
        // one track: reports at 0, 10, 1000 s; max gap 300 s -> 10 + 300 + 300 (the last report
        // stands for the gap before it, capped)
        let r = Reports::new(
            Coords::Planar,
            1,
            &[0, 0, 0],
            &[0, 0, 0],
            &[0.0, 10.0, 1000.0],
            &[[100.0, 100.0, 5.0, 5.0, 0.0]; 3],
        )
        .unwrap();
        let c = Counts::of(&r, 2_000.0, 300.0);
        assert_eq!(c.micros, vec![610_000_000]);
        // sqrt(rx ry) = 5 m per report
        assert_eq!((c.reach.clone(), c.reports.clone()), (vec![15], vec![3]));
        assert_eq!(c.grid.get(&(0, 0, 0)), Some(&610_000_000));
        assert_eq!(c.time, (0.0, 1000.0));
    }
}
