//! Monte-Carlo estimate of the normalised overlap area by importance sampling (seed 000, eq. 55).
//!
//! `g_M = sum 1{x_i in S1 ∩ S2} / p(x_i) / sum 1{x_i in S_min} / p(x_i)` with the `x_i` drawn
//! from the Gaussian `p` of the ellipse of smaller area (the first one on a tie). Samples are
//! drawn by Marsaglia's polar method (in vectorised blocks, see [`monte_carlo`]): for `(u, v)` uniform in the unit disc with `s = u^2 + v^2`,
//! `z = (u, v) sqrt(-2 ln s / s)` is standard normal and `exp(|z|^2 / 2) = 1 / s`, so the weight
//! `1 / p(x)` (up to the constant that cancels in the ratio) is `1 / s` exactly, with no
//! exponential. `x` lies in `S_min` exactly when `|z| <= 2`, i.e. `s >= e^-2`.
//!
//! Every pair draws from its own xoshiro256++ stream seeded from `(seed, pair index)`, so a seed
//! gives bit-identical results whatever the number of threads. With no sample inside `S_min`
//! (probability `0.135^N`) the estimate is 0.

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::PairScore;
use crate::ellipse::Ellipse;
use crate::fastmath::ln_pos;

/// Monte-Carlo options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MonteCarlo {
    /// Number of Gaussian samples per pair.
    pub samples: usize,
    /// Seed of the random streams.
    pub seed: u64,
}

impl Default for MonteCarlo {
    fn default() -> Self {
        Self {
            samples: 500,
            seed: 0,
        }
    }
}

/// SplitMix64 finaliser: decorrelates `(seed, index)` into a stream seed.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The random stream of pair `index` under `seed`.
pub fn stream(seed: u64, index: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(mix64(seed ^ mix64(index)))
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
/// work is branch-free and vectorises; sums are accumulated in a fixed order.
pub fn monte_carlo<R: rand::Rng>(a: &Ellipse, b: &Ellipse, samples: usize, rng: &mut R) -> f64 {
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
    while drawn < samples {
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

impl PairScore for MonteCarlo {
    type Prepared = Ellipse;

    fn prepare(&self, e: &Ellipse) -> Ellipse {
        *e
    }

    fn score(&self, a: &Ellipse, b: &Ellipse, index: u64) -> f64 {
        let mut rng = stream(self.seed, index);
        monte_carlo(a, b, self.samples, &mut rng)
    }

    fn chunk_pairs(&self) -> usize {
        ((1 << 24) / self.samples.max(1)).max(64)
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
        };
        let a = Ellipse::circle(0.0, 0.0, 1.0);
        let b = Ellipse::circle(1.0, 0.0, 1.0);
        assert_eq!(mc.score(&a, &b, 7), mc.score(&a, &b, 7));
        assert_ne!(mc.score(&a, &b, 7), mc.score(&a, &b, 8));
    }
}
