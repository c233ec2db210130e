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
pub mod evidence;
pub mod geodesy;
pub mod posterior;
pub mod reports;
pub mod schema;

use rayon::prelude::*;

use crate::ellipse::{Ellipse, Gaussian};
use crate::error::{Error, Result};
use crate::score::glr::{mahalanobis2, Frame};
use crate::score::{Interrupt, Score};

pub use align::Alignment;
pub use assign::Class;
pub use candidates::IndexOptions;
pub use combine::Combine;
pub use evidence::{Model, Picture};
pub use posterior::{Decision, Inference, Posterior};
pub use reports::{Coords, Reports, State};

/// Options of [`associate`].
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Per-instant score (the `score` column; the posterior uses the Gaussian densities).
    pub score: Score,
    /// Combination rule of the `score` column.
    pub combine: Combine,
    /// `match` when `P(same object) >= p_match`.
    pub p_match: f64,
    /// `non-match` when `P(same object) <= p_reject`.
    pub p_reject: f64,
    /// Time alignment.
    pub align: Alignment,
    /// Error correlation time of the effective number of instants (s).
    pub correlation_time: f64,
    /// Candidate index.
    pub index: IndexOptions,
    /// Covariance inflation: `None` estimates one factor per pair of sources from the data
    /// ([`combine::estimate_inflation`]); `Some(c)` multiplies every covariance by `c` (1: the
    /// AOUs as given).
    pub inflation: Option<f64>,
    /// Parameters of the pair evidence.
    pub model: Model,
    /// Settings of the inference.
    pub inference: Inference,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            score: Score::Glr(crate::score::Glr::default()),
            combine: Combine::Chi2,
            p_match: 0.99,
            p_reject: 0.01,
            align: Alignment::default(),
            correlation_time: Self::DEFAULT_CORRELATION_TIME,
            index: IndexOptions::default(),
            inflation: None,
            model: Model::default(),
            inference: Inference::default(),
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
        if !(self.p_reject > 0.0 && self.p_reject < 0.5) {
            return bad(
                "p_reject",
                format!("must be in (0, 0.5), got {}", self.p_reject),
            );
        }
        if !(self.p_match > 0.5 && self.p_match < 1.0) {
            return bad(
                "p_match",
                format!("must be in (0.5, 1), got {}", self.p_match),
            );
        }
        if self.correlation_time.is_nan() || self.correlation_time < 0.0 {
            return bad(
                "correlation_time",
                format!("must be >= 0, got {}", self.correlation_time),
            );
        }
        let model = self.model.clone().validated()?;
        let inference = self.inference.validated()?;
        if let Some(c) = self.inflation {
            if !(c.is_finite() && c > 0.0) {
                return bad("inflation", format!("must be finite and > 0, got {c}"));
            }
        }
        if self.index.window.is_nan() || self.index.window < 0.0 {
            return bad("window", format!("must be >= 0, got {}", self.index.window));
        }
        Ok(Self {
            model,
            inference,
            ..self
        })
    }
}

