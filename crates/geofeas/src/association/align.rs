//! Time alignment: a track's centre and covariance at any time inside (or just outside) its
//! span, and the common instants of two tracks.
//!
//! The scores of seed 000 compare two AOUs at "a single, common time instant"; reports of two
//! tracks are not simultaneous, so each report time of one track inside the other's span is
//! an instant at which the other track's state is interpolated between its bracketing reports
//! `(t0, c0, R0)` and `(t1, c1, R1)`, `T = t1 - t0`, `tau = t - t0`, `w = tau / T`:
//!
//! - centre: `(1 - w) c0 + w c1` (planar), the point at fraction `w` of the geodesic from `c0` to
//!   `c1` (geographic);
//! - covariance: `(1 - w) R0 + w R1 + q tau (T - tau) / T I`. The linear blend of the two
//!   covariances is what the error of the blended centre has when the two reports' errors are
//!   fully correlated, as the outputs of one tracker a few seconds apart are (independent errors
//!   would give the smaller `(1 - w)^2 R0 + w^2 R1`); the last term is the variance of a
//!   Brownian bridge: the true path's deviation from the chord when the position wanders with
//!   diffusion `q` (m^2/s per axis, the `process_noise`) around straight-line motion. For
//!   linear motion with equal covariances the interpolated centre is exact. In geographic mode
//!   both covariances are first carried into the east/north frame of the interpolated point
//!   along the geodesic (see [`super::geodesy`]).
//! - a gap `T > max_gap` is not interpolated: times inside it have no state, unless the track
//!   is still across it: `T <= max_still_gap` and the two reports at most
//!   `sqrt(chi2_2(0.99) q T)` apart, within the 99th percentile of the diffusion's own spread
//!   over the gap, measurement errors left out ([`connected`]). A ship at anchor or moored
//!   reports AIS only every 3 minutes and loses messages; its gaps are bridged, a moving ship's
//!   are not (the chord and `q` do not hold a manoeuvre), nor any whose reports are too coarse
//!   to show that the ship stayed (an HF DF track's fixes).
//! - within `horizon` seconds before the first or after the last report the state is
//!   extrapolated at the velocity of the two end reports (when they are at most `max_gap`
//!   apart, else held still) with covariance `R_end + q |t - t_end| I`.
//!
//! [`common_instants`] takes every report of either track at which the other has a state; a
//! time at which both have a report is taken once.

use super::geodesy;
use super::reports::{Coords, Reports, State};

/// Alignment options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alignment {
    /// Largest gap between two reports of one track that is interpolated (s).
    pub max_gap: f64,
    /// How far before the first / after the last report a track is extrapolated (s).
    pub horizon: f64,
    /// Diffusion `q` of the position around straight-line motion (m^2/s per axis).
    pub process_noise: f64,
    /// Longest gap between two reports of a still track that is interpolated (s; see
    /// [`connected`]).
    pub max_still_gap: f64,
}

impl Default for Alignment {
    fn default() -> Self {
        Self {
            max_gap: Self::DEFAULT_MAX_GAP,
            horizon: 0.0,
            process_noise: Self::DEFAULT_PROCESS_NOISE,
            max_still_gap: Self::DEFAULT_MAX_STILL_GAP,
        }
    }
}

impl Alignment {
    /// Default `max_gap`: 5 minutes.
    pub const DEFAULT_MAX_GAP: f64 = 300.0;
    /// Default `q` (m^2/s): a ship of 10 m/s whose heading wanders by about 1 degree per minute
    /// strays some 10 m from the chord over a minute's gap, `q tau (T - tau) / T = 0.5^2 * 15`.
    pub const DEFAULT_PROCESS_NOISE: f64 = 2.0;
    /// Default `max_still_gap`: 15 minutes, five of the 3-minute intervals at which a ship at
    /// anchor or moored reports AIS (ITU-R M.1371).
    pub const DEFAULT_MAX_STILL_GAP: f64 = 900.0;

    /// The longest gap any two reports of a track can be interpolated across (s).
    pub fn longest_gap(&self) -> f64 {
        self.max_gap.max(self.max_still_gap)
    }

    /// Checks the options.
    pub fn validated(self) -> crate::Result<Self> {
        for (name, v) in [
            ("max_gap", self.max_gap),
            ("horizon", self.horizon),
            ("process_noise", self.process_noise),
            ("max_still_gap", self.max_still_gap),
        ] {
            if v.is_nan() || v < 0.0 {
                return Err(crate::Error::InvalidOption {
                    name,
                    reason: format!("must be >= 0, got {v}"),
                });
            }
        }
        Ok(self)
    }
}

