//! Combination of per-instant scores into one track-pair score (seed 000, Section 1: "multiple
//! such geofeasibility scores would be combined (probably by using a harmonic or geometric
//! mean)"), and the calibrated default.
//!
//! For a true pair with consistent covariances the per-instant Mahalanobis distance
//! `m = d^T (R1 + R2)^-1 d` is chi-square with 2 degrees of freedom, so the per-instant GLR
//! `g = exp(-m / 2)` (eq. 71) is the chi-square survival function of `m`: uniform on `[0, 1]`.
//! Its mean logarithm is `-1`, so the plain geometric mean of `k` instants drifts to `1/e`
//! for every true pair as `k` grows, and one unlucky instant drives a minimum or a product to 0.
//! The raw rules are kept ([`Combine::Geometric`], [`Combine::Harmonic`],
//! [`Combine::Arithmetic`], [`Combine::Min`]); the calibrated ones are:
//!
//! - [`Combine::PValue`]: the chi-square test of the summed distances, `p = Q_{chi2, 2k}(sum m)`
//!   (Fisher's method on the per-instant GLRs, since `-2 ln g = m`). Uniform on `[0, 1]` for a
//!   true pair whatever `k`; for `k = 1` it is the GLR itself.
//! - [`Combine::Chi2`] (the default): the same test on the paper's operator scale. `p` is
//!   turned into the single-instant distance with the same p-value, `m_eq = -2 ln p`, and the
//!   score is `2^(-m_eq / 9)`: a track pair scores 0.5 (the paper's "best borderline") when it
//!   fits like one instant whose centres are 3 sigma apart (`m_eq = 9`), and `2^(-4/9) = 0.735`
//!   when it fits like one instant 2 sigma apart, on the rim of the 2-sigma AOUs. Its
//!   distribution for a true pair is the same for every `k`: `P(score < x) = x^(4.5 / ln 2)`,
//!   so 1.1 % of consistent true pairs fall below 0.5 and 13.5 % below 0.735.
//!
//! **Correlated instants.** Tracker outputs, and states interpolated between the same two
//! reports, are correlated in time, so `k` instants carry less than `k` instants' evidence.
//! With an error correlation `exp(-|dt| / tau)` (`tau` = `correlation_time`), the distances of
//! two instants have correlation `exp(-2 |dt| / tau)`, and the sum of `k` of them is matched
//! (Satterthwaite: same mean and variance) by `(k / k_eff) chi2_{2 k_eff}` with
//! `k_eff = k^2 / sum_ij exp(-2 |t_i - t_j| / tau)`, between 1 and `k` (`k` for `tau = 0`).
//! The p-value is then `Q_{chi2, 2 k_eff}(sum m * k_eff / k)`, a regularised upper incomplete
//! gamma function (statrs).
//!
//! For scores other than the plain GLR, `m` is `-2 ln g` (Fisher's method), which is exact
//! only when the score is uniform for true pairs.

use crate::error::{Error, Result};

/// How the per-instant scores of a track pair are combined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Combine {
    /// The calibrated default: chi-square p-value on the 3-sigma-is-0.5 scale.
    #[default]
    Chi2,
    /// The chi-square p-value itself (uniform for true pairs).
    PValue,
    /// `exp(mean ln g)`.
    Geometric,
    /// `k / sum(1 / g)`.
    Harmonic,
    /// `mean g`.
    Arithmetic,
    /// `min g`.
    Min,
}

/// Names accepted by [`Combine::from_name`].
pub const COMBINE_NAMES: [&str; 6] = [
    "chi2",
    "pvalue",
    "geometric",
    "harmonic",
    "arithmetic",
    "min",
];

/// The `m_eq` (single-instant squared Mahalanobis distance) that [`Combine::Chi2`] maps to 0.5.
pub const BORDER_M: f64 = 9.0;

/// The default upper (match) threshold: the [`Combine::Chi2`] score of `m_eq = 4`, a fit like
/// one instant 2 sigma apart.
pub fn default_upper() -> f64 {
    chi2_scale(4.0)
}