/// The sparse result of [`associate`]: one entry per candidate pair with at least one common
/// instant, sorted by `(a, b)`, `a < b`, and the object of every track.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Association {
    pub a: Vec<u32>,
    pub b: Vec<u32>,
    /// The combined per-instant score (continuity with the seed's scores; not the class).
    pub score: Vec<f64>,
    pub instants: Vec<u32>,
    /// The pair's log-likelihood ratio "one object" against "two" ([`evidence`]).
    pub llr: Vec<f64>,
    /// `P(same object)`.
    pub p_same: Vec<f64>,
    /// Standard error of `p_same` (0 where computed exactly).
    pub std_error: Vec<f64>,
    pub class: Vec<Class>,
    /// Review order of the `borderline` pairs (1 = first), 0 for the others.
    pub review_rank: Vec<u32>,
    /// Expected undecided probability mass a decision on the pair settles.
    pub review_gain: Vec<f64>,
    /// How many other pairs of its component an answer "same" / "different" takes out of the
    /// borderline band.
    pub settles: Vec<(u32, u32)>,
    /// Component of the candidate graph of each pair (`u32::MAX`: left out, `p_same = 0`).
    pub component: Vec<u32>,
    /// Per track: `P(no partner)`.
    pub p_alone: Vec<f64>,
    pub object: Vec<u32>,
    /// Number of candidate pairs from the index (including those without common instants).
    pub candidates: usize,
    /// Covariance inflation used per pair of sources `(source_lo, source_hi, c)`.
    pub inflation: Vec<(u32, u32, f64)>,
    /// Per component of the candidate graph: size, method and error of the inference.
    pub components: Vec<posterior::ComponentInfo>,
    /// Coverage `P_s` estimated per source.
    pub coverage: Vec<f64>,
    /// Per source, the share `rho_s` of its reports that its AOUs, wider than the most complete
    /// source's, leave in that source's cells, where its false tracks are counted
    /// ([`evidence::Picture::overlap`]).
    pub false_overlap: Vec<f64>,
    /// Odds `g_s` of a further track of a source in one object, estimated per source
    /// ([`evidence::track_breaks`]).
    pub track_breaks: Vec<f64>,
    /// What the posterior was computed from, so that it can be recomputed under operator
    /// decisions without scoring again ([`finish`]): the tracks, the summaries of the pairs
    /// and the picture counts.
    pub tracks: Vec<posterior::Track>,
    /// When each track has a state ([`align::TimeCover`]).
    pub time_cover: align::TimeCover,
    pub stats: Vec<PairStat>,
    pub counts: evidence::Counts,
    /// Every component's posterior, for recomputing under decisions ([`finish`]'s `memo`).
    pub memo: posterior::Memo,
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
    let (d, cb) = local_offset(coords, a, b);
    (
        Gaussian::new([0.0, 0.0], a.cov).to_ellipse(),
        Gaussian::new(d, cb).to_ellipse(),
    )
}

/// The centre of `b` relative to `a` and `b`'s covariance, in the pair's local frame.
fn local_offset(coords: Coords, a: &State, b: &State) -> ([f64; 2], [f64; 3]) {
    match coords {
        Coords::Planar => ([b.pos[0] - a.pos[0], b.pos[1] - a.pos[1]], b.cov),
        Coords::Geographic => {
            let (d, rot) = geodesy::log_map(a.pos, b.pos);
            (d, geodesy::rotate_cov(b.cov, rot))
        }
    }
}

/// Per-instant scores, squared distances and times of one pair.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PairInstants {
    pub time: Vec<f64>,
    pub g: Vec<f64>,
    pub m: Vec<f64>,
    /// The Gaussian view of every instant: `d^T S^-1 d`, `ln det S`, `tr S / det S`, `1 / det S`
    /// with `S = R_a + R_b` (before inflation).
    pub gauss: Vec<[f64; 4]>,
    /// Where the density of objects is looked up: the mean position of the reports of the
    /// less precise track (larger covariance trace at the middle instant; `a` on a tie), the
    /// same point for every pair of that track ([`centroid`]).
    pub pos: [f64; 2],
    /// Track `a`'s share of the summed covariance traces `sum tr R_a / sum (tr R_a + tr R_b)`.
    pub share_a: f64,
}

/// `[d^T S^-1 d, ln det S, tr S / det S, 1 / det S]` of one instant, `S = R_a + R_b` in the
/// pair's local frame (`NaN`-free: a singular `S` gives `+inf` distances).
pub fn gaussian_instant(coords: Coords, a: &State, b: &State) -> [f64; 4] {
    let (d, cb) = local_offset(coords, a, b);
    gaussian_of(a.cov, d, cb)
}

fn gaussian_of(ca: [f64; 3], d: [f64; 2], cb: [f64; 3]) -> [f64; 4] {
    let (sxx, sxy, syy) = (ca[0] + cb[0], ca[1] + cb[1], ca[2] + cb[2]);
    let det = sxx * syy - sxy * sxy;
    if det.is_nan() || det <= 0.0 {
        return [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::INFINITY,
        ];
    }
    let m = (syy * d[0] * d[0] - 2.0 * sxy * d[0] * d[1] + sxx * d[1] * d[1]) / det;
    [m.max(0.0), det.ln(), (sxx + syy) / det, 1.0 / det]
}