fn add_iso(cov: [f64; 3], v: f64) -> [f64; 3] {
    [cov[0] + v, cov[1], cov[2] + v]
}

fn blend(a: [f64; 3], b: [f64; 3], w: f64) -> [f64; 3] {
    [
        (1.0 - w) * a[0] + w * b[0],
        (1.0 - w) * a[1] + w * b[1],
        (1.0 - w) * a[2] + w * b[2],
    ]
}

/// 99 % quantile of the chi-square distribution with 2 degrees of freedom, `-2 ln 0.01`.
const STILL_QUANTILE: f64 = 9.210_340_371_976_184;

/// Whether the reports `i` and `i + 1` of `r` (consecutive reports of one track) are
/// interpolated between (see the module docs): their gap `T` is at most `max_gap`, or at most
/// `max_still_gap` with the two centres at most `sqrt(chi2_2(0.99) q T)` apart (the chord in
/// index space, within rounding of the distance for the short distances concerned).
pub fn connected(r: &Reports, i: usize, o: &Alignment) -> bool {
    let gap = r.time[i + 1] - r.time[i];
    if gap <= o.max_gap {
        return true;
    }
    if gap > o.max_still_gap {
        return false;
    }
    let (a, b) = (&r.point[i], &r.point[i + 1]);
    let d2 = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2);
    d2 <= STILL_QUANTILE * o.process_noise * gap
}

/// The state of track `track` at `time` (see the module docs), `None` in a gap or outside the
/// span plus horizon.
pub fn state_at(r: &Reports, track: usize, time: f64, o: &Alignment) -> Option<State> {
    let range = r.range(track);
    let start = range.start;
    let ts = &r.time[range.clone()];
    let st = &r.state[range];
    let n = ts.len();
    let j = ts.partition_point(|&x| x < time);
    if j < n && ts[j] == time {
        return Some(st[j]);
    }
    if j == 0 || j == n {
        let (e, nb) = if j == 0 {
            (0, 1)
        } else {
            (n - 1, n.wrapping_sub(2))
        };
        let dt = time - ts[e];
        if dt.abs() > o.horizon {
            return None;
        }
        let moving = n >= 2 && (ts[e] - ts[nb]).abs() <= o.max_gap;
        return Some(extrapolate(
            r.coords,
            &st[e],
            moving.then(|| (&st[nb], ts[e] - ts[nb])),
            dt,
            o,
        ));
    }
    let (t0, t1) = (ts[j - 1], ts[j]);
    let gap = t1 - t0;
    if !connected(r, start + j - 1, o) {
        return None;
    }
    let tau = time - t0;
    let w = tau / gap;
    let bridge = o.process_noise * tau * (gap - tau) / gap;
    let (s0, s1) = (&st[j - 1], &st[j]);
    Some(match r.coords {
        Coords::Planar => State {
            pos: [
                (1.0 - w) * s0.pos[0] + w * s1.pos[0],
                (1.0 - w) * s0.pos[1] + w * s1.pos[1],
            ],
            cov: add_iso(blend(s0.cov, s1.cov, w), bridge),
        },
        Coords::Geographic => {
            let (pos, r0, r1) = geodesy::interpolate(s0.pos, s1.pos, w);
            let c0 = geodesy::rotate_cov(s0.cov, r0);
            let c1 = geodesy::rotate_cov(s1.cov, r1);
            State {
                pos,
                cov: add_iso(blend(c0, c1, w), bridge),
            }
        }
    })
}

/// The states of track `track` at the instants of `times` (sorted ascending) at which it has
/// one (see the module docs: inside a gap longer than `max_gap`, or beyond the span plus
/// `horizon`, it has none), as `(index into times, state)`.
///
/// ```
/// use geofeas::association::align::{states_at, Alignment};
/// use geofeas::association::{Coords, Reports};
/// // one track: reports at 0, 10 and 400 s, moving east at 1 m/s
/// let aou = [[0.0, 0.0, 20.0, 10.0, 0.0], [10.0, 0.0, 20.0, 10.0, 0.0], [400.0, 0.0, 20.0, 10.0, 0.0]];
/// let r = Reports::new(Coords::Planar, 1, &[0; 3], &[0; 3], &[0.0, 10.0, 400.0], &aou).unwrap();
/// let got = states_at(&r, 0, &[-5.0, 5.0, 200.0, 400.0], &Alignment::default());
/// // -5 s is before the span, 200 s inside the 390 s gap (> max_gap = 300 s)
/// assert_eq!(got.iter().map(|g| g.0).collect::<Vec<_>>(), vec![1, 3]);
/// assert!((got[0].1.pos[0] - 5.0).abs() < 1e-12);
/// ```
pub fn states_at(r: &Reports, track: usize, times: &[f64], o: &Alignment) -> Vec<(usize, State)> {
    let (s0, s1) = r.span(track);
    let lo = times.partition_point(|&x| x < s0 - o.horizon);
    let hi = times.partition_point(|&x| x <= s1 + o.horizon);
    (lo..hi.max(lo))
        .filter_map(|k| state_at(r, track, times[k], o).map(|s| (k, s)))
        .collect()
}