/// `2^(-m_eq / 9)`.
pub fn chi2_scale(m_eq: f64) -> f64 {
    (-m_eq * std::f64::consts::LN_2 / BORDER_M).exp()
}

impl Combine {
    /// The rule called `name` (one of [`COMBINE_NAMES`]).
    pub fn from_name(name: &str) -> Result<Self> {
        Ok(match name {
            "chi2" => Self::Chi2,
            "pvalue" => Self::PValue,
            "geometric" => Self::Geometric,
            "harmonic" => Self::Harmonic,
            "arithmetic" => Self::Arithmetic,
            "min" => Self::Min,
            other => {
                return Err(Error::InvalidOption {
                    name: "combine",
                    reason: format!("unknown rule '{other}' (expected one of {COMBINE_NAMES:?})"),
                })
            }
        })
    }

    /// The rule's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Chi2 => "chi2",
            Self::PValue => "pvalue",
            Self::Geometric => "geometric",
            Self::Harmonic => "harmonic",
            Self::Arithmetic => "arithmetic",
            Self::Min => "min",
        }
    }

    /// Combines `k` instants: scores `g`, squared distances `m` (`-2 ln g` for scores other than
    /// the GLR) and times (sorted, for the effective number of instants). `NaN` for `k = 0`.
    pub fn combine(self, g: &[f64], m: &[f64], times: &[f64], correlation_time: f64) -> f64 {
        let k = g.len();
        if k == 0 {
            return f64::NAN;
        }
        let kf = k as f64;
        match self {
            Self::Geometric => (-m.iter().sum::<f64>() / (2.0 * kf)).exp(),
            Self::Harmonic => {
                if g.iter().any(|&x| x <= 0.0) {
                    0.0
                } else {
                    kf / g.iter().map(|&x| 1.0 / x).sum::<f64>()
                }
            }
            Self::Arithmetic => g.iter().sum::<f64>() / kf,
            Self::Min => g.iter().copied().fold(f64::INFINITY, f64::min),
            Self::PValue | Self::Chi2 => {
                let k_eff = effective_instants(times, correlation_time);
                self.from_summary(m.iter().sum::<f64>(), kf, k_eff)
            }
        }
    }

    /// Whether the rule is a chi-square test of the summed distances (so that it can be
    /// evaluated from `(sum m, k, k_eff)` and corrected by a covariance inflation).
    pub fn is_chi2(self) -> bool {
        matches!(self, Self::Chi2 | Self::PValue)
    }

    /// A chi-square rule from the pair's summary: summed distances, instants and effective
    /// instants. Other rules: `NaN`.
    pub fn from_summary(self, sum_m: f64, k: f64, k_eff: f64) -> f64 {
        let p = chi2_pvalue(sum_m, k, k_eff);
        match self {
            Self::PValue => p,
            // p^(ln 2 / 4.5) = 2^(-m_eq / 9) with m_eq = -2 ln p
            Self::Chi2 => (p.ln() * std::f64::consts::LN_2 / (0.5 * BORDER_M)).exp(),
            _ => f64::NAN,
        }
    }
}

/// Fewest mutually-best pairs from which [`estimate_inflation`] estimates a factor.
pub const MIN_INFLATION_PAIRS: usize = 8;
/// Largest inflation [`estimate_inflation`] returns (AOUs understated by 4x in sigma); pairs
/// whose ratio exceeds it are taken for different objects and left out of the estimate.
pub const MAX_INFLATION: f64 = 16.0;

