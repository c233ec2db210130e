//! Triage classes and the one-to-one assignment between two sources.
//!
//! The paper (seed 000, Section 1) wants operators to "make assessments about borderline cases
//! only". The classes come from the posterior probability that a pair is one object
//! ([`crate::association::posterior`]): `match` at or above `p_match`, `non-match` at or below
//! `p_reject`, `borderline` between.
//!
//! [`assign_one_to_one`] solves the classical assignment between two sources that maximises the
//! total score over the sparse candidate graph: per connected component, the dense
//! Hungarian / Jonker-Volgenant shortest-augmenting-path algorithm on `-score`, with missing
//! edges forbidden and every track free to stay unassigned.

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
