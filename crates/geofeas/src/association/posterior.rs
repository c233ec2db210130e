//! Posterior probabilities of the joint association (`docs/association.md`, "The joint
//! model").
//!
//! The hypotheses of a connected component of the candidate graph are the feasible partitions of
//! its tracks into objects: no object holds two tracks of one source whose time spans overlap,
//! nor two tracks an operator declared different, nor two tracks that have a common instant (a
//! report of one at which the other has a state, [`TimeCover::meet`]) without being a candidate
//! pair (their AOUs never came close while both existed), and every
//! object is connected by candidate pairs (or by operator decisions). The weight of a partition is the product of the weights of
//! its objects; a single track weighs 1, and an object of several tracks weighs
//! `exp(sum of L_e)` over a spanning tree of its tracks, where `L_e` is the log-likelihood ratio
//! of a pair ([`crate::association::evidence`]) less the term of the track the pair joins to
//! the tree (the log-odds that a track is not a false one is a property of the track: it is
//! counted once per object, with the root's first pair). The tree takes the tracks from the most
//! precise to the least and joins each to a member already in it that it has a candidate pair
//! with: the product of the Gaussian densities of one instant factorises exactly that way when
//! the reference is much more precise than the joined track, as it is for a radar, aircraft or
//! HF DF track joined to an AIS track, and the evidence of each track is counted once. Over the
//! members at least [`ANCHOR_PRECISION`] times more precise than the joined track, the track
//! joins through the mean of their pairs' evidence weighed by each pair's independent
//! instants (a pair that met the joined track at one instant, as an aircraft track meets a
//! moored ship's AIS track whose reports are further apart than `max_gap`, weighs little
//! beside the ship's radar track that saw it at 140; and two references that saw it about as
//! long count about equally, instead of the choice switching between them on a fraction of an
//! instant), measured over the union of their times: where they cover different parts of the
//! joined track's time (a ship's AIS track with a gap at a DF fix that its radar track covers),
//! the mean pair's terms are taken at the union's independent instants (`Component::anchor`);
//! without one, the most precise member with a pair. Each
//! further track of a source the object already holds adds that source's break odds
//! ([`Track::further`], `ln(g_s (1 - P_s) / P_s)`, [`crate::association::evidence::track_breaks`]):
//! a pair's `L` weighs a merge of two objects seen by different sources, and two tracks of one
//! source are one sighting broken in two, not two sightings.
//!
//! Inference, per component and in parallel over components:
//! - **Exact enumeration** of the feasible partitions (restricted growth strings with
//!   feasibility pruning) when there are at most [`Inference::exact_limit`] of them;
//! - otherwise a **Markov chain Monte-Carlo sampler** over partitions: per block of tracks, a
//!   Metropolis-Hastings move proposed in proportion to the weights of joining each object it has
//!   a candidate pair with, leaving for an object of its own, or swapping places with the (up
//!   to three) blocks of the target object it conflicts with (so that two ships' tracks can
//!   exchange partners without passing through a state of low weight), from any object,
//!   one of its own included; the reverse of the last, a swap with an object made only of
//!   blocks it conflicts with that is joined to its own object, is proposed too. The acceptance
//!   ratio is the ratio of the two neighbourhoods' total weights, which makes the chain
//!   reversible with respect to the posterior. Each sweep also redraws, for every block, its
//!   object and the object of a neighbour block or of a neighbour's neighbour (one object or
//!   two, every feasible split of their blocks weighed: an exact Gibbs update of the two,
//!   `Chain::redraw_pair`), so that two ships can exchange the tracks of an aircraft that
//!   passed between them in one step. [`Inference::chains`] independent chains, the first
//!   from the grouping that takes the strongest pairs first, the others from groupings drawn
//!   from the pairs' own odds (`random_start`), so that chains stuck in different modes show
//!   it in the standard error; each chain's marginals are
//!   Rao-Blackwellised (`Conditionals`); the standard error of each marginal is the spread of
//!   the chain means over `sqrt(chains)`, reported per component.
//!
//! Operator decisions are hard constraints: tracks declared the same form one block that moves
//! as a unit (a contradiction with the feasibility rules or with a declared difference is an
//! error naming the decisions involved), tracks declared different never share an object.

use rand::{Rng, SeedableRng};

/// A uniform double in `[0, 1)` from 53 random bits.
fn unit(rng: &mut impl Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use super::align::TimeCover;
use super::evidence::{own_prediction_between, PairEvidence};
use crate::error::{Error, Result};

/// A pair log-likelihood ratio below this is treated as impossible (`p_same = 0`): the pair is
/// left out of the candidate graph, which keeps components small. `exp(-20) ~ 2e-9`.
pub const L_CUT: f64 = -20.0;

/// A track joins an object's spanning tree through a member at least this many times more
/// precise (typical AOU size `sqrt(det R)`), where one has a pair with it: the Gaussian
/// densities of an instant factorise through the reference only when it is much more precise
/// than the joined track (see the module docs).
pub const ANCHOR_PRECISION: f64 = 2.0;

/// What the model needs to know about a track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Track {
    pub source: u32,
    pub start: f64,
    pub end: f64,
    /// Precision order: the typical AOU size `sqrt(det R)` (smaller is more precise).
    pub spread: f64,
    /// Log prior factor of the track in an object that already holds a track of its source,
    /// `ln(g_s (1 - P_s) / P_s)` ([`super::evidence::track_breaks`]); 0 leaves such objects
    /// weighed as the merge of objects seen by disjoint sources.
    pub further: f64,
}

impl Track {
    /// `spread` from the smallest and largest `rx * ry` of a track's reports: `sqrt(min * max)
    /// / 4`, the track's typical `sqrt(det R)`.
    pub fn spread_of(area_min: f64, area_max: f64) -> f64 {
        0.25 * (area_min * area_max).sqrt()
    }

    fn conflicts(&self, o: &Track) -> bool {
        self.source == o.source && self.start < o.end && o.start < self.end
    }
}

/// An operator decision: tracks `a` and `b` are the same object (`same`) or not; `row` is the
/// decision's row in the caller's table (named in errors).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Decision {
    pub a: u32,
    pub b: u32,
    pub same: bool,
    pub row: usize,
}

/// Settings of the inference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inference {
    /// Components with at most this many feasible partitions are enumerated exactly.
    pub exact_limit: usize,
    /// Independent chains of the sampler.
    pub chains: usize,
    /// Sweeps per chain (every block proposed once per sweep), after a burn-in of a quarter as
    /// many.
    pub sweeps: usize,
    /// Seed of the sampler (per component, streams derived from the seed and the component's
    /// smallest track).
    pub seed: u64,
}

impl Default for Inference {
    fn default() -> Self {
        Self {
            exact_limit: 20_000,
            chains: 4,
            sweeps: 400,
            seed: 0,
        }
    }
}

impl Inference {
    /// Checks the settings.
    pub fn validated(self) -> Result<Self> {
        let bad = |name: &'static str, reason: String| Err(Error::InvalidOption { name, reason });
        if self.chains < 2 || self.chains > 64 {
            return bad("chains", format!("must be in [2, 64], got {}", self.chains));
        }
        if self.sweeps < 10 || self.sweeps > 1_000_000 {
            return bad(
                "sweeps",
                format!("must be in [10, 1000000], got {}", self.sweeps),
            );
        }
        if self.exact_limit > 10_000_000 {
            return bad(
                "exact_limit",
                format!("must be at most 10000000, got {}", self.exact_limit),
            );
        }
        Ok(self)
    }
}

/// How the marginals of a component were computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Method {
    /// Every feasible partition enumerated.
    Exact = 0,
    /// The sampler.
    Sampled = 1,
}

/// The posterior over every component.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Posterior {
    /// `P(same object)` of every pair (in the order given).
    pub p_same: Vec<f64>,
    /// Standard error of `p_same` (0 where exact).
    pub std_error: Vec<f64>,
    /// `P(no partner)` of every track.
    pub p_alone: Vec<f64>,
    /// Component of every pair (`u32::MAX` for pairs left out, below [`L_CUT`]).
    pub component: Vec<u32>,
    /// Per component: number of tracks, number of partitions (exact) or 0, method, and the
    /// largest standard error of its marginals.
    pub components: Vec<ComponentInfo>,
    /// For every pair: the expected probability mass of the other pairs of its component that
    /// a decision on it settles (see [`review_gain`]); 0 for pairs whose conditionals were not
    /// computed.
    pub gain: Vec<f64>,
    /// For every pair: how many other pairs a "same" answer would take out of the band
    /// `(p_reject, p_match)`, and how many a "different" answer would.
    pub settles: Vec<(u32, u32)>,
    /// Every component's result, for a later call to reuse ([`Memo`]).
    pub memo: Memo,
}

/// Summary of one component.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComponentInfo {
    pub tracks: u32,
    pub partitions: u64,
    pub method: Method,
    pub max_std_error: f64,
    /// Taken from the [`Memo`] given to [`posterior`], not computed again.
    pub reused: bool,
}

/// One component's result with everything it was computed from: the component (its tracks,
/// pairs with their evidence, decisions and constraints, in local indices, and its global
/// tracks and pairs), the inference settings and the review band. The sampler's streams derive
/// from the seed and the component's smallest global track only, so the same inputs give the
/// same result bit for bit, whatever the rest of the picture.
struct Solved {
    comp: Component,
    inf: Inference,
    band: (f64, f64),
    p_pair: Vec<f64>,
    se_pair: Vec<f64>,
    p_alone: Vec<f64>,
    gain: Vec<f64>,
    settles: Vec<(u32, u32)>,
    partitions: u64,
    method: Method,
}

/// The per-component results of one call to [`posterior`], keyed by each component's smallest
/// global track. A later call given it ([`posterior`]'s `memo`) takes a component's result
/// from it when the component is the same in every input (compared exactly, not by a hash),
/// and computes the others: operator decisions recompute the components they touch and
/// nothing else, with the same result as computing everything again.
///
/// A cache: it takes no part in comparing results (`==` always holds).
#[derive(Clone, Default)]
pub struct Memo(std::collections::HashMap<u32, std::sync::Arc<Solved>>);

impl Memo {
    /// Components held.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    fn get(
        &self,
        comp: &Component,
        inf: &Inference,
        band: (f64, f64),
    ) -> Option<&std::sync::Arc<Solved>> {
        let s = self.0.get(comp.tracks.first()?)?;
        (s.inf == *inf && s.band == band && s.comp == *comp).then_some(s)
    }
}

impl std::fmt::Debug for Memo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Memo({} components)", self.0.len())
    }
}

impl PartialEq for Memo {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// Union-find.
struct Dsu(Vec<u32>);

impl Dsu {
    fn new(n: usize) -> Self {
        Self((0..n as u32).collect())
    }
    fn find(&mut self, x: u32) -> u32 {
        let mut r = x;
        while self.0[r as usize] != r {
            r = self.0[r as usize];
        }
        let mut y = x;
        while self.0[y as usize] != r {
            let next = self.0[y as usize];
            self.0[y as usize] = r;
            y = next;
        }
        r
    }
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.0[hi as usize] = lo;
        }
    }
}

/// A candidate (or decided) pair seen from one of its tracks, `x`, towards the other.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Edge {
    /// The other track.
    to: u32,
    /// The pair's log-likelihood ratio `L`.
    l: f64,
    /// The other track's own term in `L` (see [`cell_weight`](Component::cell_weight)).
    k: f64,
    /// The pair's independent instants (see [`anchor`](Component::anchor)).
    k_eff: f64,
    /// What one more independent instant adds to `L` ([`PairEvidence::fit`]).
    fit: f64,
    /// `(a, b)` of `Lambda` ([`PairEvidence::motion`]).
    motion: (f64, f64),
    /// How much of `x`'s time the other track covers, in `x`'s reports (see [`Piece`]); only
    /// computed when the other track is an anchor of `x` (at least [`ANCHOR_PRECISION`] times
    /// more precise), else 0.
    covered: f64,
    /// The covered pieces, `pieces[from..to]` of the component, sorted.
    pieces: (u32, u32),
}

/// A piece of one of a track's coverage chains ([`TimeCover`]) during which another track has
/// a state too: `[start, end]`, and the length and number of reports of the chain it lies in.
/// A track's time is measured in its reports: a chain of one report (a DF fix ten minutes from
/// the next) counts one when covered; a piece of a longer chain counts its reports in
/// proportion to the time it covers.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    start: f64,
    end: f64,
    chain: f64,
    reports: f64,
}

impl Piece {
    fn measure(&self) -> f64 {
        if self.chain > 0.0 {
            self.reports * (self.end - self.start) / self.chain
        } else {
            self.reports
        }
    }
}

/// The pieces of the chains `xs` (with `reports` each) of one track during which a track with
/// the chains `ys` (and `horizon` seconds before its first and after its last report) has a
/// state, in order.
fn cover_pieces(
    xs: &[[f64; 2]],
    reports: &[u32],
    ys: &[[f64; 2]],
    horizon: f64,
    out: &mut Vec<Piece>,
) {
    let n = ys.len();
    let (mut i, mut j) = (0, 0);
    while i < xs.len() && j < n {
        let y0 = if j == 0 { ys[j][0] - horizon } else { ys[j][0] };
        let y1 = if j + 1 == n {
            ys[j][1] + horizon
        } else {
            ys[j][1]
        };
        let (lo, hi) = (xs[i][0].max(y0), xs[i][1].min(y1));
        if lo <= hi {
            out.push(Piece {
                start: lo,
                end: hi,
                chain: xs[i][1] - xs[i][0],
                reports: f64::from(reports[i]),
            });
        }
        if xs[i][1] < y1 {
            i += 1;
        } else {
            j += 1;
        }
    }
}