/// Covariance inflation per pair of sources, estimated from the data (the `"auto"` inflation).
///
/// The chi-square rules are calibrated when the AOUs are consistent; a source whose AOUs are
/// optimistic makes every true pair look worse the more instants it has. Under a common scale
/// `c` of the covariances of two sources the mean distance of a true pair is `c` times chi-square:
/// `m_bar = sum m / k ~ c chi2_{2 k_eff} / k_eff`, whose median is `2 c (1 - 1/(9 k_eff))^3`
/// (Wilson-Hilferty). For every pair of sources, the pairs that are each other's best partner
/// in the other source (smallest `m_bar`, at least 3 instants) are taken as the likely true
/// pairs, and `c` is the median of `m_bar / (2 (1 - 1/(9 k_eff))^3)` over those whose ratio is
/// at most [`MAX_INFLATION`] (beyond, a pair is taken for two objects) — robust to up to half of
/// them being wrong — clamped to at least 1 (AOUs are never tightened). With fewer
/// than [`MIN_INFLATION_PAIRS`] such pairs the estimate pooled over all sources is used, and
/// with fewer than that in total, 1.
///
/// `pairs[i]` has summary `stats[i] = (sum m, k, k_eff)`; returns `(source_lo, source_hi, c)`
/// for every pair of sources that occurs, sorted.
pub fn estimate_inflation(
    pairs: &[(u32, u32)],
    track_source: &[u32],
    stats: &[(f64, f64, f64)],
) -> Vec<(u32, u32, f64)> {
    use std::collections::{BTreeMap, HashMap};
    let mean = |i: usize| stats[i].0 / stats[i].1;
    let mut best: HashMap<(u32, u32), usize> = HashMap::new();
    for (i, &(a, b)) in pairs.iter().enumerate() {
        if stats[i].1 < 3.0 || !mean(i).is_finite() {
            continue;
        }
        for (t, other) in [(a, b), (b, a)] {
            let key = (t, track_source[other as usize]);
            let e = best.entry(key).or_insert(i);
            if mean(i) < mean(*e) || (mean(i) == mean(*e) && i < *e) {
                *e = i;
            }
        }
    }
    let mut ratios: BTreeMap<(u32, u32), Vec<f64>> = BTreeMap::new();
    let mut all = Vec::new();
    let mut groups: BTreeMap<(u32, u32), ()> = BTreeMap::new();
    for (i, &(a, b)) in pairs.iter().enumerate() {
        let (sa, sb) = (track_source[a as usize], track_source[b as usize]);
        let key = (sa.min(sb), sa.max(sb));
        groups.insert(key, ());
        let mutual = best.get(&(a, sb)) == Some(&i) && best.get(&(b, sa)) == Some(&i);
        if mutual {
            let ke = stats[i].2;
            let r = mean(i) / (2.0 * (1.0 - 1.0 / (9.0 * ke)).powi(3));
            if r <= MAX_INFLATION {
                ratios.entry(key).or_default().push(r);
                all.push(r);
            }
        }
    }
    fn median(v: &mut [f64]) -> f64 {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        }
    }
    let pooled = if all.len() >= MIN_INFLATION_PAIRS {
        median(&mut all).max(1.0)
    } else {
        1.0
    };
    groups
        .keys()
        .map(|&(lo, hi)| {
            let c = match ratios.get_mut(&(lo, hi)) {
                Some(v) if v.len() >= MIN_INFLATION_PAIRS => median(v).max(1.0),
                _ => pooled,
            };
            (lo, hi, c)
        })
        .collect()
}

/// `Q_{chi2, 2 k_eff}(sum_m * k_eff / k)`: the p-value of `k` summed 2-dof distances worth
/// `k_eff` independent instants.
pub fn chi2_pvalue(sum_m: f64, k: f64, k_eff: f64) -> f64 {
    if sum_m.is_nan() {
        return f64::NAN;
    }
    if sum_m == f64::INFINITY {
        return 0.0;
    }
    if sum_m <= 0.0 {
        return 1.0;
    }
    let x = sum_m * k_eff / k;
    statrs::function::gamma::gamma_ur(k_eff, 0.5 * x)
}

/// `k^2 / sum_ij exp(-2 |t_i - t_j| / tau)` for sorted `times`; `k` when `tau` is 0.
pub fn effective_instants(times: &[f64], tau: f64) -> f64 {
    if tau <= 0.0 {
        return times.len() as f64;
    }
    effective_count(times, tau)
}

/// `k^2 / sum_ij rho_ij` over `k` non-decreasing error times `xs` ([`rho`]), clamped to
/// `[1, k]`.
fn effective_count(xs: &[f64], tau: f64) -> f64 {
    let kf = xs.len() as f64;
    if xs.is_empty() {
        return kf;
    }
    let total: f64 = kernel_sums(xs, |_| 1.0, tau).map(|(_, s)| s).sum();
    (kf * kf / (kf + 2.0 * total)).clamp(1.0, kf)
}

