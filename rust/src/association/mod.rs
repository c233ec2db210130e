//! Track-to-track association at the scale of a maritime picture, from the geofeasibility
//! scores of seed 000.
//!
//! The seed scores "a single, common time instant" and says the per-instant scores of two
//! tracks are combined into a total score, so that operators "make assessments about
//! borderline cases only". [`associate`] does that whole job:
//!
//! 1. [`reports`]: validated reports sorted per track, planar or geographic (WGS84);
//! 2. [`candidates`]: a space-time R-tree over track chunks yields the pairs whose AOUs can
//!    touch, never all `N^2`;
//! 3. [`align`]: per candidate pair, the common instants (interpolation between bracketing
//!    reports, max gap, horizon extrapolation with process noise), scored in the pair's local
//!    frame ([`geodesy`]) by any [`Score`];
//! 4. [`combine`]: per-instant scores into a track-pair score (the calibrated chi-square default
//!    or the seed's means);
//! 5. [`assign`]: classes `match` / `borderline` / `non-match` and the grouping of duplicate
//!    tracks into objects under the same-source/overlapping-time constraint.
//!
//! Candidate pairs are scored on rayon in chunks with an interrupt check between chunks; the
//! Monte-Carlo score draws its stream from (seed, track a, track b, instant), so results do not
//! depend on the thread count or the candidate order.

pub mod align;
pub mod assign;
pub mod candidates;
pub mod combine;
pub mod geodesy;
pub mod reports;

use rayon::prelude::*;

use crate::ellipse::{Ellipse, Gaussian};
use crate::error::{Error, Result};
use crate::score::glr::{mahalanobis2, Frame};
use crate::score::{Interrupt, Score};

pub use align::Alignment;
pub use assign::Class;
pub use candidates::IndexOptions;
pub use combine::Combine;
pub use reports::{Coords, Reports, State};

/// Options of [`associate`].
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Per-instant score.
    pub score: Score,
    /// Combination rule.
    pub combine: Combine,
    /// Below: `non-match`.
    pub lower: f64,
    /// At or above: `match` candidate (then subject to the grouping constraint).
    pub upper: f64,
    /// Time alignment.
    pub align: Alignment,
    /// Error correlation time of the effective number of instants (s).
    pub correlation_time: f64,
    /// Candidate index.
    pub index: IndexOptions,
    /// Log-likelihood margin by which a match must beat every mutually exclusive alternative
    /// ([`rival_margins`]); `None` (the default) does not check.
    pub margin: Option<f64>,
    /// Covariance inflation of the chi-square rules: `None` estimates one factor per pair of
    /// sources from the data ([`combine::estimate_inflation`]); `Some(c)` divides every summed
    /// distance by `c` (1: the AOUs as given).
    pub inflation: Option<f64>,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            score: Score::Glr(crate::score::Glr::default()),
            combine: Combine::Chi2,
            lower: 0.5,
            upper: combine::default_upper(),
            align: Alignment::default(),
            correlation_time: Self::DEFAULT_CORRELATION_TIME,
            index: IndexOptions::default(),
            inflation: None,
            margin: None,
        }
    }
}

impl Options {
    /// Default error correlation time (s): a tracker smooths over some ten scans of a 2-6 s
    /// surface radar, and states interpolated within one AIS gap share their two reports.
    pub const DEFAULT_CORRELATION_TIME: f64 = 60.0;

