//! Operator triage and association: classes from two thresholds, grouping of duplicate tracks
//! into objects, and a one-to-one assignment between two sources.
//!
//! The paper (seed 000, Section 1) wants operators to "make assessments about borderline cases
//! only", with 0.5 as "the best borderline" (Section 3). A pair scoring below `lower` is a
//! `non-match`; one scoring at least `upper` is a match candidate, and between the two it is
//! `borderline`. A threshold alone is not an association: trackers drop and renumber tracks, so
//! one track may rightly match several tracks of another source one after another, but one ship
//! cannot hold two tracks of one source that overlap in time. [`group`] therefore merges match
//! candidates into objects greedily by decreasing score (ties by track ids), with the
//! cannot-link constraint "no object holds two tracks of the same source whose time spans
//! overlap"; a candidate whose merge would break it is demoted to `borderline` for the operator.
//! Greedy merging is the standard constrained agglomeration (single linkage with cannot-links);
//! it is exact when the candidates of each object form a tree, and never produces an infeasible
//! object.
//!
//! **Merge order: the most specific evidence first.** A pair's score says how *consistent* its
//! two tracks are, not how *specific* that is: an HF direction-finding fix kilometres long is
//! consistent with every ship of a harbour and scores near 1. Merged first, such pairs chain
//! distinct ships into one object, and the cannot-link then refuses the right pairs. The merges
//! therefore go by the Gaussian likelihood of the pair, which keeps its normaliser: per instant
//! `-2 ln N(d; 0, S) = m + ln det S + const`, with `m` the single-instant equivalent distance of
//! the combined score (`m_eq = -9 log2(score)` on the [`crate::association::combine::Combine::
//! Chi2`] scale) and `ln det S ~ 2 ln(spread_a + spread_b)` from the tracks' typical AOU sizes
//! (exact for two circles). Pairs of equally precise sources are ordered as by score; a precise
//! pair goes before a vague one of the same score.
//!
//! **Crowds.** A match candidate with [`CROWD`] (30) or more match-grade rivals — tracks of the
//! partner's source, alive at the same time, that its track also fits at or above `upper` — is
//! `borderline`: no geographic score can single out one of thirty simultaneous ships, and such a
//! pair would be a guess. The value sits in the wide gap between the sensor classes measured on
//! the bundled recordings (`docs/association.md`): patrol-aircraft and radar candidates in dense
//! harbours have a handful of such rivals, an HF direction-finding fix kilometres long has on the
//! order of a hundred; any value from 20 to 40 classes the same pairs there.
//!
//! [`assign_one_to_one`] solves the classical assignment between two sources that maximises the
//! total score over the sparse candidate graph: per connected component, the dense
//! Hungarian / Jonker-Volgenant shortest-augmenting-path algorithm on `-score`, with missing
//! edges forbidden and every track free to stay unassigned.

/// A match candidate with at least this many match-grade rivals (mutually exclusive
/// alternatives scoring at least `upper`, see [`rivals`]) is ambiguous by geography alone and
/// goes to the operator as `borderline`: its AOUs are consistent with a crowd of other tracks at
/// once. See the module docs for how the value was chosen.
pub const CROWD: usize = 30;

/// Triage class of a pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Class {
    Match = 0,
    Borderline = 1,
    NonMatch = 2,
}

impl Class {
    /// `"match"`, `"borderline"` or `"non-match"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Match => "match",
            Self::Borderline => "borderline",
            Self::NonMatch => "non-match",
        }
    }
}

/// What [`group`] needs to know about each track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackInfo {
    pub source: u32,
    pub start: f64,
    pub end: f64,
    /// The track's typical AOU size `sqrt(det R)` (m^2), from the smallest and largest `rx * ry`
    /// of its reports: `sqrt(min * max) / 4` (see [`TrackInfo::spread_of`]); 0 when unknown, and
    /// the grouping then orders by score alone.
    pub spread: f64,
}

impl TrackInfo {
    /// `spread` from the smallest and largest `rx * ry` of a track's reports.
    pub fn spread_of(area_min: f64, area_max: f64) -> f64 {
        0.25 * (area_min * area_max).sqrt()
    }
}

fn overlap(a: &TrackInfo, b: &TrackInfo) -> bool {
    a.source == b.source && a.start < b.end && b.start < a.end
}

/// Classes of `pairs` (with `scores`) and the object of every track (dense ids, numbered by
/// their smallest track). See the module docs.
pub fn group(
    tracks: &[TrackInfo],
    pairs: &[(u32, u32)],
    scores: &[f64],
    lower: f64,
    upper: f64,
) -> (Vec<Class>, Vec<u32>) {
    group_unambiguous(tracks, pairs, scores, &[], lower, upper)
}

