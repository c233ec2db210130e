//! Branch-free `sin_cos` and `exp` for the batch kernels.
//!
//! `std`'s `sin_cos` and `exp` are calls into libm, which stop LLVM from vectorising a loop. These
//! inline versions use the classic fdlibm construction (Cody-Waite argument reduction, the fdlibm
//! kernel polynomials for sine and cosine on `[-pi/4, pi/4]`, and a degree-13 Taylor polynomial
//! for `exp` on `[-ln2/2, ln2/2]` scaled by `2^k` through the exponent bits), select quadrants
//! with masks instead of branches, plus fdlibm's `log` for [`ln_pos`], and are accurate to a few units in the last place (tested
//! against `std` below). [`sin_cos`] is valid for `|x| <= SIN_COS_LIMIT`; [`exp_neg`] for
//! `x <= 0` (down through the subnormal range, like `std`).

// The constants are fdlibm's, written with all the digits it publishes.
#![allow(clippy::excessive_precision)]

/// Largest `|x|` for which [`sin_cos`] keeps full accuracy.
pub const SIN_COS_LIMIT: f64 = 1.0e5;

const MAGIC: f64 = 6_755_399_441_055_744.0; // 1.5 * 2^52: adding it rounds to an integer

/// `(sin x, cos x)` for `|x| <= SIN_COS_LIMIT`.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    const TWO_OVER_PI: f64 = std::f64::consts::FRAC_2_PI;
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
    const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
    const PIO2_3: f64 = 2.022_266_248_711_166_455_8e-21;
    const S1: f64 = -1.666_666_666_666_663_243_48e-01;
    const S2: f64 = 8.333_333_333_322_489_461_24e-03;
    const S3: f64 = -1.984_126_982_985_794_931_34e-04;
    const S4: f64 = 2.755_731_370_707_006_767_89e-06;
    const S5: f64 = -2.505_076_025_340_686_341_95e-08;
    const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    const C1: f64 = 4.166_666_666_666_660_190_37e-02;
    const C2: f64 = -1.388_888_888_887_410_957_49e-03;
    const C3: f64 = 2.480_158_728_947_672_941_78e-05;
    const C4: f64 = -2.755_731_435_139_066_330_35e-07;
    const C5: f64 = 2.087_572_321_298_174_827_90e-09;
    const C6: f64 = -1.135_964_755_778_819_482_65e-11;

    let shifted = x * TWO_OVER_PI + MAGIC;
    let q = shifted.to_bits();
    let k = shifted - MAGIC;
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let z = r * r;
    let s = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c =
        w + (((1.0 - w) - hz) + z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6))))));
    let swap = q & 1 == 1;
    let (mut sin, mut cos) = if swap { (c, s) } else { (s, c) };
    if q & 2 == 2 {
        sin = -sin;
    }
    if q.wrapping_add(1) & 2 == 2 {
        cos = -cos;
    }
    (sin, cos)
}

/// `exp(x)` for `x <= 0`, gradually underflowing to the subnormals like `f64::exp`; exactly 0
/// for `x < -746` (where `exp(x)` rounds to 0).
#[inline(always)]
pub fn exp_neg(x: f64) -> f64 {
    const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-01;
    const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
    const INV_LN2: f64 = std::f64::consts::LOG2_E;
    let xc = if x < -746.0 { -746.0 } else { x };
    let shifted = xc * INV_LN2 + MAGIC;
    let k = shifted - MAGIC;
    let r = (xc - k * LN2_HI) - k * LN2_LO;
    // Taylor series of exp on |r| <= ln2/2, degree 13 (truncation < 1e-17 relative).
    let mut p = 1.0 / 6_227_020_800.0;
    p = p * r + 1.0 / 479_001_600.0;
    p = p * r + 1.0 / 39_916_800.0;
    p = p * r + 1.0 / 3_628_800.0;
    p = p * r + 1.0 / 362_880.0;
    p = p * r + 1.0 / 40_320.0;
    p = p * r + 1.0 / 5_040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    // k is an integer in [-1077, 0]: 2^k as the product of two normal powers of two, so that
    // results below the normal range round once into the subnormals.
    let ki = shifted.to_bits().wrapping_sub(MAGIC.to_bits()) as i64;
    let k1 = ki >> 1;
    let k2 = ki - k1;
    let s1 = f64::from_bits(((k1 + 1023) as u64) << 52);
    let s2 = f64::from_bits(((k2 + 1023) as u64) << 52);
    if x < -746.0 {
        0.0
    } else {
        (p * s1) * s2
    }
}