/// The correlation of the squared distances at error times `dt >= 0` apart: 1 for one report's
/// error (`dt = 0`), `exp(-2 dt / tau)` otherwise (0 when `tau` is 0).
fn rho(dt: f64, tau: f64) -> f64 {
    if dt == 0.0 {
        1.0
    } else if tau > 0.0 {
        (-2.0 * dt / tau).exp()
    } else {
        0.0
    }
}

/// `(i, S_i)` for `i = 1..`, `S_i = sum_{j<i} w_j rho_ji` over non-decreasing error times `xs`,
/// by the exponential kernel's recursion `S_i = rho_{i-1,i} (S_{i-1} + w_{i-1})`.
fn kernel_sums<'a>(
    xs: &'a [f64],
    w: impl Fn(usize) -> f64 + 'a,
    tau: f64,
) -> impl Iterator<Item = (usize, f64)> + 'a {
    (1..xs.len()).scan(0.0, move |s, i| {
        *s = rho(xs[i] - xs[i - 1], tau) * (*s + w(i - 1));
        Some((i, *s))
    })
}

/// `sum_ij w_i w_j rho_ij` over non-decreasing error times `xs`.
fn weighted_correlation_sum(xs: &[f64], w: &[f64], tau: f64) -> f64 {
    let mut total: f64 = w.iter().map(|x| x * x).sum();
    for (i, s) in kernel_sums(xs, |j| w[j], tau) {
        total += 2.0 * w[i] * s;
    }
    total
}

/// `sum_j rho_ij` for every `i` over non-decreasing error times `xs` (the recursion forwards
/// and backwards).
fn correlation_mass(xs: &[f64], tau: f64) -> Vec<f64> {
    let n = xs.len();
    let mut mass = vec![1.0; n];
    for (i, s) in kernel_sums(xs, |_| 1.0, tau) {
        mass[i] += s;
    }
    let mut s = 0.0;
    for i in (0..n.saturating_sub(1)).rev() {
        s = rho(xs[i + 1] - xs[i], tau) * (s + 1.0);
        mass[i] += s;
    }
    mass
}

/// Each instant's nearest report time in `reports` (sorted; ties to the earlier), for sorted
/// `times`: the report whose error the instant carries.
fn snapped(times: &[f64], reports: &[f64]) -> Vec<f64> {
    let mut j = 0;
    times
        .iter()
        .map(|&t| {
            while j < reports.len() && reports[j] < t {
                j += 1;
            }
            match (j.checked_sub(1).map(|i| reports[i]), reports.get(j)) {
                (Some(lo), Some(&hi)) => {
                    if t - lo <= hi - t {
                        lo
                    } else {
                        hi
                    }
                }
                (Some(lo), None) => lo,
                (None, Some(&hi)) => hi,
                (None, None) => t,
            }
        })
        .collect()
}

/// What the instants of a track pair are worth (`docs/association.md`, "Combination and
/// calibration" and "The joint model").
#[derive(Debug, Clone, PartialEq)]
pub struct PairInstantCounts {
    /// Independent instants of the plain sum over the instants (the `score` column's).
    pub k_eff: f64,
    /// Each instant's weight in the evidence's means.
    pub weights: Vec<f64>,
    /// Independent instants of the evidence's weighted means.
    pub evidence_k_eff: f64,
}

