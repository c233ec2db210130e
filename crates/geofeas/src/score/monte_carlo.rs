//! Monte-Carlo estimate of the normalised overlap area by importance sampling (seed 000, eq. 55).
//!
//! `g_M = sum 1{x_i in S1 ∩ S2} / p(x_i) / sum 1{x_i in S_min} / p(x_i)` with the `x_i` drawn
//! from the Gaussian `p` of the ellipse of smaller area (the first one on a tie). Samples are
//! drawn by Marsaglia's polar method (in vectorised blocks, see [`monte_carlo`]): for `(u, v)` uniform in the unit disc with `s = u^2 + v^2`,
//! `z = (u, v) sqrt(-2 ln s / s)` is standard normal and `exp(|z|^2 / 2) = 1 / s`, so the weight
//! `1 / p(x)` (up to the constant that cancels in the ratio) is `1 / s` exactly, with no
//! exponential. `x` lies in `S_min` exactly when `|z| <= 2`, i.e. `s >= e^-2`.
//!
//! Every pair draws from its own xoshiro256++ stream seeded from `(seed, pair index)`
//! ([`crate::rng::stream`]), so a seed
//! gives bit-identical results whatever the number of threads. With no sample inside `S_min`
//! (probability `0.135^N`) the estimate is 0.
//!
//! **Samplers.** [`Sampler::Importance`] is eq. 55 as above (the default, bit-for-bit what it
//! has always been). Two more sample-efficient estimators of the same `g` (eq. 49):
//! [`Sampler::Uniform`] draws the points uniformly inside `S_min` (the affine image of uniform
//! points of the unit disc, drawn by rejection from the square), so `g` is the fraction of them
//! inside the other ellipse, with variance `g (1 - g) / N` and no ratio bias; [`Sampler::Sobol`]
//! uses the first `N` points of the two-dimensional Sobol sequence with a hash-based nested
//! uniform (Owen) scrambling drawn from the pair's stream (Burley 2020, "Practical hash-based
//! Owen scrambling"), mapped to the unit disc by the area-preserving concentric map of Shirley &
//! Chiu (1997) and then to `S_min`. Randomised quasi-Monte-Carlo stays unbiased, and for the
//! indicator of a region with a smooth boundary its root-mean-square error falls like
//! `N^(-3/4)` instead of `N^(-1/2)`, so 64 points match the accuracy of eq. 55 at N = 500.

use super::{Cancel, PairScore};
use crate::ellipse::Ellipse;
use crate::fastmath::ln_pos;
use crate::rng::stream;

/// How the sample points are drawn (see the module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Sampler {
    /// Gaussian samples of `S_min` weighted by `1 / p` (eq. 55).
    #[default]
    Importance,
    /// Uniform samples inside `S_min`.
    Uniform,
    /// Owen-scrambled Sobol points mapped into `S_min` (randomised quasi-Monte-Carlo).
    Sobol,
}

impl Sampler {
    /// Names accepted by [`Sampler::from_name`].
    pub const NAMES: [&'static str; 3] = ["importance", "uniform", "sobol"];

    /// The sampler called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "importance" => Some(Self::Importance),
            "uniform" => Some(Self::Uniform),
            "sobol" => Some(Self::Sobol),
            _ => None,
        }
    }
}

/// Monte-Carlo options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MonteCarlo {
    /// Number of samples per pair.
    pub samples: usize,
    /// Seed of the random streams.
    pub seed: u64,
    /// How the samples are drawn.
    pub sampler: Sampler,
}

impl MonteCarlo {
    /// Most samples per pair: the length of the 32-bit Sobol sequence (beyond it the points
    /// would repeat), shared by every sampler so the option has one domain. An estimate from
    /// that many samples has a standard error below 1e-5; one such pair runs for minutes, and
    /// the sample loops check the driver's [`Cancel`] flag every [`CANCEL_CHECK`] samples, so
    /// Ctrl-C stops it promptly.
    pub const MAX_SAMPLES: usize = 1 << 32;
}