thread_local! {
    /// The pieces of a join's union ([`Component::anchor`]), reused: the join is weighed at
    /// every move of the sampler.
    static UNION: std::cell::RefCell<Vec<Piece>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The measure of the union of `pieces` (sorted in place).
fn union_measure(pieces: &mut [Piece]) -> f64 {
    pieces.sort_unstable_by(|a, b| a.start.total_cmp(&b.start));
    let mut total = 0.0;
    let mut run: Option<Piece> = None;
    for p in pieces.iter() {
        match &mut run {
            Some(r) if p.start <= r.end => r.end = r.end.max(p.end),
            _ => {
                if let Some(r) = run {
                    total += r.measure();
                }
                run = Some(*p);
            }
        }
    }
    total + run.map_or(0.0, |r| r.measure())
}

/// One component, in local indices.
#[derive(PartialEq)]
struct Component {
    /// Global track of each local track.
    tracks: Vec<u32>,
    info: Vec<Track>,
    /// Sorted adjacency per local track (candidate pairs and decided pairs).
    adj: Vec<Vec<Edge>>,
    /// The other track of each edge of `adj`, row by row: what the sampler searches and walks
    /// at every move, 4 bytes a pair where an [`Edge`] takes 72.
    neighbours: Vec<Vec<u32>>,
    /// The pieces of [`Edge::pieces`].
    pieces: Vec<Piece>,
    /// Number of reports of each local track (its whole measure, see [`Piece`]).
    reports: Vec<u32>,
    /// Local tracks of each block (tracks declared the same).
    blocks: Vec<Vec<u32>>,
    /// Block of each local track.
    block_of: Vec<u32>,
    /// Pairs declared different (local tracks, sorted).
    different: Vec<(u32, u32)>,
    /// Pairs with a common instant and no candidate pair (local tracks, sorted): their AOUs
    /// were far apart while both existed, so they are two objects.
    apart: Vec<(u32, u32)>,
    /// The pairs of this component: (global pair index, local a, local b).
    pairs: Vec<(usize, u32, u32)>,
    /// Precision order of the local tracks.
    rank: Vec<u32>,
    /// Whether two local tracks may not share an object, row `x` bit `y` (rows of
    /// `ceil(tracks / 64)` words), built from the rules of [`Component::compatible`] when the
    /// component has at most [`CLASH_MATRIX_TRACKS`] tracks (empty otherwise): the sampler
    /// asks it at every move.
    clash: Vec<u64>,
}

/// The most tracks of a component whose pairwise feasibility is held as a bit matrix
/// ([`Component::clash`], at most 8 MiB); a larger one applies the rules at each question.
const CLASH_MATRIX_TRACKS: usize = 8192;

impl Component {
    fn edge(&self, x: u32, y: u32) -> Option<f64> {
        self.edge_from(x, y).map(|e| e.l)
    }

    /// The pair `x`, `y` seen from `x`.
    fn edge_from(&self, x: u32, y: u32) -> Option<&Edge> {
        let k = self.neighbours[x as usize].binary_search(&y).ok()?;
        Some(&self.adj[x as usize][k])
    }

    fn different(&self, x: u32, y: u32) -> bool {
        let key = (x.min(y), x.max(y));
        self.different.binary_search(&key).is_ok()
    }

    fn apart(&self, x: u32, y: u32) -> bool {
        let key = (x.min(y), x.max(y));
        self.apart.binary_search(&key).is_ok()
    }

    /// Whether the tracks `xs` and `ys` may share an object: no two of one source at
    /// overlapping times, none declared different, and every two that have a common instant
    /// a candidate pair (or declared the same): tracks whose AOUs never came close while both
    /// existed are two objects.
    fn compatible(&self, xs: &[u32], ys: &[u32]) -> bool {
        if !self.clash.is_empty() {
            let words = self.tracks.len().div_ceil(64);
            return xs.iter().all(|&x| {
                let row = &self.clash[x as usize * words..][..words];
                ys.iter()
                    .all(|&y| row[y as usize >> 6] >> (y & 63) & 1 == 0)
            });
        }
        xs.iter()
            .all(|&x| ys.iter().all(|&y| self.pair_compatible(x, y)))
    }

    /// [`Component::compatible`] of two tracks, from the rules.
    fn pair_compatible(&self, x: u32, y: u32) -> bool {
        let (tx, ty) = (&self.info[x as usize], &self.info[y as usize]);
        !tx.conflicts(ty) && !self.different(x, y) && !self.apart(x, y)
    }

    /// Builds [`Component::clash`] (once `different` and `apart` are final), when the
    /// component is small enough.
    fn build_clash(&mut self) {
        let m = self.tracks.len();
        if m > CLASH_MATRIX_TRACKS {
            return;
        }
        let words = m.div_ceil(64);
        let mut clash = vec![0u64; m * words];
        for x in 0..m as u32 {
            for y in x + 1..m as u32 {
                if !self.pair_compatible(x, y) {
                    clash[x as usize * words + (y as usize >> 6)] |= 1 << (y & 63);
                    clash[y as usize * words + (x as usize >> 6)] |= 1 << (x & 63);
                }
            }
        }
        self.clash = clash;
    }

    /// `(L, k_y)` through which `x` joins the tree of `attached` members: over the members at
    /// least [`ANCHOR_PRECISION`] times more precise than `x` that have a pair with it (its
    /// anchors), the means of their pairs' `L` and of their own terms `k_y`, each pair weighed
    /// by its independent instants; without such a member, the most precise member with a
    /// pair.
    /// Each of those pairs measures `x` against the object's path through another reference;
    /// one that met `x` at one instant weighs little beside one that saw it all along, and
    /// two references that saw it about as long count about equally, where taking the one
    /// with the most instants switched between them on a fraction of an instant.
    ///
    /// `x` is measured over the union of their times, since the object has a path wherever
    /// one of them has a state: when they cover different parts of `x`'s time (a ship's AIS
    /// track with a gap at a DF fix that its radar track covers; a radar track broken in two),
    /// the mean pair's independent instants `k` are scaled by the union's measure over the
    /// mean pair's ([`Piece`]), `K = k m_union / m`, and the instants beyond `k` add what the
    /// mean pair's instants add: `L = mean L + (K - k) mean fit + Lambda(K) - Lambda(k)`
    /// ([`PairEvidence::fit`]; `Lambda` at the mean `(a, b)`, [`PairEvidence::motion`]).
    fn anchor(&self, x: u32, attached: &[u32]) -> Option<(f64, f64)> {
        let sx = self.info[x as usize].spread;
        let whole = f64::from(self.reports[x as usize]);
        let mut first = None;
        let (mut sum_w, mut sum_l, mut sum_k) = (0.0, 0.0, 0.0);
        let (mut sum_keff, mut sum_fit, mut sum_m) = (0.0, 0.0, 0.0);
        let (mut sum_a, mut sum_b) = (0.0, 0.0);
        let (mut anchors, mut full, mut partial) = (0usize, false, 0usize);
        for &y in attached {
            if let Some(e) = self.edge_from(x, y) {
                if first.is_none() {
                    first = Some((e.l, e.k));
                }
                if self.info[y as usize].spread * ANCHOR_PRECISION <= sx {
                    let w = e.k_eff.max(f64::MIN_POSITIVE);
                    sum_w += w;
                    sum_l += w * e.l;
                    sum_k += w * e.k;
                    sum_keff += w * e.k_eff;
                    sum_fit += w * e.fit;
                    sum_m += w * e.covered;
                    sum_a += w * e.motion.0;
                    sum_b += w * e.motion.1;
                    anchors += 1;
                    // covers all of x's time
                    let all = e.covered >= whole * (1.0 - 1e-12);
                    full |= all;
                    partial += usize::from(!all);
                }
            }
        }
        if anchors == 0 {
            return first;
        }
        let (l, k) = (sum_l / sum_w, sum_k / sum_w);
        let m_mean = sum_m / sum_w;
        // the union adds nothing with one anchor, or when every anchor covers all of x's time
        let m_union = if anchors == 1 || partial == 0 || m_mean <= 0.0 {
            m_mean
        } else if full {
            whole
        } else {
            UNION.with_borrow_mut(|pieces| {
                pieces.clear();
                for &y in attached {
                    if let Some(e) = self.edge_from(x, y) {
                        if self.info[y as usize].spread * ANCHOR_PRECISION <= sx {
                            let (from, to) = (e.pieces.0 as usize, e.pieces.1 as usize);
                            pieces.extend_from_slice(&self.pieces[from..to]);
                        }
                    }
                }
                union_measure(pieces)
            })
        };
        if m_union <= m_mean {
            return Some((l, k));
        }
        let k_mean = sum_keff / sum_w;
        let big_k = k_mean * m_union / m_mean;
        let (a, b) = (sum_a / sum_w, sum_b / sum_w);
        let more =
            (big_k - k_mean) * (sum_fit / sum_w) + own_prediction_between(k_mean, big_k, a, b);
        Some((l + more, k))
    }

    /// Log-weight of an object holding the tracks `members` (assumed feasible); `-inf` if the
    /// candidate pairs do not connect them.
    fn cell_weight(&self, members: &[u32], scratch: &mut Vec<u32>) -> f64 {
        if members.len() < 2 {
            return 0.0;
        }
        scratch.clear();
        scratch.extend_from_slice(members);
        scratch.sort_by_key(|&x| self.rank[x as usize]);
        // scratch[..attached] are in the tree; the rest wait for a neighbour in it
        let mut attached = 1usize;
        let mut total = 0.0;
        while attached < scratch.len() {
            let mut progress = false;
            let mut k = attached;
            while k < scratch.len() {
                let x = scratch[k];
                // the attached member x joins through (`anchor`); a pair's ratio holds a
                // term of each of its tracks (the odds that the track is not a false one,
                // were it alone), counted once per object: the root's with its first pair
                let best = self.anchor(x, &scratch[..attached]);
                if let Some((l, k_y)) = best {
                    total += if attached == 1 { l } else { l - k_y };
                    scratch[attached..=k].rotate_right(1);
                    attached += 1;
                    progress = true;
                }
                k += 1;
            }
            if !progress {
                return f64::NEG_INFINITY;
            }
        }
        // every further track of a source the object already holds: its break odds
        for (i, &x) in scratch.iter().enumerate() {
            let t = &self.info[x as usize];
            if scratch[..i]
                .iter()
                .any(|&y| self.info[y as usize].source == t.source)
            {
                total += t.further;
            }
        }
        total
    }
}

fn log_sum_exp(xs: impl Iterator<Item = f64> + Clone) -> f64 {
    let m = xs.clone().fold(f64::NEG_INFINITY, f64::max);
    if m == f64::NEG_INFINITY {
        return m;
    }
    m + xs.map(|x| (x - m).exp()).sum::<f64>().ln()
}

/// Whether operator `decisions` on `tracks` (only their sources and spans are read) are
/// possible together: every decision names two distinct tracks; no "different" decision is
/// joined by a chain of "same" ones; no chain of "same" decisions makes one object of two
/// tracks of one source at overlapping times. The error ([`Error::Decisions`]) names the
/// decisions involved by their `row`: the shortest chain of "same" decisions, then the
/// "different" one. The engine checks this first; the review station's decision log checks an
/// operator's new decision with it before writing it.
pub fn check_decisions(tracks: &[Track], decisions: &[Decision]) -> Result<()> {
    same_blocks(tracks, decisions).map(|_| ())
}

/// The blocks of tracks `decisions` declare the same, once [`check_decisions`] passes.
fn same_blocks(tracks: &[Track], decisions: &[Decision]) -> Result<Dsu> {
    let n = tracks.len();
    for d in decisions {
        if d.a as usize >= n || d.b as usize >= n || d.a == d.b {
            return Err(Error::Decisions {
                rows: vec![d.row],
                reason: "not two distinct tracks of the picture".into(),
            });
        }
    }
    // blocks of tracks declared the same
    let mut same = Dsu::new(n);
    for d in decisions.iter().filter(|d| d.same) {
        same.union(d.a, d.b);
    }
    for d in decisions.iter().filter(|d| !d.same) {
        if same.find(d.a) == same.find(d.b) {
            let mut rows = same_path(decisions, d.a, d.b);
            rows.push(d.row);
            return Err(Error::Decisions {
                rows,
                reason: "the last declares two tracks different that the others make one object"
                    .into(),
            });
        }
    }
    let mut members: std::collections::HashMap<u32, Vec<u32>> = Default::default();
    for t in 0..n as u32 {
        members.entry(same.find(t)).or_default().push(t);
    }
    for ms in members.values() {
        for (i, &x) in ms.iter().enumerate() {
            for &y in &ms[i + 1..] {
                if tracks[x as usize].conflicts(&tracks[y as usize]) {
                    return Err(Error::Decisions {
                        rows: same_path(decisions, x, y),
                        reason: "make one object of two tracks of one source at overlapping \
                                 times"
                            .into(),
                    });
                }
            }
        }
    }
    Ok(same)
}

/// The rows of decisions "same" along a shortest chain of them from track `a` to track `b`, in
/// chain order (empty if none joins them).
fn same_path(decisions: &[Decision], a: u32, b: u32) -> Vec<usize> {
    use std::collections::{HashMap, VecDeque};
    let mut adj: HashMap<u32, Vec<(u32, usize)>> = HashMap::new();
    for d in decisions.iter().filter(|d| d.same) {
        adj.entry(d.a).or_default().push((d.b, d.row));
        adj.entry(d.b).or_default().push((d.a, d.row));
    }
    let mut prev: HashMap<u32, (u32, usize)> = HashMap::new();
    let mut queue = VecDeque::from([a]);
    while let Some(x) = queue.pop_front() {
        if x == b {
            break;
        }
        for &(y, row) in adj.get(&x).map_or(&[][..], |v| &v[..]) {
            if y != a && !prev.contains_key(&y) {
                prev.insert(y, (x, row));
                queue.push_back(y);
            }
        }
    }
    let mut rows = Vec::new();
    let mut x = b;
    while let Some(&(p, row)) = prev.get(&x) {
        rows.push(row);
        x = p;
    }
    rows.reverse();
    rows
}

/// Builds the components of the candidate graph of `pairs` with their `evidence` (pairs whose
/// log-likelihood ratio is below [`L_CUT`] left out) and `decisions`, checking the decisions.
fn components(
    tracks: &[Track],
    cover: &TimeCover,
    pairs: &[(u32, u32)],
    evidence: &[PairEvidence],
    decisions: &[Decision],
) -> Result<Vec<Component>> {
    let n = tracks.len();
    let llr: Vec<f64> = evidence.iter().map(|e| e.llr).collect();
    let mut same = same_blocks(tracks, decisions)?;
    // components: candidate pairs above the cut and decisions
    let mut dsu = Dsu::new(n);
    for (k, &(a, b)) in pairs.iter().enumerate() {
        if llr[k] >= L_CUT {
            dsu.union(a, b);
        }
    }
    for d in decisions {
        dsu.union(d.a, d.b);
    }
    let mut local = vec![u32::MAX; n];
    let mut comp_of_root: std::collections::HashMap<u32, usize> = Default::default();
    let mut comps: Vec<Component> = Vec::new();
    for t in 0..n as u32 {
        let r = dsu.find(t);
        let c = *comp_of_root.entry(r).or_insert_with(|| {
            comps.push(Component {
                tracks: Vec::new(),
                info: Vec::new(),
                adj: Vec::new(),
                neighbours: Vec::new(),
                pieces: Vec::new(),
                reports: Vec::new(),
                blocks: Vec::new(),
                block_of: Vec::new(),
                different: Vec::new(),
                apart: Vec::new(),
                pairs: Vec::new(),
                rank: Vec::new(),
                clash: Vec::new(),
            });
            comps.len() - 1
        });
        local[t as usize] = comps[c].tracks.len() as u32;
        comps[c].tracks.push(t);
        comps[c].info.push(tracks[t as usize]);
        comps[c].adj.push(Vec::new());
        comps[c]
            .reports
            .push(cover.reports_of(t as usize).iter().sum());
    }
    let comp_of = |t: u32, dsu: &mut Dsu| comp_of_root[&dsu.find(t)];
    for (k, &(a, b)) in pairs.iter().enumerate() {
        if llr[k] >= L_CUT {
            let c = comp_of(a, &mut dsu);
            let (la, lb) = (local[a as usize], local[b as usize]);
            let comp = &mut comps[c];
            let (ga, gb) = (a as usize, b as usize);
            let own = evidence[k].own;
            for (x, y, gx, gy, k_y) in [(la, lb, ga, gb, own.1), (lb, la, gb, ga, own.0)] {
                // the coverage of x by y, where y may be an anchor of x
                let from = comp.pieces.len() as u32;
                if tracks[gy].spread * ANCHOR_PRECISION <= tracks[gx].spread {
                    cover_pieces(
                        cover.of_track(gx),
                        cover.reports_of(gx),
                        cover.of_track(gy),
                        cover.horizon,
                        &mut comp.pieces,
                    );
                }
                let to = comp.pieces.len() as u32;
                let covered: f64 = comp.pieces[from as usize..]
                    .iter()
                    .map(Piece::measure)
                    .sum();
                let e = &evidence[k];
                comp.adj[x as usize].push(Edge {
                    to: y,
                    l: e.llr,
                    k: k_y,
                    k_eff: e.k_eff,
                    fit: e.fit,
                    motion: e.motion,
                    covered,
                    pieces: (from, to),
                });
            }
            comp.pairs.push((k, la, lb));
        }
    }
    for d in decisions {
        let c = comp_of(d.a, &mut dsu);
        let (la, lb) = (local[d.a as usize], local[d.b as usize]);
        let comp = &mut comps[c];
        if d.same {
            // a decided pair connects its object even without a candidate pair
            if !comp.adj[la as usize].iter().any(|e| e.to == lb) {
                for (x, y) in [(la, lb), (lb, la)] {
                    comp.adj[x as usize].push(Edge {
                        to: y,
                        l: 0.0,
                        k: 0.0,
                        k_eff: 0.0,
                        fit: 0.0,
                        motion: (0.0, 0.0),
                        covered: 0.0,
                        pieces: (0, 0),
                    });
                }
            }
        } else {
            comp.different.push((la.min(lb), la.max(lb)));
        }
    }
    for comp in &mut comps {
        for row in &mut comp.adj {
            row.sort_by(|x, y| x.to.cmp(&y.to).then(y.l.total_cmp(&x.l)));
            row.dedup_by_key(|e| e.to);
        }
        comp.neighbours = comp
            .adj
            .iter()
            .map(|row| row.iter().map(|e| e.to).collect())
            .collect();
        comp.different.sort_unstable();
        comp.different.dedup();
        // tracks with a common instant but no pair, swept in order of their first report
        let mut by_start: Vec<u32> = (0..comp.tracks.len() as u32).collect();
        by_start.sort_by(|&x, &y| {
            comp.info[x as usize]
                .start
                .total_cmp(&comp.info[y as usize].start)
        });
        for (i, &x) in by_start.iter().enumerate() {
            let end_x = comp.info[x as usize].end + cover.horizon;
            for &y in &by_start[i + 1..] {
                if comp.info[y as usize].start - cover.horizon > end_x {
                    break;
                }
                // (two tracks of one source are never compared: the time rule of
                // `Track::conflicts` decides them)
                if comp.info[x as usize].source != comp.info[y as usize].source
                    && comp.edge(x, y).is_none()
                    && cover.meet(
                        comp.tracks[x as usize] as usize,
                        comp.tracks[y as usize] as usize,
                    )
                {
                    comp.apart.push((x.min(y), x.max(y)));
                }
            }
        }
        comp.apart.sort_unstable();
        let m = comp.tracks.len();
        let mut order: Vec<u32> = (0..m as u32).collect();
        order.sort_by(|&x, &y| {
            comp.info[x as usize]
                .spread
                .total_cmp(&comp.info[y as usize].spread)
                .then(comp.tracks[x as usize].cmp(&comp.tracks[y as usize]))
        });
        comp.rank = vec![0; m];
        for (r, &x) in order.iter().enumerate() {
            comp.rank[x as usize] = r as u32;
        }
        let mut root_block: std::collections::HashMap<u32, u32> = Default::default();
        comp.block_of = vec![0; m];
        for x in 0..m as u32 {
            let r = same.find(comp.tracks[x as usize]);
            let b = *root_block.entry(r).or_insert_with(|| {
                comp.blocks.push(Vec::new());
                comp.blocks.len() as u32 - 1
            });
            comp.blocks[b as usize].push(x);
            comp.block_of[x as usize] = b;
        }
    }
    comps.par_iter_mut().for_each(Component::build_clash);
    Ok(comps)
}

/// Marginals of one component from weighted partitions (`labels` per block).
struct Marginals {
    p_pair: Vec<f64>,
    se_pair: Vec<f64>,
    p_alone: Vec<f64>,
    partitions: u64,
    method: Method,
    /// The partitions with their normalised weights (exact) or equal weights (sampled).
    samples: Vec<Vec<u32>>,
    weights: Vec<f64>,
}

/// The depth-first walk of [`enumerate`] over restricted growth strings: block `k` joins each
/// compatible cell of blocks `0..k`, or opens a new one.
struct Walk<'a> {
    comp: &'a Component,
    /// The blocks in the order they are placed: the most precise first.
    order: Vec<u32>,
    /// Whether the block placed `k`-th has a pair with a block placed after it.
    reach: Vec<bool>,
    /// Cell of each block (indexed by block).
    labels: Vec<u32>,
    cells: Vec<Vec<u32>>,
    out_labels: Vec<Vec<u32>>,
    out_logw: Vec<f64>,
    scratch: Vec<u32>,
    limit: usize,
    /// Placements left to try before the walk gives up (see [`ENUMERATION_WORK`]).
    budget: usize,
}

