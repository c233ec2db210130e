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

/// The 2-sigma growth of an interpolated segment of `gap` seconds whose ends are `chord` apart
/// in index space: the Brownian-bridge term `2 sqrt(q T / 4)` and, geographic, the sagitta of a
/// geodesic of that length over its chord. Increasing in `gap` and in `chord`.
fn segment_growth(q: f64, gap: f64, chord: f64, geo: bool) -> f64 {
    let mut g = 2.0 * (q * gap / 4.0).sqrt();
    if geo {
        // the geodesic is at most ~c long for c << R; bound its sagitta
        let l = chord * (1.0 + chord * chord / (MIN_CURVATURE_RADIUS.powi(2)));
        g += l * l / (8.0 * MIN_CURVATURE_RADIUS);
    }
    g
}

/// The growth for the extrapolation by `horizon` at one end of a track: `|v| h + 2 sqrt(q h)`
/// (+ the sagitta), the speed `|v|` taken from the end report and its neighbour (`dt` seconds
/// and `chord` metres apart) when they are connected (`dt <= max_gap`), else 0.
fn end_growth(align: &Alignment, neighbour: Option<(f64, f64)>, geo: bool) -> f64 {
    let (q, h) = (align.process_noise, align.horizon);
    if h <= 0.0 {
        return 0.0;
    }
    let speed = neighbour
        .filter(|&(dt, _)| dt.abs() <= align.max_gap)
        .map_or(0.0, |(dt, c)| {
            // chord <= geodesic; bound the speed by the geodesic via the sagitta-free chord
            // times a safety factor for curvature at short range
            let arc = if geo {
                c * (1.0 + c * c / (MIN_CURVATURE_RADIUS.powi(2)))
            } else {
                c
            };
            arc / dt.abs()
        });
    let l = speed * h;
    let sag = if geo {
        l * l / (8.0 * MIN_CURVATURE_RADIUS)
    } else {
        0.0
    };
    l + 2.0 * (q * h).sqrt() + sag
}

/// The box `[lo - g - m, hi + g + m]` of the points in `[lo, hi]` grown by `g`, with a margin
/// `m = margin |v|` (at least `margin`) so that rounding never separates touching boxes.
fn grown(lo: [f64; 3], hi: [f64; 3], g: f64, margin: f64, geo: bool) -> ([f64; 3], [f64; 3]) {
    let pad = |v: f64| g + margin * v.abs().max(1.0);
    let (mut out_lo, mut out_hi) = ([0.0; 3], [0.0; 3]);
    for k in 0..3 {
        out_lo[k] = lo[k] - pad(lo[k]);
        out_hi[k] = hi[k] + pad(hi[k]);
    }
    if !geo {
        out_lo[2] = 0.0;
        out_hi[2] = 0.0;
    }
    (out_lo, out_hi)
}

/// The relative margin of a chunk box; a track box takes twice as much.
const MARGIN: f64 = 1e-9;

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
            let connected = |i: usize| i + 1 < end && super::align::connected(r, i, align);
            let neighbour =
                |e: usize, n: usize| (r.time[e] - r.time[n], dist3(&r.point[e], &r.point[n]));
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
                    let chord = dist3(&r.point[i], &r.point[i + 1]);
                    extra = extra.max(segment_growth(q, r.time[i + 1] - r.time[i], chord, geo));
                }
                lo[3] = r.time[s];
                hi[3] = r.time[e];
                if s == start {
                    lo[3] -= h;
                    let nb = (start + 1 < end).then(|| neighbour(start, start + 1));
                    extra = extra.max(end_growth(align, nb, geo));
                }
                if e + 1 == end {
                    hi[3] += h;
                    let nb = (e > start).then(|| neighbour(e, e - 1));
                    extra = extra.max(end_growth(align, nb, geo));
                }
                let (l3, h3) = grown(
                    [lo[0], lo[1], lo[2]],
                    [hi[0], hi[1], hi[2]],
                    grow + extra,
                    MARGIN,
                    geo,
                );
                lo[..3].copy_from_slice(&l3);
                hi[..3].copy_from_slice(&h3);
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