/// Extrapolation from the end report `e` by `dt` seconds; `prev` is the neighbouring report and
/// `t_e - t_prev` when the two are close enough to give a velocity.
fn extrapolate(
    coords: Coords,
    e: &State,
    prev: Option<(&State, f64)>,
    dt: f64,
    o: &Alignment,
) -> State {
    let grow = o.process_noise * dt.abs();
    match coords {
        Coords::Planar => {
            let v = prev.map_or([0.0, 0.0], |(p, h)| {
                [(e.pos[0] - p.pos[0]) / h, (e.pos[1] - p.pos[1]) / h]
            });
            State {
                pos: [e.pos[0] + v[0] * dt, e.pos[1] + v[1] * dt],
                cov: add_iso(e.cov, grow),
            }
        }
        Coords::Geographic => {
            let v = prev.map_or([0.0, 0.0], |(p, h)| {
                // vector from e to the neighbour in e's frame, reversed
                let (d, _) = geodesy::log_map(e.pos, p.pos);
                [-d[0] / h, -d[1] / h]
            });
            let (pos, rot) = geodesy::offset(e.pos, [v[0] * dt, v[1] * dt]);
            State {
                pos,
                cov: add_iso(geodesy::rotate_cov(e.cov, rot), grow),
            }
        }
    }
}

/// One common instant of two tracks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instant {
    pub time: f64,
    pub a: State,
    pub b: State,
}

/// The common instants of tracks `a` and `b`, sorted by time (see the module docs).
pub fn common_instants(r: &Reports, a: usize, b: usize, o: &Alignment) -> Vec<Instant> {
    let mut out = Vec::new();
    let (ra, rb) = (r.range(a), r.range(b));
    let (ta, tb) = (&r.time[ra.clone()], &r.time[rb.clone()]);
    let (sa0, sa1) = r.span(a);
    let (sb0, sb1) = r.span(b);
    // reports of a inside b's extended span
    let lo = ta.partition_point(|&x| x < sb0 - o.horizon);
    let hi = ta.partition_point(|&x| x <= sb1 + o.horizon);
    for (k, &t) in ta.iter().enumerate().take(hi).skip(lo) {
        if let Some(sb) = state_at(r, b, t, o) {
            out.push(Instant {
                time: t,
                a: r.state[ra.start + k],
                b: sb,
            });
        }
    }
    let lo = tb.partition_point(|&x| x < sa0 - o.horizon);
    let hi = tb.partition_point(|&x| x <= sa1 + o.horizon);
    let before = out.len();
    for (k, &t) in tb.iter().enumerate().take(hi).skip(lo) {
        if ta.binary_search_by(|x| x.total_cmp(&t)).is_ok() {
            continue; // a has a report at t: already an instant
        }
        if let Some(sa) = state_at(r, a, t, o) {
            out.push(Instant {
                time: t,
                a: sa,
                b: r.state[rb.start + k],
            });
        }
    }
    if before > 0 && out.len() > before {
        out.sort_by(|x, y| x.time.total_cmp(&y.time));
    }
    out
}

/// When each track has a state ([`state_at`]): per track, its chains of reports with gaps of at
/// most `max_gap` as closed time intervals (a lone report is a point), sorted and disjoint, and
/// `horizon` seconds beyond its first and last report. Two tracks have a common instant
/// ([`common_instants`]) exactly when [`TimeCover::meet`] says so: the posterior needs this to
/// tell tracks that were compared (and found far apart, so are two objects) from tracks that
/// never existed at a common instant (a DF track with fixes ten minutes apart and an aircraft
/// track of a few minutes between two fixes), which the evidence says nothing about.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TimeCover {
    /// Track `t`'s intervals are `spans[offsets[t]..offsets[t + 1]]`.
    pub offsets: Vec<u32>,
    /// `[first, last]` report time of every chain.
    pub spans: Vec<[f64; 2]>,
    /// Number of reports in every chain.
    pub reports: Vec<u32>,
    /// The extrapolation horizon (s).
    pub horizon: f64,
}