impl Walk<'_> {
    /// Places the blocks `order[k..]`; false when the limit or the work budget is exceeded.
    /// A block joins a cell only if it has a pair with one of its tracks or with a block still
    /// to place: otherwise the cell could never be connected.
    fn rec(&mut self, k: usize) -> bool {
        let comp = self.comp;
        if self.budget == 0 {
            return false;
        }
        self.budget -= 1;
        if k == comp.blocks.len() {
            let mut w = 0.0;
            for c in &self.cells {
                w += comp.cell_weight(c, &mut self.scratch);
            }
            if w > f64::NEG_INFINITY {
                if self.out_labels.len() >= self.limit {
                    return false;
                }
                self.out_labels.push(self.labels.clone());
                self.out_logw.push(w);
            }
            return true;
        }
        let b = self.order[k] as usize;
        let block = &comp.blocks[b];
        for c in 0..self.cells.len() {
            let linked = self.reach[k]
                || block
                    .iter()
                    .any(|&x| self.cells[c].iter().any(|&y| comp.edge(x, y).is_some()));
            if linked && comp.compatible(&self.cells[c], block) {
                self.labels[b] = c as u32;
                let before = self.cells[c].len();
                self.cells[c].extend_from_slice(block);
                let ok = self.rec(k + 1);
                self.cells[c].truncate(before);
                if !ok {
                    return false;
                }
            }
        }
        self.labels[b] = self.cells.len() as u32;
        self.cells.push(block.clone());
        let ok = self.rec(k + 1);
        self.cells.pop();
        ok
    }
}

/// Placements the enumeration may try per partition of its limit. Objects must be connected by
/// candidate pairs, which only a complete partition shows, so the walk also visits partial
/// partitions that lead to none: many tracks of one source at different times, met only by a
/// few tracks that come later in the order, make almost all of them. Past this budget the
/// component goes to the sampler, as one of more than `limit` partitions does.
const ENUMERATION_WORK: usize = 64;

fn enumerate(comp: &Component, limit: usize) -> Option<(Vec<Vec<u32>>, Vec<f64>)> {
    let nb = comp.blocks.len();
    // a quick bound: components of many blocks cannot be enumerated within the limit
    if nb > 24 {
        return None;
    }
    let key = |b: usize| comp.blocks[b].iter().map(|&x| comp.rank[x as usize]).min();
    let mut order: Vec<u32> = (0..nb as u32).collect();
    order.sort_by_key(|&b| key(b as usize));
    let mut pos = vec![0usize; nb];
    for (k, &b) in order.iter().enumerate() {
        pos[b as usize] = k;
    }
    let reach: Vec<bool> = order
        .iter()
        .enumerate()
        .map(|(k, &b)| {
            comp.blocks[b as usize].iter().any(|&x| {
                comp.adj[x as usize]
                    .iter()
                    .any(|e| pos[comp.block_of[e.to as usize] as usize] > k)
            })
        })
        .collect();
    let mut walk = Walk {
        comp,
        order,
        reach,
        labels: vec![0u32; nb],
        cells: Vec::new(),
        out_labels: Vec::new(),
        out_logw: Vec::new(),
        scratch: Vec::new(),
        limit,
        budget: limit.saturating_mul(ENUMERATION_WORK),
    };
    if walk.rec(0) {
        Some((walk.out_labels, walk.out_logw))
    } else {
        None
    }
}

/// The sampler's state: cell label per block, members (local tracks) and blocks per cell, and
/// the cached log-weight per cell.
struct Chain<'a> {
    comp: &'a Component,
    label: Vec<u32>,
    cell_blocks: Vec<Vec<u32>>,
    cell_tracks: Vec<Vec<u32>>,
    cell_w: Vec<f64>,
    free: Vec<u32>,
    scratch: Vec<u32>,
    /// Buffers of [`Chain::moves`] and [`Chain::step`].
    bufs: MoveBuffers,
    /// Buffers of [`Chain::redraw_pair`]: its options, the tracks of an object it weighs, the
    /// blocks it may draw from and the blocks it holds in each of the two objects.
    pair_options: Vec<(u32, f64)>,
    pair_tracks: Vec<u32>,
    pair_others: Vec<u32>,
    pair_held: [Vec<u32>; 2],
    /// The most blocks [`Chain::redraw_pair`] redraws ([`PAIR_BLOCKS`]; fewer in tests, so
    /// that small components exercise the redraw with blocks held).
    pair_blocks: usize,
    /// Inverse temperature: the chain samples the posterior raised to `beta`.
    beta: f64,
    /// Log-weight of the current partition.
    logw: f64,
}

/// The buffers [`Chain::moves`] fills at every move, kept between moves: the moves forward and
/// back, the tracks of the mover's object without it, of an object it would make, and the cells
/// near it.
#[derive(Default)]
struct MoveBuffers {
    fwd: Vec<(Move, f64)>,
    rev: Vec<(Move, f64)>,
    rest: Vec<u32>,
    joined: Vec<u32>,
    back: Vec<u32>,
    near: Vec<u32>,
    extra: Vec<u32>,
    /// Per cell, the stamp of the last search that found it (a search's cells once each).
    seen: Vec<u32>,
    stamp: u32,
}

/// Inverse temperatures of the tempered copies of every chain (the first is the posterior).
const TEMPERATURES: [f64; 4] = [1.0, 0.5, 0.25, 0.12];

/// The most blocks a swap move displaces.
const MAX_SWAP: usize = 3;

/// The most blocks [`Chain::redraw_pair`] redraws (it weighs `2^(n - 2) + 1` groupings of `n`
/// blocks); two objects that hold more between them have the others held where they are.
const PAIR_BLOCKS: usize = 12;

/// A move of one block.
#[derive(Clone, Copy, Debug)]
enum Move {
    Stay,
    Alone,
    Join(u32),
    /// Join the cell, and the (up to [`MAX_SWAP`]) blocks there that conflict with the mover go
    /// to the mover's old cell.
    Swap(u32, [u32; MAX_SWAP], usize),
}

impl<'a> Chain<'a> {
    fn new(comp: &'a Component, labels: &[u32]) -> Self {
        let nb = comp.blocks.len();
        let ncell = labels.iter().map(|&l| l as usize + 1).max().unwrap_or(0);
        let mut cell_blocks = vec![Vec::new(); nb.max(ncell)];
        for (b, &l) in labels.iter().enumerate() {
            cell_blocks[l as usize].push(b as u32);
        }
        let mut ch = Self {
            comp,
            label: labels.to_vec(),
            cell_tracks: vec![Vec::new(); cell_blocks.len()],
            cell_w: vec![0.0; cell_blocks.len()],
            cell_blocks,
            free: Vec::new(),
            scratch: Vec::new(),
            bufs: MoveBuffers::default(),
            pair_options: Vec::new(),
            pair_tracks: Vec::new(),
            pair_others: Vec::new(),
            pair_held: [Vec::new(), Vec::new()],
            pair_blocks: PAIR_BLOCKS,
            beta: 1.0,
            logw: 0.0,
        };
        for c in 0..ch.cell_blocks.len() {
            ch.refresh(c as u32);
            if ch.cell_blocks[c].is_empty() {
                ch.free.push(c as u32);
            }
        }
        ch
    }

    fn refresh(&mut self, c: u32) {
        let mut t = std::mem::take(&mut self.cell_tracks[c as usize]);
        t.clear();
        for &k in &self.cell_blocks[c as usize] {
            t.extend_from_slice(&self.comp.blocks[k as usize]);
        }
        let w = self.comp.cell_weight(&t, &mut self.scratch);
        self.logw += w - self.cell_w[c as usize];
        self.cell_w[c as usize] = w;
        self.cell_tracks[c as usize] = t;
    }

    fn weight_of(&mut self, tracks: &[u32]) -> f64 {
        let mut s = std::mem::take(&mut self.scratch);
        let w = self.comp.cell_weight(tracks, &mut s);
        self.scratch = s;
        w
    }

    /// The moves of block `b` from the current state, with their log-weight changes, into
    /// `out` (emptied first).
    fn moves(&mut self, b: u32, out: &mut Vec<(Move, f64)>) {
        let comp = self.comp;
        let old = self.label[b as usize];
        let mine = &comp.blocks[b as usize];
        let mut old_rest = std::mem::take(&mut self.bufs.rest);
        old_rest.clear();
        old_rest.extend(
            self.cell_tracks[old as usize]
                .iter()
                .copied()
                .filter(|x| comp.block_of[*x as usize] != b),
        );
        let w_old = self.cell_w[old as usize];
        let w_old_rest = if old_rest.is_empty() {
            0.0
        } else {
            self.weight_of(&old_rest)
        };
        out.clear();
        out.push((Move::Stay, 0.0));
        if !old_rest.is_empty() && w_old_rest > f64::NEG_INFINITY {
            out.push((Move::Alone, w_old_rest - w_old));
        }
        // target cells: those holding a neighbour of the block; and those of at most
        // MAX_SWAP blocks, all in conflict with it, that hold a neighbour of its cell, which it
        // may swap with (it leaves for an object of its own, they join its cell): the reverse
        // of a swap made by a block alone, which must be proposed for the chain to be reversible
        // each cell once (marked with this call's stamp), then in order: the tracks of an
        // object share most of their neighbours
        let mut seen = std::mem::take(&mut self.bufs.seen);
        seen.resize(self.cell_blocks.len(), 0);
        let mut stamp = self.bufs.stamp;
        let mut cells_of = |ch: &Self, xs: &[u32], cs: &mut Vec<u32>| {
            stamp = stamp.wrapping_add(1);
            if stamp == 0 {
                seen.fill(0);
                stamp = 1;
            }
            cs.clear();
            for &x in xs {
                for &y in &comp.neighbours[x as usize] {
                    let c = ch.label[comp.block_of[y as usize] as usize];
                    if c != old && seen[c as usize] != stamp {
                        seen[c as usize] = stamp;
                        cs.push(c);
                    }
                }
            }
            cs.sort_unstable();
        };
        let mut near = std::mem::take(&mut self.bufs.near);
        let mut extra = std::mem::take(&mut self.bufs.extra);
        cells_of(self, mine, &mut near);
        cells_of(self, &old_rest, &mut extra);
        self.bufs.seen = seen;
        self.bufs.stamp = stamp;
        extra.retain(|&c| {
            let cell = &self.cell_blocks[c as usize];
            near.binary_search(&c).is_err()
                && cell.len() <= MAX_SWAP
                && cell
                    .iter()
                    .all(|&k| !comp.compatible(&comp.blocks[k as usize], mine))
        });
        let mut joined = std::mem::take(&mut self.bufs.joined);
        let mut back = std::mem::take(&mut self.bufs.back);
        for &c in near.iter().chain(&extra) {
            let cell = &self.cell_blocks[c as usize];
            // the blocks of the cell in conflict with the mover (the first MAX_SWAP of them)
            let mut conflicts = [0u32; MAX_SWAP];
            let mut n = 0usize;
            for &k in cell {
                if !comp.compatible(&comp.blocks[k as usize], mine) {
                    if n < MAX_SWAP {
                        conflicts[n] = k;
                    }
                    n += 1;
                }
            }
            if n == cell.len() && old_rest.is_empty() {
                // a block alone trading places with a whole cell changes no object
                continue;
            }
            let w_c = self.cell_w[c as usize];
            if n == 0 {
                joined.clear();
                joined.extend_from_slice(&self.cell_tracks[c as usize]);
                joined.extend_from_slice(mine);
                let w = self.weight_of(&joined);
                if w > f64::NEG_INFINITY && w_old_rest > f64::NEG_INFINITY {
                    out.push((Move::Join(c), w + w_old_rest - w_c - w_old));
                }
            } else if n <= MAX_SWAP {
                let conflicts = &conflicts[..n];
                back.clear();
                back.extend_from_slice(&old_rest);
                let rest = back.len();
                back.extend(
                    conflicts
                        .iter()
                        .flat_map(|&k| comp.blocks[k as usize].iter().copied()),
                );
                if !comp.compatible(&back[rest..], &old_rest) {
                    continue;
                }
                joined.clear();
                joined.extend(
                    self.cell_tracks[c as usize]
                        .iter()
                        .copied()
                        .filter(|x| !conflicts.contains(&comp.block_of[*x as usize])),
                );
                joined.extend_from_slice(mine);
                let (w1, w2) = (self.weight_of(&joined), self.weight_of(&back));
                if w1 > f64::NEG_INFINITY && w2 > f64::NEG_INFINITY {
                    let mut ks = [0u32; MAX_SWAP];
                    ks[..n].copy_from_slice(conflicts);
                    out.push((Move::Swap(c, ks, n), w1 + w2 - w_c - w_old));
                }
            }
        }
        self.bufs.rest = old_rest;
        self.bufs.near = near;
        self.bufs.extra = extra;
        self.bufs.joined = joined;
        self.bufs.back = back;
    }

    fn set(&mut self, b: u32, to: u32) {
        let from = self.label[b as usize];
        self.cell_blocks[from as usize].retain(|&x| x != b);
        self.cell_blocks[to as usize].push(b);
        self.label[b as usize] = to;
    }

