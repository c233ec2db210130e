//! Areas of uncertainty as ellipses, and their Gaussian equivalents (seed 000, eqs. 56-59).
//!
//! An area of uncertainty (AOU) is the 2-sigma ellipse `(x0, y0, rx, ry, phi)`: centre
//! `(x0, y0)` with x east and y north, 2-sigma semi-axes `rx`, `ry`, and `phi` the bearing of the
//! `rx` axis in radians, clockwise from north. Its Gaussian is `N(mu, R)` with `mu = (x0, y0)`
//! and `R = U Lambda U^T`, `U = [[sin phi, cos phi], [cos phi, -sin phi]]`,
//! `Lambda = diag(rx^2/4, ry^2/4)` (eqs. 56-59). [`Ellipse::to_gaussian`] and
//! [`Gaussian::to_ellipse`] convert both ways; the latter uses a closed-form symmetric 2x2
//! eigen-decomposition that is exact for circles and keeps its digits for nearly singular
//! covariances.

use crate::error::{Error, Result};

/// Names of the five ellipse fields, in array column order.
pub const FIELDS: [&str; 5] = ["x0", "y0", "rx", "ry", "phi"];

/// Largest accepted `|x0|`, `|y0|`, `rx`, `ry` (see [`Ellipse::validated`]).
pub const MAX_LENGTH: f64 = 1e50;
/// Smallest accepted semi-axis.
pub const MIN_SEMI_AXIS: f64 = 1e-50;
/// Largest accepted aspect ratio `max(rx, ry) / min(rx, ry)`.
pub const MAX_ASPECT: f64 = 1e8;

/// A 2-sigma area of uncertainty. `repr(C)`: a row-major `(n, 5)` float64 array is a
/// `[Ellipse]` (see [`Ellipse::from_flat`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct Ellipse {
    /// Centre, east (metres or any planar unit).
    pub x0: f64,
    /// Centre, north.
    pub y0: f64,
    /// 2-sigma semi-axis along the bearing `phi`.
    pub rx: f64,
    /// 2-sigma semi-axis perpendicular to `phi`.
    pub ry: f64,
    /// Bearing of the `rx` axis, radians clockwise from north.
    pub phi: f64,
}

/// A bivariate Gaussian: mean and the symmetric covariance `[[xx, xy], [xy, yy]]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gaussian {
    pub mean: [f64; 2],
    /// `[xx, xy, yy]`.
    pub cov: [f64; 3],
}

/// Axis-aligned bounding box `[xmin, ymin, xmax, ymax]`.
pub type BBox = [f64; 4];

impl Ellipse {
    /// A new ellipse; not validated (see [`Ellipse::validated`]).
    pub const fn new(x0: f64, y0: f64, rx: f64, ry: f64, phi: f64) -> Self {
        Self {
            x0,
            y0,
            rx,
            ry,
            phi,
        }
    }

    /// A circle of 2-sigma radius `r`.
    pub const fn circle(x0: f64, y0: f64, r: f64) -> Self {
        Self::new(x0, y0, r, r, 0.0)
    }

    /// From a row `[x0, y0, rx, ry, phi]`.
    pub fn from_row(row: &[f64]) -> Self {
        Self::new(row[0], row[1], row[2], row[3], row[4])
    }

    /// Views a flat row-major buffer of `5 n` values as `n` ellipses, without copying.
    pub fn from_flat(data: &[f64]) -> Result<&[Ellipse]> {
        if data.len() % 5 != 0 {
            return Err(Error::Shape {
                what: "ellipses",
                expected: "a multiple of 5 values".into(),
                got: data.len().to_string(),
            });
        }
        // SAFETY: `Ellipse` is `repr(C)` with five `f64` fields, so it has the size (40) and
        // alignment (8) of `[f64; 5]`; the slice covers exactly `data.len() / 5` such records
        // and borrows `data` for its whole lifetime.
        Ok(unsafe { std::slice::from_raw_parts(data.as_ptr().cast::<Ellipse>(), data.len() / 5) })
    }