/// Samples drawn between two checks of the [`Cancel`] flag (about 0.2 ms of work).
pub const CANCEL_CHECK: usize = 4096;

impl Default for MonteCarlo {
    fn default() -> Self {
        Self {
            samples: 500,
            seed: 0,
            sampler: Sampler::Importance,
        }
    }
}

/// Candidate samples drawn and evaluated together.
const BLOCK: usize = 64;

/// A uniform double in `[-1, 1)` from 53 random bits.
#[inline(always)]
fn symmetric_unit(x: u64) -> f64 {
    ((x >> 11) as f64) * (2.0 / (1u64 << 53) as f64) - 1.0
}

/// Eq. 55 for one pair with an explicit random stream.
///
/// Candidates `(u, v)` are drawn in blocks of 64; the first `samples` accepted ones (inside the
/// unit disc) are used, in draw order, so the result depends only on the stream. The per-sample
/// work is branch-free and vectorises; sums are accumulated in a fixed order. Once `cancel` is
/// raised (checked every [`CANCEL_CHECK`] candidates) the loop stops and returns NaN, which the
/// driver discards.
pub fn monte_carlo<R: rand::Rng>(
    a: &Ellipse,
    b: &Ellipse,
    samples: usize,
    rng: &mut R,
    cancel: &Cancel,
) -> f64 {
    let (small, other) = if a.area() <= b.area() { (a, b) } else { (b, a) };
    // x = c_s + (rx_s/2) z1 e1 + (ry_s/2) z2 e2, mapped straight into other's normalised frame:
    // n(x) = w + M z.
    let ([e1x, e1y], [e2x, e2y]) = small.axes();
    let (so, co) = other.phi.sin_cos();
    let to_o = |dx: f64, dy: f64| {
        [
            (dx * so + dy * co) / other.rx,
            (dx * co - dy * so) / other.ry,
        ]
    };
    let w = to_o(small.x0 - other.x0, small.y0 - other.y0);
    let c1 = to_o(0.5 * small.rx * e1x, 0.5 * small.rx * e1y);
    let c2 = to_o(0.5 * small.ry * e2x, 0.5 * small.ry * e2y);
    let s_min = (-2.0f64).exp();
    let mut u = [0.0f64; BLOCK];
    let mut v = [0.0f64; BLOCK];
    let mut wden = [0.0f64; BLOCK];
    let mut wnum = [0.0f64; BLOCK];
    let mut den = [0.0f64; 4];
    let mut num = [0.0f64; 4];
    let mut drawn = 0;
    let mut blocks = 0usize;
    while drawn < samples {
        blocks += 1;
        if blocks % (CANCEL_CHECK / BLOCK) == 0 && cancel.is_raised() {
            return f64::NAN;
        }
        for i in 0..BLOCK {
            u[i] = symmetric_unit(rng.next_u64());
            v[i] = symmetric_unit(rng.next_u64());
        }
        // keep the candidates up to the `samples`-th accepted one
        let mut limit = BLOCK;
        for i in 0..BLOCK {
            let s = u[i] * u[i] + v[i] * v[i];
            if s < 1.0 && s > 0.0 {
                drawn += 1;
                if drawn == samples {
                    limit = i + 1;
                    break;
                }
            }
        }
        for i in 0..BLOCK {
            let s = u[i] * u[i] + v[i] * v[i];
            // |z| <= 2 (inside S_min) exactly when s >= e^-2; s < 1 is the polar acceptance
            let used = s < 1.0 && s >= s_min && i < limit;
            let sc = s.clamp(s_min, 1.0);
            let f = (-2.0 * ln_pos(sc) / sc).sqrt();
            let (z1, z2) = (u[i] * f, v[i] * f);
            let p = w[0] + c1[0] * z1 + c2[0] * z2;
            let q = w[1] + c1[1] * z1 + c2[1] * z2;
            let weight = if used { 1.0 / sc } else { 0.0 };
            wden[i] = weight;
            wnum[i] = if p * p + q * q <= 1.0 { weight } else { 0.0 };
        }
        for i in (0..BLOCK).step_by(4) {
            for l in 0..4 {
                den[l] += wden[i + l];
                num[l] += wnum[i + l];
            }
        }
    }
    let den = (den[0] + den[1]) + (den[2] + den[3]);
    let num = (num[0] + num[1]) + (num[2] + num[3]);
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// The smaller ellipse (the first on a tie) and the map of its normalised frame into the
/// normalised frame of the other: `n(u, v) = w + u c1 + v c2`.
fn small_to_other(a: &Ellipse, b: &Ellipse) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let (small, other) = if a.area() <= b.area() { (a, b) } else { (b, a) };
    let ([e1x, e1y], [e2x, e2y]) = small.axes();
    let (so, co) = other.phi.sin_cos();
    let to_o = |dx: f64, dy: f64| {
        [
            (dx * so + dy * co) / other.rx,
            (dx * co - dy * so) / other.ry,
        ]
    };
    (
        to_o(small.x0 - other.x0, small.y0 - other.y0),
        to_o(small.rx * e1x, small.rx * e1y),
        to_o(small.ry * e2x, small.ry * e2y),
    )
}

