//! The generalized likelihood ratio score (seed 000, eq. 71) and its thresholded variant.
//!
//! `g_G = exp(-0.5 d^T (R1 + R2)^-1 d)` with `d = mu1 - mu2`, the GLR of "same position" against
//! "different positions" for two Gaussian reports. It never reaches 0 or 1, so the thresholded
//! variant argued for in Section 3 of the paper returns exactly 0 when the two ellipses do not
//! touch and exactly 1 when one lies inside the other, which makes it satisfy constraints 46-48.

use super::PairScore;
use crate::ellipse::{Ellipse, Gaussian};
use crate::relation::{relation, Relation};

/// GLR options.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Glr {
    /// Force 0 for disjoint ellipses and 1 for nested ones.
    pub threshold: bool,
}

/// The GLR of two Gaussians (eq. 71).
///
/// ```
/// use geofeas::{glr, Ellipse};
/// let a = Ellipse::circle(0.0, 0.0, 2.0); // sigma 1
/// assert_eq!(glr(&a.to_gaussian(), &a.to_gaussian()), 1.0);
/// let b = Ellipse::circle(2.0, 0.0, 2.0);
/// // d = 2, R1 + R2 = 2 I: exp(-0.5 * 4 / 2)
/// assert!((glr(&a.to_gaussian(), &b.to_gaussian()) - (-1.0f64).exp()).abs() < 1e-15);
/// ```
#[inline]
pub fn glr(a: &Gaussian, b: &Gaussian) -> f64 {
    let dx = a.mean[0] - b.mean[0];
    let dy = a.mean[1] - b.mean[1];
    let sxx = a.cov[0] + b.cov[0];
    let sxy = a.cov[1] + b.cov[1];
    let syy = a.cov[2] + b.cov[2];
    let det = sxx * syy - sxy * sxy;
    let q = (syy * dx * dx - 2.0 * sxy * dx * dy + sxx * dy * dy) / det;
    (-0.5 * q).exp()
}

impl PairScore for Glr {
    type Prepared = (Ellipse, Gaussian);

    fn prepare(&self, e: &Ellipse) -> Self::Prepared {
        (*e, e.to_gaussian())
    }

    #[inline]
    fn score(&self, a: &Self::Prepared, b: &Self::Prepared, _index: u64) -> f64 {
        let g = glr(&a.1, &b.1);
        if !self.threshold {
            return g;
        }
        match relation(&a.0, &b.0) {
            Relation::Disjoint => 0.0,
            Relation::AInsideB | Relation::BInsideA => 1.0,
            Relation::Crossing => g,
        }
    }

    fn chunk_pairs(&self) -> usize {
        if self.threshold {
            1 << 15
        } else {
            1 << 18
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symmetric_and_translation_invariant() {
        let a = Ellipse::new(1.0, 2.0, 3.0, 1.0, 0.3);
        let b = Ellipse::new(2.5, 1.0, 2.0, 2.5, 1.3);
        let s = Glr::default();
        let g = s.score_one(&a, &b);
        assert_eq!(g, s.score_one(&b, &a));
        let g2 = s.score_one(&a.shifted(-5e5, -4e6), &b.shifted(-5e5, -4e6));
        assert!((g - g2).abs() < 1e-9);
    }

    #[test]
    fn thresholded_meets_constraints() {
        let s = Glr { threshold: true };
        let a = Ellipse::circle(0.0, 0.0, 1.0);
        assert_eq!(s.score_one(&a, &Ellipse::circle(3.0, 0.0, 1.0)), 0.0);
        assert_eq!(s.score_one(&a, &Ellipse::circle(0.1, 0.0, 5.0)), 1.0);
        let g = s.score_one(&a, &Ellipse::circle(1.0, 0.0, 1.0));
        assert!(g > 0.0 && g < 1.0);
    }
}
