//! Double-double arithmetic: a value `hi + lo` with `|lo| <= ulp(hi) / 2`, about 106 bits.
//!
//! The error-free transformations of Knuth (two-sum) and Dekker (1971, the split product), the
//! renormalised sums and products of Hida, Li & Bailey's QD library, and `sin`/`cos` of a double
//! by a reduction with the four-part `pi / 2` of fdlibm followed by Taylor series. The exact
//! overlap uses them to polish crossings whose position is ill-conditioned (a boundary crossing
//! the other at a very shallow angle), where one rounding of a double moves the area by more
//! than the kernel's accuracy target.

/// A double-double value `hi + lo`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

/// `a + b = s + e` exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b = s + e` exactly, for `|a| >= |b|`.
#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// Veltkamp's split of `a` into two halves of 26 bits (valid for `|a| < 1e300`).
#[inline]
fn split(a: f64) -> (f64, f64) {
    let c = 134_217_729.0 * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `a b = p + e` exactly (Dekker's product).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

impl Dd {
    /// The double `x`.
    pub const fn new(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    #[inline]
    fn renorm(s: f64, e: f64) -> Self {
        let (hi, lo) = quick_two_sum(s, e);
        Self { hi, lo }
    }

    /// `a - b` of two doubles, exactly.
    #[inline]
    pub fn diff(a: f64, b: f64) -> Self {
        let (s, e) = two_sum(a, -b);
        Self::renorm(s, e)
    }
}

impl std::ops::Add for Dd {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = quick_two_sum(s, e + t);
        Self::renorm(s, e + f)
    }
}

impl std::ops::Neg for Dd {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl std::ops::Sub for Dd {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        self + (-o)
    }
}

impl std::ops::Mul for Dd {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let (p, e) = two_prod(self.hi, o.hi);
        Self::renorm(p, e + (self.hi * o.lo + self.lo * o.hi))
    }
}

impl std::ops::Mul<f64> for Dd {
    type Output = Self;
    #[inline]
    fn mul(self, b: f64) -> Self {
        let (p, e) = two_prod(self.hi, b);
        Self::renorm(p, e + self.lo * b)
    }
}

impl std::ops::Div<f64> for Dd {
    type Output = Self;
    /// The quotient by a non-zero double.
    #[inline]
    fn div(self, d: f64) -> Self {
        let q1 = self.hi / d;
        let (p, e) = two_prod(q1, d);
        // self - q1 d; hi - p is exact (Sterbenz)
        let r = ((self.hi - p) - e) + self.lo;
        Self::renorm(q1, r / d)
    }
}

/// `pi / 2` in four parts of 33, 33, 33 and 53 bits (fdlibm's `pio2_1`, `pio2_2`, `pio2_3`,
/// `pio2_3t`): `k` times each of the first three is exact for `|k| < 2^20`. Written with all
/// the digits fdlibm publishes.
#[allow(clippy::excessive_precision)]
const PIO2: [f64; 4] = [
    1.570_796_326_734_125_614_17,
    6.077_100_506_303_965_976_60e-11,
    2.022_266_248_711_166_455_80e-21,
    8.478_427_660_368_899_569_97e-32,
];

/// Largest `|x|` accepted by [`sin_cos`] (the reduction stays exact well beyond it).
pub const SIN_COS_LIMIT: f64 = 1.0e5;

/// `(sin x, cos x)` to about `1e-31` for `|x| <= SIN_COS_LIMIT` (`None` beyond).
pub fn sin_cos(x: f64) -> Option<(Dd, Dd)> {
    if x.abs() > SIN_COS_LIMIT {
        return None;
    }
    let k = (x * std::f64::consts::FRAC_2_PI).round();
    // x - k pio2_1 is exact: k pio2_1 is exact and within a factor 2 of x (or x is small)
    let r = Dd::new(x - k * PIO2[0])
        - Dd::new(k * PIO2[1])
        - Dd::new(k * PIO2[2])
        - Dd::new(k * PIO2[3]);
    let r2 = r * r;
    // Taylor series on |r| <= pi / 4 (+ rounding): terms fall below 1e-33 by the 15th
    let (mut sin, mut cos) = (r, Dd::new(1.0));
    let (mut ts, mut tc) = (r, Dd::new(1.0));
    for n in 1..=15 {
        let n = n as f64;
        ts = ts * r2 / (-(2.0 * n) * (2.0 * n + 1.0));
        tc = tc * r2 / (-(2.0 * n - 1.0) * (2.0 * n));
        sin = sin + ts;
        cos = cos + tc;
        if ts.hi.abs() < 1e-34 && tc.hi.abs() < 1e-34 {
            break;
        }
    }
    Some(match (k as i64).rem_euclid(4) {
        0 => (sin, cos),
        1 => (cos, -sin),
        2 => (-sin, -cos),
        _ => (-cos, sin),
    })
}

#[cfg(test)]
#[allow(clippy::excessive_precision)]
mod tests {
    use super::*;

    /// A decimal reference written as `hi + lo`: the double nearest to it and the remainder.
    fn close(x: Dd, hi: f64, lo: f64, tol: f64) -> bool {
        let d = Dd::new(x.hi) - Dd::new(hi) + Dd::new(x.lo - lo);
        d.hi.abs() <= tol
    }

    #[test]
    fn products_and_quotients_are_exact_to_106_bits() {
        // (1 + 2^-30)^2 = 1 + 2^-29 + 2^-60: the last term is below one ulp of a double
        let x = Dd::new(1.0 + 2f64.powi(-30));
        let sq = x * x;
        assert_eq!(sq.hi, 1.0 + 2f64.powi(-29));
        assert_eq!(sq.lo, 2f64.powi(-60));
        // 1 / 3 times 3 is 1 to about 1e-32
        let third = Dd::new(1.0) / 3.0;
        let one = third * 3.0 - Dd::new(1.0);
        assert!(one.hi.abs() < 1e-31);
        assert_eq!(
            Dd::diff(1.0, 1e-20),
            Dd {
                hi: 1.0,
                lo: -1e-20
            }
        );
    }

    #[test]
    fn sin_cos_matches_50_digit_values() {
        // (x, sin x, cos x) with 40 digits (mpmath at 50 digits), split as hi + lo
        let cases: [(f64, &str, &str); 5] = [
            (
                1.0,
                "0.8414709848078965066525023216302989996226",
                "0.5403023058681397174009366074429766037323",
            ),
            (
                0.5,
                "0.4794255386042030002732879352155713880818",
                "0.8775825618903727161162815826038296519916",
            ),
            (
                2.794422513907926,
                "0.3402381444587459755181913641751697716935",
                "-0.9403393031535316535686812748965538558777",
            ),
            (
                -1.2291512879642885,
                "-0.9422047909409205243655641930091169256323",
                "0.3350375082404599202722027859623535604773",
            ),
            (
                100.25,
                "-0.2772828564548513033536720570194358868443",
                "0.9607883312760612034423445613620499861238",
            ),
        ];
        for (x, s, c) in cases {
            let (ds, dc) = sin_cos(x).unwrap();
            for (got, want) in [(ds, s), (dc, c)] {
                let (hi, lo) = decimal(want);
                assert!(close(got, hi, lo, 1e-30), "{x}: {got:?} vs {want}");
            }
        }
        assert!(sin_cos(2e5).is_none());
    }

    /// A decimal string as a double-double (its first 17 digits, then the rest).
    fn decimal(text: &str) -> (f64, f64) {
        let (sign, digits) = match text.strip_prefix('-') {
            Some(rest) => (-1.0, rest),
            None => (1.0, text),
        };
        let frac = digits.strip_prefix("0.").unwrap();
        // value = sum of 8-digit groups times 10^(-8 i), accumulated in double-double
        let mut acc = Dd::new(0.0);
        let mut scale = Dd::new(1.0);
        for chunk in frac.as_bytes().chunks(8) {
            let group: f64 = std::str::from_utf8(chunk).unwrap().parse().unwrap();
            let width = 10f64.powi(chunk.len() as i32);
            scale = scale / width;
            acc = acc + scale * group;
        }
        (sign * acc.hi, sign * acc.lo)
    }
}