/// The counts of a track pair's instants.
///
/// The error of the difference at instant `t` is the sum of the two tracks' errors there, each
/// that of the track's report nearest to `t` (an interpolated state carries the errors of the
/// reports around it, so instants between two sparse reports share them), correlated over the
/// tracker's correlation time `tau` ([`rho`]). With `w_x` track `x`'s share of the summed
/// covariance traces, instants `i`, `j` correlate as `rho_ij = w_a rho^a_ij + w_b rho^b_ij`.
///
/// - `k_eff = 1 / (w_a / K_a + w_b / K_b)`, `K_x = k^2 / sum_ij rho^x_ij` the effective count of
///   track `x`'s errors at the instants: what the plain mean over the instants is worth,
///   between the two counts and at most `k`.
/// - Instant `i` weighs `1 / sum_j rho_ij` in the evidence, so that a group of instants
///   carrying one report's error counts once however many instants fall in it: the instants
///   between two HF DF fixes 200 s apart, at every radar scan, weigh together as much as one
///   isolated fix does. The weighted mean's variance gives
///   `evidence_k_eff = (sum w)^2 / sum_ij w_i w_j rho_ij`, clamped to `[1, k]`: the number of
///   groups for groups of fully correlated instants, `k` for independent ones.
///
/// `times` are the instants (sorted), `reports_a` / `reports_b` the report times of each track
/// (sorted), `share_a` is `w_a`.
pub fn pair_instant_counts(
    times: &[f64],
    reports_a: &[f64],
    reports_b: &[f64],
    share_a: f64,
    tau: f64,
) -> PairInstantCounts {
    let k = times.len();
    if k < 2 {
        return PairInstantCounts {
            k_eff: k as f64,
            weights: vec![1.0; k],
            evidence_k_eff: k as f64,
        };
    }
    let w = if share_a.is_finite() {
        share_a.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let kf = k as f64;
    let (xa, xb) = (snapped(times, reports_a), snapped(times, reports_b));
    let (ka, kb) = (effective_count(&xa, tau), effective_count(&xb, tau));
    let (ma, mb) = (correlation_mass(&xa, tau), correlation_mass(&xb, tau));
    let weights: Vec<f64> = ma
        .iter()
        .zip(&mb)
        .map(|(a, b)| 1.0 / (w * a + (1.0 - w) * b))
        .collect();
    let sum: f64 = weights.iter().sum();
    let var = w * weighted_correlation_sum(&xa, &weights, tau)
        + (1.0 - w) * weighted_correlation_sum(&xb, &weights, tau);
    PairInstantCounts {
        k_eff: (1.0 / (w / ka + (1.0 - w) / kb)).clamp(1.0, kf),
        evidence_k_eff: (sum * sum / var).clamp(1.0, kf),
        weights,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Instants between two reports of a sparse track carry the errors of those two reports.
    #[test]
    fn pair_instants_count_the_reports_behind_them() {
        let times: Vec<f64> = (0..=100).map(f64::from).collect();
        let sparse = [0.0, 100.0];
        // tau = 0: k^2 / sum of squared group sizes, 51 instants nearer 0, 50 nearer 100
        let k_a = 101.0 * 101.0 / (51.0 * 51.0 + 50.0 * 50.0);
        let got = pair_instant_counts(&times, &sparse, &times, 1.0, 0.0).k_eff;
        assert!((got - k_a).abs() < 1e-12, "{got}");
        // the dense track's own errors are independent at every instant
        let got = pair_instant_counts(&times, &sparse, &times, 0.0, 0.0).k_eff;
        assert!((got - 101.0).abs() < 1e-12, "{got}");
        // shares weigh the two counts harmonically
        let got = pair_instant_counts(&times, &sparse, &times, 0.5, 0.0).k_eff;
        assert!(
            (got - 1.0 / (0.5 / k_a + 0.5 / 101.0)).abs() < 1e-12,
            "{got}"
        );
        // both tracks reporting at every instant: the single-track rule
        let got = pair_instant_counts(&times, &times, &times, 0.3, 20.0).k_eff;
        assert!(
            (got - effective_instants(&times, 20.0)).abs() < 1e-9,
            "{got}"
        );
    }

    /// An HF DF-like track: two fixes 10 s apart with a dense partner between them, then two
    /// isolated fixes. Each fix's group of instants weighs 1 in all, and the instants are worth
    /// the four fixes (the unweighted mean's count, `k^2 / sum g^2`, is 169 / 63).
    #[test]
    fn instant_weights_count_each_report_once() {
        let mut times: Vec<f64> = (0..=10).map(f64::from).collect();
        times.extend([1000.0, 2000.0]);
        let vague = [0.0, 10.0, 1000.0, 2000.0];
        let c = pair_instant_counts(&times, &vague, &times, 1.0, 0.0);
        let (w, k_eff) = (c.weights, c.evidence_k_eff);
        // instants 0..=5 are nearest the fix at 0 (the tie at 5 to the earlier), 6..=10 the fix at 10
        for (i, x) in w.iter().enumerate() {
            let want = match i {
                0..=5 => 1.0 / 6.0,
                6..=10 => 1.0 / 5.0,
                _ => 1.0,
            };
            assert!((x - want).abs() < 1e-15, "{i}: {x}");
        }
        assert!((k_eff - 4.0).abs() < 1e-12, "{k_eff}");
        // the dense partner's errors are independent at every instant
        let c = pair_instant_counts(&times, &vague, &times, 0.0, 0.0);
        let (w, k_eff) = (c.weights, c.evidence_k_eff);
        assert!(w.iter().all(|&x| x == 1.0));
        assert_eq!(k_eff, 13.0);
    }

    /// The weights and both counts against brute-force sums over all pairs of instants.
    #[test]
    fn instant_weights_match_brute_force() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        for case in 0..40 {
            let k = rng.random_range(2..60);
            // times on a 10 s grid, so that instants and reports coincide now and then
            let mut times: Vec<f64> = (0..k)
                .map(|_| 10.0 * f64::from(rng.random_range(0..300)))
                .collect();
            times.sort_by(f64::total_cmp);
            let mut reports = |n: usize| {
                let mut r: Vec<f64> = (0..n)
                    .map(|_| 10.0 * f64::from(rng.random_range(0..300)))
                    .collect();
                r.sort_by(f64::total_cmp);
                r
            };
            let (ra, rb) = (reports(1 + case % 7), reports(1 + 3 * case));
            let share: f64 = rng.random_range(0.0..1.0);
            let tau = [0.0, 30.0, 300.0][case % 3];
            let c = pair_instant_counts(&times, &ra, &rb, share, tau);
            let (w, k_eff) = (c.weights, c.evidence_k_eff);
            let (xa, xb) = (snapped(&times, &ra), snapped(&times, &rb));
            let r = |x: &[f64], i: usize, j: usize| rho((x[i] - x[j]).abs(), tau);
            let corr = |i: usize, j: usize| share * r(&xa, i, j) + (1.0 - share) * r(&xb, i, j);
            let mut var = 0.0;
            for i in 0..k {
                let mass: f64 = (0..k).map(|j| corr(i, j)).sum();
                assert!((w[i] * mass - 1.0).abs() < 1e-9, "case {case}, instant {i}");
                for j in 0..k {
                    var += w[i] * w[j] * corr(i, j);
                }
            }
            // the plain mean's count: the two tracks' counts, weighed harmonically
            let count = |x: &[f64]| {
                let total: f64 = (0..k)
                    .flat_map(|i| (0..k).map(move |j| (i, j)))
                    .map(|(i, j)| r(x, i, j))
                    .sum();
                (k * k) as f64 / total
            };
            let plain =
                (1.0 / (share / count(&xa) + (1.0 - share) / count(&xb))).clamp(1.0, k as f64);
            assert!(
                (c.k_eff - plain).abs() < 1e-9 * plain,
                "case {case}: {} {plain}",
                c.k_eff
            );
            let sum: f64 = w.iter().sum();
            let want = (sum * sum / var).clamp(1.0, k as f64);
            assert!(
                (k_eff - want).abs() < 1e-9 * want,
                "case {case}: {k_eff} {want}"
            );
        }
    }

    #[test]
    fn hand_computed_rules() {
        let g = [0.5, 0.25, 1.0];
        let m: Vec<f64> = g.iter().map(|x: &f64| -2.0 * x.ln()).collect();
        let t = [0.0, 1.0, 2.0];
        let c = |r: Combine| r.combine(&g, &m, &t, 0.0);
        assert!((c(Combine::Geometric) - 0.125f64.powf(1.0 / 3.0)).abs() < 1e-15);
        assert!((c(Combine::Harmonic) - 3.0 / 7.0).abs() < 1e-15);
        assert!((c(Combine::Arithmetic) - 1.75 / 3.0).abs() < 1e-15);
        assert_eq!(c(Combine::Min), 0.25);
        // sum m = -2 ln(1/8) = 6 ln 2; Q(3, 3 ln 2) = e^-x (1 + x + x^2/2), x = 3 ln 2
        let x = 3.0 * std::f64::consts::LN_2;
        let p = (-x).exp() * (1.0 + x + 0.5 * x * x);
        assert!((c(Combine::PValue) - p).abs() < 1e-14);
        assert!((c(Combine::Chi2) - chi2_scale(-2.0 * p.ln())).abs() < 1e-14);
    }

    #[test]
    fn one_instant_pvalue_is_the_glr() {
        for m in [0.0f64, 0.3, 2.0, 9.0, 40.0] {
            let g: f64 = (-0.5 * m).exp();
            let p = Combine::PValue.combine(&[g], &[m], &[0.0], 30.0);
            assert!((p - g).abs() < 1e-14 * g.max(1e-300), "{m}: {p} {g}");
            let s = Combine::Chi2.combine(&[g], &[m], &[0.0], 30.0);
            assert!((s - 2f64.powf(-m / 9.0)).abs() < 1e-14);
        }
        assert!((chi2_scale(9.0) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn effective_instants_limits() {
        let t: Vec<f64> = (0..100).map(|k| k as f64).collect();
        assert_eq!(effective_instants(&t, 0.0), 100.0);
        let k1 = effective_instants(&t, 1e9);
        assert!((k1 - 1.0).abs() < 1e-6);
        // far apart instants are independent
        let far: Vec<f64> = (0..10).map(|k| k as f64 * 1e6).collect();
        assert!((effective_instants(&far, 10.0) - 10.0).abs() < 1e-9);
        // brute force sum
        let tau = 7.0;
        let mut s = 0.0;
        for a in &t {
            for b in &t {
                s += (-2.0 * (a - b).abs() / tau).exp();
            }
        }
        assert!((effective_instants(&t, tau) - 1e4 / s).abs() < 1e-9);
    }

    #[test]
    fn inflation_is_the_median_of_the_mutual_best_pairs() {
        // tracks 0..20 of source 0 and 20..40 of source 1; true pairs (i, 20 + i) with mean
        // distance 2 c; each track also has a worse partner, and 4 of the true pairs are replaced
        // by far pairs (ratio above the cap) that are mutually best too
        let c = 1.7;
        let ke: f64 = 50.0;
        let wh = (1.0 - 1.0 / (9.0 * ke)).powi(3);
        let mut source = vec![0u32; 20];
        source.extend(vec![1u32; 20]);
        let mut pairs = Vec::new();
        let mut stats = Vec::new();
        for i in 0..20u32 {
            let spread = 1.0 + 0.01 * (i as f64 - 10.0);
            let m_bar = if i < 4 { 200.0 } else { 2.0 * c * wh * spread };
            pairs.push((i, 20 + i));
            stats.push((m_bar * 100.0, 100.0, ke));
            pairs.push((i, 20 + (i + 1) % 20));
            stats.push((500.0 * 100.0, 100.0, ke));
        }
        let got = estimate_inflation(&pairs, &source, &stats);
        assert_eq!(got.len(), 1);
        assert_eq!((got[0].0, got[0].1), (0, 1));
        assert!((got[0].2 - c * 1.015).abs() < 0.02, "{got:?}");
        // consistent AOUs: never below 1
        let stats1: Vec<_> = stats.iter().map(|&(s, k, e)| (s / 4.0, k, e)).collect();
        assert_eq!(estimate_inflation(&pairs, &source, &stats1)[0].2, 1.0);
        // too few pairs: 1
        assert_eq!(
            estimate_inflation(&pairs[..6], &source, &stats[..6])[0].2,
            1.0
        );
    }

    #[test]
    fn zero_score_zeroes_chi2() {
        let s = Combine::Chi2.combine(&[0.0, 1.0], &[f64::INFINITY, 0.0], &[0.0, 1.0], 0.0);
        assert_eq!(s, 0.0);
        assert_eq!(
            Combine::Harmonic.combine(&[0.0, 1.0], &[f64::INFINITY, 0.0], &[0.0, 1.0], 0.0),
            0.0
        );
    }
}