    /// The row `[x0, y0, rx, ry, phi]`.
    pub fn to_row(&self) -> [f64; 5] {
        [self.x0, self.y0, self.rx, self.ry, self.phi]
    }

    /// Checks that every field is finite, both semi-axes are strictly positive, and the ellipse
    /// lies in the input domain of the scores: `|x0|, |y0| <= 1e50`, semi-axes in
    /// `[1e-50, 1e50]`, aspect ratio `max(rx, ry) / min(rx, ry) <= 1e8`. Inside it every score
    /// of every pair is computed without overflow or underflow; outside it is refused rather
    /// than answered inaccurately. `row` is reported in the error.
    pub fn validated(self, row: usize) -> Result<Self> {
        self.validated_shape(row)?;
        let out = |field: &'static str, value: f64, reason: &'static str| Error::OutOfDomain {
            what: "ellipse",
            row,
            field,
            value,
            reason,
        };
        for (field, value) in [("x0", self.x0), ("y0", self.y0)] {
            if value.abs() > MAX_LENGTH {
                return Err(out(field, value, "|centre| must be <= 1e50"));
            }
        }
        for (field, value) in [("rx", self.rx), ("ry", self.ry)] {
            if !(MIN_SEMI_AXIS..=MAX_LENGTH).contains(&value) {
                return Err(out(field, value, "semi-axes must be in [1e-50, 1e50]"));
            }
        }
        let (big, small, field) = if self.rx >= self.ry {
            (self.rx, self.ry, "ry")
        } else {
            (self.ry, self.rx, "rx")
        };
        if big > MAX_ASPECT * small {
            return Err(out(
                field,
                small,
                "aspect ratio max(rx, ry) / min(rx, ry) must be <= 1e8",
            ));
        }
        Ok(self)
    }

    /// Checks that every field is finite and both semi-axes are strictly positive (no
    /// magnitude limits: for geometry that does not feed the scores). `row` is reported in the
    /// error.
    pub fn validated_shape(self, row: usize) -> Result<Self> {
        for (field, value) in FIELDS.iter().zip(self.to_row()) {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    what: "ellipse",
                    row,
                    field,
                    value,
                });
            }
        }
        for (field, value) in [("rx", self.rx), ("ry", self.ry)] {
            if value <= 0.0 {
                return Err(Error::NonPositive {
                    what: "ellipse",
                    row,
                    field,
                    value,
                });
            }
        }
        Ok(self)
    }

    /// Area `pi rx ry` of the 2-sigma ellipse.
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * self.rx * self.ry
    }

    /// Unit vectors of the `rx` axis and the `ry` axis (the columns of `U`, eq. 56).
    pub fn axes(&self) -> ([f64; 2], [f64; 2]) {
        let (s, c) = self.phi.sin_cos();
        ([s, c], [c, -s])
    }

    /// The Gaussian of this AOU (eqs. 56-59).
    pub fn to_gaussian(&self) -> Gaussian {
        let (s, c) = self.phi.sin_cos();
        let a = 0.25 * self.rx * self.rx;
        let b = 0.25 * self.ry * self.ry;
        Gaussian {
            mean: [self.x0, self.y0],
            cov: [
                a * s * s + b * c * c,
                (a - b) * s * c,
                a * c * c + b * s * s,
            ],
        }
    }

    /// Half-widths of the axis-aligned bounding box.
    pub fn half_extents(&self) -> [f64; 2] {
        let (s, c) = self.phi.sin_cos();
        [
            (self.rx * s).hypot(self.ry * c),
            (self.rx * c).hypot(self.ry * s),
        ]
    }

    /// Axis-aligned bounding box.
    pub fn bbox(&self) -> BBox {
        let [hx, hy] = self.half_extents();
        [self.x0 - hx, self.y0 - hy, self.x0 + hx, self.y0 + hy]
    }

    /// Coordinates of `(x, y)` in the ellipse's normalised frame: the ellipse is the unit disc.
    #[inline]
    pub fn normalise(&self, x: f64, y: f64) -> [f64; 2] {
        let (s, c) = self.phi.sin_cos();
        let (dx, dy) = (x - self.x0, y - self.y0);
        [(dx * s + dy * c) / self.rx, (dx * c - dy * s) / self.ry]
    }

    /// Whether `(x, y)` lies in the closed ellipse.
    #[inline]
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let [u, v] = self.normalise(x, y);
        u * u + v * v <= 1.0
    }

    /// The boundary point at parametric angle `t`: `c + rx cos t e1 + ry sin t e2`.
    pub fn point_at(&self, t: f64) -> [f64; 2] {
        let ([e1x, e1y], [e2x, e2y]) = self.axes();
        let (st, ct) = t.sin_cos();
        [
            self.x0 + self.rx * ct * e1x + self.ry * st * e2x,
            self.y0 + self.rx * ct * e1y + self.ry * st * e2y,
        ]
    }

    /// The same ellipse translated by `(-dx, -dy)`.
    pub fn shifted(&self, dx: f64, dy: f64) -> Self {
        Self::new(self.x0 - dx, self.y0 - dy, self.rx, self.ry, self.phi)
    }
}