/// The mean position of the reports of `track`: `(x, y)` metres, or `(lat, lon)` degrees with
/// the longitudes taken about the first report's (a track across the antimeridian averages to
/// a point on it, not to the far side of the Earth), in `[-180, 180)`.
///
/// The density of objects of a pair is read here ([`PairInstants::pos`]). Reading it where the
/// track is at the pair's middle instant made it differ between the pairs of one track: an HF
/// DF track's position at an instant is one fix, anywhere in a 36 km ellipse, and the density
/// at two fixes differs severalfold, so the ships of one harbour got `p_same` three times
/// apart that their fits could not tell apart.
pub fn centroid(r: &Reports, track: usize) -> [f64; 2] {
    let st = &r.state[r.range(track)];
    let Some(first) = st.first() else {
        return [0.0; 2];
    };
    let n = st.len() as f64;
    match r.coords {
        Coords::Planar => [
            st.iter().map(|s| s.pos[0]).sum::<f64>() / n,
            st.iter().map(|s| s.pos[1]).sum::<f64>() / n,
        ],
        Coords::Geographic => {
            let lon0 = first.pos[1];
            let lat = st.iter().map(|s| s.pos[0]).sum::<f64>() / n;
            let dlon = st
                .iter()
                .map(|s| geodesy::wrap_lon(s.pos[1] - lon0))
                .sum::<f64>()
                / n;
            [lat, geodesy::wrap_lon(lon0 + dlon)]
        }
    }
}