    fn apply(&mut self, b: u32, m: Move) {
        let old = self.label[b as usize];
        match m {
            Move::Stay => return,
            Move::Alone => {
                let c = self.free.pop().expect("a free cell: one per block");
                self.set(b, c);
                self.refresh(c);
            }
            Move::Join(c) => {
                self.set(b, c);
                self.refresh(c);
            }
            Move::Swap(c, ks, n) => {
                self.set(b, c);
                for &k in &ks[..n] {
                    self.set(k, old);
                }
                self.refresh(c);
            }
        }
        self.refresh(old);
        if self.cell_blocks[old as usize].is_empty() {
            self.free.push(old);
        }
    }

    /// A Gibbs update of two objects: the objects of block `b1` and of its neighbour block
    /// `b2` (one object if they share it) are redrawn, the rest of the partition held, from
    /// every feasible way of holding their blocks in one object or in two, one with `b1` and
    /// one with `b2`, in proportion to the posterior (raised to `beta`). The set of blocks and
    /// the pair `(b1, b2)` are the same from every state the update can reach, so it samples
    /// the posterior restricted to that set exactly: two ships exchange the tracks of an
    /// aircraft that passed between them, which block moves can only do through a state in
    /// which each holds the other's radar track.
    ///
    /// Two objects of more than [`PAIR_BLOCKS`] blocks between them (a ship's AIS track, its
    /// radar fragments and a patrol aircraft's passes) redraw `b1`, `b2` and `PAIR_BLOCKS - 2`
    /// of their other blocks drawn uniformly, the others held in their objects, between the
    /// two objects only. The union of the two objects, and so the draw, is the same from every
    /// state the update reaches, and the held blocks stay where they are: the update samples
    /// the posterior restricted to the drawn blocks' ways exactly. Without it, two moored
    /// ships' aircraft passes that one chain put on the wrong ships (Solent, seed 0) stayed
    /// there: no move of one block leaves the state, and `p_same` was 0.75 where the other
    /// chains gave 1.000. Objects of more blocks that share one are left alone (with blocks
    /// held, the one object could not be told from the two).
    fn redraw_pair(&mut self, b1: u32, b2: u32, rng: &mut Xoshiro256PlusPlus) {
        let comp = self.comp;
        let (c1, c2) = (self.label[b1 as usize], self.label[b2 as usize]);
        let cells = [c1, c2];
        let cells = &cells[..if c1 == c2 { 1 } else { 2 }];
        let total: usize = cells
            .iter()
            .map(|&c| self.cell_blocks[c as usize].len())
            .sum();
        let limit = self.pair_blocks;
        if total > limit && c1 == c2 {
            return;
        }
        // b1 first, b2 second, then the others: bit k of a split puts set[k + 2] with b2
        let mut others = std::mem::take(&mut self.pair_others);
        others.clear();
        for &c in cells {
            others.extend(
                self.cell_blocks[c as usize]
                    .iter()
                    .filter(|&&k| k != b1 && k != b2),
            );
        }
        // a draw that depends on the union of the two objects alone: the blocks in order,
        // then the first `limit - 2` of a partial Fisher-Yates shuffle
        let mut held = std::mem::take(&mut self.pair_held);
        held[0].clear();
        held[1].clear();
        if total > limit {
            others.sort_unstable();
            for i in 0..limit - 2 {
                let j = i + below(others.len() - i, rng);
                others.swap(i, j);
            }
            for &k in &others[limit - 2..] {
                held[usize::from(self.label[k as usize] != c1)].push(k);
            }
            others.truncate(limit - 2);
        }
        let mut set = [0u32; PAIR_BLOCKS];
        (set[0], set[1]) = (b1, b2);
        set[2..2 + others.len()].copy_from_slice(&others);
        let n = 2 + others.len();
        self.pair_others = others;
        let set = &set[..n];
        let mut clash = [0u32; PAIR_BLOCKS];
        for i in 0..n {
            for j in i + 1..n {
                let (x, y) = (&comp.blocks[set[i] as usize], &comp.blocks[set[j] as usize]);
                if !comp.compatible(x, y) {
                    clash[i] |= 1 << j;
                    clash[j] |= 1 << i;
                }
            }
        }
        // the drawn blocks that conflict with a block held with b1 (bit i) or with b2
        let mut held_clash = [0u32; 2];
        for (g, blocks) in held.iter().enumerate() {
            for (i, &k) in set.iter().enumerate() {
                let x = &comp.blocks[k as usize];
                if blocks
                    .iter()
                    .any(|&h| !comp.compatible(x, &comp.blocks[h as usize]))
                {
                    held_clash[g] |= 1 << i;
                }
            }
        }
        let feasible = |bits: u32| (0..n).all(|i| bits >> i & 1 == 0 || clash[i] & bits == 0);
        let mut tracks = std::mem::take(&mut self.pair_tracks);
        // the object of the drawn blocks `bits` and of the blocks held in it
        let mut weight = |ch: &mut Self, bits: u32, held: &[u32]| -> f64 {
            tracks.clear();
            for (i, &k) in set.iter().enumerate() {
                if bits >> i & 1 == 1 {
                    tracks.extend_from_slice(&comp.blocks[k as usize]);
                }
            }
            for &k in held {
                tracks.extend_from_slice(&comp.blocks[k as usize]);
            }
            ch.weight_of(&tracks)
        };
        let all = (1u32 << n) - 1;
        // the options: the bits of b2's object (0: one object of all), and their log-weight
        let mut options = std::mem::take(&mut self.pair_options);
        options.clear();
        let holds = !held[0].is_empty() || !held[1].is_empty();
        if !holds && feasible(all) {
            let w = weight(self, all, &[]);
            if w > f64::NEG_INFINITY {
                options.push((0, w));
            }
        }
        for split in 0..1u32 << (n - 2) {
            let with_b2 = 2 | split << 2;
            let with_b1 = all & !with_b2;
            if !feasible(with_b1)
                || !feasible(with_b2)
                || held_clash[0] & with_b1 != 0
                || held_clash[1] & with_b2 != 0
            {
                continue;
            }
            let w1 = weight(self, with_b1, &held[0]);
            if w1 == f64::NEG_INFINITY {
                continue;
            }
            let w2 = weight(self, with_b2, &held[1]);
            if w2 > f64::NEG_INFINITY {
                options.push((with_b2, w1 + w2));
            }
        }
        let beta = self.beta;
        let z = log_sum_exp(options.iter().map(|o| beta * o.1));
        let u = unit(rng);
        let mut acc = 0.0;
        let mut pick = options.len() - 1;
        for (i, o) in options.iter().enumerate() {
            acc += (beta * o.1 - z).exp();
            if u < acc {
                pick = i;
                break;
            }
        }
        let with_b2 = options[pick].0;
        // the buffers back to the chain for the next update
        self.pair_options = options;
        self.pair_tracks = tracks;
        self.pair_held = held;
        // b1's blocks stay in (or go to) c1; b2's go to c2, or to a free cell if c1 == c2
        let to = if with_b2 == 0 {
            c1
        } else if c1 == c2 {
            self.free.pop().expect("a free cell: one per block")
        } else {
            c2
        };
        for (i, &k) in set.iter().enumerate() {
            self.set(k, if with_b2 >> i & 1 == 1 { to } else { c1 });
        }
        self.refresh(c1);
        if to != c1 {
            self.refresh(to);
        }
        if c2 != c1 && c2 != to {
            self.refresh(c2);
            self.free.push(c2);
        }
    }

    /// Adds to `acc` the conditional probabilities, given where every other block is, that
    /// block `b` shares an object with each track it has a pair with, and that each of its
    /// tracks is alone (the Rao-Blackwellised estimate, from the untempered moves `fwd` of `b`).
    fn rao_blackwell(&self, b: u32, fwd: &[(Move, f64)], acc: &mut Conditionals) {
        let comp = self.comp;
        let old = self.label[b as usize];
        // b's placements that leave the other blocks where they are: its cell, a cell of its
        // own (`None`), or a cell it can join; with the partition's log-weight relative to the
        // current one
        let placement = |m: Move| match m {
            Move::Stay => Some(Some(old)),
            Move::Alone => Some(None),
            Move::Join(c) => Some(Some(c)),
            Move::Swap(..) => None,
        };
        let z = log_sum_exp(fwd.iter().filter(|m| placement(m.0).is_some()).map(|m| m.1));
        // the probability of each placement, by cell (a vague track has hundreds of pairs)
        let mut new_cell = 0.0;
        for &(m, d) in fwd {
            match placement(m) {
                Some(Some(c)) => acc.cell_p[c as usize] = (d - z).exp(),
                Some(None) => new_cell = (d - z).exp(),
                None => {}
            }
        }
        let mine = &comp.blocks[b as usize];
        let alone = if mine.len() > 1 {
            0.0
        } else if self.cell_blocks[old as usize].len() == 1 {
            acc.cell_p[old as usize]
        } else {
            new_cell
        };
        for &x in mine {
            acc.alone[x as usize] += alone;
            acc.alone_n[x as usize] += 1;
            for &(y, i) in &acc.incident[x as usize] {
                let by = comp.block_of[y as usize];
                acc.pair[i] += if by == b {
                    1.0
                } else {
                    acc.cell_p[self.label[by as usize] as usize]
                };
                acc.pair_n[i] += 1;
            }
        }
        for &(m, _) in fwd {
            if let Some(Some(c)) = placement(m) {
                acc.cell_p[c as usize] = 0.0;
            }
        }
    }

    /// One Metropolis-Hastings move of block `b`; on the untempered chain, with `acc`, it first
    /// adds the Rao-Blackwellised marginals of the current state.
    fn step(&mut self, b: u32, rng: &mut Xoshiro256PlusPlus, acc: Option<&mut Conditionals>) {
        let beta = self.beta;
        let mut fwd = std::mem::take(&mut self.bufs.fwd);
        self.moves(b, &mut fwd);
        if let Some(acc) = acc {
            debug_assert_eq!(beta, 1.0);
            self.rao_blackwell(b, &fwd, acc);
        }
        let lse_fwd = log_sum_exp(fwd.iter().map(|m| beta * m.1));
        let u = unit(rng);
        let mut acc = 0.0;
        let mut pick = fwd.len() - 1;
        for (i, m) in fwd.iter().enumerate() {
            acc += (beta * m.1 - lse_fwd).exp();
            if u < acc {
                pick = i;
                break;
            }
        }
        let (mv, delta) = fwd[pick];
        self.bufs.fwd = fwd;
        if matches!(mv, Move::Stay) {
            return;
        }
        let old = self.label[b as usize];
        let was_alone = self.cell_blocks[old as usize].len() == 1;
        self.apply(b, mv);
        let mut rev = std::mem::take(&mut self.bufs.rev);
        self.moves(b, &mut rev);
        let lse_rev = log_sum_exp(rev.iter().map(|m| beta * m.1));
        self.bufs.rev = rev;
        let log_accept = lse_fwd - beta * delta - lse_rev;
        if log_accept < 0.0 && unit(rng) >= log_accept.exp() {
            // undo with the inverse move (cell ids are arbitrary labels)
            let back = match mv {
                Move::Swap(_, ks, n) => Move::Swap(old, ks, n),
                _ if was_alone => Move::Alone,
                _ => Move::Join(old),
            };
            self.apply(b, back);
        }
    }
}

/// Running sums of the Rao-Blackwellised marginals of one chain: per pair of the component and
/// per track, the sum of the conditional probabilities at each visit of a block, and the number
/// of visits. A pair is estimated at the visits of its less precise track's block: a vague
/// track's placement given the rest weighs every ship that fits it at once, while a ship's
/// placement given the rest only sees whether the vague track sits alone at that moment.
struct Conditionals {
    /// Per local track, `(other track, index in the component's pairs)` of the pairs it is the
    /// less precise track of.
    incident: Vec<Vec<(u32, usize)>>,
    pair: Vec<f64>,
    pair_n: Vec<u32>,
    alone: Vec<f64>,
    alone_n: Vec<u32>,
    /// Scratch: the probability of the visited block's placement in each cell (0 elsewhere);
    /// cells are numbered below the number of blocks.
    cell_p: Vec<f64>,
}

impl Conditionals {
    fn new(comp: &Component) -> Self {
        let mut incident = vec![Vec::new(); comp.tracks.len()];
        for (i, &(_, a, b)) in comp.pairs.iter().enumerate() {
            let (vague, other) = if comp.rank[a as usize] > comp.rank[b as usize] {
                (a, b)
            } else {
                (b, a)
            };
            incident[vague as usize].push((other, i));
        }
        Self {
            incident,
            pair: vec![0.0; comp.pairs.len()],
            pair_n: vec![0; comp.pairs.len()],
            alone: vec![0.0; comp.tracks.len()],
            alone_n: vec![0; comp.tracks.len()],
            cell_p: vec![0.0; comp.blocks.len()],
        }
    }

    /// The chain's estimates: per pair, per track.
    fn means(&self) -> (Vec<f64>, Vec<f64>) {
        let mean = |s: &[f64], n: &[u32]| {
            s.iter()
                .zip(n)
                .map(|(&s, &n)| if n == 0 { 0.0 } else { s / f64::from(n) })
                .collect::<Vec<f64>>()
        };
        (
            mean(&self.pair, &self.pair_n),
            mean(&self.alone, &self.alone_n),
        )
    }
}

/// The feasible grouping that takes the strongest pairs first: the first chain's start.
fn greedy_start(comp: &Component) -> Vec<u32> {
    let mut edges: Vec<(f64, u32, u32)> = comp
        .pairs
        .iter()
        .map(|&(_, a, b)| (comp.edge(a, b).unwrap_or(f64::NEG_INFINITY), a, b))
        .filter(|e| e.0 > 0.0)
        .collect();
    edges.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    join_in_order(comp, edges.into_iter().map(|e| (e.1, e.2)))
}

/// A start drawn from the pairs' own odds, the other chains' starts: each pair is kept with
/// probability `1 / (1 + e^-L)`, as if it were alone, and the kept pairs are joined in random
/// order where feasible. Chains that start apart and still agree have forgotten their start;
/// chains that do not, show it in the standard error.
fn random_start(comp: &Component, rng: &mut Xoshiro256PlusPlus) -> Vec<u32> {
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for &(_, a, b) in &comp.pairs {
        if let Some(l) = comp.edge(a, b) {
            if unit(rng) * (1.0 + (-l).exp()) < 1.0 {
                edges.push((a, b));
            }
        }
    }
    for i in (1..edges.len()).rev() {
        let j = ((unit(rng) * (i + 1) as f64) as usize).min(i);
        edges.swap(i, j);
    }
    join_in_order(comp, edges.into_iter())
}

/// The grouping that joins the objects of the pairs `edges`, in order, where feasible.
fn join_in_order(comp: &Component, edges: impl Iterator<Item = (u32, u32)>) -> Vec<u32> {
    let nb = comp.blocks.len();
    let mut label: Vec<u32> = (0..nb as u32).collect();
    let mut cell: Vec<Vec<u32>> = (0..nb).map(|b| comp.blocks[b].clone()).collect();
    for (a, b) in edges {
        let (ca, cb) = (
            label[comp.block_of[a as usize] as usize],
            label[comp.block_of[b as usize] as usize],
        );
        if ca == cb || !comp.compatible(&cell[ca as usize], &cell[cb as usize]) {
            continue;
        }
        let moved = std::mem::take(&mut cell[cb as usize]);
        for l in label.iter_mut().filter(|l| **l == cb) {
            *l = ca;
        }
        cell[ca as usize].extend(moved);
    }
    label
}

fn marginals_of(comp: &Component, samples: &[Vec<u32>], weights: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut p_pair = vec![0.0; comp.pairs.len()];
    let mut p_alone = vec![0.0; comp.tracks.len()];
    let mut cell_size = Vec::new();
    for (s, &w) in samples.iter().zip(weights) {
        for (i, &(_, a, b)) in comp.pairs.iter().enumerate() {
            if s[comp.block_of[a as usize] as usize] == s[comp.block_of[b as usize] as usize] {
                p_pair[i] += w;
            }
        }
        cell_size.clear();
        cell_size.resize(s.len(), 0usize);
        for (blk, &l) in s.iter().enumerate() {
            cell_size[l as usize] += comp.blocks[blk].len();
        }
        for x in 0..comp.tracks.len() {
            if cell_size[s[comp.block_of[x] as usize] as usize] == 1 {
                p_alone[x] += w;
            }
        }
    }
    (p_pair, p_alone)
}