/// One of the two earliest or two latest reports of a track, in a [`TrackPartial`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndReport {
    /// Time (s).
    pub time: f64,
    /// Index-space point (see [`Reports::point`]).
    pub point: [f64; 3],
    /// The report's row as given (`x, y, rx, ry, phi` or `lat, lon, rx, ry, bearing`).
    pub aou: [f64; 5],
}

/// What the halo box of a track needs of its reports, from any subset of them and mergeable
/// ([`TrackPartial::merge`]) over any split: so a picture partitioned by rows (not by track)
/// gets every track's box without moving its reports (the distributed path, `geofeas.integrations.dask`).
///
/// [`TrackPartial::halo_box`] contains every chunk box [`chunks`] gives the track, whatever the
/// window: the property test in `rust/tests/association.rs`.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackPartial {
    /// Number of reports.
    pub reports: u64,
    /// Earliest and latest report time (s).
    pub t_min: f64,
    pub t_max: f64,
    /// Largest 2-sigma semi-axis (m).
    pub radius_max: f64,
    /// Smallest and largest `rx * ry` (m^2).
    pub area_min: f64,
    pub area_max: f64,
    /// Box of the index-space points.
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    /// The two earliest and the two latest reports (all of them when there are at most four),
    /// sorted by time.
    pub ends: Vec<EndReport>,
}

/// Numbers in one row of [`TrackPartial::to_row`].
pub const PARTIAL_WIDTH: usize = 13 + 4 * 9;

impl TrackPartial {
    /// The partial of every track of `r` (`aou`: the rows `r` was built from, in the caller's
    /// order).
    pub fn of(r: &Reports, aou: &[[f64; 5]]) -> Vec<Self> {
        (0..r.n_tracks)
            .map(|t| {
                let range = r.range(t);
                let mut p = Self {
                    reports: range.len() as u64,
                    t_min: f64::INFINITY,
                    t_max: f64::NEG_INFINITY,
                    radius_max: 0.0,
                    area_min: f64::INFINITY,
                    area_max: 0.0,
                    lo: [f64::INFINITY; 3],
                    hi: [f64::NEG_INFINITY; 3],
                    ends: Vec::new(),
                };
                for i in range.clone() {
                    p.t_min = p.t_min.min(r.time[i]);
                    p.t_max = p.t_max.max(r.time[i]);
                    p.radius_max = p.radius_max.max(r.radius[i]);
                    p.area_min = p.area_min.min(r.area[i]);
                    p.area_max = p.area_max.max(r.area[i]);
                    for k in 0..3 {
                        p.lo[k] = p.lo[k].min(r.point[i][k]);
                        p.hi[k] = p.hi[k].max(r.point[i][k]);
                    }
                }
                let n = range.len();
                p.ends = range
                    .enumerate()
                    .filter(|&(k, _)| k < 2 || k + 2 >= n)
                    .map(|(_, i)| EndReport {
                        time: r.time[i],
                        point: r.point[i],
                        aou: aou[r.row[i]],
                    })
                    .collect();
                p
            })
            .collect()
    }