    /// Checks the options.
    pub fn validated(self) -> Result<Self> {
        self.align.validated()?;
        let bad = |name: &'static str, reason: String| Err(Error::InvalidOption { name, reason });
        if !(0.0..=1.0).contains(&self.lower) {
            return bad("lower", format!("must be in [0, 1], got {}", self.lower));
        }
        if !(self.lower..=1.0).contains(&self.upper) {
            return bad(
                "upper",
                format!(
                    "must be in [lower, 1] = [{}, 1], got {}",
                    self.lower, self.upper
                ),
            );
        }
        if self.correlation_time.is_nan() || self.correlation_time < 0.0 {
            return bad(
                "correlation_time",
                format!("must be >= 0, got {}", self.correlation_time),
            );
        }
        if self.margin.is_some_and(f64::is_nan) {
            return bad("margin", "must not be NaN".into());
        }
        if let Some(c) = self.inflation {
            if !(c.is_finite() && c > 0.0) {
                return bad("inflation", format!("must be finite and > 0, got {c}"));
            }
        }
        if self.index.window.is_nan() || self.index.window < 0.0 {
            return bad("window", format!("must be >= 0, got {}", self.index.window));
        }
        Ok(self)
    }
}

/// The sparse result of [`associate`]: one entry per candidate pair with at least one common
/// instant, sorted by `(a, b)`, `a < b`, and the object of every track.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Association {
    pub a: Vec<u32>,
    pub b: Vec<u32>,
    pub score: Vec<f64>,
    pub instants: Vec<u32>,
    pub class: Vec<Class>,
    pub object: Vec<u32>,
    /// Number of candidate pairs from the index (including those without common instants).
    pub candidates: usize,
    /// Covariance inflation used per pair of sources `(source_lo, source_hi, c)` (chi-square
    /// rules only).
    pub inflation: Vec<(u32, u32, f64)>,
}

fn mix(a: u32, b: u32, k: usize) -> u64 {
    // splitmix64 of the pair and instant: a stream index independent of the candidate order
    let mut z = ((a as u64) << 32 | b as u64) ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The two AOUs of one instant in the pair's local frame (planar: as they are; geographic: the
/// AEQD frame centred on the first, see [`geodesy`]).
pub fn local_pair(coords: Coords, a: &State, b: &State) -> (Ellipse, Ellipse) {
    match coords {
        Coords::Planar => (
            Gaussian::new(a.pos, a.cov).to_ellipse(),
            Gaussian::new(b.pos, b.cov).to_ellipse(),
        ),
        Coords::Geographic => {
            let (d, rot) = geodesy::log_map(a.pos, b.pos);
            (
                Gaussian::new([0.0, 0.0], a.cov).to_ellipse(),
                Gaussian::new(d, geodesy::rotate_cov(b.cov, rot)).to_ellipse(),
            )
        }
    }
}

/// Per-instant scores, squared distances and times of one pair.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PairInstants {
    pub time: Vec<f64>,
    pub g: Vec<f64>,
    pub m: Vec<f64>,
}

/// Aligns and scores the instants of tracks `a`, `b`.
pub fn pair_instants(r: &Reports, a: usize, b: usize, o: &Options) -> PairInstants {
    let inst = align::common_instants(r, a, b, &o.align);
    let mut out = PairInstants {
        time: Vec::with_capacity(inst.len()),
        g: Vec::with_capacity(inst.len()),
        m: Vec::with_capacity(inst.len()),
    };
    let plain_glr = matches!(o.score, Score::Glr(g) if !g.threshold);
    for (k, i) in inst.iter().enumerate() {
        let (ea, eb) = local_pair(r.coords, &i.a, &i.b);
        let (g, m) = if plain_glr {
            let m = mahalanobis2(&Frame::new(&ea), &Frame::new(&eb));
            ((-0.5 * m).exp(), m)
        } else {
            let g = o.score.one(&ea, &eb, mix(r.stream[a], r.stream[b], k));
            (
                g,
                if g > 0.0 {
                    -2.0 * g.ln()
                } else {
                    f64::INFINITY
                },
            )
        };
        out.time.push(i.time);
        out.g.push(g);
        out.m.push(m.max(0.0));
    }
    out
}

/// The summary of one scored pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairStat {
    /// Combined score (`NaN` without common instants).
    pub score: f64,
    /// Number of common instants.
    pub instants: u32,
    /// Sum of the per-instant squared distances.
    pub sum_m: f64,
    /// Effective number of instants (see [`combine::effective_instants`]).
    pub k_eff: f64,
}

