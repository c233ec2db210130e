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
            let g = o.score.one(&ea, &eb, mix(a as u32, b as u32, k));
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

/// The combined score and the number of instants of tracks `a`, `b` (`NaN`, 0 without common
/// instants).
pub fn score_pair(r: &Reports, a: usize, b: usize, o: &Options) -> (f64, u32) {
    let p = pair_instants(r, a, b, o);
    let s = o.combine.combine(&p.g, &p.m, &p.time, o.correlation_time);
    (s, p.g.len() as u32)
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
) -> Result<Vec<(f64, u32)>> {
    let mut out = vec![(f64::NAN, 0u32); pairs.len()];
    let chunk = 1 << 14;
    for (c, block) in out.chunks_mut(chunk).enumerate() {
        if interrupt() {
            return Err(Error::Interrupted);
        }
        let base = c * chunk;
        block.par_iter_mut().enumerate().for_each(|(k, slot)| {
            let (a, b) = pairs[base + k];
            *slot = score_pair(r, a as usize, b as usize, o);
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
    for (&(a, b), &(s, k)) in pairs.iter().zip(&scored) {
        if k == 0 {
            continue;
        }
        res.a.push(a);
        res.b.push(b);
        res.score.push(s);
        res.instants.push(k);
        kept.push((a, b));
    }
    let tracks: Vec<assign::TrackInfo> = (0..r.n_tracks)
        .map(|t| {
            let (start, end) = r.span(t);
            assign::TrackInfo {
                source: r.source[t],
                start,
                end,
            }
        })
        .collect();
    let (class, object) = assign::group(&tracks, &kept, &res.score, o.lower, o.upper);
    res.class = class;
    res.object = object;
    Ok(res)
}
