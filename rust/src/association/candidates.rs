//! Candidate track pairs from a space-time R-tree (rstar) instead of all `N^2` pairs.
//!
//! Each track is cut into chunks of consecutive reports spanning at most `window` seconds
//! (neighbouring chunks share their boundary report; a gap longer than `max_gap`, which is
//! never interpolated, ends a chunk without sharing). A chunk's bounding volume is a 4-D box:
//! the time range of its reports (stretched by `horizon` at the ends of the track) times the
//! 3-D box of its centres (`(x, y, 0)` planar, WGS84 ECEF geographic) grown by
//!
//! - the largest 2-sigma semi-axis of its reports: the interpolated covariance
//!   `(1 - w) R0 + w R1` has a support function `2 sqrt(u^T R u)` no larger than the larger of
//!   the two, so every interpolated AOU lies inside;
//! - `2 sqrt(q T / 4)`, the largest 2-sigma Brownian-bridge term over its segments of length
//!   `T` (see [`super::align`]), and at track ends `|v| h + 2 sqrt(q h)` for the extrapolation;
//! - in geographic mode the sagitta `L^2 / (8 R_min)` of a geodesic of length `L` over its
//!   chord, and nothing for the AOU itself because an ECEF chord is never longer than the
//!   geodesic.
//!
//! So whenever two tracks have a common instant at which their AOUs touch, two of their chunks'
//! boxes intersect, and the pair is a candidate. [`candidate_pairs`] bulk-loads the boxes into an
//! `rstar::RTree` and, per track in parallel, queries each of its chunks; [`brute_force_pairs`]
//! tests every pair of chunks and returns the same set (the property test in
//! `rust/tests/association.rs`). Memory is the chunks plus the candidates.

use rayon::prelude::*;
use rstar::{primitives::GeomWithData, primitives::Rectangle, RTree, AABB};

use super::align::Alignment;
use super::geodesy::MIN_CURVATURE_RADIUS;
use super::reports::{Coords, Reports};

/// Index options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndexOptions {
    /// Longest time span of one chunk (s).
    pub window: f64,
    /// Whether pairs of tracks from the same source are candidates.
    pub same_source: bool,
}

impl Default for IndexOptions {
    fn default() -> Self {
        Self {
            window: 300.0,
            same_source: false,
        }
    }
}

/// A chunk of one track: its 4-D box `[x, y, z, t]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chunk {
    pub track: u32,
    pub lo: [f64; 4],
    pub hi: [f64; 4],
}

impl Chunk {
    /// Whether the closed boxes intersect.
    pub fn intersects(&self, other: &Chunk) -> bool {
        (0..4).all(|k| self.lo[k] <= other.hi[k] && other.lo[k] <= self.hi[k])
    }
}

