//! Generalized optimal sub-pattern assignment (GOSPA) metric between a set of true positions and
//! a set of estimated positions, with its decomposition into localisation, missed and false
//! targets (Rahmathullah, Garcia-Fernandez and Svensson, "Generalized optimal sub-pattern
//! assignment metric", FUSION 2017, eq. 2 with `alpha = 2`).
//!
//! With cut-off `c` and order `p`,
//! `d = (min_gamma sum_{(i,j) in gamma} d(x_i, y_j)^p + c^p / 2 (|X| - |gamma| + |Y| - |gamma|))^(1/p)`
//! over partial assignments `gamma` of pairs closer than `c`. The optimum is found with the
//! Hungarian algorithm on a square matrix padded with "missed" and "false" dummies (cost
//! `c^p / 2` each); a truth-estimate pair at distance `>= c` costs `c^p` and is then counted as
//! one missed and one false target. Both trackers' studies report it beside the papers' metrics.

use geofeas::association::assign::hungarian;

/// The GOSPA distance and its parts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Gospa {
    /// The distance `d`.
    pub distance: f64,
    /// `sum d(x_i, y_j)^p` over the assigned pairs (the localisation term, before the root).
    pub localisation: f64,
    /// Number of true positions left unassigned.
    pub missed: usize,
    /// Number of estimates left unassigned.
    pub false_targets: usize,
}

/// GOSPA (`alpha = 2`) between `truth` and `estimates` with cut-off `c > 0` and order `p >= 1`.
pub fn gospa(truth: &[[f64; 2]], estimates: &[[f64; 2]], c: f64, p: f64) -> Gospa {
    let (m, k) = (truth.len(), estimates.len());
    let half = 0.5 * c.powf(p);
    if m == 0 || k == 0 {
        let n = m + k;
        return Gospa {
            distance: (half * n as f64).powf(1.0 / p),
            localisation: 0.0,
            missed: m,
            false_targets: k,
        };
    }
    let dist =
        |i: usize, j: usize| (truth[i][0] - estimates[j][0]).hypot(truth[i][1] - estimates[j][1]);
    // Rows: m truths then k "false" dummies; columns: k estimates then m "missed" dummies.
    let n = m + k;
    let mut cost = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            cost[i * n + j] = match (i < m, j < k) {
                (true, true) => dist(i, j).min(c).powf(p),
                (true, false) => half,
                (false, true) => half,
                (false, false) => 0.0,
            };
        }
    }
    let col = hungarian(&cost, n);
    let mut out = Gospa::default();
    let mut total = 0.0;
    for (i, &j) in col.iter().enumerate() {
        total += cost[i * n + j];
        match (i < m, j < k) {
            (true, true) => {
                let d = dist(i, j);
                if d < c {
                    out.localisation += d.powf(p);
                } else {
                    out.missed += 1;
                    out.false_targets += 1;
                }
            }
            (true, false) => out.missed += 1,
            (false, true) => out.false_targets += 1,
            (false, false) => {}
        }
    }
    out.distance = total.max(0.0).powf(1.0 / p);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force over every partial one-to-one assignment.
    fn brute(truth: &[[f64; 2]], est: &[[f64; 2]], c: f64, p: f64) -> f64 {
        fn rec(
            i: usize,
            used: &mut Vec<bool>,
            truth: &[[f64; 2]],
            est: &[[f64; 2]],
            c: f64,
            p: f64,
        ) -> f64 {
            if i == truth.len() {
                let unused = used.iter().filter(|u| !**u).count();
                return 0.5 * c.powf(p) * unused as f64;
            }
            // Truth i missed.
            let mut best = 0.5 * c.powf(p) + rec(i + 1, used, truth, est, c, p);
            for j in 0..est.len() {
                if used[j] {
                    continue;
                }
                let d = (truth[i][0] - est[j][0]).hypot(truth[i][1] - est[j][1]);
                if d >= c {
                    continue;
                }
                used[j] = true;
                best = best.min(d.powf(p) + rec(i + 1, used, truth, est, c, p));
                used[j] = false;
            }
            best
        }
        rec(0, &mut vec![false; est.len()], truth, est, c, p).powf(1.0 / p)
    }

    #[test]
    fn matches_brute_force_on_small_sets() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..400 {
            let m = case % 5;
            let k = (case / 5) % 5;
            let truth: Vec<[f64; 2]> = (0..m).map(|_| [10.0 * next(), 10.0 * next()]).collect();
            let est: Vec<[f64; 2]> = (0..k).map(|_| [10.0 * next(), 10.0 * next()]).collect();
            let (c, p) = if case % 2 == 0 {
                (3.0, 2.0)
            } else {
                (5.0, 1.0)
            };
            let g = gospa(&truth, &est, c, p);
            let b = brute(&truth, &est, c, p);
            assert!((g.distance - b).abs() < 1e-9, "case {case}: {g:?} vs {b}");
            // The parts add up to the distance.
            let sum = g.localisation + 0.5 * c.powf(p) * (g.missed + g.false_targets) as f64;
            assert!((sum.powf(1.0 / p) - g.distance).abs() < 1e-9, "case {case}");
            assert_eq!(
                g.missed as isize - g.false_targets as isize,
                m as isize - k as isize
            );
        }
    }

    #[test]
    fn closed_forms() {
        // Perfect estimate.
        assert_eq!(gospa(&[[1.0, 2.0]], &[[1.0, 2.0]], 5.0, 2.0).distance, 0.0);
        // One localisation error of 3 m: d = 3.
        let g = gospa(&[[0.0, 0.0]], &[[3.0, 0.0]], 5.0, 2.0);
        assert!((g.distance - 3.0).abs() < 1e-12 && g.missed == 0 && g.false_targets == 0);
        // Beyond the cut-off: one missed and one false, d = c.
        let g = gospa(&[[0.0, 0.0]], &[[30.0, 0.0]], 5.0, 2.0);
        assert!((g.distance - 5.0).abs() < 1e-12 && g.missed == 1 && g.false_targets == 1);
        // Two truths, no estimate: d = (2 c^2 / 2)^(1/2) = c.
        let g = gospa(&[[0.0, 0.0], [9.0, 9.0]], &[], 5.0, 2.0);
        assert!((g.distance - 5.0).abs() < 1e-12 && g.missed == 2);
    }
}