impl TimeCover {
    /// The coverage of every track of `r` under the alignment `o`.
    pub fn of(r: &Reports, o: &Alignment) -> Self {
        let mut offsets = Vec::with_capacity(r.n_tracks + 1);
        let mut spans = Vec::new();
        let mut reports = Vec::new();
        offsets.push(0u32);
        for t in 0..r.n_tracks {
            let ts = r.times(t);
            let start = r.range(t).start;
            let (mut lo, mut first) = (ts[0], 0usize);
            for (i, w) in ts.windows(2).enumerate() {
                if !connected(r, start + i, o) {
                    spans.push([lo, w[0]]);
                    reports.push((i + 1 - first) as u32);
                    lo = w[1];
                    first = i + 1;
                }
            }
            spans.push([lo, ts[ts.len() - 1]]);
            reports.push((ts.len() - first) as u32);
            offsets.push(spans.len() as u32);
        }
        Self {
            offsets,
            spans,
            reports,
            horizon: o.horizon,
        }
    }

    /// A coverage given as arrays (from another process), checked: `offsets` start at 0, never
    /// decrease and end at `spans.len()`, every track's intervals are finite, ordered and
    /// disjoint, and every chain holds at least one report (`reports`, one per chain).
    pub fn from_parts(
        offsets: Vec<u32>,
        spans: Vec<[f64; 2]>,
        reports: Vec<u32>,
        horizon: f64,
    ) -> crate::Result<Self> {
        let bad = |m: String| Err(crate::Error::Invalid(m));
        if reports.len() != spans.len() || reports.contains(&0) {
            return bad(format!(
                "coverage reports must be one count of at least 1 per interval ({}), got {} \
                 counts",
                spans.len(),
                reports.len()
            ));
        }
        if offsets.first() != Some(&0) || *offsets.last().unwrap_or(&0) as usize != spans.len() {
            return bad(format!(
                "coverage offsets must start at 0 and end at {} (the number of intervals)",
                spans.len()
            ));
        }
        if !(horizon.is_finite() && horizon >= 0.0) {
            return bad(format!(
                "coverage horizon must be finite and >= 0, got {horizon}"
            ));
        }
        for (t, w) in offsets.windows(2).enumerate() {
            if w[0] >= w[1] {
                return bad(format!("coverage of track {t}: no interval"));
            }
            let s = &spans[w[0] as usize..w[1] as usize];
            if s.iter()
                .any(|x| !(x[0].is_finite() && x[1].is_finite() && x[0] <= x[1]))
                || s.windows(2).any(|p| p[0][1] >= p[1][0])
            {
                return bad(format!(
                    "coverage of track {t}: intervals must be finite, ordered and disjoint"
                ));
            }
        }
        Ok(Self {
            offsets,
            spans,
            reports,
            horizon,
        })
    }

    /// Number of tracks.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there is no track.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The intervals of track `t`.
    pub fn of_track(&self, t: usize) -> &[[f64; 2]] {
        &self.spans[self.offsets[t] as usize..self.offsets[t + 1] as usize]
    }

    /// The number of reports in each interval of track `t`.
    pub fn reports_of(&self, t: usize) -> &[u32] {
        &self.reports[self.offsets[t] as usize..self.offsets[t + 1] as usize]
    }

    /// First and last report time of track `t`.
    pub fn span(&self, t: usize) -> (f64, f64) {
        let s = self.of_track(t);
        (s[0][0], s[s.len() - 1][1])
    }