/// The rivals of every match candidate (score at least `upper`): the pairs scoring at least
/// `lower` that share a track `t` with it and whose other track has the same source as the
/// candidate's partner and a time span overlapping the partner's, so that one object cannot hold
/// both. Returned as `(rival pair, shared track)` lists, empty for pairs below `upper`.
pub fn rivals(
    tracks: &[TrackInfo],
    pairs: &[(u32, u32)],
    scores: &[f64],
    lower: f64,
    upper: f64,
) -> Vec<Vec<(usize, u32)>> {
    let n = tracks.len();
    let mut by_track: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (k, &(a, b)) in pairs.iter().enumerate() {
        if scores[k] >= lower {
            by_track[a as usize].push(k);
            by_track[b as usize].push(k);
        }
    }
    let other = |k: usize, t: u32| {
        let (a, b) = pairs[k];
        if a == t {
            b
        } else {
            a
        }
    };
    (0..pairs.len())
        .map(|p| {
            let mut out = Vec::new();
            if scores[p] < upper {
                return out;
            }
            let (a, b) = pairs[p];
            for (t, partner) in [(a, b), (b, a)] {
                let pi = &tracks[partner as usize];
                for &q in &by_track[t as usize] {
                    if q == p {
                        continue;
                    }
                    let rival = &tracks[other(q, t) as usize];
                    if rival.source == pi.source && rival.start < pi.end && pi.start < rival.end {
                        out.push((q, t));
                    }
                }
            }
            out
        })
        .collect()
}

/// The merge priority of a match candidate (smaller first): `m_eq + 2 ln(spread_a + spread_b)`,
/// or `m_eq` alone when a spread is unknown (see the module docs).
pub fn merge_key(tracks: &[TrackInfo], (a, b): (u32, u32), score: f64) -> f64 {
    let m_eq = -9.0 * score.log2();
    let (sa, sb) = (tracks[a as usize].spread, tracks[b as usize].spread);
    if sa > 0.0 && sb > 0.0 {
        m_eq + 2.0 * (sa + sb).ln()
    } else {
        m_eq
    }
}