impl Gaussian {
    /// A Gaussian; not validated (see [`Gaussian::validated`]).
    pub const fn new(mean: [f64; 2], cov: [f64; 3]) -> Self {
        Self { mean, cov }
    }

    /// Checks finiteness and positive definiteness. `row` is reported in the error.
    pub fn validated(self, row: usize) -> Result<Self> {
        let names = ["mean_x", "mean_y", "cov_xx", "cov_xy", "cov_yy"];
        let values = [
            self.mean[0],
            self.mean[1],
            self.cov[0],
            self.cov[1],
            self.cov[2],
        ];
        for (field, value) in names.into_iter().zip(values) {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    what: "gaussian",
                    row,
                    field,
                    value,
                });
            }
        }
        let [xx, xy, yy] = self.cov;
        if xx <= 0.0 || yy <= 0.0 {
            return Err(Error::NotPositiveDefinite {
                row,
                reason: format!("diagonal ({xx}, {yy}) must be > 0"),
            });
        }
        let (_, l2) = eig_sym2(xx, xy, yy);
        if l2 <= 0.0 {
            return Err(Error::NotPositiveDefinite {
                row,
                reason: format!("determinant {} <= 0", xx * yy - xy * xy),
            });
        }
        Ok(self)
    }

    /// The 2-sigma AOU of this Gaussian. `phi` is returned in `[0, pi)`; for a circle it is 0.
    pub fn to_ellipse(&self) -> Ellipse {
        let [xx, xy, yy] = self.cov;
        let (l1, l2) = eig_sym2(xx, xy, yy);
        // Major eigenvector at angle theta counter-clockwise from +x; bearing = pi/2 - theta.
        let theta = 0.5 * (2.0 * xy).atan2(xx - yy);
        if l1 == l2 {
            // A circle: every bearing is an axis; report 0.
            return Ellipse::new(
                self.mean[0],
                self.mean[1],
                2.0 * l1.sqrt(),
                2.0 * l1.sqrt(),
                0.0,
            );
        }
        let mut phi = std::f64::consts::FRAC_PI_2 - theta;
        phi = phi.rem_euclid(std::f64::consts::PI);
        if phi >= std::f64::consts::PI {
            phi = 0.0;
        }
        Ellipse::new(
            self.mean[0],
            self.mean[1],
            2.0 * l1.sqrt(),
            2.0 * l2.max(0.0).sqrt(),
            phi,
        )
    }

    /// Determinant of the covariance.
    pub fn det(&self) -> f64 {
        let [xx, xy, yy] = self.cov;
        xx * yy - xy * xy
    }
}