/// Aligns, scores and combines tracks `a`, `b`.
pub fn pair_stat(r: &Reports, a: usize, b: usize, o: &Options) -> PairStat {
    let p = pair_instants(r, a, b, o);
    let k_eff = combine::effective_instants(&p.time, o.correlation_time);
    let sum_m: f64 = p.m.iter().sum();
    let k = p.g.len();
    let score = if k == 0 {
        f64::NAN
    } else if o.combine.is_chi2() {
        o.combine
            .from_summary(sum_m / o.inflation.unwrap_or(1.0), k as f64, k_eff)
    } else {
        o.combine.combine(&p.g, &p.m, &p.time, o.correlation_time)
    };
    PairStat {
        score,
        instants: k as u32,
        sum_m,
        k_eff,
    }
}

/// The combined score and the number of instants of tracks `a`, `b` (`NaN`, 0 without common
/// instants), with the inflation of `o` (1 when it is to be estimated).
pub fn score_pair(r: &Reports, a: usize, b: usize, o: &Options) -> (f64, u32) {
    let s = pair_stat(r, a, b, o);
    (s.score, s.instants)
}

/// Candidate pairs of `r` (see [`candidates`]).
pub fn candidate_pairs(r: &Reports, o: &Options) -> Vec<(u32, u32)> {
    let chunks = candidates::chunks(r, &o.align, &o.index);
    candidates::candidate_pairs(r, &chunks, &o.index)
}

/// Scores `pairs` in parallel, chunk by chunk with `interrupt` between chunks.
pub fn score_pairs(
    r: &Reports,
    pairs: &[(u32, u32)],
    o: &Options,
    interrupt: Interrupt<'_>,
) -> Result<Vec<PairStat>> {
    let empty = PairStat {
        score: f64::NAN,
        instants: 0,
        sum_m: 0.0,
        k_eff: 0.0,
    };
    let mut out = vec![empty; pairs.len()];
    let chunk = 1 << 14;
    for (c, block) in out.chunks_mut(chunk).enumerate() {
        if interrupt() {
            return Err(Error::Interrupted);
        }
        let base = c * chunk;
        block.par_iter_mut().enumerate().for_each(|(k, slot)| {
            let (a, b) = pairs[base + k];
            *slot = pair_stat(r, a as usize, b as usize, o);
        });
    }
    Ok(out)
}

/// The whole pipeline: candidates, alignment, scores, combination, triage and grouping.
pub fn associate(r: &Reports, o: &Options, interrupt: Interrupt<'_>) -> Result<Association> {
    let o = o.clone().validated()?;
    let pairs = candidate_pairs(r, &o);
    let scored = score_pairs(r, &pairs, &o, interrupt)?;
    let mut res = Association {
        candidates: pairs.len(),
        ..Association::default()
    };
    let mut kept = Vec::with_capacity(pairs.len());
    let mut stats = Vec::with_capacity(pairs.len());
    for (&(a, b), st) in pairs.iter().zip(&scored) {
        if st.instants == 0 {
            continue;
        }
        res.a.push(a);
        res.b.push(b);
        res.score.push(st.score);
        res.instants.push(st.instants);
        kept.push((a, b));
        stats.push((st.sum_m, st.instants as f64, st.k_eff));
    }
    let mut scale = vec![1.0; kept.len()];
    if o.combine.is_chi2() {
        res.inflation = match o.inflation {
            Some(c) => {
                let mut groups: Vec<(u32, u32, f64)> = kept
                    .iter()
                    .map(|&(a, b)| {
                        let (sa, sb) = (r.source[a as usize], r.source[b as usize]);
                        (sa.min(sb), sa.max(sb), c)
                    })
                    .collect();
                groups.sort_by_key(|x| (x.0, x.1));
                groups.dedup_by(|x, y| (x.0, x.1) == (y.0, y.1));
                scale.iter_mut().for_each(|s| *s = c);
                groups
            }
            None => {
                let inflation = combine::estimate_inflation(&kept, &r.source, &stats);
                for (i, &(a, b)) in kept.iter().enumerate() {
                    let (sa, sb) = (r.source[a as usize], r.source[b as usize]);
                    let key = (sa.min(sb), sa.max(sb));
                    let c = inflation
                        .binary_search_by(|x| (x.0, x.1).cmp(&key))
                        .map_or(1.0, |j| inflation[j].2);
                    let (sum_m, k, k_eff) = stats[i];
                    res.score[i] = o.combine.from_summary(sum_m / c, k, k_eff);
                    scale[i] = c;
                }
                inflation
            }
        };
    }
    let tracks: Vec<assign::TrackInfo> = (0..r.n_tracks)
        .map(|t| {
            let (start, end) = r.span(t);
            let (area_min, area_max) = r.area_range(t);
            assign::TrackInfo {
                source: r.source[t],
                start,
                end,
                spread: assign::TrackInfo::spread_of(area_min, area_max),
            }
        })
        .collect();
    let unclear: Vec<bool> = match o.margin {
        Some(margin) => rival_margins(r, &tracks, &kept, &res.score, &scale, &o)
            .iter()
            .map(|&m| m < margin)
            .collect(),
        None => Vec::new(),
    };
    let (class, object) =
        assign::group_unambiguous(&tracks, &kept, &res.score, &unclear, o.lower, o.upper);
    res.class = class;
    res.object = object;
    Ok(res)
}