fn infer(comp: &Component, inf: &Inference) -> Marginals {
    if let Some((labels, logw)) = enumerate(comp, inf.exact_limit.max(1)) {
        let z = log_sum_exp(logw.iter().copied());
        let weights: Vec<f64> = logw.iter().map(|w| (w - z).exp()).collect();
        let (p_pair, p_alone) = marginals_of(comp, &labels, &weights);
        return Marginals {
            se_pair: vec![0.0; p_pair.len()],
            p_pair,
            p_alone,
            partitions: labels.len() as u64,
            method: Method::Exact,
            samples: labels,
            weights,
        };
    }
    sample(comp, inf, PAIR_BLOCKS)
}

/// The sampler's marginals of `comp`; [`Chain::redraw_pair`] redraws at most `pair_blocks`
/// (at least 3, at most [`PAIR_BLOCKS`]) blocks of two objects.
fn sample(comp: &Component, inf: &Inference, pair_blocks: usize) -> Marginals {
    debug_assert!((3..=PAIR_BLOCKS).contains(&pair_blocks));
    let greedy = greedy_start(comp);
    let nb = comp.blocks.len();
    let burn = inf.sweeps / 4;
    let first = comp.tracks[0] as u64;
    // the blocks each block has a candidate pair with (the partners of its two-object updates)
    let block_adj: Vec<Vec<u32>> = (0..nb)
        .map(|b| {
            let mut near: Vec<u32> = comp.blocks[b]
                .iter()
                .flat_map(|&x| comp.adj[x as usize].iter())
                .map(|e| comp.block_of[e.to as usize])
                .filter(|&k| k != b as u32)
                .collect();
            near.sort_unstable();
            near.dedup();
            near
        })
        .collect();
    let per_chain: Vec<(Vec<Vec<u32>>, Conditionals)> = (0..inf.chains)
        .into_par_iter()
        .map(|c| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(crate::rng::mix64(
                inf.seed ^ crate::rng::mix64(first.wrapping_mul(0x1_0000) ^ c as u64),
            ));
            // the first chain from the strongest pairs, the others from the pairs' own odds
            let own = (c > 0).then(|| random_start(comp, &mut rng));
            let start = own.as_deref().unwrap_or(&greedy);
            // parallel tempering: the chain at beta = 1 is the sample; hotter copies cross
            // the barriers that single-block moves cannot, and swap states with it
            let mut ladder: Vec<Chain> = TEMPERATURES
                .iter()
                .map(|&beta| {
                    let mut ch = Chain::new(comp, start);
                    ch.beta = beta;
                    ch.pair_blocks = pair_blocks;
                    ch
                })
                .collect();
            let mut kept = Vec::with_capacity(inf.sweeps);
            let mut acc = Conditionals::new(comp);
            for sweep in 0..burn + inf.sweeps {
                for (i, ch) in ladder.iter_mut().enumerate() {
                    let estimate = i == 0 && sweep >= burn;
                    for b in 0..nb as u32 {
                        ch.step(b, &mut rng, estimate.then_some(&mut acc));
                    }
                    // each block with a neighbour, or with a neighbour's neighbour: the
                    // AIS tracks of two ships an aircraft track fits both of (a choice that
                    // does not depend on the state, so each update keeps the posterior)
                    for (b, near) in block_adj.iter().enumerate() {
                        if let Some(&y) = pick(near, &mut rng) {
                            let z = match pick(&block_adj[y as usize], &mut rng) {
                                Some(&z) if z != b as u32 && unit(&mut rng) < 0.5 => z,
                                _ => y,
                            };
                            ch.redraw_pair(b as u32, z, &mut rng);
                        }
                    }
                }
                for i in 0..ladder.len() - 1 {
                    let (bi, bj) = (ladder[i].beta, ladder[i + 1].beta);
                    let log_r = (bi - bj) * (ladder[i + 1].logw - ladder[i].logw);
                    if log_r >= 0.0 || unit(&mut rng) < log_r.exp() {
                        ladder.swap(i, i + 1);
                        ladder[i].beta = bi;
                        ladder[i + 1].beta = bj;
                    }
                }
                if sweep >= burn {
                    kept.push(ladder[0].label.clone());
                }
            }
            (kept, acc)
        })
        .collect();
    // each chain's marginals are the means of the conditional probabilities at its visits
    // (Rao-Blackwell): a vague track's pairs with the tens of ships that fit it each get the
    // probability of joining that ship given the rest of the picture, not a count of the rare
    // sweeps it sat there
    let (chain_p, chain_a): (Vec<Vec<f64>>, Vec<Vec<f64>>) =
        per_chain.iter().map(|(_, acc)| acc.means()).unzip();
    let nc = inf.chains as f64;
    let mean_sd = |rows: &[Vec<f64>], i: usize| {
        let m = rows.iter().map(|r| r[i]).sum::<f64>() / nc;
        let v = rows.iter().map(|r| (r[i] - m).powi(2)).sum::<f64>() / (nc - 1.0);
        (m, (v / nc).sqrt())
    };
    let (p_pair, se_pair): (Vec<f64>, Vec<f64>) =
        (0..comp.pairs.len()).map(|i| mean_sd(&chain_p, i)).unzip();
    let p_alone: Vec<f64> = (0..comp.tracks.len())
        .map(|i| mean_sd(&chain_a, i).0)
        .collect();
    let samples: Vec<Vec<u32>> = per_chain.into_iter().flat_map(|(k, _)| k).collect();
    let w = 1.0 / samples.len() as f64;
    Marginals {
        p_pair,
        se_pair,
        p_alone,
        partitions: 0,
        method: Method::Sampled,
        weights: vec![w; samples.len()],
        samples,
    }
}

/// A uniformly drawn element of `xs`.
fn pick<'a, T>(xs: &'a [T], rng: &mut Xoshiro256PlusPlus) -> Option<&'a T> {
    xs.get(below(xs.len(), rng))
}

/// A uniform index in `0..n` (`0` when `n` is 0).
fn below(n: usize, rng: &mut Xoshiro256PlusPlus) -> usize {
    ((unit(rng) * n as f64) as usize).min(n.saturating_sub(1))
}

/// Most pairs a review value looks at beyond those sharing a track with the pair.
const NEAR_BUDGET: usize = 256;

/// The review value of every pair of a component: the expected probability mass of true pairs
/// a decision on it settles, the reduction of `U = sum_q p_q` over the undecided pairs `q` (those
/// in `(p_reject, p_match)`: the expected number of true pairs still waiting for the operator)
/// among the pair itself and the pairs of the component that share a track with it or (up to
/// [`NEAR_BUDGET`] of them) with a pair sharing a track with it, from deciding it (`p` "same",
/// `1 - p` "different"); and how many of those pairs each answer takes out of the band. Since
/// the conditionals average to the marginals, the reduction is the expected mass of the pairs
/// that leave the band: those confirmed or taken to `match`, at nearly their whole mass, and
/// those taken to `non-match`, at almost none.
fn review_gain(
    comp: &Component,
    m: &Marginals,
    p_reject: f64,
    p_match: f64,
) -> (Vec<f64>, Vec<(u32, u32)>) {
    let np = comp.pairs.len();
    let undecided = |p: f64| p > p_reject && p < p_match;
    let mut gain = vec![0.0; np];
    let mut settles = vec![(0u32, 0u32); np];
    // pairs by local track
    let mut by_track: Vec<Vec<usize>> = vec![Vec::new(); comp.tracks.len()];
    for (i, &(_, a, b)) in comp.pairs.iter().enumerate() {
        by_track[a as usize].push(i);
        by_track[b as usize].push(i);
    }
    let same_in = |s: &[u32], i: usize| {
        let (_, a, b) = comp.pairs[i];
        s[comp.block_of[a as usize] as usize] == s[comp.block_of[b as usize] as usize]
    };
    let decided: Vec<usize> = (0..np).filter(|&i| undecided(m.p_pair[i])).collect();
    let results: Vec<(usize, f64, (u32, u32))> = decided
        .par_iter()
        .map(|&i| {
            let (_, a, b) = comp.pairs[i];
            // neighbourhood: the undecided pairs sharing a track with i, then those sharing a
            // track with one of them while the neighbourhood stays within NEAR_BUDGET (the
            // cost is neighbourhood x samples per pair: an HF DF fix with 300 candidates would
            // otherwise look at tens of thousands of pairs for every one of its own)
            let undecided_of = |t: u32| {
                by_track[t as usize]
                    .iter()
                    .copied()
                    .filter(|&q| q != i && undecided(m.p_pair[q]))
            };
            let mut near: Vec<usize> = undecided_of(a).chain(undecided_of(b)).collect();
            near.sort_unstable();
            near.dedup();
            let first = near.clone();
            for &q in &first {
                let (_, qa, qb) = comp.pairs[q];
                let more: Vec<usize> = undecided_of(qa).chain(undecided_of(qb)).collect();
                if near.len() + more.len() > NEAR_BUDGET {
                    break;
                }
                near.extend(more);
                near.sort_unstable();
                near.dedup();
            }
            let mut w_same = 0.0;
            let mut joint = vec![0.0; near.len()];
            let mut marg = vec![0.0; near.len()];
            for (s, &w) in m.samples.iter().zip(&m.weights) {
                let si = same_in(s, i);
                if si {
                    w_same += w;
                }
                for (j, &q) in near.iter().enumerate() {
                    if same_in(s, q) {
                        marg[j] += w;
                        if si {
                            joint[j] += w;
                        }
                    }
                }
            }
            let total: f64 = m.weights.iter().sum();
            let p = w_same / total;
            // the probability of being a true pair still in the band
            let u = |x: f64| if undecided(x) { x } else { 0.0 };
            let mut before = u(m.p_pair[i]);
            let mut after = 0.0;
            let (mut s_same, mut s_diff) = (0u32, 0u32);
            for j in 0..near.len() {
                let pq = marg[j] / total;
                let c_same = if w_same > 0.0 { joint[j] / w_same } else { pq };
                let c_diff = if total - w_same > 0.0 {
                    (marg[j] - joint[j]) / (total - w_same)
                } else {
                    pq
                };
                before += u(pq);
                after += p * u(c_same) + (1.0 - p) * u(c_diff);
                s_same += u32::from(!undecided(c_same));
                s_diff += u32::from(!undecided(c_diff));
            }
            (i, (before - after).max(0.0), (s_same, s_diff))
        })
        .collect();
    for (i, g, s) in results {
        gain[i] = g;
        settles[i] = s;
    }
    (gain, settles)
}

/// The posterior of every pair and track (see the module docs). `pairs[k]` has log-likelihood
/// ratio `evidence[k].llr`, of which `evidence[k].own` are the terms of its two tracks alone
/// (the log-odds that each is not a false track, counted once per object); `p_reject` and `p_match` bound the band
/// in which review values are computed. A component found unchanged in `memo` (an earlier
/// call's [`Posterior::memo`]) is taken from it instead of computed again; the result is the
/// same.
#[allow(clippy::too_many_arguments)]
pub fn posterior(
    tracks: &[Track],
    cover: &TimeCover,
    pairs: &[(u32, u32)],
    evidence: &[PairEvidence],
    decisions: &[Decision],
    inf: &Inference,
    band: (f64, f64),
    memo: Option<&Memo>,
) -> Result<Posterior> {
    if evidence.len() != pairs.len() {
        return Err(Error::LengthMismatch {
            left: pairs.len(),
            right: evidence.len(),
        });
    }
    if let Some(k) = evidence.iter().position(|e| e.llr.is_nan()) {
        return Err(Error::Invalid(format!(
            "pair {k}: log-likelihood ratio is NaN"
        )));
    }
    let inf = inf.validated()?;
    if cover.len() != tracks.len() {
        return Err(Error::LengthMismatch {
            left: tracks.len(),
            right: cover.len(),
        });
    }
    let comps = components(tracks, cover, pairs, evidence, decisions)?;
    let solved: Vec<(std::sync::Arc<Solved>, bool)> = comps
        .into_par_iter()
        .map(|comp| {
            if let Some(s) = memo.and_then(|m| m.get(&comp, &inf, band)) {
                return (s.clone(), true);
            }
            let m = infer(&comp, &inf);
            let (gain, settles) = review_gain(&comp, &m, band.0, band.1);
            let s = Solved {
                comp,
                inf,
                band,
                p_pair: m.p_pair,
                se_pair: m.se_pair,
                p_alone: m.p_alone,
                gain,
                settles,
                partitions: m.partitions,
                method: m.method,
            };
            (std::sync::Arc::new(s), false)
        })
        .collect();
    let mut out = Posterior {
        p_same: vec![0.0; pairs.len()],
        std_error: vec![0.0; pairs.len()],
        p_alone: vec![1.0; tracks.len()],
        component: vec![u32::MAX; pairs.len()],
        components: Vec::with_capacity(solved.len()),
        gain: vec![0.0; pairs.len()],
        settles: vec![(0, 0); pairs.len()],
        memo: Memo::default(),
    };
    for (c, (s, reused)) in solved.into_iter().enumerate() {
        let comp = &s.comp;
        for (i, &(k, a, b)) in comp.pairs.iter().enumerate() {
            // decided pairs are certain, not merely close to it
            out.p_same[k] = if comp.block_of[a as usize] == comp.block_of[b as usize] {
                1.0
            } else if comp.different(a, b) {
                0.0
            } else {
                s.p_pair[i].clamp(0.0, 1.0)
            };
            out.std_error[k] = s.se_pair[i];
            out.component[k] = c as u32;
            out.gain[k] = s.gain[i];
            out.settles[k] = s.settles[i];
        }
        for (x, &t) in comp.tracks.iter().enumerate() {
            out.p_alone[t as usize] = s.p_alone[x].clamp(0.0, 1.0);
        }
        out.components.push(ComponentInfo {
            tracks: comp.tracks.len() as u32,
            partitions: s.partitions,
            method: s.method,
            max_std_error: s.se_pair.iter().copied().fold(0.0, f64::max),
            reused,
        });
        out.memo.0.insert(comp.tracks[0], s);
    }
    Ok(out)
}

