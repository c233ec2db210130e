//! Measurement-to-filter assignment of seed 003, section III (the paper's "data association":
//! which intensity peak of a frame each particle filter takes; unrelated to the track-to-track
//! association of [`geofeas::association`]).
//!
//! For filter `i` with prior particles `(x_i^n, y_i^n)` and prior normalised weights `w_i^n`,
//! and peak `j` at `(x*_j, y*_j)`: `r_ij^n = |(x_i^n, y_i^n) - (x*_j, y*_j)|` and the weighted
//! mean distance `R_i^j = sum_n w_i^n r_ij^n`. The paper's rule ([`Assignment::Nearest`]) gives
//! filter `i` the peak `j* = argmin_j R_i^j`, independently for each filter, so two filters may
//! take the same peak. [`Assignment::OneToOne`] instead picks the assignment of distinct peaks
//! to filters that minimises `sum_i R_i^{j(i)}` (exact, by dynamic programming over subsets of
//! peaks, for up to 16 peaks; greedy by increasing `R` beyond).

use crate::pf::motion::Particles;
use crate::pf::peaks::Peak;
use geofeas::error::{Error, Result};

/// How filters take peaks (the `association` option of the filters).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Assignment {
    /// The paper's rule: each filter its nearest peak by `R_i^j`.
    #[default]
    Nearest,
    /// Distinct peaks, minimum total `R`.
    OneToOne,
}

impl Assignment {
    /// `"nearest"` or `"one-to-one"`.
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "nearest" => Ok(Self::Nearest),
            "one-to-one" | "one_to_one" => Ok(Self::OneToOne),
            other => Err(Error::InvalidOption {
                name: "association",
                reason: format!("expected 'nearest' or 'one-to-one', got '{other}'"),
            }),
        }
    }

    /// The name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Nearest => "nearest",
            Self::OneToOne => "one-to-one",
        }
    }

    /// The peak of each filter given the matrix `r[i][j] = R_i^j` (`None` when there are no peaks
    /// or, one-to-one, fewer peaks than filters and filter `i` is left without).
    pub fn assign(&self, r: &[Vec<f64>]) -> Vec<Option<usize>> {
        match self {
            Self::Nearest => r
                .iter()
                .map(|row| {
                    row.iter()
                        .enumerate()
                        .min_by(|a, b| a.1.total_cmp(b.1))
                        .map(|(j, _)| j)
                })
                .collect(),
            Self::OneToOne => one_to_one(r),
        }
    }
}

/// `R_i^j` of one filter for every peak.
pub fn weighted_distances(p: &Particles, w: &[f64], peaks: &[Peak]) -> Vec<f64> {
    peaks
        .iter()
        .map(|pk| {
            p.x.iter()
                .zip(&p.y)
                .zip(w)
                .map(|((&x, &y), &wn)| {
                    let (dx, dy) = (x - pk.x, y - pk.y);
                    wn * (dx * dx + dy * dy).sqrt()
                })
                .sum()
        })
        .collect()
}