/// Eigenvalues `(l1 >= l2)` of the symmetric matrix `[[a, b], [b, c]]`.
///
/// The larger is computed without cancellation; the smaller as `det / l1`, which keeps relative
/// accuracy for nearly singular matrices.
pub fn eig_sym2(a: f64, b: f64, c: f64) -> (f64, f64) {
    let m = 0.5 * (a + c);
    let h = (0.5 * (a - c)).hypot(b);
    let l1 = m + h;
    if l1 <= 0.0 {
        return (l1, m - h);
    }
    // det computed as a*c - b*b; with a, c > 0 the product form is exact to rounding.
    let det = a.mul_add(c, -b * b);
    (l1, det / l1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn gaussian_of_north_pointing_ellipse() {
        // phi = 0: rx axis points north, so the y variance is rx^2/4.
        let g = Ellipse::new(1.0, 2.0, 4.0, 2.0, 0.0).to_gaussian();
        assert_eq!(g.mean, [1.0, 2.0]);
        assert!((g.cov[0] - 1.0).abs() < 1e-15);
        assert!(g.cov[1].abs() < 1e-15);
        assert!((g.cov[2] - 4.0).abs() < 1e-15);
    }

    #[test]
    fn round_trip() {
        for &(rx, ry, phi) in &[
            (3.0, 1.0, 0.3),
            (1.0, 3.0, 2.0),
            (5.0, 5.0, 1.0),
            (1e3, 1.0, 3.1),
        ] {
            let e = Ellipse::new(10.0, -4.0, rx, ry, phi);
            let back = e.to_gaussian().to_ellipse();
            let g1 = e.to_gaussian();
            let g2 = back.to_gaussian();
            for k in 0..3 {
                assert!((g1.cov[k] - g2.cov[k]).abs() <= 1e-12 * g1.cov[0].max(g1.cov[2]));
            }
            assert!(back.rx >= back.ry);
            assert!((0.0..PI).contains(&back.phi));
        }
    }

    #[test]
    fn swapped_axes_same_gaussian() {
        let a = Ellipse::new(0.0, 0.0, 3.0, 1.0, 0.4).to_gaussian();
        let b = Ellipse::new(0.0, 0.0, 1.0, 3.0, 0.4 + FRAC_PI_2).to_gaussian();
        for k in 0..3 {
            assert!((a.cov[k] - b.cov[k]).abs() < 1e-14);
        }
    }

    #[test]
    fn circle_has_zero_bearing() {
        let e = Gaussian::new([0.0, 0.0], [2.0, 0.0, 2.0]).to_ellipse();
        assert_eq!(e.phi, 0.0);
        assert!((e.rx - e.ry).abs() < 1e-15);
    }

    #[test]
    fn validation_names_row_and_field() {
        let err = Ellipse::new(0.0, f64::NAN, 1.0, 1.0, 0.0)
            .validated(7)
            .unwrap_err();
        assert!(err.to_string().contains("row 7") && err.to_string().contains("y0"));
        let err = Ellipse::new(0.0, 0.0, 1.0, 0.0, 0.0)
            .validated(3)
            .unwrap_err();
        assert!(err.to_string().contains("ry"));
        assert!(Gaussian::new([0.0, 0.0], [1.0, 2.0, 1.0])
            .validated(0)
            .is_err());
    }

    #[test]
    fn bbox_and_contains() {
        let e = Ellipse::new(0.0, 0.0, 2.0, 1.0, FRAC_PI_2); // rx axis points east
        let b = e.bbox();
        assert!((b[2] - 2.0).abs() < 1e-15 && (b[3] - 1.0).abs() < 1e-15);
        assert!(e.contains(1.99, 0.0) && !e.contains(0.0, 1.01));
        let p = e.point_at(0.0);
        assert!((p[0] - 2.0).abs() < 1e-15 && p[1].abs() < 1e-15);
    }
}