    /// The partial of the union of the reports behind `self` and `other` (a report in both,
    /// same time, counts once among the ends).
    pub fn merge(&mut self, other: &Self) {
        self.reports += other.reports;
        self.t_min = self.t_min.min(other.t_min);
        self.t_max = self.t_max.max(other.t_max);
        self.radius_max = self.radius_max.max(other.radius_max);
        self.area_min = self.area_min.min(other.area_min);
        self.area_max = self.area_max.max(other.area_max);
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(other.lo[k]);
            self.hi[k] = self.hi[k].max(other.hi[k]);
        }
        self.ends.extend_from_slice(&other.ends);
        self.ends.sort_by(|a, b| a.time.total_cmp(&b.time));
        self.ends.dedup_by(|a, b| a.time == b.time);
        let n = self.ends.len();
        if n > 4 {
            self.ends.drain(2..n - 2);
        }
    }

    /// A 4-D box `[x, y, z, t]` holding every chunk box of the track, with the spatial halo at
    /// least `halo`: the points' box grown by the largest semi-axis, the largest interpolation
    /// term (a segment is at most `min(span, max(max_gap, max_still_gap))` long and its chord at
    /// most the box's diagonal) and the larger extrapolation term of the two ends, each term of
    /// a chunk being no larger (the functions are increasing); the margin is twice a chunk's.
    pub fn halo_box(&self, align: &Alignment, geo: bool, halo: f64) -> ([f64; 4], [f64; 4]) {
        self.box_grown_by(align, geo, self.growth(align, geo, halo))
    }

    /// The box of [`TrackPartial::halo_box`] for a spatial growth `g` already computed by
    /// [`TrackPartial::growth`].
    pub fn box_grown_by(&self, align: &Alignment, geo: bool, g: f64) -> ([f64; 4], [f64; 4]) {
        let (l3, h3) = grown(self.lo, self.hi, g, 2.0 * MARGIN, geo);
        (
            [l3[0], l3[1], l3[2], self.t_min - align.horizon],
            [h3[0], h3[1], h3[2], self.t_max + align.horizon],
        )
    }

    /// The spatial growth of [`TrackPartial::halo_box`] (m, before the rounding margin).
    pub fn growth(&self, align: &Alignment, geo: bool, halo: f64) -> f64 {
        let span = (self.t_max - self.t_min).min(align.longest_gap()).max(0.0);
        let seg = segment_growth(align.process_noise, span, dist3(&self.lo, &self.hi), geo);
        let e = &self.ends;
        let n = e.len();
        let pair = |i: usize, j: usize| {
            (n > 1).then(|| (e[i].time - e[j].time, dist3(&e[i].point, &e[j].point)))
        };
        let first = end_growth(align, pair(0, 1), geo);
        let last = end_growth(align, pair(n.max(2) - 1, n.max(2) - 2), geo);
        (self.radius_max + seg + first.max(last)).max(halo)
    }

    /// The partial as [`PARTIAL_WIDTH`] numbers (an opaque row for a caller to move between
    /// machines and give back to [`TrackPartial::from_row`]).
    pub fn to_row(&self) -> [f64; PARTIAL_WIDTH] {
        let mut out = [f64::NAN; PARTIAL_WIDTH];
        out[..13].copy_from_slice(&[
            self.reports as f64,
            self.t_min,
            self.t_max,
            self.radius_max,
            self.area_min,
            self.area_max,
            self.lo[0],
            self.lo[1],
            self.lo[2],
            self.hi[0],
            self.hi[1],
            self.hi[2],
            self.ends.len() as f64,
        ]);
        for (k, end) in self.ends.iter().enumerate() {
            let row = &mut out[13 + 9 * k..13 + 9 * (k + 1)];
            row[0] = end.time;
            row[1..4].copy_from_slice(&end.point);
            row[4..].copy_from_slice(&end.aou);
        }
        out
    }

    /// The partial of a row of [`TrackPartial::to_row`]; `row` names it in errors.
    pub fn from_row(v: &[f64], row: usize) -> crate::Result<Self> {
        let bad = |why: &str| {
            crate::Error::Invalid(format!("partial row {row}: {why} (not a track partial)"))
        };
        if v.len() != PARTIAL_WIDTH {
            return Err(bad(&format!(
                "{} numbers, expected {PARTIAL_WIDTH}",
                v.len()
            )));
        }
        let n = v[12];
        if !((1.0..=4.0).contains(&n) && n.fract() == 0.0 && v[0] >= n && v[0].fract() == 0.0) {
            return Err(bad("counts out of range"));
        }
        let n = n as usize;
        if v[1..12]
            .iter()
            .chain(&v[13..13 + 9 * n])
            .any(|x| !x.is_finite())
        {
            return Err(bad("a value is not finite"));
        }
        let ends: Vec<EndReport> = (0..n)
            .map(|k| {
                let e = &v[13 + 9 * k..13 + 9 * (k + 1)];
                EndReport {
                    time: e[0],
                    point: [e[1], e[2], e[3]],
                    aou: [e[4], e[5], e[6], e[7], e[8]],
                }
            })
            .collect();
        if ends.windows(2).any(|w| w[0].time >= w[1].time) {
            return Err(bad("end reports not sorted by time"));
        }
        Ok(Self {
            reports: v[0] as u64,
            t_min: v[1],
            t_max: v[2],
            radius_max: v[3],
            area_min: v[4],
            area_max: v[5],
            lo: [v[6], v[7], v[8]],
            hi: [v[9], v[10], v[11]],
            ends,
        })
    }
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