/// Minimum-total-cost assignment of distinct columns to rows (rows may stay unassigned only when
/// there are fewer columns than rows; as many rows as possible are assigned).
fn one_to_one(r: &[Vec<f64>]) -> Vec<Option<usize>> {
    let rows = r.len();
    let cols = r.first().map_or(0, Vec::len);
    if rows == 0 || cols == 0 {
        return vec![None; rows];
    }
    if cols > 16 {
        return greedy(r);
    }
    // dp[mask] over rows processed so far: (number assigned, cost), lexicographic (max, min).
    let full = 1usize << cols;
    let worst = (usize::MAX, f64::INFINITY);
    let better = |a: (usize, f64), b: (usize, f64)| {
        if b.0 == usize::MAX {
            true
        } else {
            a.0 > b.0 || (a.0 == b.0 && a.1 < b.1)
        }
    };
    let mut dp = vec![vec![worst; full]; rows + 1];
    let mut from = vec![vec![(0usize, None::<usize>); full]; rows + 1];
    dp[0][0] = (0, 0.0);
    for i in 0..rows {
        for mask in 0..full {
            let cur = dp[i][mask];
            if cur.0 == usize::MAX {
                continue;
            }
            // Leave row i unassigned.
            if better(cur, dp[i + 1][mask]) {
                dp[i + 1][mask] = cur;
                from[i + 1][mask] = (mask, None);
            }
            for (j, &rij) in r[i].iter().enumerate() {
                if mask & (1 << j) != 0 {
                    continue;
                }
                let next = (cur.0 + 1, cur.1 + rij);
                let m2 = mask | (1 << j);
                if better(next, dp[i + 1][m2]) {
                    dp[i + 1][m2] = next;
                    from[i + 1][m2] = (mask, Some(j));
                }
            }
        }
    }
    let mut mask = (0..full)
        .filter(|&m| dp[rows][m].0 != usize::MAX)
        .fold(None::<usize>, |best, m| match best {
            Some(b) if !better(dp[rows][m], dp[rows][b]) => Some(b),
            _ => Some(m),
        })
        .unwrap_or(0);
    let mut out = vec![None; rows];
    for i in (1..=rows).rev() {
        let (prev, j) = from[i][mask];
        out[i - 1] = j;
        mask = prev;
    }
    out
}

fn greedy(r: &[Vec<f64>]) -> Vec<Option<usize>> {
    let mut pairs: Vec<(f64, usize, usize)> = r
        .iter()
        .enumerate()
        .flat_map(|(i, row)| row.iter().enumerate().map(move |(j, &v)| (v, i, j)))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = vec![None; r.len()];
    let mut used = vec![false; r.first().map_or(0, Vec::len)];
    for (_, i, j) in pairs {
        if out[i].is_none() && !used[j] {
            out[i] = Some(j);
            used[j] = true;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_distance_is_the_paper_sum() {
        let p = Particles {
            x: vec![0.0, 3.0],
            y: vec![0.0, 4.0],
            vx: vec![0.0; 2],
            vy: vec![0.0; 2],
        };
        let pk = Peak {
            x: 0.0,
            y: 0.0,
            value: 0.0,
        };
        let r = weighted_distances(&p, &[0.25, 0.75], &[pk]);
        assert!((r[0] - 3.75).abs() < 1e-15);
    }

    #[test]
    fn nearest_may_share_one_to_one_does_not() {
        let r = vec![
            vec![1.0, 2.0, 9.0],
            vec![1.5, 5.0, 9.0],
            vec![9.0, 9.0, 3.0],
        ];
        assert_eq!(
            Assignment::Nearest.assign(&r),
            vec![Some(0), Some(0), Some(2)]
        );
        // Total 2 + 1.5 + 3 = 6.5 beats 1 + 5 + 3 = 9.
        assert_eq!(
            Assignment::OneToOne.assign(&r),
            vec![Some(1), Some(0), Some(2)]
        );
    }

    #[test]
    fn one_to_one_matches_brute_force() {
        let mut s = 12345u64;
        let mut rnd = || {
            s = geofeas::rng::mix64(s);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200 {
            let r: Vec<Vec<f64>> = (0..4).map(|_| (0..5).map(|_| rnd()).collect()).collect();
            let a = Assignment::OneToOne.assign(&r);
            let cost: f64 = a.iter().enumerate().map(|(i, j)| r[i][j.unwrap()]).sum();
            let mut best = f64::INFINITY;
            for a0 in 0..5 {
                for a1 in 0..5 {
                    for a2 in 0..5 {
                        for a3 in 0..5 {
                            let v = [a0, a1, a2, a3];
                            let distinct = (0..4).all(|i| (0..i).all(|k| v[i] != v[k]));
                            if distinct {
                                best = best.min(r[0][a0] + r[1][a1] + r[2][a2] + r[3][a3]);
                            }
                        }
                    }
                }
            }
            assert!((cost - best).abs() < 1e-12);
        }
        // Fewer peaks than filters: as many as possible assigned.
        let a = Assignment::OneToOne.assign(&[vec![1.0], vec![0.5]]);
        assert_eq!(a, vec![None, Some(0)]);
        assert_eq!(Assignment::Nearest.assign(&[vec![]]), vec![None]);
    }
}
