//! Trilateration of two range / range-rate detections into a Cartesian state (seed 004, eqs. 1-9).
//!
//! For sensors at arbitrary positions `s_a`, `s_b` (the paper puts them on the x axis) the
//! position is the intersection of the circles `|p - s_a| = r_a`, `|p - s_b| = r_b` (eqs. 1-5):
//! with `d = |s_b - s_a|`, `e = (s_b - s_a) / d` and `n` its left normal,
//! `p = s_a + a e +- h n`, `a = (r_a^2 - r_b^2 + d^2) / (2 d)`, `h = sqrt(r_a^2 - a^2)`; of the
//! two mirror solutions the one inside both beams is kept ("in front of the sensors", eq. 5).
//! The velocity solves `u_a . v = r'_a`, `u_b . v = r'_b` with the lines of sight
//! `u_i = (p - s_i) / r_i`, which is eqs. 6-7 written without the implicit derivatives.
//!
//! The Jacobian of `(r_a, r'_a, r_b, r'_b) -> (x, y, vx, vy)` is closed form: with `A` the 2x2
//! matrix of rows `u_i`, `dp/dr = A^-1`, `dv/dr' = A^-1` and `dv/dr = -A^-1 B A^-1` where row i
//! of `B` is `(v - r'_i u_i) / r_i`. The covariance is `J C J^T` (eq. 8), first order only.

use nalgebra::{Matrix2, Matrix4, Vector2, Vector4};

use super::sensor::Sensor;

/// A trilaterated Cartesian state and the Jacobian of the transformation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trilateration {
    /// `(x, y, vx, vy)`.
    pub state: Vector4<f64>,
    /// `d state / d (r_a, r'_a, r_b, r'_b)`.
    pub jacobian: Matrix4<f64>,
    /// `|sin|` of the angle between the two lines of sight (0: degenerate geometry).
    pub sin_angle: f64,
}

/// Intersects the two detections `za = (r_a, r'_a)` of `a` and `zb` of `b`.
///
/// Returns `None` when the circles do not intersect, the sensors coincide, the lines of sight are
/// parallel, or neither intersection lies in both beams.
///
/// ```
/// use geofeas_tracking::mht::{trilaterate, Sensor};
/// use nalgebra::Vector2;
/// // Sensors at x = -10 and 10 m facing +y; a target at (0, 10 sqrt 3) moving at (0, 1) m/s.
/// let (a, b) = (Sensor::paper(-10.0, 0.5), Sensor::paper(10.0, 0.7));
/// let (r, rr) = (20.0, 3f64.sqrt() / 2.0);
/// let t = trilaterate(&a, Vector2::new(r, rr), &b, Vector2::new(r, rr)).unwrap();
/// assert!(t.state[0].abs() < 1e-12 && (t.state[1] - 10.0 * 3f64.sqrt()).abs() < 1e-12);
/// assert!(t.state[2].abs() < 1e-12 && (t.state[3] - 1.0).abs() < 1e-12);
/// ```
pub fn trilaterate(
    a: &Sensor,
    za: Vector2<f64>,
    b: &Sensor,
    zb: Vector2<f64>,
) -> Option<Trilateration> {
    let sa = Vector2::from(a.position);
    let sb = Vector2::from(b.position);
    let base = sb - sa;
    let d = base.norm();
    if [d, za[0], zb[0]].iter().any(|v| v.is_nan() || *v <= 0.0) {
        return None;
    }
    let e = base / d;
    let n = Vector2::new(-e[1], e[0]);
    let along = (za[0] * za[0] - zb[0] * zb[0] + d * d) / (2.0 * d);
    let h2 = za[0] * za[0] - along * along;
    if h2.is_nan() || h2 <= 0.0 {
        return None;
    }
    let h = h2.sqrt();
    let score = |p: &Vector2<f64>| -> Option<f64> {
        let pa = [p[0], p[1]];
        if !(a.in_beam(pa) && b.in_beam(pa)) {
            return None;
        }
        let off = |s: &Sensor| {
            let (sn, cs) = s.boresight.sin_cos();
            let dp = p - Vector2::from(s.position);
            (dp[0] * cs + dp[1] * sn) / dp.norm()
        };
        Some(off(a).min(off(b)))
    };
    let plus = sa + e * along + n * h;
    let minus = sa + e * along - n * h;
    let p = match (score(&plus), score(&minus)) {
        (Some(x), Some(y)) => {
            if x >= y {
                plus
            } else {
                minus
            }
        }
        (Some(_), None) => plus,
        (None, Some(_)) => minus,
        (None, None) => return None,
    };
    let ua = (p - sa) / za[0];
    let ub = (p - sb) / zb[0];
    let am = Matrix2::new(ua[0], ua[1], ub[0], ub[1]);
    let det = am.determinant();
    if det.abs() < 1e-9 {
        return None;
    }
    let ainv = am.try_inverse()?;
    let v = ainv * Vector2::new(za[1], zb[1]);
    let ba = (v - ua * za[1]) / za[0];
    let bb = (v - ub * zb[1]) / zb[0];
    let bm = Matrix2::new(ba[0], ba[1], bb[0], bb[1]);
    let dvdr = -(ainv * bm * ainv);
    // Columns: r_a, r'_a, r_b, r'_b.
    let mut j = Matrix4::zeros();
    for row in 0..2 {
        j[(row, 0)] = ainv[(row, 0)];
        j[(row, 2)] = ainv[(row, 1)];
        j[(row + 2, 0)] = dvdr[(row, 0)];
        j[(row + 2, 2)] = dvdr[(row, 1)];
        j[(row + 2, 1)] = ainv[(row, 0)];
        j[(row + 2, 3)] = ainv[(row, 1)];
    }
    Some(Trilateration {
        state: Vector4::new(p[0], p[1], v[0], v[1]),
        jacobian: j,
        sin_angle: det.abs(),
    })
}

/// Trilateration with covariance: `za ~ N(., ca)`, `zb ~ N(., cb)` independent; returns the state
/// and `J blockdiag(ca, cb) J^T` (eq. 8).
pub fn trilaterate_gaussian(
    a: &Sensor,
    za: Vector2<f64>,
    ca: &Matrix2<f64>,
    b: &Sensor,
    zb: Vector2<f64>,
    cb: &Matrix2<f64>,
) -> Option<(Vector4<f64>, Matrix4<f64>)> {
    let t = trilaterate(a, za, b, zb)?;
    let mut c = Matrix4::zeros();
    c.fixed_view_mut::<2, 2>(0, 0).copy_from(ca);
    c.fixed_view_mut::<2, 2>(2, 2).copy_from(cb);
    let p = t.jacobian * c * t.jacobian.transpose();
    Some((t.state, 0.5 * (p + p.transpose())))
}