/// Aligns and scores the instants of tracks `a`, `b`.
pub fn pair_instants(r: &Reports, a: usize, b: usize, o: &Options) -> PairInstants {
    let inst = align::common_instants(r, a, b, &o.align);
    let mut out = PairInstants {
        time: Vec::with_capacity(inst.len()),
        g: Vec::with_capacity(inst.len()),
        m: Vec::with_capacity(inst.len()),
        gauss: Vec::with_capacity(inst.len()),
        // where the less precise track is: under "two objects" it is the object whose
        // position the picture's density accounts for (whichever of the two is named first);
        // read at a point of that track alone, so that its pairs differ only in their fits
        pos: inst.get(inst.len() / 2).map_or([0.0; 2], |i| {
            if i.a.cov[0] + i.a.cov[2] >= i.b.cov[0] + i.b.cov[2] {
                centroid(r, a)
            } else {
                centroid(r, b)
            }
        }),
        share_a: 0.5,
    };
    let (mut tr_a, mut tr_b) = (0.0, 0.0);
    let plain_glr = matches!(o.score, Score::Glr(g) if !g.threshold);
    for (k, i) in inst.iter().enumerate() {
        let (d, cb) = local_offset(r.coords, &i.a, &i.b);
        let (ea, eb) = (
            Gaussian::new([0.0, 0.0], i.a.cov).to_ellipse(),
            Gaussian::new(d, cb).to_ellipse(),
        );
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
        out.gauss.push(gaussian_of(i.a.cov, d, cb));
        tr_a += i.a.cov[0] + i.a.cov[2];
        tr_b += i.b.cov[0] + i.b.cov[2];
    }
    if tr_a + tr_b > 0.0 {
        out.share_a = tr_a / (tr_a + tr_b);
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
    /// Effective number of instants of the plain sum (see [`combine::pair_instant_counts`]).
    pub k_eff: f64,
    /// The evidence's means over the instants, each instant weighed by
    /// [`combine::pair_instant_counts`]: of the Gaussian squared distances `d^T S^-1 d` (the
    /// plain GLR's `m`),
    pub mean_mg: f64,
    /// of `ln det S`,
    pub mean_ln_det: f64,
    /// of `tr S / det S`
    pub mean_trace_over_det: f64,
    /// and of `1 / det S`.
    pub mean_inv_det: f64,
    /// The independent instants the weighted means are worth.
    pub evidence_k_eff: f64,
    /// Position of the less precise track at the middle instant (density look-up).
    pub pos: [f64; 2],
}

impl PairStat {
    /// The summary of a pair without common instants.
    pub const EMPTY: Self = Self {
        score: f64::NAN,
        instants: 0,
        sum_m: 0.0,
        k_eff: 0.0,
        mean_mg: 0.0,
        mean_ln_det: 0.0,
        mean_trace_over_det: 0.0,
        mean_inv_det: 0.0,
        evidence_k_eff: 0.0,
        pos: [0.0; 2],
    };
}

/// Aligns, scores and combines tracks `a`, `b`.
pub fn pair_stat(r: &Reports, a: usize, b: usize, o: &Options) -> PairStat {
    let p = pair_instants(r, a, b, o);
    let counts = combine::pair_instant_counts(
        &p.time,
        r.times(a),
        r.times(b),
        p.share_a,
        o.correlation_time,
    );
    let k_eff = counts.k_eff;
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
    let weights = &counts.weights;
    let total: f64 = weights.iter().sum();
    let mean = |f: usize| -> f64 {
        if k == 0 {
            0.0
        } else {
            p.gauss
                .iter()
                .zip(weights)
                .map(|(x, w)| w * x[f])
                .sum::<f64>()
                / total
        }
    };
    PairStat {
        score,
        instants: k as u32,
        sum_m,
        k_eff,
        mean_mg: mean(0),
        mean_ln_det: mean(1),
        mean_trace_over_det: mean(2),
        mean_inv_det: mean(3),
        evidence_k_eff: counts.evidence_k_eff,
        pos: p.pos,
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
    let mut out = vec![PairStat::EMPTY; pairs.len()];
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

/// The whole pipeline: candidates, alignment, scores, combination, the joint posterior,
/// triage and grouping. `decisions` are operator decisions (hard constraints).
pub fn associate(
    r: &Reports,
    o: &Options,
    decisions: &[Decision],
    interrupt: Interrupt<'_>,
) -> Result<Association> {
    let o = o.clone().validated()?;
    let pairs = candidate_pairs(r, &o);
    let scored = score_pairs(r, &pairs, &o, interrupt)?;
    let kept: Vec<((u32, u32), PairStat)> = pairs
        .iter()
        .zip(&scored)
        .filter(|(_, st)| st.instants > 0)
        .map(|(&p, st)| (p, *st))
        .collect();
    let counts = evidence::Counts::of(r, o.model.cell, o.align.max_gap);
    let picture = Picture::from_counts(counts.clone(), &o.model);
    let mut res = finish(
        &track_summaries(r),
        &align::TimeCover::of(r, &o.align),
        &picture,
        &o,
        &kept,
        decisions,
        None,
        interrupt,
    )?;
    res.candidates = pairs.len();
    res.counts = counts;
    Ok(res)
}

/// What the posterior needs of every track of `r`: source, time span and typical AOU size.
pub fn track_summaries(r: &Reports) -> Vec<posterior::Track> {
    (0..r.n_tracks)
        .map(|t| {
            let (start, end) = r.span(t);
            let (area_min, area_max) = r.area_range(t);
            posterior::Track {
                source: r.source[t],
                start,
                end,
                spread: posterior::Track::spread_of(area_min, area_max),
                further: 0.0,
            }
        })
        .collect()
}

/// The review order `order` (pairs by decreasing value) rearranged so that an operator working
/// down the list spends no answer on a question an earlier one settles. `object` is each
/// track's object (the tracks the `match` pairs and decisions "same" join).
///
/// - One question per pair of objects: the pairs that join the same two objects as a pair
///   earlier in the order (an HF DF fix with a ship's AIS, radar and aircraft tracks, which the
///   matches hold together at `p_same >= p_match`) ask the question that pair asks, and
///   whatever its answer, it settles them; they go after every pair that asks something else.
/// - Rounds: each round takes, in order, the pairs none of whose objects an earlier pair of
///   the round holds, and defers the others to the next round. An answer about an object moves
///   the probabilities of every other pair of it (confirming one of its pairs settles its
///   rivals), so a batch of answers taken between two re-associations asks about as many
///   objects as it can; with re-association after every answer only the first pair matters,
///   and it is the most valuable one either way.
fn one_question_per_object(order: Vec<usize>, pairs: &[(u32, u32)], object: &[u32]) -> Vec<usize> {
    let key = |k: usize| {
        let (a, b) = (object[pairs[k].0 as usize], object[pairs[k].1 as usize]);
        (a.min(b), a.max(b))
    };
    let mut asked = std::collections::HashSet::with_capacity(order.len());
    let (first, repeat): (Vec<usize>, Vec<usize>) =
        order.into_iter().partition(|&k| asked.insert(key(k)));
    let mut out = Vec::with_capacity(first.len() + repeat.len());
    let mut round = vec![u32::MAX; object.len()];
    let mut r = 0u32;
    for mut pending in [first, repeat] {
        while !pending.is_empty() {
            let mut later = Vec::new();
            for k in pending {
                let (a, b) = key(k);
                let (a, b) = (a as usize, b as usize);
                if round[a] == r || round[b] == r {
                    later.push(k);
                } else {
                    round[a] = r;
                    round[b] = r;
                    out.push(k);
                }
            }
            pending = later;
            r += 1;
        }
    }
    out
}

/// The steps after scoring, shared by [`associate`] and the distributed path: covariance
/// inflation, scores, pair evidence, the posterior per component, triage, review order and
/// objects. `tracks` describes every track ([`track_summaries`]), `picture` the picture's
/// density and coverage, `kept` the scored pairs with at least one common instant, sorted by
/// `(a, b)`; `o` must be validated. The components found unchanged in `memo` (an earlier
/// result's [`Association::memo`], as when an operator's decisions are added) are taken from it.
#[allow(clippy::too_many_arguments)]
pub fn finish(
    tracks: &[posterior::Track],
    cover: &align::TimeCover,
    picture: &Picture,
    o: &Options,
    kept: &[((u32, u32), PairStat)],
    decisions: &[Decision],
    memo: Option<&posterior::Memo>,
    interrupt: Interrupt<'_>,
) -> Result<Association> {
    let mut res = Association::default();
    let pairs: Vec<(u32, u32)> = kept.iter().map(|x| x.0).collect();
    let stats: Vec<(f64, f64, f64)> = kept
        .iter()
        .map(|(_, st)| (st.sum_m, st.instants as f64, st.k_eff))
        .collect();
    let n = tracks.len();
    if let Some(((a, b), _)) = kept
        .iter()
        .find(|((a, b), _)| *a as usize >= n || *b as usize >= n || a == b)
    {
        return Err(Error::Invalid(format!(
            "pair ({a}, {b}): tracks must be two distinct indices in 0..{n}"
        )));
    }
    let track_source: Vec<u32> = tracks.iter().map(|t| t.source).collect();
    let key = |a: u32, b: u32| {
        let (sa, sb) = (track_source[a as usize], track_source[b as usize]);
        (sa.min(sb), sa.max(sb))
    };
    res.inflation = match o.inflation {
        Some(c) => {
            let mut groups: Vec<(u32, u32, f64)> = pairs
                .iter()
                .map(|&(a, b)| {
                    let (lo, hi) = key(a, b);
                    (lo, hi, c)
                })
                .collect();
            groups.sort_by_key(|x| (x.0, x.1));
            groups.dedup_by(|x, y| (x.0, x.1) == (y.0, y.1));
            groups
        }
        None => combine::estimate_inflation(&pairs, &track_source, &stats),
    };
    let scale: Vec<f64> = pairs
        .iter()
        .map(|&(a, b)| {
            let k = key(a, b);
            res.inflation
                .binary_search_by(|x| (x.0, x.1).cmp(&k))
                .map_or(1.0, |j| res.inflation[j].2)
        })
        .collect();
    for (i, (&(a, b), st)) in pairs.iter().zip(kept.iter().map(|x| &x.1)).enumerate() {
        res.a.push(a);
        res.b.push(b);
        res.instants.push(st.instants);
        res.score.push(if o.combine.is_chi2() {
            o.combine
                .from_summary(st.sum_m / scale[i], st.instants as f64, st.k_eff)
        } else {
            st.score
        });
    }
    if interrupt() {
        return Err(Error::Interrupted);
    }
    res.coverage = picture.coverage.clone();
    res.false_overlap = picture.overlap.clone();
    let evidence: Vec<evidence::PairEvidence> = kept
        .par_iter()
        .zip(scale.par_iter())
        .map(|((p, st), &c)| {
            evidence::log_likelihood_ratio(
                st,
                c,
                (track_source[p.0 as usize], track_source[p.1 as usize]),
                picture,
                &o.model,
                o.align.process_noise,
                o.correlation_time,
            )
        })
        .collect();
    res.llr = evidence.iter().map(|e| e.llr).collect();
    // an object's further tracks of one source: odds g_s of a break against the (1 - P_s) / P_s
    // the merge of two objects both seen by s assumed in L (see `evidence::track_breaks`)
    res.track_breaks = evidence::track_breaks(
        &track_source,
        &picture.coverage,
        picture.reference,
        &o.model,
    );
    let further: Vec<f64> = res
        .track_breaks
        .iter()
        .zip(&picture.coverage)
        .map(|(g, p)| g.ln() + ((1.0 - p) / p).ln())
        .collect();
    let weighed: Vec<posterior::Track> = tracks
        .iter()
        .map(|t| posterior::Track {
            further: further.get(t.source as usize).copied().unwrap_or(0.0),
            ..*t
        })
        .collect();
    let post = posterior::posterior(
        &weighed,
        cover,
        &pairs,
        &evidence,
        decisions,
        &o.inference,
        (o.p_reject, o.p_match),
        memo,
    )?;
    if interrupt() {
        return Err(Error::Interrupted);
    }
    let (object, joined) = posterior::objects(tracks, &pairs, &post.p_same, decisions, o.p_match);
    res.class = (0..pairs.len())
        .map(|k| {
            let p = post.p_same[k];
            if p >= o.p_match && joined[k] {
                Class::Match
            } else if p <= o.p_reject {
                Class::NonMatch
            } else {
                Class::Borderline
            }
        })
        .collect();
    let mut order: Vec<usize> = (0..pairs.len())
        .filter(|&k| res.class[k] == Class::Borderline)
        .collect();
    order.sort_by(|&i, &j| {
        post.gain[j]
            .total_cmp(&post.gain[i])
            .then(
                (post.p_same[i] - 0.5)
                    .abs()
                    .total_cmp(&(post.p_same[j] - 0.5).abs()),
            )
            .then(pairs[i].cmp(&pairs[j]))
    });
    let order = one_question_per_object(order, &pairs, &object);
    res.review_rank = vec![0; pairs.len()];
    for (rank, &k) in order.iter().enumerate() {
        res.review_rank[k] = rank as u32 + 1;
    }
    res.p_same = post.p_same;
    res.std_error = post.std_error;
    res.review_gain = post.gain;
    res.settles = post.settles;
    res.component = post.component;
    res.p_alone = post.p_alone;
    res.components = post.components;
    res.memo = post.memo;
    res.object = object;
    res.tracks = tracks.to_vec();
    res.time_cover = cover.clone();
    res.stats = kept.iter().map(|x| x.1).collect();
    Ok(res)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn review_rounds_ask_one_question_per_track() {
        let pairs = [(0, 1), (0, 2), (3, 4), (1, 5), (2, 6)];
        let object: Vec<u32> = (0..7).collect();
        let got = one_question_per_object(vec![0, 1, 2, 3, 4], &pairs, &object);
        // round 0: (0 1), (3 4), (2 6); round 1: (0 2), (1 5)
        assert_eq!(got, vec![0, 2, 4, 1, 3]);
    }

    /// An HF DF fix (track 0) against two ships, each an AIS track and a radar track the
    /// matches join (objects {1, 2} and {3, 4}), and an aircraft track (5) between the ships.
    /// By value: the fix with ship 1's AIS, with its radar, with ship 2's AIS, with its radar,
    /// the aircraft with ship 1's radar and with ship 2's AIS. The fix's second pair with each
    /// ship asks the question its first one asks, and goes last; the aircraft's pair with ship
    /// 1 waits a round, since the fix's pair with ship 1 holds that object.
    #[test]
    fn review_asks_one_question_per_pair_of_objects() {
        let pairs = [(0, 1), (0, 2), (0, 3), (0, 4), (5, 2), (5, 3)];
        let object = [0, 1, 1, 3, 3, 5];
        let got = one_question_per_object(vec![0, 1, 2, 3, 4, 5], &pairs, &object);
        // distinct questions: (0 1), (0 3), (5 1), (5 3); round 0: (0 1), (5 3); round 1:
        // (0 3), (5 1); then the repeats (0 2) and (0 4) in rounds of their own
        assert_eq!(got, vec![0, 5, 2, 4, 1, 3]);
    }

    /// An HF DF track (track 0: fixes at 0, 1000 and 2000 s, at x = -9, 3 and 9 km, 20 x 4 km
    /// AOUs) and two still ships near it: ship 1's AIS covers all three fixes, ship 2's only
    /// the last two, so the middle instants of the two pairs are different fixes (3 and 9 km).
    /// Both pairs read the density at the fixes' mean, x = 1 km; read at the middle instant,
    /// they read it 6 km apart, and a harbour's ships got `p_same` several times apart that
    /// their fits could not tell apart.
    #[test]
    fn every_pair_of_a_track_reads_the_density_at_the_same_point() {
        let mut track = vec![];
        let mut time = vec![];
        let mut aou = vec![];
        for (t, x) in [(0.0, -9000.0), (1000.0, 3000.0), (2000.0, 9000.0)] {
            track.push(0);
            time.push(t);
            aou.push([x, 0.0, 20_000.0, 4_000.0, 0.0]);
        }
        for (k, (t0, x)) in [(1, (0.0, 0.0)), (2, (1000.0, 50.0))] {
            for j in 0..=(2000.0 - t0) as usize / 100 {
                track.push(k);
                time.push(t0 + 100.0 * j as f64);
                aou.push([x, 0.0, 20.0, 20.0, 0.0]);
            }
        }
        let source: Vec<u32> = track.iter().map(|&t| u32::from(t > 0)).collect();
        let r = Reports::new(Coords::Planar, 3, &track, &source, &time, &aou).unwrap();
        let o = Options::default();
        let (s1, s2) = (pair_stat(&r, 0, 1, &o), pair_stat(&r, 0, 2, &o));
        assert_eq!((s1.instants, s2.instants), (3, 2));
        for s in [s1.pos, s2.pos] {
            assert!((s[0] - 1000.0).abs() < 1e-9 && s[1].abs() < 1e-9, "{s:?}");
        }
    }

    /// The mean position of a track whose reports straddle the antimeridian lies on it: lat
    /// (10 + 12) / 2 = 11, lon 179.8 + (0 + 0.6) / 2 = 180.1, i.e. -179.9 (a plain mean of the
    /// longitudes, 0.1, is on the far side of the Earth).
    #[test]
    fn a_track_across_the_antimeridian_has_its_mean_on_it() {
        let aou = [
            [10.0, 179.8, 50.0, 50.0, 0.0],
            [12.0, -179.6, 50.0, 50.0, 0.0],
        ];
        let r = Reports::new(Coords::Geographic, 1, &[0, 0], &[0, 0], &[0.0, 10.0], &aou).unwrap();
        let c = centroid(&r, 0);
        assert!(
            (c[0] - 11.0).abs() < 1e-9 && (c[1] + 179.9).abs() < 1e-9,
            "{c:?}"
        );
    }

    /// A vague track's fixes weigh once each in the evidence, however many instants of its
    /// precise partner fall between two of them: fixes at 0 and 10 s (eleven instants between
    /// them, `m = 0`), then isolated fixes at 1000 s (`m = 4`) and 2000 s (`m = 8`). The
    /// evidence's mean is (0 + 0 + 4 + 8) / 4 = 3 over four independent fixes; the plain mean
    /// over the 13 instants would be 12 / 13.
    #[test]
    fn evidence_weighs_each_fix_once() {
        let s: f64 = 0.25 + 1.0e6; // R_a + R_b per axis: 2-sigma radii 1 m and 2 km
        let mut track = vec![];
        let mut time = vec![];
        let mut aou = vec![];
        for t in 0..=2000 {
            track.push(0);
            time.push(f64::from(t));
            aou.push([0.0, 0.0, 1.0, 1.0, 0.0]);
        }
        for (t, x) in [
            (0.0, 0.0),
            (10.0, 0.0),
            (1000.0, (4.0 * s).sqrt()),
            (2000.0, (8.0 * s).sqrt()),
        ] {
            track.push(1);
            time.push(t);
            aou.push([x, 0.0, 2000.0, 2000.0, 0.0]);
        }
        let source: Vec<u32> = track.clone();
        let r = Reports::new(Coords::Planar, 2, &track, &source, &time, &aou).unwrap();
        let o = Options {
            correlation_time: 0.0,
            inflation: Some(1.0),
            align: Alignment {
                process_noise: 0.0,
                ..Alignment::default()
            },
            ..Options::default()
        };
        let st = pair_stat(&r, 0, 1, &o);
        assert_eq!(st.instants, 13);
        // track 0 holds 2.5e-7 of the covariance, whose independent errors move the weights
        // of a group of g instants by about that share times g: 1e-5 is far above that and far
        // below the plain mean's distance from the weighted one
        assert!((st.mean_mg - 3.0).abs() < 1e-5, "{}", st.mean_mg);
        assert!((st.mean_ln_det - 2.0 * s.ln()).abs() < 1e-5);
        assert!(
            (st.evidence_k_eff - 4.0).abs() < 1e-5,
            "{}",
            st.evidence_k_eff
        );
    }
}