/// `g` by `samples` points uniform in the smaller ellipse (rejection from the square); NaN once
/// `cancel` is raised.
pub fn monte_carlo_uniform<R: rand::Rng>(
    a: &Ellipse,
    b: &Ellipse,
    samples: usize,
    rng: &mut R,
    cancel: &Cancel,
) -> f64 {
    let (w, c1, c2) = small_to_other(a, b);
    let mut inside = 0usize;
    let mut drawn = 0usize;
    while drawn < samples {
        if drawn % CANCEL_CHECK == 0 && cancel.is_raised() {
            return f64::NAN;
        }
        let u = symmetric_unit(rng.next_u64());
        let v = symmetric_unit(rng.next_u64());
        if u * u + v * v >= 1.0 {
            continue;
        }
        drawn += 1;
        let p = w[0] + c1[0] * u + c2[0] * v;
        let q = w[1] + c1[1] * u + c2[1] * v;
        inside += usize::from(p * p + q * q <= 1.0);
    }
    inside as f64 / samples as f64
}

/// Reverses the bits of a 32-bit word.
#[inline]
fn reverse(x: u32) -> u32 {
    x.reverse_bits()
}

/// The Laine-Karras hash permutation (as tuned by Burley 2020): a random-looking bijection of
/// 32-bit words where each bit depends only on the bits below it.
#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Nested uniform (Owen) scrambling of a 32-bit fixed-point coordinate.
#[inline]
fn owen(x: u32, seed: u32) -> u32 {
    reverse(laine_karras(reverse(x), seed))
}

/// Direction numbers of the second Sobol dimension (primitive polynomial `x + 1`):
/// `m_k = 2 m_(k-1) xor m_(k-1)`, `m_1 = 1`, as 32-bit fixed point.
const SOBOL_DIM1: [u32; 32] = {
    let mut v = [0u32; 32];
    let mut m: u64 = 1;
    let mut k = 0;
    while k < 32 {
        v[k] = (m << (31 - k)) as u32;
        m = (m << 1) ^ m;
        k += 1;
    }
    v
};

/// Point `i` of the two-dimensional Sobol sequence, as 32-bit fixed point.
#[inline]
pub fn sobol2(i: u32) -> (u32, u32) {
    let x = reverse(i);
    let mut y = 0u32;
    let mut bits = i;
    while bits != 0 {
        let k = bits.trailing_zeros() as usize;
        y ^= SOBOL_DIM1[k];
        bits &= bits - 1;
    }
    (x, y)
}