/// [`group`] where the match candidates flagged in `unclear` (ambiguous ones, see
/// `association::ambiguous`) are `borderline` and take no part in the grouping. An empty
/// `unclear` flags none.
pub fn group_unambiguous(
    tracks: &[TrackInfo],
    pairs: &[(u32, u32)],
    scores: &[f64],
    unclear: &[bool],
    lower: f64,
    upper: f64,
) -> (Vec<Class>, Vec<u32>) {
    let n = tracks.len();
    let none = vec![false; pairs.len()];
    let unclear = if unclear.is_empty() {
        &none[..]
    } else {
        unclear
    };
    let mut class: Vec<Class> = scores
        .iter()
        .map(|&s| {
            if s >= upper {
                Class::Match
            } else if s >= lower {
                Class::Borderline
            } else {
                Class::NonMatch
            }
        })
        .collect();
    let crowd = rivals(tracks, pairs, scores, upper, upper);
    for (k, c) in class.iter_mut().enumerate() {
        if unclear[k] || crowd[k].len() >= CROWD {
            *c = Class::Borderline;
        }
    }
    let mut order: Vec<usize> = (0..pairs.len())
        .filter(|&k| class[k] == Class::Match)
        .collect();
    let keys: Vec<f64> = (0..pairs.len())
        .map(|k| merge_key(tracks, pairs[k], scores[k]))
        .collect();
    order.sort_by(|&i, &j| keys[i].total_cmp(&keys[j]).then(pairs[i].cmp(&pairs[j])));
    let mut root: Vec<u32> = (0..n as u32).collect();
    let mut members: Vec<Vec<u32>> = (0..n as u32).map(|t| vec![t]).collect();
    for k in order {
        let (a, b) = pairs[k];
        let (ra, rb) = (root[a as usize], root[b as usize]);
        if ra == rb {
            continue;
        }
        let conflict = members[ra as usize].iter().any(|&x| {
            members[rb as usize]
                .iter()
                .any(|&y| overlap(&tracks[x as usize], &tracks[y as usize]))
        });
        if conflict {
            class[k] = Class::Borderline;
            continue;
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
    (class, object)
}

/// The one-to-one assignment between the tracks on the two sides of `pairs` (`pairs[k].0` on
/// the left, `.1` on the right) maximising the total score over edges scoring at least
/// `min_score`; returns the indices of the chosen pairs, sorted.
pub fn assign_one_to_one(pairs: &[(u32, u32)], scores: &[f64], min_score: f64) -> Vec<usize> {
    // connected components over the bipartite graph (left ids and right ids kept apart)
    let edges: Vec<usize> = (0..pairs.len())
        .filter(|&k| scores[k] >= min_score && scores[k].is_finite())
        .collect();
    let mut left: Vec<u32> = edges.iter().map(|&k| pairs[k].0).collect();
    let mut right: Vec<u32> = edges.iter().map(|&k| pairs[k].1).collect();
    left.sort_unstable();
    left.dedup();
    right.sort_unstable();
    right.dedup();
    let nl = left.len();
    let node_l = |t: u32| left.binary_search(&t).unwrap();
    let node_r = |t: u32| nl + right.binary_search(&t).unwrap();
    let mut dsu: Vec<usize> = (0..nl + right.len()).collect();
    fn find(d: &mut [usize], mut x: usize) -> usize {
        while d[x] != x {
            d[x] = d[d[x]];
            x = d[x];
        }
        x
    }
    for &k in &edges {
        let (a, b) = (
            find(&mut dsu, node_l(pairs[k].0)),
            find(&mut dsu, node_r(pairs[k].1)),
        );
        if a != b {
            dsu[a] = b;
        }
    }
    let mut comp: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for &k in &edges {
        let c = find(&mut dsu, node_l(pairs[k].0));
        comp.entry(c).or_default().push(k);
    }
    let mut chosen = Vec::new();
    for (_, es) in comp {
        let mut ls: Vec<u32> = es.iter().map(|&k| pairs[k].0).collect();
        let mut rs: Vec<u32> = es.iter().map(|&k| pairs[k].1).collect();
        ls.sort_unstable();
        ls.dedup();
        rs.sort_unstable();
        rs.dedup();
        // square cost matrix: rows = left + right dummies, columns = right + left dummies;
        // a real edge costs -score, "unassigned" costs 0, a missing edge is forbidden.
        let n = ls.len() + rs.len();
        const FORBID: f64 = 1e18;
        let mut cost = vec![FORBID; n * n];
        let mut edge_at = vec![usize::MAX; n * n];
        for &k in &es {
            let i = ls.binary_search(&pairs[k].0).unwrap();
            let j = rs.binary_search(&pairs[k].1).unwrap();
            if -scores[k] < cost[i * n + j] {
                cost[i * n + j] = -scores[k];
                edge_at[i * n + j] = k;
            }
        }
        for i in 0..ls.len() {
            cost[i * n + rs.len() + i] = 0.0; // left i unassigned
        }
        for j in 0..rs.len() {
            cost[(ls.len() + j) * n + j] = 0.0; // right j unassigned
            for d in 0..ls.len() {
                cost[(ls.len() + j) * n + rs.len() + d] = 0.0; // dummy-dummy
            }
        }
        let col_of_row = hungarian(&cost, n);
        for (i, &j) in col_of_row.iter().enumerate().take(ls.len()) {
            if j < rs.len() && edge_at[i * n + j] != usize::MAX {
                chosen.push(edge_at[i * n + j]);
            }
        }
    }
    chosen.sort_unstable();
    chosen
}

/// Minimum-cost perfect assignment of a dense `n x n` cost matrix (row-major): the column of
/// each row. Shortest augmenting paths with potentials (Jonker-Volgenant / Kuhn-Munkres),
/// `O(n^3)`.
pub fn hungarian(cost: &[f64], n: usize) -> Vec<usize> {
    // 1-based arrays as in the classical formulation; column 0 is the virtual start
    let mut u = vec![0.0; n + 1];
    let mut v = vec![0.0; n + 1];
    let mut p = vec![0usize; n + 1]; // p[j] = row matched to column j
    let mut way = vec![0usize; n + 1];
    for i in 1..=n {
        p[0] = i;
        let mut j0 = 0usize;
        let mut minv = vec![f64::INFINITY; n + 1];
        let mut used = vec![false; n + 1];
        loop {
            used[j0] = true;
            let i0 = p[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0usize;
            for j in 1..=n {
                if !used[j] {
                    let cur = cost[(i0 - 1) * n + (j - 1)] - u[i0] - v[j];
                    if cur < minv[j] {
                        minv[j] = cur;
                        way[j] = j0;
                    }
                    if minv[j] < delta {
                        delta = minv[j];
                        j1 = j;
                    }
                }
            }
            for j in 0..=n {
                if used[j] {
                    u[p[j]] += delta;
                    v[j] -= delta;
                } else {
                    minv[j] -= delta;
                }
            }
            j0 = j1;
            if p[j0] == 0 {
                break;
            }
        }
        loop {
            let j1 = way[j0];
            p[j0] = p[j1];
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    let mut col = vec![0usize; n];
    for j in 1..=n {
        if p[j] > 0 {
            col[p[j] - 1] = j - 1;
        }
    }
    col
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(source: u32, start: f64, end: f64) -> TrackInfo {
        TrackInfo {
            source,
            start,
            end,
            spread: 0.0,
        }
    }

    #[test]
    fn a_track_that_fits_a_crowd_is_left_to_the_operator() {
        // track 0 fits n simultaneous tracks of another source, the first one best
        let classes = |n: u32| {
            let mut tracks = vec![info(0, 0.0, 100.0)];
            tracks.extend((0..n).map(|_| info(1, 0.0, 100.0)));
            let pairs: Vec<(u32, u32)> = (1..=n).map(|j| (0, j)).collect();
            let scores: Vec<f64> = (1..=n).map(|j| 0.99 - 0.001 * j as f64).collect();
            group(&tracks, &pairs, &scores, 0.5, 0.735).0
        };
        let few = classes(5);
        assert_eq!(few[0], Class::Match);
        assert!(few[1..].iter().all(|&c| c == Class::Borderline));
        // CROWD rivals: every candidate has n - 1 >= CROWD alternatives
        let crowd = classes(CROWD as u32 + 1);
        assert!(crowd.iter().all(|&c| c == Class::Borderline));
        let just_below = classes(CROWD as u32);
        assert_eq!(just_below[0], Class::Match);
    }

    #[test]
    fn renumbered_tracks_join_one_object_but_overlapping_ones_do_not() {
        // 0: AIS 0..100; 1: radar 0..50; 2: radar 60..100 (renumbered); 3: radar 40..90
        let tracks = [
            info(0, 0.0, 100.0),
            info(1, 0.0, 50.0),
            info(1, 60.0, 100.0),
            info(1, 40.0, 90.0),
        ];
        let pairs = [(0, 1), (0, 2), (0, 3)];
        let scores = [0.9, 0.95, 0.8];
        let (class, object) = group(&tracks, &pairs, &scores, 0.5, 0.7);
        assert_eq!(class, vec![Class::Match, Class::Match, Class::Borderline]);
        assert_eq!(object[0], object[1]);
        assert_eq!(object[0], object[2]);
        assert_ne!(object[0], object[3]);
    }

    #[test]
    fn rivals_are_exclusive_alternatives() {
        // AIS track 0; radar tracks 1 and 2 at the same time, radar 3 later, radar 4 overlapping 1
        // but scoring below lower
        let tracks = [
            info(0, 0.0, 100.0),
            info(1, 0.0, 50.0),
            info(1, 0.0, 50.0),
            info(1, 60.0, 100.0),
            info(1, 10.0, 40.0),
        ];
        let pairs = [(0, 1), (0, 2), (0, 3), (0, 4)];
        let scores = [0.95, 0.9, 0.9, 0.4];
        let r = rivals(&tracks, &pairs, &scores, 0.5, 0.7);
        assert_eq!(r[0], vec![(1, 0)]);
        assert_eq!(r[1], vec![(0, 0)]);
        assert!(r[2].is_empty() && r[3].is_empty());
        let (class, object) = group_unambiguous(
            &tracks,
            &pairs,
            &scores,
            &[false, true, false, false],
            0.5,
            0.7,
        );
        assert_eq!(
            class,
            vec![
                Class::Match,
                Class::Borderline,
                Class::Match,
                Class::NonMatch
            ]
        );
        assert_eq!(object[0], object[1]);
        assert_eq!(object[0], object[3]);
        assert_ne!(object[0], object[2]);
    }

    #[test]
    fn thresholds() {
        let tracks = [info(0, 0.0, 1.0), info(1, 0.0, 1.0)];
        let (class, _) = group(
            &tracks,
            &[(0, 1), (0, 1), (0, 1)],
            &[0.2, 0.6, 0.8],
            0.5,
            0.7,
        );
        assert_eq!(class[0], Class::NonMatch);
        assert_eq!(class[1], Class::Borderline);
    }

    #[test]
    fn hungarian_small() {
        // classic 3x3: optimum 1 + 2 + 2 = 5? rows: [4,1,3],[2,0,5],[3,2,2]
        let c = [4.0, 1.0, 3.0, 2.0, 0.0, 5.0, 3.0, 2.0, 2.0];
        let col = hungarian(&c, 3);
        let total: f64 = col.iter().enumerate().map(|(i, &j)| c[i * 3 + j]).sum();
        assert_eq!(total, 5.0);
    }

    #[test]
    fn one_to_one_prefers_total_score() {
        // greedy would take (0, 10) = 0.9 and leave 1 alone; optimum is 0.8 + 0.85
        let pairs = [(0, 10), (0, 11), (1, 10)];
        let scores = [0.9, 0.8, 0.85];
        assert_eq!(assign_one_to_one(&pairs, &scores, 0.0), vec![1, 2]);
    }
}