/// The log-likelihood margin of every match candidate over its rivals ([`assign::rivals`]: the
/// shared track `t` with another track of the partner's source overlapping the partner in
/// time), on the instants the two pairs share; `+inf` without rivals. With `Options::margin`,
/// a candidate whose margin is below it is ambiguous and becomes `borderline`. With per-instant squared
/// distances `m_P`, `m_Q` (each divided by its pair's covariance inflation) at the `n` common
/// times, the GLR of eq. 71 gives `LLR = 0.5 sum (m_Q - m_P)`, discounted to `k_eff / n` of it
/// for correlated instants ([`combine::effective_instants`] of the common times). A rival
/// without common instants is not counted. The margin is the smallest LLR over the rivals.
pub fn rival_margins(
    r: &Reports,
    tracks: &[assign::TrackInfo],
    pairs: &[(u32, u32)],
    scores: &[f64],
    scale: &[f64],
    o: &Options,
) -> Vec<f64> {
    let rivals = assign::rivals(tracks, pairs, scores, o.lower, o.upper);
    let other = |k: usize, t: u32| {
        let (a, b) = pairs[k];
        if a == t {
            b
        } else {
            a
        }
    };
    (0..pairs.len())
        .into_par_iter()
        .map(|p| {
            rivals[p].iter().fold(f64::INFINITY, |acc, &(q, t)| {
                let ip = pair_instants(r, t as usize, other(p, t) as usize, o);
                let iq = pair_instants(r, t as usize, other(q, t) as usize, o);
                let (mut i, mut j) = (0, 0);
                let mut times = Vec::new();
                let mut diff = 0.0;
                while i < ip.time.len() && j < iq.time.len() {
                    match ip.time[i].total_cmp(&iq.time[j]) {
                        std::cmp::Ordering::Less => i += 1,
                        std::cmp::Ordering::Greater => j += 1,
                        std::cmp::Ordering::Equal => {
                            diff += iq.m[j] / scale[q] - ip.m[i] / scale[p];
                            times.push(ip.time[i]);
                            i += 1;
                            j += 1;
                        }
                    }
                }
                if times.is_empty() {
                    return acc;
                }
                let k_eff = combine::effective_instants(&times, o.correlation_time);
                let llr = 0.5 * diff * k_eff / times.len() as f64;
                if llr.is_nan() {
                    f64::NEG_INFINITY
                } else {
                    acc.min(llr)
                }
            })
        })
        .collect()
}