/// `ln(x)` for normal positive `x` (fdlibm's `log` polynomial, branch-free).
#[inline(always)]
pub fn ln_pos(x: f64) -> f64 {
    const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-01;
    const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
    const LG1: f64 = 6.666_666_666_666_735_130e-01;
    const LG2: f64 = 3.999_999_999_940_941_908e-01;
    const LG3: f64 = 2.857_142_874_366_239_149e-01;
    const LG4: f64 = 2.222_219_843_214_978_396e-01;
    const LG5: f64 = 1.818_357_216_161_805_012e-01;
    const LG6: f64 = 1.531_383_769_920_937_332e-01;
    const LG7: f64 = 1.479_819_860_511_658_591e-01;
    let bits = x.to_bits();
    let mut e = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let mut m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    let big = m > std::f64::consts::SQRT_2;
    m = if big { 0.5 * m } else { m };
    e += big as i64;
    let k = e as f64;
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
    let r = t2 + t1;
    let hfsq = 0.5 * f * f;
    k * LN2_HI - ((hfsq - (s * (hfsq + r) + k * LN2_LO)) - f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    fn ulps(a: f64, b: f64) -> f64 {
        if a == b {
            return 0.0;
        }
        (a - b).abs() / (f64::EPSILON * b.abs().max(f64::MIN_POSITIVE))
    }

    #[test]
    fn sin_cos_matches_std() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(1);
        let mut worst: f64 = 0.0;
        for i in 0..400_000 {
            let x: f64 = match i % 3 {
                0 => rng.random_range(-7.0..7.0),
                1 => rng.random_range(-SIN_COS_LIMIT..SIN_COS_LIMIT),
                _ => rng.random_range(-1e-6..1e-6),
            };
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            // absolute error relative to 1 (the values' scale) is what the kernels need
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst < 4.0 * f64::EPSILON, "worst abs error {worst:e}");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
    }

    #[test]
    fn exp_matches_std() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(2);
        let mut worst: f64 = 0.0;
        for i in 0..400_000 {
            let x: f64 = match i % 3 {
                0 => -rng.random_range(0.0..5.0),
                1 => -rng.random_range(0.0..708.0),
                _ => -rng.random_range(708.0..746.0),
            };
            worst = worst.max(ulps(exp_neg(x), x.exp()));
        }
        assert!(worst <= 4.0, "worst {worst} ulp");
        // the subnormal range, gradually (the eq. 71 kernel must not flush it to zero)
        assert!(exp_neg(-720.0) > 0.0 && exp_neg(-744.0) > 0.0);
        assert_eq!(exp_neg(-745.2), (-745.2f64).exp());
        assert_eq!(exp_neg(0.0), 1.0);
        assert_eq!(exp_neg(-800.0), 0.0);
        assert_eq!(exp_neg(f64::NEG_INFINITY), 0.0);
    }

    #[test]
    fn ln_matches_std() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
        let mut worst: f64 = 0.0;
        for i in 0..400_000 {
            let x: f64 = match i % 3 {
                0 => rng.random_range(0.1..1.0),
                1 => rng.random_range(1e-30..1e30),
                _ => 1.0 + rng.random_range(-1e-8..1e-8),
            };
            // absolute error against max(1, |ln x|): what the sampler needs
            let err = (ln_pos(x) - x.ln()).abs() / x.ln().abs().max(1.0);
            worst = worst.max(err);
        }
        assert!(worst < 4.0 * f64::EPSILON, "worst {worst:e}");
        assert_eq!(ln_pos(1.0), 0.0);
    }
}