fn dist3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The chunks of every track (see the module docs).
pub fn chunks(r: &Reports, align: &Alignment, o: &IndexOptions) -> Vec<Chunk> {
    let geo = r.coords == Coords::Geographic;
    let q = align.process_noise;
    let h = align.horizon;
    let window = o.window.max(0.0);
    let per_track: Vec<Vec<Chunk>> = (0..r.n_tracks)
        .into_par_iter()
        .map(|t| {
            let range = r.range(t);
            let (start, end) = (range.start, range.end);
            let connected = |i: usize| i + 1 < end && r.time[i + 1] - r.time[i] <= align.max_gap;
            // growth for the extrapolation at one end: |v| h + 2 sqrt(q h) (+ sagitta)
            let end_growth = |e: usize, nb: Option<usize>| -> f64 {
                if h <= 0.0 {
                    return 0.0;
                }
                let speed = nb
                    .filter(|&n| (r.time[e] - r.time[n]).abs() <= align.max_gap)
                    .map_or(0.0, |n| {
                        // chord <= geodesic; bound the speed by the geodesic via the sagitta-free
                        // chord times a safety factor for curvature at short range
                        let c = dist3(&r.point[e], &r.point[n]);
                        let arc = if geo {
                            c * (1.0 + c * c / (MIN_CURVATURE_RADIUS.powi(2)))
                        } else {
                            c
                        };
                        arc / (r.time[e] - r.time[n]).abs()
                    });
                let l = speed * h;
                let sag = if geo {
                    l * l / (8.0 * MIN_CURVATURE_RADIUS)
                } else {
                    0.0
                };
                l + 2.0 * (q * h).sqrt() + sag
            };
            let mut out = Vec::new();
            let mut s = start;
            while s < end {
                let mut e = s;
                while connected(e) && (e == s || r.time[e + 1] - r.time[s] <= window) {
                    e += 1;
                }
                let mut lo = [f64::INFINITY; 4];
                let mut hi = [f64::NEG_INFINITY; 4];
                let mut grow: f64 = 0.0;
                for i in s..=e {
                    for k in 0..3 {
                        lo[k] = lo[k].min(r.point[i][k]);
                        hi[k] = hi[k].max(r.point[i][k]);
                    }
                    grow = grow.max(r.radius[i]);
                }
                let mut extra: f64 = 0.0;
                for i in s..e {
                    let gap = r.time[i + 1] - r.time[i];
                    let mut g = 2.0 * (q * gap / 4.0).sqrt();
                    if geo {
                        let c = dist3(&r.point[i], &r.point[i + 1]);
                        // the geodesic is at most ~c long for c << R; bound its sagitta
                        let l = c * (1.0 + c * c / (MIN_CURVATURE_RADIUS.powi(2)));
                        g += l * l / (8.0 * MIN_CURVATURE_RADIUS);
                    }
                    extra = extra.max(g);
                }
                lo[3] = r.time[s];
                hi[3] = r.time[e];
                if s == start {
                    lo[3] -= h;
                    extra = extra.max(end_growth(start, (start + 1 < end).then_some(start + 1)));
                }
                if e + 1 == end {
                    hi[3] += h;
                    extra = extra.max(end_growth(e, (e > start).then(|| e - 1)));
                }
                let g = grow + extra;
                // one ulp-scale margin so that rounding never separates touching boxes
                let pad = |v: f64| g + 1e-9 * v.abs().max(1.0);
                for k in 0..3 {
                    let (a, b) = (lo[k], hi[k]);
                    lo[k] = a - pad(a);
                    hi[k] = b + pad(b);
                }
                if !geo {
                    lo[2] = 0.0;
                    hi[2] = 0.0;
                }
                out.push(Chunk {
                    track: t as u32,
                    lo,
                    hi,
                });
                s = if connected(e) && e > s { e } else { e + 1 };
            }
            out
        })
        .collect();
    per_track.into_iter().flatten().collect()
}

fn admissible(r: &Reports, o: &IndexOptions, a: u32, b: u32) -> bool {
    a < b && (o.same_source || r.source[a as usize] != r.source[b as usize])
}

/// Candidate pairs `(a, b)`, `a < b`, sorted, from the R-tree (see the module docs).
pub fn candidate_pairs(r: &Reports, chunks: &[Chunk], o: &IndexOptions) -> Vec<(u32, u32)> {
    type Item = GeomWithData<Rectangle<[f64; 4]>, u32>;
    let items: Vec<Item> = chunks
        .iter()
        .map(|c| GeomWithData::new(Rectangle::from_corners(c.lo, c.hi), c.track))
        .collect();
    let tree: RTree<Item> = RTree::bulk_load(items);
    // chunks are grouped by track in order; find each track's run
    let mut starts = vec![0usize; r.n_tracks + 1];
    for c in chunks {
        starts[c.track as usize + 1] += 1;
    }
    for t in 0..r.n_tracks {
        starts[t + 1] += starts[t];
    }
    let per_track: Vec<Vec<(u32, u32)>> = (0..r.n_tracks)
        .into_par_iter()
        .map(|t| {
            let mut partners: Vec<u32> = Vec::new();
            for c in &chunks[starts[t]..starts[t + 1]] {
                let env = AABB::from_corners(c.lo, c.hi);
                for hit in tree.locate_in_envelope_intersecting(env) {
                    if admissible(r, o, t as u32, hit.data) {
                        partners.push(hit.data);
                    }
                }
            }
            partners.sort_unstable();
            partners.dedup();
            partners.into_iter().map(|b| (t as u32, b)).collect()
        })
        .collect();
    per_track.into_iter().flatten().collect()
}

/// The same pairs as [`candidate_pairs`] by testing every pair of chunks: the reference for
/// tests and the baseline of the benchmark.
pub fn brute_force_pairs(r: &Reports, chunks: &[Chunk], o: &IndexOptions) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = chunks
        .par_iter()
        .flat_map_iter(|a| {
            chunks
                .iter()
                .filter(move |b| admissible(r, o, a.track, b.track) && a.intersects(b))
                .map(move |b| (a.track, b.track))
        })
        .collect();
    out.par_sort_unstable();
    out.dedup();
    out
}