/// The concentric map of the unit square onto the unit disc (Shirley & Chiu 1997): area
/// preserving and continuous, so low-discrepancy points stay low-discrepancy.
#[inline]
pub fn concentric(x: f64, y: f64) -> (f64, f64) {
    let (a, b) = (2.0 * x - 1.0, 2.0 * y - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let quarter = std::f64::consts::FRAC_PI_4;
    let (r, theta) = if a * a > b * b {
        (a, quarter * (b / a))
    } else {
        (b, 2.0 * quarter - quarter * (a / b))
    };
    let (s, c) = crate::fastmath::sin_cos(theta);
    (r * c, r * s)
}

/// `g` by the first `samples` points of an Owen-scrambled Sobol sequence (seeded by `rng`)
/// mapped uniformly into the smaller ellipse; NaN once `cancel` is raised. At most
/// [`MonteCarlo::MAX_SAMPLES`] points (the sequence's length).
pub fn monte_carlo_sobol<R: rand::Rng>(
    a: &Ellipse,
    b: &Ellipse,
    samples: usize,
    rng: &mut R,
    cancel: &Cancel,
) -> f64 {
    debug_assert!(samples <= MonteCarlo::MAX_SAMPLES);
    let (w, c1, c2) = small_to_other(a, b);
    let bits = rng.next_u64();
    let (sx, sy) = (bits as u32, (bits >> 32) as u32);
    let scale = 1.0 / 4_294_967_296.0;
    let mut inside = 0usize;
    for i in 0..samples {
        if i % CANCEL_CHECK == 0 && cancel.is_raised() {
            return f64::NAN;
        }
        let (x, y) = sobol2(i as u32);
        let (x, y) = (owen(x, sx), owen(y, sy));
        // the centre of the 2^-32 cell, so no coordinate is exactly 0 or 1
        let (u, v) = concentric((f64::from(x) + 0.5) * scale, (f64::from(y) + 0.5) * scale);
        let p = w[0] + c1[0] * u + c2[0] * v;
        let q = w[1] + c1[1] * u + c2[1] * v;
        inside += usize::from(p * p + q * q <= 1.0);
    }
    inside as f64 / samples as f64
}

impl PairScore for MonteCarlo {
    type Prepared = Ellipse;

    fn prepare(&self, e: &Ellipse) -> Ellipse {
        *e
    }

    fn score(&self, a: &Ellipse, b: &Ellipse, index: u64) -> f64 {
        self.score_cancellable(a, b, index, Cancel::never())
    }

    fn score_cancellable(&self, a: &Ellipse, b: &Ellipse, index: u64, cancel: &Cancel) -> f64 {
        let mut rng = stream(self.seed, index);
        match self.sampler {
            Sampler::Importance => monte_carlo(a, b, self.samples, &mut rng, cancel),
            Sampler::Uniform => monte_carlo_uniform(a, b, self.samples, &mut rng, cancel),
            Sampler::Sobol => monte_carlo_sobol(a, b, self.samples, &mut rng, cancel),
        }
    }

    fn long_pairs(&self) -> bool {
        // 2^18 samples take about ten milliseconds
        self.samples >= 1 << 18
    }

    fn chunk_pairs(&self) -> usize {
        // about 2^24 samples per chunk, at least one pair per thread
        ((1 << 24) / self.samples.max(1)).max(rayon::current_num_threads())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_and_disjoint() {
        let mc = MonteCarlo::default();
        let a = Ellipse::new(5.0, 5.0, 3.0, 1.0, 0.5);
        assert_eq!(mc.score_one(&a, &a), 1.0);
        assert_eq!(mc.score_one(&a, &Ellipse::circle(100.0, 0.0, 1.0)), 0.0);
    }

    #[test]
    fn seeded_streams_reproduce() {
        let mc = MonteCarlo {
            samples: 200,
            seed: 42,
            ..MonteCarlo::default()
        };
        let a = Ellipse::circle(0.0, 0.0, 1.0);
        let b = Ellipse::circle(1.0, 0.0, 1.0);
        assert_eq!(mc.score(&a, &b, 7), mc.score(&a, &b, 7));
        assert_ne!(mc.score(&a, &b, 7), mc.score(&a, &b, 8));
    }

    #[test]
    fn sobol_points_are_a_net() {
        // the first 2^m points put exactly one point in every 2^-j x 2^-(m-j) box
        let m = 6;
        for j in 0..=m {
            let mut seen = vec![false; 1 << m];
            for i in 0..(1u32 << m) {
                let (x, y) = sobol2(i);
                let (x, y) = (owen(x, 0x1234_5678), owen(y, 0x9abc_def0));
                let xi = (u64::from(x) >> (32 - j)) as usize;
                let yi = (u64::from(y) >> (32 - (m - j))) as usize;
                let cell = (xi << (m - j)) | yi;
                assert!(!seen[cell], "box {cell} twice (j = {j})");
                seen[cell] = true;
            }
        }
    }

    #[test]
    fn concentric_map_preserves_area() {
        // points of a fine grid land uniformly: the fraction inside radius 1/2 is 1/4
        let n = 400;
        let mut inside = 0;
        for i in 0..n {
            for j in 0..n {
                let (u, v) = concentric((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                assert!(u * u + v * v <= 1.0 + 1e-15);
                inside += usize::from(u * u + v * v <= 0.25);
            }
        }
        assert!((inside as f64 / (n * n) as f64 - 0.25).abs() < 2e-3);
    }

    #[test]
    fn raised_cancel_stops_one_long_pair() {
        // 2^24 samples would take most of a second; a raised flag stops the loop at once
        let cancel = Cancel::default();
        cancel.raise();
        let (a, b) = (
            Ellipse::circle(0.0, 0.0, 1.0),
            Ellipse::circle(1.0, 0.0, 1.0),
        );
        for sampler in [Sampler::Importance, Sampler::Uniform, Sampler::Sobol] {
            let mc = MonteCarlo {
                samples: 1 << 24,
                seed: 1,
                sampler,
            };
            assert!(
                mc.score_cancellable(&a, &b, 0, &cancel).is_nan(),
                "{sampler:?}"
            );
            // and a flag that is never raised changes nothing
            let few = MonteCarlo {
                samples: 5000,
                ..mc
            };
            assert_eq!(
                few.score_cancellable(&a, &b, 3, Cancel::never()),
                few.score(&a, &b, 3)
            );
        }
    }

    #[test]
    fn driver_interrupts_one_long_pair() {
        // the hook returns true on its second call, which can only come from the calling
        // thread polling while the single pair runs on the pool
        let mc = MonteCarlo {
            samples: 1 << 26,
            seed: 1,
            ..MonteCarlo::default()
        };
        let a = [Ellipse::circle(0.0, 0.0, 1.0)];
        let b = [Ellipse::circle(1.0, 0.0, 1.0)];
        let mut out = [0.0];
        let mut calls = 0;
        let mut hook = || {
            calls += 1;
            calls >= 2
        };
        let err = super::super::score_pairs(&mc, &a, &b, &mut out, &mut hook).unwrap_err();
        assert_eq!(err, crate::error::Error::Interrupted);
        assert!(calls >= 2);
    }

    #[test]
    fn samplers_identical_and_disjoint() {
        let a = Ellipse::new(5.0, 5.0, 3.0, 1.0, 0.5);
        let far = Ellipse::circle(100.0, 0.0, 1.0);
        for sampler in [Sampler::Uniform, Sampler::Sobol] {
            let mc = MonteCarlo {
                sampler,
                samples: 64,
                seed: 3,
            };
            assert_eq!(mc.score_one(&a, &a), 1.0);
            assert_eq!(mc.score_one(&a, &far), 0.0);
        }
    }
}