    /// Whether tracks `a` and `b` have a common instant: a report of one at which the other has
    /// a state. Two chains that overlap hold one (the later start is a report inside the other
    /// chain); otherwise only the horizon can give one, and then a chain end of one track lies
    /// in the other's horizon window.
    pub fn meet(&self, a: usize, b: usize) -> bool {
        let (sa, sb) = (self.of_track(a), self.of_track(b));
        let (mut i, mut j) = (0, 0);
        while i < sa.len() && j < sb.len() {
            if sa[i][0] <= sb[j][1] && sb[j][0] <= sa[i][1] {
                return true;
            }
            if sa[i][1] < sb[j][1] {
                i += 1;
            } else {
                j += 1;
            }
        }
        if self.horizon > 0.0 {
            let h = self.horizon;
            let ends_in = |s: &[[f64; 2]], lo: f64, hi: f64| {
                // the smallest chain end at or after lo
                let k = s.partition_point(|x| x[1] < lo);
                k < s.len() && (if s[k][0] >= lo { s[k][0] } else { s[k][1] }) <= hi
            };
            for (x, y) in [(sa, sb), (sb, sa)] {
                let (first, last) = (x[0][0], x[x.len() - 1][1]);
                if ends_in(y, first - h, first) || ends_in(y, last, last + h) {
                    return true;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize, v: [f64; 2], dt: f64) -> Vec<[f64; 5]> {
        (0..n)
            .map(|k| {
                let t = k as f64 * dt;
                [10.0 + v[0] * t, -5.0 + v[1] * t, 20.0, 10.0, 0.7]
            })
            .collect()
    }

    #[test]
    fn interpolation_is_exact_for_linear_motion() {
        let aou = line(5, [3.0, -2.0], 10.0);
        let time: Vec<f64> = (0..5).map(|k| k as f64 * 10.0).collect();
        let r = Reports::new(Coords::Planar, 1, &[0; 5], &[0; 5], &time, &aou).unwrap();
        let o = Alignment {
            process_noise: 0.0,
            ..Alignment::default()
        };
        let s = state_at(&r, 0, 23.7, &o).unwrap();
        assert!((s.pos[0] - (10.0 + 3.0 * 23.7)).abs() < 1e-12);
        assert!((s.pos[1] - (-5.0 - 2.0 * 23.7)).abs() < 1e-12);
        for k in 0..3 {
            assert!((s.cov[k] - r.state[0].cov[k]).abs() < 1e-12);
        }
        assert!(state_at(&r, 0, 40.5, &o).is_none());
        let o = Alignment {
            horizon: 5.0,
            process_noise: 1.0,
            ..Alignment::default()
        };
        let s = state_at(&r, 0, 43.0, &o).unwrap();
        assert!((s.pos[0] - (10.0 + 3.0 * 43.0)).abs() < 1e-9);
        assert!((s.cov[0] - r.state[4].cov[0] - 3.0).abs() < 1e-12);
        let s = state_at(&r, 0, 15.0, &o).unwrap();
        assert!((s.cov[2] - r.state[0].cov[2] - 2.5).abs() < 1e-12);
    }

    #[test]
    fn gaps_are_not_interpolated() {
        // reports at 0, 1 and 500 s, 1 m apart: the 499 s gap is longer than max_gap but the
        // track stays still across it (1 m against sqrt(9.21 q 499) = 96 m)
        let at = |xs: [f64; 3], times: [f64; 3]| {
            let aou: Vec<[f64; 5]> = xs.iter().map(|&x| [x, 0.0, 20.0, 10.0, 0.7]).collect();
            Reports::new(Coords::Planar, 1, &[0; 3], &[0; 3], &times, &aou).unwrap()
        };
        let o = Alignment::default();
        let still = at([10.0, 11.0, 12.0], [0.0, 1.0, 500.0]);
        assert!(state_at(&still, 0, 0.5, &o).is_some());
        let s = state_at(&still, 0, 200.0, &o).expect("a still gap is bridged");
        // the chord and the Brownian bridge, q tau (T - tau) / T
        let (tau, gap) = (199.0, 499.0);
        assert!((s.pos[0] - (11.0 + tau / gap)).abs() < 1e-12);
        let bridge = o.process_noise * tau * (gap - tau) / gap;
        assert!((s.cov[0] - still.state[1].cov[0] - bridge).abs() < 1e-9);
        assert!(connected(&still, 1, &o));
        // the same gap without the still rule, and longer than max_still_gap
        let plain = Alignment {
            max_still_gap: 0.0,
            ..o
        };
        assert!(state_at(&still, 0, 200.0, &plain).is_none());
        let long = at([10.0, 11.0, 12.0], [0.0, 1.0, 1000.0]);
        assert!(state_at(&long, 0, 200.0, &o).is_none());
        // moving: 100 m over the gap is beyond the diffusion's 99th percentile (96 m)
        let moving = at([10.0, 11.0, 111.0], [0.0, 1.0, 500.0]);
        assert!(!connected(&moving, 1, &o));
        assert!(state_at(&moving, 0, 200.0, &o).is_none());
        // just inside it, bridged
        let limit = (STILL_QUANTILE * o.process_noise * 499.0).sqrt();
        let slow = at([10.0, 11.0, 11.0 + 0.999 * limit], [0.0, 1.0, 500.0]);
        assert!(state_at(&slow, 0, 200.0, &o).is_some());
        // the time cover follows the same rule: one chain when still, two when moving
        assert_eq!(TimeCover::of(&still, &o).of_track(0).len(), 1);
        assert_eq!(TimeCover::of(&moving, &o).of_track(0).len(), 2);
    }

    /// `TimeCover::meet` against the definition: `common_instants` is not empty.
    #[test]
    fn coverage_meets_exactly_when_there_is_a_common_instant() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        let (mut met, mut apart) = (0, 0);
        for case in 0..3000 {
            let n_tracks = 2;
            let (mut track, mut time) = (Vec::new(), Vec::new());
            for t in 0..n_tracks {
                let n = rng.random_range(1..7);
                let mut x: f64 = rng.random_range(0.0..400.0);
                for _ in 0..n {
                    track.push(t as u32);
                    time.push(x.round());
                    x += [5.0, 60.0, 250.0, 400.0][rng.random_range(0..4)];
                }
            }
            let aou = vec![[0.0, 0.0, 10.0, 10.0, 0.0]; time.len()];
            let r = Reports::new(Coords::Planar, n_tracks, &track, &track, &time, &aou).unwrap();
            let o = Alignment {
                max_gap: 300.0,
                horizon: [0.0, 30.0, 120.0][case % 3],
                process_noise: 1.0,
                // still tracks (every centre at the origin): gaps up to 600 s are bridged
                max_still_gap: 600.0,
            };
            let cov = TimeCover::of(&r, &o);
            // every chain's report count is the number of the track's report times in it
            for t in 0..n_tracks {
                let ts = r.times(t);
                for (c, &n) in cov.of_track(t).iter().zip(cov.reports_of(t)) {
                    let inside = ts.iter().filter(|&&x| c[0] <= x && x <= c[1]).count();
                    assert_eq!(n as usize, inside, "case {case}: {time:?}");
                }
            }
            let truth = !common_instants(&r, 0, 1, &o).is_empty();
            assert_eq!(cov.meet(0, 1), truth, "case {case}: {time:?}");
            assert_eq!(cov.meet(1, 0), truth, "case {case}: {time:?}");
            if truth {
                met += 1;
            } else {
                apart += 1;
            }
        }
        assert!(met > 500 && apart > 500, "{met} {apart}");
    }

    #[test]
    fn coverage_parts_are_checked() {
        let one = |n: usize| vec![1u32; n];
        assert!(TimeCover::from_parts(vec![0, 1], vec![[0.0, 1.0]], one(1), 0.0).is_ok());
        let two = vec![[0.0, 1.0], [1.0, 2.0]];
        assert!(TimeCover::from_parts(vec![0, 2], two, one(2), 0.0).is_err());
        assert!(TimeCover::from_parts(vec![0, 1], vec![[2.0, 1.0]], one(1), 0.0).is_err());
        assert!(TimeCover::from_parts(vec![0, 0], vec![], one(0), 0.0).is_err());
        assert!(TimeCover::from_parts(vec![1], vec![[0.0, 1.0]], one(1), 0.0).is_err());
        assert!(TimeCover::from_parts(vec![0, 1], vec![[0.0, f64::NAN]], one(1), 0.0).is_err());
        assert!(TimeCover::from_parts(vec![0, 1], vec![[0.0, 1.0]], vec![0], 0.0).is_err());
        assert!(TimeCover::from_parts(vec![0, 1], vec![[0.0, 1.0]], one(2), 0.0).is_err());
    }

    #[test]
    fn common_instants_take_both_tracks_once() {
        let aou = line(3, [1.0, 0.0], 1.0);
        let mut all = aou.clone();
        all.extend(aou);
        let time = [0.0, 10.0, 20.0, 5.0, 10.0, 30.0];
        let r = Reports::new(
            Coords::Planar,
            2,
            &[0, 0, 0, 1, 1, 1],
            &[0, 0, 0, 1, 1, 1],
            &time,
            &all,
        )
        .unwrap();
        let got: Vec<f64> = common_instants(&r, 0, 1, &Alignment::default())
            .iter()
            .map(|i| i.time)
            .collect();
        assert_eq!(got, vec![5.0, 10.0, 20.0]);
    }
}
