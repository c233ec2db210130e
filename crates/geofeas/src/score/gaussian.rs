//! Closed-form overlap scores of the two Gaussians of a pair of AOUs (seed 000, eqs. 56-59):
//! the Bhattacharyya coefficient, the Hellinger distance, and the normalised product of the two
//! densities (the red line of the paper's Fig. 6).
//!
//! With `S = R1 + R2`, `q = d^T S^-1 d` (`d = mu1 - mu2`, the quadratic form of the GLR,
//! eq. 71) and `P = 4 sqrt(det R1 det R2)`:
//!
//! - Bhattacharyya coefficient `BC = integral sqrt(p1 p2) = sqrt(P / det S) exp(-q / 4)`;
//! - Hellinger distance `H = sqrt(1 - BC)`;
//! - normalised product `integral p1 p2 / sqrt(integral p1^2 integral p2^2) =
//!   sqrt(P / det S) exp(-q / 2)`, the GLR times the shape factor `sqrt(P / det S)`.
//!
//! All three are 1 for identical ellipses and in `(0, 1]` otherwise. **Without cancellation:**
//! `det S = det R1 + det R2 + tr(adj(R1) R2)`, and with `s = rx / 2`, `t = ry / 2` for each
//! ellipse and `D = phi2 - phi1` the excess over `P` is a sum of squares,
//! `det S - P = (s1 t1 - s2 t2)^2 + sin^2 D (s1 s2 - t1 t2)^2 + cos^2 D (s1 t2 - s2 t1)^2`,
//! so `sqrt(P / det S) = exp(-ln1p(E / P) / 2)` keeps full relative accuracy for nearly identical
//! shapes, and `1 - BC` is computed by `expm1` so `H` keeps its digits as `BC -> 1`. `q` is the
//! cancellation-free form of [`super::glr::mahalanobis2`].

use super::glr::{mahalanobis2, Frame};
use super::PairScore;
use crate::ellipse::Ellipse;

/// `ln sqrt(P / det S)` and `q` of a pair (see the module docs).
#[inline]
fn shape_and_distance(a: &Frame, b: &Frame) -> (f64, f64) {
    // Frame holds A = rx^2 / 4 and B = ry^2 / 4: s = sqrt(A), t = sqrt(B)
    let (s1, t1, s2, t2) = (a.a.sqrt(), a.b.sqrt(), b.a.sqrt(), b.b.sqrt());
    let sd = b.s * a.c - b.c * a.s;
    let cd = b.c * a.c + b.s * a.s;
    let excess = (s1 * t1 - s2 * t2).powi(2)
        + sd * sd * (s1 * s2 - t1 * t2).powi(2)
        + cd * cd * (s1 * t2 - s2 * t1).powi(2);
    let p = 4.0 * (s1 * t1) * (s2 * t2);
    (-0.5 * (excess / p).ln_1p(), mahalanobis2(a, b))
}

/// `ln BC` of two ellipses' Gaussians.
#[inline]
pub fn ln_bhattacharyya(a: &Ellipse, b: &Ellipse) -> f64 {
    let (shape, q) = shape_and_distance(&Frame::new(a), &Frame::new(b));
    shape - 0.25 * q
}

/// Which closed-form Gaussian score.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GaussianScore {
    /// `integral sqrt(p1 p2)`.
    Bhattacharyya,
    /// `sqrt(1 - BC)` (a distance: 0 for identical ellipses).
    Hellinger,
    /// `integral p1 p2 / sqrt(integral p1^2 integral p2^2)`.
    Product,
}

impl GaussianScore {
    /// The score of two prepared ellipses.
    #[inline]
    pub fn eval(&self, a: &Frame, b: &Frame) -> f64 {
        let (shape, q) = shape_and_distance(a, b);
        match self {
            Self::Bhattacharyya => (shape - 0.25 * q).exp(),
            Self::Hellinger => (-(shape - 0.25 * q).exp_m1()).max(0.0).sqrt(),
            Self::Product => (shape - 0.5 * q).exp(),
        }
    }
}

/// The Bhattacharyya coefficient of the Gaussians of two ellipses.
///
/// ```
/// use geofeas::{score::gaussian::bhattacharyya, Ellipse};
/// let a = Ellipse::circle(0.0, 0.0, 2.0); // sigma 1
/// assert_eq!(bhattacharyya(&a, &a), 1.0);
/// // equal covariances I: BC = exp(-|d|^2 / 8)
/// let b = Ellipse::circle(2.0, 0.0, 2.0);
/// assert!((bhattacharyya(&a, &b) - (-0.5f64).exp()).abs() < 1e-15);
/// ```
pub fn bhattacharyya(a: &Ellipse, b: &Ellipse) -> f64 {
    GaussianScore::Bhattacharyya.eval(&Frame::new(a), &Frame::new(b))
}

impl PairScore for GaussianScore {
    type Prepared = Frame;

    fn prepare(&self, e: &Ellipse) -> Frame {
        Frame::new(e)
    }

    fn score(&self, a: &Frame, b: &Frame, _index: u64) -> f64 {
        self.eval(a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scores_of_identical_and_far() {
        let a = Ellipse::new(3.0, 1.0, 4.0, 1.0, 0.3);
        for s in [GaussianScore::Bhattacharyya, GaussianScore::Product] {
            assert_eq!(s.score_one(&a, &a), 1.0);
            assert!(s.score_one(&a, &Ellipse::circle(1e4, 0.0, 1.0)) < 1e-300);
        }
        assert_eq!(GaussianScore::Hellinger.score_one(&a, &a), 0.0);
        let swapped = Ellipse::new(3.0, 1.0, 1.0, 4.0, 0.3 + std::f64::consts::FRAC_PI_2);
        assert!(GaussianScore::Hellinger.score_one(&a, &swapped) < 1e-7);
    }

    #[test]
    fn concentric_shapes_closed_form() {
        // concentric circles of sigma 1 and sigma k: BC = 2k / (1 + k^2)
        for k in [1.0 + 1e-9, 1.5, 10.0] {
            let a = Ellipse::circle(0.0, 0.0, 2.0);
            let b = Ellipse::circle(0.0, 0.0, 2.0 * k);
            let bc = bhattacharyya(&a, &b);
            assert!((bc - 2.0 * k / (1.0 + k * k)).abs() < 1e-15);
            // Hellinger keeps relative accuracy: 1 - BC = (k - 1)^2 / (1 + k^2)
            let h = GaussianScore::Hellinger.score_one(&a, &b);
            let truth = ((k - 1.0) * (k - 1.0) / (1.0 + k * k)).sqrt();
            assert!((h - truth).abs() <= 1e-6 * truth, "{h} vs {truth}");
        }
    }
}
