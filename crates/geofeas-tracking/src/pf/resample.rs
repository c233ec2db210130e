//! Resampling schemes of the particle filter (seed 003 uses the standard re-sampling step of
//! Gordon, Salmond and Smith, its reference 1; the schemes are those of Douc and Cappe's
//! comparison).
//!
//! Each draws `N` ancestor indices from normalised weights `w` in O(N), in increasing order:
//! - systematic: one uniform `u`, points `(k + u) / N` (the default; lowest variance in practice);
//! - stratified: one uniform per stratum, `(k + u_k) / N`;
//! - multinomial: `N` sorted uniforms (from normalised exponential spacings);
//! - residual: `floor(N w_n)` copies of each particle, the rest multinomial on the residuals.

use rand::{Rng, RngExt};

use geofeas::error::{Error, Result};

/// A resampling scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Resampling {
    /// One uniform offset shared by all strata.
    #[default]
    Systematic,
    /// One uniform per stratum.
    Stratified,
    /// Independent draws.
    Multinomial,
    /// Deterministic copies plus multinomial residuals.
    Residual,
}

impl Resampling {
    /// The scheme named `"systematic"`, `"stratified"`, `"multinomial"` or `"residual"`.
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "systematic" => Ok(Self::Systematic),
            "stratified" => Ok(Self::Stratified),
            "multinomial" => Ok(Self::Multinomial),
            "residual" => Ok(Self::Residual),
            other => Err(Error::InvalidOption {
                name: "resampling",
                reason: format!(
                    "expected 'systematic', 'stratified', 'multinomial' or 'residual', got '{other}'"
                ),
            }),
        }
    }

    /// The name of the scheme.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Systematic => "systematic",
            Self::Stratified => "stratified",
            Self::Multinomial => "multinomial",
            Self::Residual => "residual",
        }
    }

    /// Writes `w.len()` ancestor indices drawn from the normalised weights `w` into `out`.
    pub fn resample<R: Rng>(&self, w: &[f64], rng: &mut R, out: &mut Vec<usize>) {
        let n = w.len();
        out.clear();
        if n == 0 {
            return;
        }
        match self {
            Self::Systematic => {
                let u = rng.random::<f64>();
                invert(w, n, |k| (k as f64 + u) / n as f64, out);
            }
            Self::Stratified => {
                let us: Vec<f64> = (0..n)
                    .map(|k| (k as f64 + rng.random::<f64>()) / n as f64)
                    .collect();
                invert(w, n, |k| us[k], out);
            }
            Self::Multinomial => {
                let us = sorted_uniforms(n, rng);
                invert(w, n, |k| us[k], out);
            }
            Self::Residual => {
                let mut resid = Vec::with_capacity(n);
                for (i, &wi) in w.iter().enumerate() {
                    let c = (n as f64 * wi).floor() as usize;
                    out.extend(std::iter::repeat(i).take(c));
                    resid.push(n as f64 * wi - c as f64);
                }
                let m = n.saturating_sub(out.len());
                if m > 0 {
                    let total: f64 = resid.iter().sum();
                    if total > 0.0 {
                        resid.iter_mut().for_each(|r| *r /= total);
                        let us = sorted_uniforms(m, rng);
                        let mut extra = Vec::with_capacity(m);
                        invert(&resid, m, |k| us[k], &mut extra);
                        out.extend(extra);
                    } else {
                        // Rounding left no residual mass: repeat the heaviest particle.
                        let best = (0..n).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
                        out.extend(std::iter::repeat(best).take(m));
                    }
                }
                out.truncate(n);
                out.sort_unstable();
            }
        }
    }
}

/// `m` sorted uniforms on [0, 1) from normalised exponential spacings.
fn sorted_uniforms<R: Rng>(m: usize, rng: &mut R) -> Vec<f64> {
    let mut e: Vec<f64> = (0..=m).map(|_| -(1.0 - rng.random::<f64>()).ln()).collect();
    let total: f64 = e.iter().sum();
    let mut acc = 0.0;
    for v in e.iter_mut() {
        acc += *v;
        *v = acc / total;
    }
    e.truncate(m);
    e
}

/// Inverse-CDF lookup of the `m` increasing points `point(k)` in the cumulative weights.
fn invert(w: &[f64], m: usize, point: impl Fn(usize) -> f64, out: &mut Vec<usize>) {
    let n = w.len();
    let mut i = 0;
    let mut cum = w[0];
    for k in 0..m {
        let u = point(k);
        while cum <= u && i + 1 < n {
            i += 1;
            cum += w[i];
        }
        out.push(i);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geofeas::rng::stream;

    #[test]
    fn every_scheme_is_unbiased() {
        let w = [0.1, 0.4, 0.05, 0.3, 0.15];
        for s in [
            Resampling::Systematic,
            Resampling::Stratified,
            Resampling::Multinomial,
            Resampling::Residual,
        ] {
            let mut counts = [0usize; 5];
            let mut rng = stream(4, 0);
            let mut out = Vec::new();
            let reps = 20_000;
            for _ in 0..reps {
                s.resample(&w, &mut rng, &mut out);
                assert_eq!(out.len(), 5);
                assert!(out.windows(2).all(|p| p[0] <= p[1]));
                for &i in &out {
                    counts[i] += 1;
                }
            }
            for (c, wi) in counts.iter().zip(w) {
                let f = *c as f64 / (5 * reps) as f64;
                assert!((f - wi).abs() < 0.006, "{} {f} {wi}", s.name());
            }
        }
    }

    #[test]
    fn systematic_and_residual_keep_deterministic_copies() {
        // N w = (2, 1, 1, 0): both always return exactly those copies.
        let w = [0.5, 0.25, 0.25, 0.0];
        let mut out = Vec::new();
        let mut rng = stream(1, 1);
        for _ in 0..100 {
            Resampling::Systematic.resample(&w, &mut rng, &mut out);
            assert_eq!(out, vec![0, 0, 1, 2]);
            Resampling::Residual.resample(&w, &mut rng, &mut out);
            assert_eq!(out, vec![0, 0, 1, 2]);
        }
    }

    #[test]
    fn names_round_trip() {
        for n in ["systematic", "stratified", "multinomial", "residual"] {
            assert_eq!(Resampling::from_name(n).unwrap().name(), n);
        }
        assert!(Resampling::from_name("x").is_err());
    }
}