/// Objects from the confident pairs: tracks joined by pairs with `p_same >= p_match` (and by
/// decisions "same"), a join that would put two conflicting tracks (or two tracks declared
/// different) in one object being skipped. Returns the object of every track (dense ids,
/// numbered by their smallest track) and, per pair, whether it was joined.
pub fn objects(
    tracks: &[Track],
    pairs: &[(u32, u32)],
    p_same: &[f64],
    decisions: &[Decision],
    p_match: f64,
) -> (Vec<u32>, Vec<bool>) {
    let n = tracks.len();
    let mut root: Vec<u32> = (0..n as u32).collect();
    let mut members: Vec<Vec<u32>> = (0..n as u32).map(|t| vec![t]).collect();
    let mut different: Vec<(u32, u32)> = decisions
        .iter()
        .filter(|d| !d.same)
        .map(|d| (d.a.min(d.b), d.a.max(d.b)))
        .collect();
    different.sort_unstable();
    let mut order: Vec<usize> = (0..pairs.len()).filter(|&k| p_same[k] >= p_match).collect();
    order.sort_by(|&i, &j| {
        p_same[j]
            .total_cmp(&p_same[i])
            .then(pairs[i].cmp(&pairs[j]))
    });
    let forced: Vec<(u32, u32)> = decisions
        .iter()
        .filter(|d| d.same)
        .map(|d| (d.a, d.b))
        .collect();
    let mut joined = vec![false; pairs.len()];
    let join = |a: u32, b: u32, root: &mut Vec<u32>, members: &mut Vec<Vec<u32>>| {
        let (ra, rb) = (root[a as usize], root[b as usize]);
        if ra == rb {
            return true;
        }
        let ok = members[ra as usize].iter().all(|&x| {
            members[rb as usize].iter().all(|&y| {
                !tracks[x as usize].conflicts(&tracks[y as usize])
                    && different.binary_search(&(x.min(y), x.max(y))).is_err()
            })
        });
        if !ok {
            return false;
        }
        let (big, small) = if members[ra as usize].len() >= members[rb as usize].len() {
            (ra, rb)
        } else {
            (rb, ra)
        };
        let moved = std::mem::take(&mut members[small as usize]);
        for &x in &moved {
            root[x as usize] = big;
        }
        members[big as usize].extend(moved);
        true
    };
    for (a, b) in forced {
        join(a, b, &mut root, &mut members);
    }
    for k in order {
        let (a, b) = pairs[k];
        joined[k] = join(a, b, &mut root, &mut members);
    }
    let mut id = vec![u32::MAX; n];
    let mut next = 0u32;
    let mut object = vec![0u32; n];
    for t in 0..n {
        let r = root[t] as usize;
        if id[r] == u32::MAX {
            id[r] = next;
            next += 1;
        }
        object[t] = id[r];
    }
    different.clear();
    (object, joined)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tr(source: u32, start: f64, end: f64, spread: f64) -> Track {
        Track {
            source,
            start,
            end,
            spread,
            further: 0.0,
        }
    }

    /// Pair evidence without track terms.
    fn own(llr: &[f64]) -> Vec<PairEvidence> {
        llr.iter()
            .map(|&llr| PairEvidence {
                llr,
                own: (0.0, 0.0),
                k_eff: 1.0,
                fit: 0.0,
                motion: (0.0, 0.0),
            })
            .collect()
    }

    fn whole(tracks: &[Track]) -> TimeCover {
        // one chain per track over its whole span
        let spans = tracks.iter().map(|t| [t.start, t.end]).collect();
        let reports = vec![1; tracks.len()];
        TimeCover::from_parts((0..=tracks.len() as u32).collect(), spans, reports, 0.0).unwrap()
    }

    #[test]
    fn two_tracks_are_a_logistic_of_their_ratio() {
        let tracks = [tr(0, 0.0, 10.0, 1.0), tr(1, 0.0, 10.0, 2.0)];
        for l in [-5.0, 0.0, 2.0, 7.0] {
            let p = posterior(
                &tracks,
                &whole(&tracks),
                &[(0, 1)],
                &own(&[l]),
                &[],
                &Inference::default(),
                (0.01, 0.99),
                None,
            )
            .unwrap();
            let want = 1.0 / (1.0 + (-l).exp());
            assert!((p.p_same[0] - want).abs() < 1e-12, "{l}: {}", p.p_same[0]);
            assert!((p.p_alone[0] - (1.0 - want)).abs() < 1e-12);
        }
    }

    /// A random component: `n` tracks of 3 sources with random spans, every pair of different
    /// sources a candidate with a random ratio.
    fn random_component(seed: u64, n: usize) -> (Vec<Track>, Vec<(u32, u32)>, Vec<f64>) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let tracks: Vec<Track> = (0..n)
            .map(|_| {
                let s = (rng.next_u64() % 3) as u32;
                let t0 = unit(&mut rng) * 10.0;
                tr(s, t0, t0 + 2.0 + unit(&mut rng) * 8.0, unit(&mut rng))
            })
            .collect();
        let mut pairs = Vec::new();
        let mut llr = Vec::new();
        for a in 0..n as u32 {
            for b in a + 1..n as u32 {
                if tracks[a as usize].source != tracks[b as usize].source && unit(&mut rng) < 0.7 {
                    pairs.push((a, b));
                    llr.push(unit(&mut rng) * 8.0 - 3.0);
                }
            }
        }
        (tracks, pairs, llr)
    }

    /// The posterior of one component by the sampler alone (enumeration off).
    fn sampled(
        tracks: &[Track],
        pairs: &[(u32, u32)],
        llr: &[f64],
        sweeps: usize,
        seed: u64,
    ) -> Posterior {
        let inf = Inference {
            exact_limit: 0,
            chains: 4,
            sweeps,
            seed,
        };
        let p = posterior(
            tracks,
            &whole(tracks),
            pairs,
            &own(llr),
            &[],
            &inf,
            (0.01, 0.99),
            None,
        )
        .unwrap();
        // (a lone track's one partition is enumerated whatever the limit)
        assert!(p
            .components
            .iter()
            .all(|c| c.tracks == 1 || c.method == Method::Sampled));
        p
    }

    #[test]
    fn the_sampler_agrees_with_enumeration() {
        let mut worst: f64 = 0.0;
        for seed in 0..8 {
            let (tracks, pairs, llr) = random_component(seed, 7);
            let exact = posterior(
                &tracks,
                &whole(&tracks),
                &pairs,
                &own(&llr),
                &[],
                &Inference::default(),
                (0.01, 0.99),
                None,
            )
            .unwrap();
            assert!(exact.components.iter().all(|c| c.method == Method::Exact));
            let sampled = sampled(&tracks, &pairs, &llr, 2500, seed);
            for k in 0..pairs.len() {
                let err = (exact.p_same[k] - sampled.p_same[k]).abs();
                worst = worst.max(err);
                // within 5 standard errors (and 0.01 for marginals the chains all agree on)
                assert!(
                    err <= 5.0 * sampled.std_error[k] + 0.02,
                    "seed {seed} pair {k}: exact {} sampled {} +- {}",
                    exact.p_same[k],
                    sampled.p_same[k],
                    sampled.std_error[k]
                );
            }
            for t in 0..tracks.len() {
                assert!((exact.p_alone[t] - sampled.p_alone[t]).abs() < 0.05);
            }
        }
        assert!(worst < 0.05, "worst {worst}");
    }

    /// The bit matrix of which tracks may share an object answers as the rules do, on random
    /// components with pairs left out (tracks with a common instant and no pair are apart) and
    /// decisions "different", for single tracks and for groups of them.
    #[test]
    fn the_clash_matrix_answers_as_the_rules() {
        for seed in 0..6 {
            let (tracks, mut pairs, mut llr) = random_component(seed, 11);
            // every third pair left out: apart where the two tracks meet
            let keep: Vec<bool> = (0..pairs.len()).map(|k| k % 3 != 1).collect();
            let mut it = keep.iter();
            pairs.retain(|_| *it.next().unwrap());
            let mut it = keep.iter();
            llr.retain(|_| *it.next().unwrap());
            let dec: Vec<Decision> = pairs
                .iter()
                .step_by(4)
                .enumerate()
                .map(|(row, &(a, b))| Decision {
                    a,
                    b,
                    same: false,
                    row,
                })
                .collect();
            let comps = components(&tracks, &whole(&tracks), &pairs, &own(&llr), &dec).unwrap();
            let (mut apart, mut different, mut clash) = (0, 0, 0);
            for comp in &comps {
                assert!(!comp.clash.is_empty());
                apart += comp.apart.len();
                different += comp.different.len();
                let m = comp.tracks.len() as u32;
                for x in 0..m {
                    for y in 0..m {
                        let rules = x == y || comp.pair_compatible(x, y);
                        assert_eq!(comp.compatible(&[x], &[y]), rules, "seed {seed} ({x}, {y})");
                        clash += usize::from(!rules);
                    }
                }
                for x in 0..m.saturating_sub(2) {
                    let (xs, ys) = ([x, x + 1], [x + 2]);
                    let rules = xs
                        .iter()
                        .all(|&a| ys.iter().all(|&b| comp.pair_compatible(a, b)));
                    assert_eq!(comp.compatible(&xs, &ys), rules);
                }
            }
            // the rules were exercised: apart pairs, decisions and clashes
            assert!(apart > 0 && different > 0 && clash > 0, "seed {seed}");
        }
    }

    /// A memo from an earlier call: the same inputs take every component from it; under a
    /// decision, the components the decision does not touch are taken from it and the one it
    /// touches is computed again, and the result is the one computed from scratch, bit for
    /// bit. Sampled components (enumeration off), so that a stale result would show.
    #[test]
    fn decisions_recompute_only_the_components_they_change() {
        let (t1, p1, l1) = random_component(3, 7);
        let (t2, p2, l2) = random_component(4, 7);
        let n1 = t1.len() as u32;
        let tracks: Vec<Track> = t1.iter().chain(&t2).copied().collect();
        let pairs: Vec<(u32, u32)> = p1
            .iter()
            .copied()
            .chain(p2.iter().map(|&(a, b)| (a + n1, b + n1)))
            .collect();
        let llr: Vec<f64> = l1.iter().chain(&l2).copied().collect();
        let inf = Inference {
            exact_limit: 0,
            chains: 4,
            sweeps: 200,
            seed: 5,
        };
        let cover = whole(&tracks);
        let ev = own(&llr);
        let run = |dec: &[Decision], memo: Option<&Memo>| {
            posterior(&tracks, &cover, &pairs, &ev, dec, &inf, (0.01, 0.99), memo).unwrap()
        };
        let base = run(&[], None);
        assert!(base.components.iter().all(|c| !c.reused));
        assert_eq!(base.memo.len(), base.components.len());
        // the same result, bit for bit (every field but `reused`)
        let same = |x: &Posterior, y: &Posterior| {
            let bits = |v: &Vec<f64>| v.iter().map(|p| p.to_bits()).collect::<Vec<u64>>();
            for (u, v) in [
                (&x.p_same, &y.p_same),
                (&x.std_error, &y.std_error),
                (&x.p_alone, &y.p_alone),
                (&x.gain, &y.gain),
            ] {
                assert_eq!(bits(u), bits(v));
            }
            assert_eq!(x.settles, y.settles);
            assert_eq!(x.component, y.component);
            let info = |p: &Posterior| {
                p.components
                    .iter()
                    .map(|c| ComponentInfo {
                        reused: false,
                        ..*c
                    })
                    .collect::<Vec<_>>()
            };
            assert_eq!(info(x), info(y));
        };
        let again = run(&[], Some(&base.memo));
        assert!(again.components.iter().all(|c| c.reused));
        same(&again, &base);
        // "different" on the second part's strongest pair
        let k = (p1.len()..pairs.len())
            .max_by(|&i, &j| llr[i].total_cmp(&llr[j]))
            .unwrap();
        let (a, b) = pairs[k];
        let dec = [Decision {
            a,
            b,
            same: false,
            row: 0,
        }];
        let fresh = run(&dec, None);
        let reused = run(&dec, Some(&base.memo));
        let touched = fresh.component[k] as usize;
        for (c, info) in reused.components.iter().enumerate() {
            assert_eq!(info.reused, c != touched, "component {c}");
        }
        same(&fresh, &reused);
        // the decision moved the touched component's other pairs (the memo's were stale)
        let moved = (0..pairs.len())
            .filter(|&i| i != k && fresh.component[i] as usize == touched)
            .any(|i| (fresh.p_same[i] - base.p_same[i]).abs() > 0.01);
        assert!(moved);
        assert_eq!(reused.p_same[k], 0.0);
    }

    /// The two-object update with blocks held keeps the posterior: with at most 3 blocks
    /// redrawn (the two chosen and one drawn), every update of two objects of more than 3
    /// blocks between them holds the others, on the random components above; the marginals
    /// agree with enumeration as the full sampler's do.
    #[test]
    fn the_two_object_update_with_blocks_held_agrees_with_enumeration() {
        let mut worst: f64 = 0.0;
        for seed in 0..8 {
            let (tracks, pairs, llr) = random_component(seed, 7);
            let comps = components(&tracks, &whole(&tracks), &pairs, &own(&llr), &[]).unwrap();
            for comp in &comps {
                let exact = infer(comp, &Inference::default());
                assert_eq!(exact.method, Method::Exact);
                let inf = Inference {
                    exact_limit: 0,
                    chains: 4,
                    sweeps: 2500,
                    seed,
                };
                let sampled = sample(comp, &inf, 3);
                for (i, (&e, (&p, &se))) in exact
                    .p_pair
                    .iter()
                    .zip(sampled.p_pair.iter().zip(&sampled.se_pair))
                    .enumerate()
                {
                    worst = worst.max((e - p).abs());
                    assert!(
                        (e - p).abs() <= 5.0 * se + 0.02,
                        "seed {seed} pair {i}: exact {e} sampled {p} +- {se}"
                    );
                }
            }
        }
        assert!(worst < 0.05, "worst {worst}");
    }

    /// Every pair is found from both of its tracks, with its own ratio, through the rows of
    /// neighbours the sampler searches, whatever order the pairs come in; and no other.
    #[test]
    fn every_pair_is_found_from_both_its_tracks() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        for seed in 0..6 {
            let (tracks, mut pairs, mut llr) = random_component(seed, 12);
            for i in (1..pairs.len()).rev() {
                let j = below(i + 1, &mut rng);
                pairs.swap(i, j);
                llr.swap(i, j);
                let (a, b) = pairs[i];
                if unit(&mut rng) < 0.5 {
                    pairs[i] = (b, a);
                }
            }
            let comps = components(&tracks, &whole(&tracks), &pairs, &own(&llr), &[]).unwrap();
            let mut found = 0;
            for comp in &comps {
                for x in 0..comp.tracks.len() as u32 {
                    for y in 0..comp.tracks.len() as u32 {
                        let (gx, gy) = (comp.tracks[x as usize], comp.tracks[y as usize]);
                        let want = pairs
                            .iter()
                            .position(|&p| p == (gx, gy) || p == (gy, gx))
                            .map(|k| llr[k]);
                        assert_eq!(comp.edge(x, y), want, "seed {seed}: {gx} {gy}");
                        found += usize::from(want.is_some());
                    }
                }
            }
            assert_eq!(found, 2 * pairs.len(), "seed {seed}");
        }
    }

    #[test]
    fn a_vague_track_over_many_ships_is_estimated_exactly() {
        // an HF DF fix (source 1) over twelve concurrent AIS ships (source 0): it is alone or
        // with one ship, so p(ship i) = e^L_i / (1 + sum_j e^L_j) in closed form. Only the fix
        // moves between partitions, and its placement given the rest is exactly that law at
        // every visit: the Rao-Blackwellised sampler must give it to rounding, where counting
        // the sweeps the fix sits on each ship errs by about 0.001.
        let n = 12u32;
        let mut tracks: Vec<Track> = (0..n).map(|_| tr(0, 0.0, 10.0, 0.1)).collect();
        tracks.push(tr(1, 0.0, 10.0, 30.0));
        let pairs: Vec<(u32, u32)> = (0..n).map(|i| (i, n)).collect();
        let llr: Vec<f64> = (0..n).map(|i| -3.5 + 0.4 * f64::from(i)).collect();
        let z = 1.0 + llr.iter().map(|l| l.exp()).sum::<f64>();
        let sampled = sampled(&tracks, &pairs, &llr, 100, 3);
        for (k, l) in llr.iter().enumerate() {
            let want = l.exp() / z;
            assert!(
                (sampled.p_same[k] - want).abs() < 1e-9,
                "pair {k}: {} against {want}",
                sampled.p_same[k]
            );
            assert!(sampled.std_error[k] < 1e-9);
        }
        assert!((sampled.p_alone[n as usize] - 1.0 / z).abs() < 1e-9);
    }

    #[test]
    fn two_rivals_for_one_ship_trade_places_in_one_move() {
        // a ship seen by AIS (source 0) and radar (source 2), bound together overwhelmingly,
        // and two concurrent aircraft tracks (source 1) that both fit it well: by symmetry each
        // is the ship's with probability 1/2. From the greedy start (one on the ship, the other
        // alone) the chain must swap them in one move; by "leave" then "join" it would cross a
        // valley of e^-100, which even the hottest copy (e^-12) does not cross, and splitting
        // the ship between them costs as much.
        let tracks = [
            tr(0, 0.0, 10.0, 0.1),
            tr(2, 0.0, 10.0, 0.5),
            tr(1, 0.0, 10.0, 1.0),
            tr(1, 0.0, 10.0, 1.0),
        ];
        let pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3)];
        let llr = [200.0, 100.0, 100.0, 100.0, 100.0];
        let sampled = sampled(&tracks, &pairs, &llr, 400, 5);
        assert!(sampled.p_same[0] > 1.0 - 1e-9, "{}", sampled.p_same[0]);
        for k in 1..5 {
            near_half(&sampled, k);
        }
    }

    #[test]
    fn two_ships_exchange_an_aircraft_s_tracks_in_one_update() {
        // two ships, each seen by AIS (source 0) and radar (source 2) bound together, and two
        // passes of one aircraft (source 1, at different times) that fit both ships equally
        // and are bound to each other (a second track of the aircraft in an object weighs
        // e^200): the passes go with one ship or the other, 1/2 each. Single-block moves
        // cross from one to the other only through a state with a pass on each ship (e^-200
        // below; e^-24 in the hottest copy); the two-object update of the ships' AIS tracks
        // (neighbours through a pass) redraws both objects at once.
        let mut pass = [tr(1, 0.0, 10.0, 1.0), tr(1, 20.0, 30.0, 1.0)];
        for t in &mut pass {
            t.further = 200.0;
        }
        let tracks = [
            tr(0, 0.0, 30.0, 0.1),
            tr(2, 0.0, 30.0, 0.5),
            tr(0, 0.0, 30.0, 0.1),
            tr(2, 0.0, 30.0, 0.5),
            pass[0],
            pass[1],
        ];
        let pairs = [
            (0, 1),
            (2, 3),
            (0, 4),
            (1, 4),
            (2, 4),
            (3, 4),
            (0, 5),
            (1, 5),
            (2, 5),
            (3, 5),
        ];
        let llr = [
            200.0, 200.0, 100.0, 100.0, 100.0, 100.0, 100.0, 100.0, 100.0, 100.0,
        ];
        let exact = exact(&tracks, &pairs, &llr, &[]);
        let sampled = sampled(&tracks, &pairs, &llr, 400, 3);
        for k in 2..pairs.len() {
            assert!((exact.p_same[k] - 0.5).abs() < 1e-9, "{}", exact.p_same[k]);
            near_half(&sampled, k);
        }
    }

    /// Two moored ships (AIS tracks 0 and 7, source 0, over `0..root_end`), each with six
    /// tracks of sources 2-7 paired with it at `L = 200`, at the times `extra(source)`, and
    /// an aircraft's two passes (source 1, at 0-10 and 20-30 s, bound together: `further =
    /// 200`), each paired with ship 0's AIS track at `pass_llr[0]` and ship 1's at
    /// `pass_llr[1]`. The passes' four pairs come last: pass 0 with ship 0, with ship 1,
    /// then pass 1 likewise.
    fn two_ships_and_passes(
        root_end: f64,
        extra: impl Fn(u32) -> (f64, f64),
        pass_llr: [f64; 2],
    ) -> (Vec<Track>, Vec<(u32, u32)>, Vec<f64>) {
        let mut tracks = Vec::new();
        let mut pairs = Vec::new();
        let mut llr = Vec::new();
        for _ in 0..2 {
            let root = tracks.len() as u32;
            tracks.push(tr(0, 0.0, root_end, 0.1));
            for source in 2..8 {
                pairs.push((root, tracks.len() as u32));
                llr.push(200.0);
                let (start, end) = extra(source);
                tracks.push(tr(source, start, end, 0.5));
            }
        }
        for (start, end) in [(0.0, 10.0), (20.0, 30.0)] {
            let mut pass = tr(1, start, end, 2.0);
            pass.further = 200.0;
            for (root, l) in [(0, pass_llr[0]), (7, pass_llr[1])] {
                pairs.push((root, tracks.len() as u32));
                llr.push(l);
            }
            tracks.push(pass);
        }
        (tracks, pairs, llr)
    }

    #[test]
    fn chains_that_start_apart_report_the_modes_they_cannot_join() {
        // as above, but each ship also has six tracks of six more sources over the passes'
        // times, with no pair between them or with the passes: an object holds at most one of
        // them, and not with a pass. Each ship holds its AIS track and either both passes or
        // one of its six tracks, and the passes cross from one ship to the other only if the
        // other ship's track leaves for an object of its own at the same time: three objects,
        // which no move of the sampler changes at once. By symmetry each pass is each ship's
        // with probability 1/2. Chains that all start where the strongest pairs put the
        // passes agree on one ship with a standard error of 0; chains that start from the
        // pairs' own odds (the passes on either ship, or one on each, from which they fall to
        // either) disagree, and the standard error says so.
        let (tracks, pairs, llr) = two_ships_and_passes(30.0, |_| (0.0, 30.0), [100.0, 100.0]);
        let inf = Inference {
            exact_limit: 0,
            chains: 16,
            sweeps: 100,
            seed: 1,
        };
        let p = posterior(
            &tracks,
            &whole(&tracks),
            &pairs,
            &own(&llr),
            &[],
            &inf,
            (0.01, 0.99),
            None,
        )
        .unwrap();
        // the pairs of the passes with the ships' AIS tracks
        for k in pairs.len() - 4..pairs.len() {
            assert!(
                p.std_error[k] > 0.05 && (p.p_same[k] - 0.5).abs() <= 4.0 * p.std_error[k],
                "pair {k}: {} +- {}",
                p.p_same[k],
                p.std_error[k]
            );
        }
    }

    /// Two moored ships, each an AIS track and six short tracks of six more sources (16 blocks
    /// between them, beyond the two-object update's [`PAIR_BLOCKS`]), and a patrol aircraft's
    /// two passes, which belong together (`further`: a break of one aircraft track costs
    /// e^-200) and fit ship 0 by e^1 better each. Exactly: both passes on ship 0 with
    /// probability e^2 / (1 + e^2) = 0.881. No move of one block takes a pass across (it
    /// would leave the other behind), so a chain that starts with them on ship 1 stays there;
    /// the update that redraws ten of the two ships' blocks, the others held, takes both across.
    #[test]
    fn two_ships_beyond_the_two_object_update_exchange_their_passes() {
        // the six tracks at times of their own: two tracks with a common instant and no pair
        // between them are two objects
        let (tracks, pairs, llr) = two_ships_and_passes(
            70.0,
            |source| {
                let t = 40.0 + 5.0 * f64::from(source);
                (t, t + 4.0)
            },
            [101.0, 100.0],
        );
        let run = |inf: &Inference| {
            posterior(
                &tracks,
                &whole(&tracks),
                &pairs,
                &own(&llr),
                &[],
                inf,
                (0.01, 0.99),
                None,
            )
            .unwrap()
        };
        let exact = run(&Inference {
            exact_limit: 1_000_000,
            ..Inference::default()
        });
        assert_eq!(exact.components[0].method, Method::Exact);
        let e2 = 2.0f64.exp();
        let sampled = run(&Inference {
            exact_limit: 0,
            chains: 4,
            sweeps: 400,
            seed: 3,
        });
        for k in pairs.len() - 4..pairs.len() {
            let want = if k % 2 == 0 {
                e2 / (1.0 + e2)
            } else {
                1.0 / (1.0 + e2)
            };
            assert!((exact.p_same[k] - want).abs() < 1e-9, "{}", exact.p_same[k]);
            assert!(
                (sampled.p_same[k] - want).abs() < 0.05,
                "pair {k}: {} +- {} against {want}",
                sampled.p_same[k],
                sampled.std_error[k]
            );
        }
    }

    /// The sampled marginal of pair `k` is 1/2 within 0.1.
    fn near_half(sampled: &Posterior, k: usize) {
        assert!(
            (sampled.p_same[k] - 0.5).abs() < 0.1,
            "pair {k}: {} +- {}",
            sampled.p_same[k],
            sampled.std_error[k]
        );
    }

    fn exact(tracks: &[Track], pairs: &[(u32, u32)], llr: &[f64], dec: &[Decision]) -> Posterior {
        with_evidence(tracks, &whole(tracks), pairs, &own(llr), dec)
    }

    /// The posterior with the default inference.
    fn with_evidence(
        tracks: &[Track],
        cover: &TimeCover,
        pairs: &[(u32, u32)],
        evidence: &[PairEvidence],
        dec: &[Decision],
    ) -> Posterior {
        posterior(
            tracks,
            cover,
            pairs,
            evidence,
            dec,
            &Inference::default(),
            (0.01, 0.99),
            None,
        )
        .unwrap()
    }

    #[test]
    fn three_tracks_of_three_sources_by_hand() {
        // A (most precise), B, C: all at one time, all pairs candidates
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 0.0, 10.0, 2.0),
            tr(2, 0.0, 10.0, 3.0),
        ];
        let (ab, ac, bc) = (1.5_f64, -0.5_f64, 2.5_f64);
        let p = exact(&tracks, &[(0, 1), (0, 2), (1, 2)], &[ab, ac, bc], &[]);
        // partitions: {A}{B}{C}, {AB}{C}, {AC}{B}, {BC}{A}, {ABC} (B and C both join A, the
        // most precise: ab + ac)
        let w = [1.0, ab.exp(), ac.exp(), bc.exp(), (ab + ac).exp()];
        let z: f64 = w.iter().sum();
        let want = [(w[1] + w[4]) / z, (w[2] + w[4]) / z, (w[3] + w[4]) / z];
        for (k, w) in want.iter().enumerate() {
            assert!((p.p_same[k] - w).abs() < 1e-12, "{k}: {} {w}", p.p_same[k]);
        }
        assert!((p.p_alone[0] - (w[0] + w[3]) / z).abs() < 1e-12);
        assert!((p.p_alone[2] - (w[0] + w[1]) / z).abs() < 1e-12);
        assert_eq!(p.components[0].partitions, 5);
    }

    /// Ten radar fragments of one source at different times, each met only by a vague DF
    /// track placed after them: almost every partial partition of the fragments leads to no
    /// connected partition (1,024 of them against about 850,000 placements). With a limit of
    /// 2,000 partitions the enumeration gives up past its work budget and the sampler answers;
    /// each fragment joins the DF track independently, with the logistic of its ratio.
    #[test]
    fn an_enumeration_of_mostly_disconnected_partitions_gives_up_to_the_sampler() {
        let mut tracks: Vec<Track> = (0..10)
            .map(|k| tr(1, 10.0 * k as f64, 10.0 * k as f64 + 5.0, 1.0))
            .collect();
        tracks.push(tr(4, 0.0, 100.0, 100.0));
        let pairs: Vec<(u32, u32)> = (0..10).map(|k| (k, 10)).collect();
        let llr: Vec<f64> = (0..10).map(|k| -2.0 + 0.5 * k as f64).collect();
        let inf = Inference {
            exact_limit: 2_000,
            ..Inference::default()
        };
        let p = posterior(
            &tracks,
            &whole(&tracks),
            &pairs,
            &own(&llr),
            &[],
            &inf,
            (0.01, 0.99),
            None,
        )
        .unwrap();
        assert_eq!(p.components[0].method, Method::Sampled);
        for (k, l) in llr.iter().enumerate() {
            let want = 1.0 / (1.0 + (-l).exp());
            let tol = 5.0 * p.std_error[k] + 0.02;
            assert!(
                (p.p_same[k] - want).abs() < tol,
                "{k}: {} {want}",
                p.p_same[k]
            );
        }
    }

    /// A pair's evidence with log-likelihood ratio `llr` worth `k_eff` independent instants.
    fn ev(llr: f64, k_eff: f64) -> PairEvidence {
        PairEvidence {
            llr,
            own: (0.0, 0.0),
            k_eff,
            fit: 0.0,
            motion: (0.0, 0.0),
        }
    }

    /// An aircraft track X with pairs to an AIS track A (one independent instant) and a radar
    /// track R (fifty): in the object of all three, X joins through the mean of its two pairs
    /// weighed by their independent instants, so R's, the pair that saw X longest, counts
    /// fifty times A's; when R is not much more precise than X, through A alone.
    #[test]
    fn a_track_joins_through_the_precise_members_weighed_by_what_they_saw() {
        let (c, a, b) = (8.0_f64, 1.0_f64, 4.0_f64);
        let evidence = [ev(c, 100.0), ev(a, 1.0), ev(b, 50.0)];
        let pairs = [(0, 1), (0, 2), (1, 2)];
        let mean = (a + 50.0 * b) / 51.0;
        // R precise enough: the two pairs' mean by independent instants; else A's alone
        for (r_spread, through) in [(3.0, mean), (6.0, a)] {
            let tracks = [
                tr(0, 0.0, 100.0, 1.0),
                tr(1, 0.0, 100.0, r_spread),
                tr(2, 0.0, 100.0, 10.0),
            ];
            let p = with_evidence(&tracks, &whole(&tracks), &pairs, &evidence, &[]);
            // {A}{R}{X}, {A R}{X}, {A X}{R}, {R X}{A}, {A R X}
            let w = [1.0, c.exp(), a.exp(), b.exp(), (c + through).exp()];
            let z: f64 = w.iter().sum();
            let want = [(w[1] + w[4]) / z, (w[2] + w[4]) / z, (w[3] + w[4]) / z];
            for (k, w) in want.iter().enumerate() {
                assert!(
                    (p.p_same[k] - w).abs() < 1e-12,
                    "{r_spread} {k}: {} {w}",
                    p.p_same[k]
                );
            }
        }
    }

    /// The covered pieces of a track's chains, by hand: a chain of 100 s holding 10 reports and
    /// a lone report;
    /// one reference covers 0-60 s; another has reports from 50 to 120 s and from 250 to 290 s,
    /// and with a horizon of 10 s before its first report and after its last it covers 40-100
    /// s and the lone report at 300 s. Each covers 0.6 of the chain, 6 reports' worth;
    /// together they cover all of it, and the lone report once: 11.
    #[test]
    fn covered_pieces_and_their_union_by_hand() {
        let (xs, n) = ([[0.0, 100.0], [300.0, 300.0]], [10, 1]);
        let mut p = Vec::new();
        cover_pieces(&xs, &n, &[[-50.0, 60.0]], 0.0, &mut p);
        let first = p.len();
        assert!((p.iter().map(Piece::measure).sum::<f64>() - 6.0).abs() < 1e-12);
        cover_pieces(&xs, &n, &[[50.0, 120.0], [250.0, 290.0]], 10.0, &mut p);
        let second: f64 = p[first..].iter().map(Piece::measure).sum();
        assert!((second - 7.0).abs() < 1e-12, "{second}");
        // without the horizon the lone report is not covered
        let mut q = Vec::new();
        cover_pieces(&xs, &n, &[[50.0, 120.0], [250.0, 290.0]], 0.0, &mut q);
        assert!((q.iter().map(Piece::measure).sum::<f64>() - 5.0).abs() < 1e-12);
        assert!((union_measure(&mut p) - 11.0).abs() < 1e-12);
    }

    /// An HF DF track X with four fixes (at 0, 1000, 2000 and 3000 s, each a chain of its own)
    /// over two ships: ship 1's AIS track A has a gap from 1500 s, where its radar track R
    /// takes over, so A and R each cover two fixes; ship 2's AIS track B covers all four. Every
    /// fix fits as well (`fit` 1, `base` -2), so X's pairs are `L = -2 + (k - 1) + ln k`: -0.31
    /// with A or R (2 instants) and 2.39 with B (4). In the object of A, R and X, X is measured
    /// against the path of A and R together, which covers its four fixes: it joins with B's
    /// `L`, and the two ships are about equally likely, 0.476 and 0.479. (Through the mean of
    /// its pairs with A and R it joined with -0.31: 0.058 against 0.862.)
    #[test]
    fn a_track_is_measured_over_the_union_of_its_references_times() {
        let tracks = [
            tr(0, 0.0, 1500.0, 1.0),    // A
            tr(1, 1500.0, 3500.0, 2.0), // R
            tr(0, 0.0, 3500.0, 1.0),    // B
            tr(3, 0.0, 3000.0, 100.0),  // X
        ];
        let fixes = [
            [0.0, 0.0],
            [1000.0, 1000.0],
            [2000.0, 2000.0],
            [3000.0, 3000.0],
        ];
        let mut spans = vec![[0.0, 1500.0], [1500.0, 3500.0], [0.0, 3500.0]];
        spans.extend(fixes);
        let cover = TimeCover::from_parts(vec![0, 1, 2, 3, 7], spans, vec![1; 7], 0.0).unwrap();
        let pair_l = |k: f64| -2.0 + (k - 1.0) + k.ln();
        let evf = |k: f64| PairEvidence {
            llr: pair_l(k),
            own: (0.0, 0.0),
            k_eff: k,
            fit: 1.0,
            motion: (0.0, 0.0),
        };
        let l_ar = 5.0;
        // A-R, A-X, R-X, B-X (B and R meet without a pair: two objects)
        let pairs = [(0, 1), (0, 3), (1, 3), (2, 3)];
        let evidence = [ev(l_ar, 1.0), evf(2.0), evf(2.0), evf(4.0)];
        let p = with_evidence(&tracks, &cover, &pairs, &evidence, &[]);
        let (half, whole) = (pair_l(2.0), pair_l(4.0));
        // {A}{R}{B}{X}, {AR}, {AX}, {RX}, {BX}, {AR}{BX}, {ARX}
        let w = [
            1.0,
            l_ar.exp(),
            half.exp(),
            half.exp(),
            whole.exp(),
            (l_ar + whole).exp(),
            (l_ar + whole).exp(),
        ];
        let z: f64 = w.iter().sum();
        let want = [
            (w[1] + w[5] + w[6]) / z,
            (w[2] + w[6]) / z,
            (w[3] + w[6]) / z,
            (w[4] + w[5]) / z,
        ];
        assert_eq!(p.components[0].partitions, 7);
        for (k, w) in want.iter().enumerate() {
            assert!((p.p_same[k] - w).abs() < 1e-12, "{k}: {} {w}", p.p_same[k]);
        }
        assert!((p.p_same[1] - 0.476).abs() < 1e-3 && (p.p_same[3] - 0.479).abs() < 1e-3);
    }

    /// Two references that saw an aircraft track X about as long (independent instants 50 and
    /// 50 +- 0.01) but with `L` two apart: how X joins their object does not jump when one
    /// overtakes the other. With the reference of the most instants taken alone, `p_same` of
    /// A and X moved from the object's weight with `L = 2` to that with `L = 4` on a hundredth
    /// of an instant (New York Harbor: aircraft tracks between moored ships whose AIS and radar
    /// pairs saw them about equally long went to the ship where the switch fell their way).
    #[test]
    fn joining_through_two_references_is_continuous_in_their_instants() {
        let (c, a, b) = (8.0_f64, 2.0_f64, 4.0_f64);
        let tracks = [
            tr(0, 0.0, 100.0, 1.0),
            tr(1, 0.0, 100.0, 3.0),
            tr(2, 0.0, 100.0, 10.0),
        ];
        let pairs = [(0, 1), (0, 2), (1, 2)];
        let p_ax = |eps: f64| {
            let evidence = [ev(c, 100.0), ev(a, 50.0 + eps), ev(b, 50.0 - eps)];
            with_evidence(&tracks, &whole(&tracks), &pairs, &evidence, &[]).p_same[1]
        };
        let (below, above) = (p_ax(-0.01), p_ax(0.01));
        assert!((below - above).abs() < 1e-3, "{below} {above}");
        // and it is the mean of the two: the object weighs exp(c + (a + b) / 2)
        let w = [1.0, c.exp(), a.exp(), b.exp(), (c + 0.5 * (a + b)).exp()];
        let z: f64 = w.iter().sum();
        assert!((p_ax(0.0) - (w[2] + w[4]) / z).abs() < 1e-12);
    }

    /// An AIS track over two radar tracks, one after the other: the object of all three holds
    /// a further radar track, which weighs its source's break odds (`Track::further`); the
    /// AIS track's own factor never counts, being the object's only AIS track.
    #[test]
    fn a_further_track_of_one_source_weighs_its_break_odds() {
        let (l1, l2) = (2.0_f64, 1.0_f64);
        for further in [0.0, -3.0, 1.5] {
            let mut tracks = [
                tr(0, 0.0, 100.0, 1.0),
                tr(1, 0.0, 40.0, 5.0),
                tr(1, 60.0, 100.0, 5.0),
            ];
            tracks[0].further = -7.0;
            tracks[1].further = further;
            tracks[2].further = further;
            let p = exact(&tracks, &[(0, 1), (0, 2)], &[l1, l2], &[]);
            // {A}{R1}{R2}, {A R1}{R2}, {A R2}{R1}, {A R1 R2}
            let w = [1.0, l1.exp(), l2.exp(), (l1 + l2 + further).exp()];
            let z: f64 = w.iter().sum();
            let want = [(w[1] + w[3]) / z, (w[2] + w[3]) / z];
            for (k, w) in want.iter().enumerate() {
                assert!(
                    (p.p_same[k] - w).abs() < 1e-12,
                    "{further} {k}: {} {w}",
                    p.p_same[k]
                );
            }
            assert!((p.p_alone[1] - (w[0] + w[2]) / z).abs() < 1e-12);
            assert_eq!(p.components[0].partitions, 4);
        }
    }

    /// A DF track of two fixes a minute apart, an AIS track over both and an aircraft track
    /// between the fixes: the DF and aircraft tracks never have a common instant, so the three
    /// may be one object (the time spans overlap, which is not evidence of two objects).
    #[test]
    fn tracks_without_a_common_instant_may_share_an_object() {
        let tracks = [
            tr(0, 0.0, 100.0, 1.0),
            tr(1, 0.0, 60.0, 50.0),
            tr(2, 20.0, 40.0, 5.0),
        ];
        let cover = TimeCover::from_parts(
            vec![0, 1, 3, 4],
            vec![[0.0, 100.0], [0.0, 0.0], [60.0, 60.0], [20.0, 40.0]],
            vec![1; 4],
            0.0,
        )
        .unwrap();
        let (pairs, llr) = ([(0, 1), (0, 2)], [2.0_f64, 5.0]);
        let run = |cover: &TimeCover| with_evidence(&tracks, cover, &pairs, &own(&llr), &[]);
        let p = run(&cover);
        // {0}{1}{2}, {0 1}{2}, {0 2}{1}, {0 1 2} (the tree joins 1 and 2 to 0)
        let z = 1.0 + 2f64.exp() + 5f64.exp() + 7f64.exp();
        assert!((p.p_same[0] - (2f64.exp() + 7f64.exp()) / z).abs() < 1e-12);
        assert!((p.p_same[1] - (5f64.exp() + 7f64.exp()) / z).abs() < 1e-12);
        // with the time spans as the cover, 1 and 2 meet without a pair: never one object
        let p = run(&whole(&tracks));
        let z = 1.0 + 2f64.exp() + 5f64.exp();
        assert!((p.p_same[0] - 2f64.exp() / z).abs() < 1e-12);
    }

    /// The term of a track alone (`own`) is counted once per object, however many pairs join
    /// it: a vague track holding several others is not charged its false-track odds per pair.
    #[test]
    fn a_track_term_is_counted_once_per_object() {
        // (1 and 2 at different times: they need no pair of their own)
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 0.0, 4.0, 2.0),
            tr(2, 6.0, 10.0, 3.0),
        ];
        let pairs = [(0, 1), (0, 2)];
        // L_01 = core + (-0.5) + (-1), L_02 = core + (-0.5) + (-2)
        let own = [
            PairEvidence {
                llr: 3.0,
                own: (-0.5, -1.0),
                k_eff: 1.0,
                fit: 0.0,
                motion: (0.0, 0.0),
            },
            PairEvidence {
                llr: 4.0,
                own: (-0.5, -2.0),
                k_eff: 1.0,
                fit: 0.0,
                motion: (0.0, 0.0),
            },
        ];
        let p = with_evidence(&tracks, &whole(&tracks), &pairs, &own, &[]);
        // {0 1 2}: 3 + (4 - (-0.5)) = 7.5, track 0's term once
        let w = [1.0, 3f64.exp(), 4f64.exp(), 7.5f64.exp()];
        let z: f64 = w.iter().sum();
        assert!((p.p_same[0] - (w[1] + w[3]) / z).abs() < 1e-12);
        assert!((p.p_same[1] - (w[2] + w[3]) / z).abs() < 1e-12);
        assert!((p.p_alone[0] - 1.0 / z).abs() < 1e-12);
    }

    #[test]
    fn a_radar_track_between_two_ais_ships() {
        // two AIS tracks at one time (one source: never one object) and a radar track that fits
        // both
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 2.0, 8.0, 5.0),
        ];
        let (l1, l2) = (4.0_f64, 3.0_f64);
        let p = exact(&tracks, &[(0, 2), (1, 2)], &[l1, l2], &[]);
        let z = 1.0 + l1.exp() + l2.exp();
        assert!((p.p_same[0] - l1.exp() / z).abs() < 1e-12);
        assert!((p.p_same[1] - l2.exp() / z).abs() < 1e-12);
        assert!((p.p_alone[2] - 1.0 / z).abs() < 1e-12);
        assert_eq!(p.components[0].partitions, 3);
        // renumbered radar: a second radar track after the first fits ship 0 as well; the two
        // radar tracks may both join ship 0 (one after the other)
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 0.0, 5.0, 5.0),
            tr(1, 5.0, 10.0, 5.0),
        ];
        let p = exact(&tracks, &[(0, 2), (0, 3), (1, 2)], &[5.0, 5.0, 1.0], &[]);
        // {0 2 3} is feasible and dominates
        let w_all = (10.0_f64).exp();
        assert!(p.p_same[1] > 0.9 && p.p_same[1] < 1.0);
        let z = 1.0 + 5f64.exp() * 2.0 + 1f64.exp() + w_all + (1.0f64 + 5.0).exp();
        assert!((p.p_same[0] - (5f64.exp() + w_all) / z).abs() < 1e-12);
    }

    #[test]
    fn concurrent_tracks_without_a_candidate_pair_are_two_objects() {
        // B and C exist at the same time but their AOUs never touched (no pair): the object
        // {A, B, C} is impossible even though A fits both
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 0.0, 10.0, 2.0),
            tr(2, 0.0, 10.0, 3.0),
        ];
        let p = exact(&tracks, &[(0, 1), (0, 2)], &[3.0, 3.0], &[]);
        let z = 1.0 + 2.0 * 3f64.exp();
        assert!((p.p_same[0] - 3f64.exp() / z).abs() < 1e-12);
        assert_eq!(p.components[0].partitions, 3);
    }

    #[test]
    fn a_decision_settles_its_rivals() {
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 0.0, 10.0, 2.0),
            tr(2, 0.0, 10.0, 3.0),
        ];
        let (ab, ac, bc) = (1.5_f64, -0.5_f64, 2.5_f64);
        let pairs = [(0, 1), (0, 2), (1, 2)];
        let same = Decision {
            a: 0,
            b: 1,
            same: true,
            row: 0,
        };
        let p = exact(&tracks, &pairs, &[ab, ac, bc], &[same]);
        // given A = B: {AB}{C} or {ABC}
        let want = ac.exp() / (1.0 + ac.exp());
        assert_eq!(p.p_same[0], 1.0);
        assert!((p.p_same[1] - want).abs() < 1e-12);
        assert!((p.p_same[2] - want).abs() < 1e-12);
        // radar between two ships: confirming ship 0 rules out ship 1
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 2.0, 8.0, 5.0),
        ];
        let confirm = Decision {
            a: 2,
            b: 0,
            same: true,
            row: 0,
        };
        let p = exact(&tracks, &[(0, 2), (1, 2)], &[1.0, 1.2], &[confirm]);
        assert_eq!((p.p_same[0], p.p_same[1], p.p_alone[2]), (1.0, 0.0, 0.0));
        let reject = Decision {
            same: false,
            ..confirm
        };
        let p = exact(&tracks, &[(0, 2), (1, 2)], &[1.0, 1.2], &[reject]);
        let z = 1.0 + 1.2f64.exp();
        assert_eq!(p.p_same[0], 0.0);
        assert!((p.p_same[1] - 1.2f64.exp() / z).abs() < 1e-12);
    }

    #[test]
    fn contradictory_decisions_are_refused_with_their_rows() {
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 0.0, 10.0, 2.0),
            tr(2, 0.0, 10.0, 3.0),
            tr(0, 5.0, 20.0, 1.0),
        ];
        let pairs = [(0, 1), (0, 2), (1, 2), (1, 3)];
        let llr = [1.0; 4];
        let d = |a, b, same, row| Decision { a, b, same, row };
        let refused = |decisions: &[Decision]| {
            let err = posterior(
                &tracks,
                &whole(&tracks),
                &pairs,
                &own(&llr),
                decisions,
                &Inference::default(),
                (0.01, 0.99),
                None,
            )
            .unwrap_err();
            let rows = err.rows().map(|r| r.0.to_vec());
            (rows, err.to_string())
        };
        let (rows, err) = refused(&[d(0, 1, true, 4), d(1, 2, true, 7), d(0, 2, false, 9)]);
        assert_eq!(rows, Some(vec![4, 7, 9]), "{err}");
        assert!(err.contains("different"), "{err}");
        // only the chain of decisions that joins the two tracks is named: row 5 is another's
        let (rows, err) = refused(&[
            d(1, 2, true, 7),
            d(1, 3, true, 5),
            d(0, 1, true, 4),
            d(0, 2, false, 9),
        ]);
        assert_eq!(rows, Some(vec![4, 7, 9]), "{err}");
        // two AIS tracks at overlapping times declared one object
        let (rows, err) = refused(&[d(1, 0, true, 2), d(1, 3, true, 3)]);
        assert_eq!(rows, Some(vec![2, 3]), "{err}");
        assert!(
            err.contains("rows 2, 3") && err.contains("one source"),
            "{err}"
        );
    }

    /// A radar track (2) between two ships (0, 1), both pairs of log-likelihood ratio `L`: the
    /// partitions {0 2}{1}, {1 2}{0} and {0}{1}{2} weigh `e^L`, `e^L` and 1, so each pair has
    /// `p = e^L / (2 e^L + 1)`, and "different" on one takes the other to `e^L / (e^L + 1)`.
    /// At `L = 3` that is 0.953, still in the band: the answer "same" settles the pair's mass
    /// and nothing else's ("different" leaves the rival's expected mass where it was), so the
    /// value is `p`. At `L = 5` it is 0.993, a match: either answer settles both pairs, worth
    /// `2 p`. A lone pair of `L = 0` (`p = 1 / 2`) is worth its own `p`. The pair that settles
    /// most comes first: the pairs of `L = 5` before the lone pair before those of `L = 3`.
    #[test]
    fn the_review_order_puts_the_decision_that_settles_most_first() {
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 2.0, 8.0, 5.0),
            tr(0, 20.0, 30.0, 1.0),
            tr(1, 20.0, 30.0, 5.0),
            tr(0, 40.0, 50.0, 1.0),
            tr(0, 40.0, 50.0, 1.0),
            tr(1, 42.0, 48.0, 5.0),
        ];
        let pairs = [(0, 2), (1, 2), (3, 4), (5, 7), (6, 7)];
        let p = exact(&tracks, &pairs, &[3.0, 3.0, 0.0, 5.0, 5.0], &[]);
        let between = |l: f64| l.exp() / (2.0 * l.exp() + 1.0);
        for (k, want) in [
            (0, between(3.0)),
            (1, between(3.0)),
            (2, 0.5),
            (3, 2.0 * between(5.0)),
            (4, 2.0 * between(5.0)),
        ] {
            assert!((p.gain[k] - want).abs() < 1e-12, "pair {k}: {:?}", p.gain);
        }
        // "same" on (0, 2) takes (1, 2) to 0: out of the band; "different" leaves it in
        assert_eq!(p.settles[0], (1, 0));
        assert_eq!(p.settles[3], (1, 1));
        assert_eq!(p.settles[2], (0, 0));
    }

    #[test]
    fn objects_join_confident_pairs_only() {
        let tracks = [
            tr(0, 0.0, 10.0, 1.0),
            tr(1, 0.0, 10.0, 2.0),
            tr(2, 0.0, 10.0, 3.0),
        ];
        let (object, joined) = objects(
            &tracks,
            &[(0, 1), (0, 2), (1, 2)],
            &[0.995, 0.5, 0.3],
            &[],
            0.99,
        );
        assert_eq!(joined, vec![true, false, false]);
        assert_eq!(object[0], object[1]);
        assert_ne!(object[0], object[2]);
    }
}
