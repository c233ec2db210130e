//! How two ellipses lie relative to each other: disjoint, one inside the other, or crossing.
//!
//! The predicate behind the exact 0 and 1 of constraints 47-48 (seed 000). The boundary of `a`,
//! `p_a(t) = c_a + rx_a cos t e1 + ry_a sin t e2`, is written in the normalised frame of `b`
//! (where `b` is the unit disc) as `z(t) = w + P cos t + Q sin t`, so that
//! `f(t) = |z(t)|^2 = K0 + K1 cos 2t + K2 sin 2t + K3 cos t + K4 sin t`, a trigonometric
//! polynomial of degree 2. `a` lies inside `b` exactly when `max f <= 1`; the boundary of `a`
//! misses `b` exactly when `min f > 1`. The extremes are found by bracketing the sign changes of
//! `f'` on a grid fine enough for a degree-2 polynomial and polishing them by safeguarded
//! Newton steps; all work is done relative to the centre of `b`, so coordinates far from the
//! origin lose no digits.

use crate::ellipse::Ellipse;
use crate::fastmath::sin_cos;

/// The relative position of two closed ellipses `a` and `b`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Relation {
    /// The closed ellipses do not meet.
    Disjoint,
    /// `a` lies inside `b` (this includes `a == b`).
    AInsideB,
    /// `b` lies inside `a`, and `a` not inside `b`.
    BInsideA,
    /// The boundaries cross or touch.
    Crossing,
}

/// `f(t) = K0 + K1 cos 2t + K2 sin 2t + K3 cos t + K4 sin t`: the squared normalised radius of
/// the boundary of one ellipse measured in the frame of another.
#[derive(Debug, Clone, Copy)]
pub struct BoundaryFn {
    pub k: [f64; 5],
}

impl BoundaryFn {
    /// The boundary of `a` in the normalised frame of `b`.
    pub fn new(a: &Ellipse, b: &Ellipse) -> Self {
        let (sb, cb) = b.phi.sin_cos();
        let (sa, ca) = a.phi.sin_cos();
        // Map a vector (dx, dy) to b's normalised frame.
        let to_b = |dx: f64, dy: f64| [(dx * sb + dy * cb) / b.rx, (dx * cb - dy * sb) / b.ry];
        let w = to_b(a.x0 - b.x0, a.y0 - b.y0);
        let p = to_b(a.rx * sa, a.rx * ca);
        let q = to_b(a.ry * ca, -a.ry * sa);
        let pp = p[0] * p[0] + p[1] * p[1];
        let qq = q[0] * q[0] + q[1] * q[1];
        let pq = p[0] * q[0] + p[1] * q[1];
        let ww = w[0] * w[0] + w[1] * w[1];
        let wp = w[0] * p[0] + w[1] * p[1];
        let wq = w[0] * q[0] + w[1] * q[1];
        Self {
            k: [
                ww + 0.5 * (pp + qq),
                0.5 * (pp - qq),
                pq,
                2.0 * wp,
                2.0 * wq,
            ],
        }
    }

    /// `f(t)`, for `|t| <= fastmath::SIN_COS_LIMIT`.
    #[inline]
    pub fn value(&self, t: f64) -> f64 {
        let (s, c) = sin_cos(t);
        let (s2, c2) = (2.0 * s * c, c * c - s * s);
        let k = &self.k;
        k[0] + k[1] * c2 + k[2] * s2 + k[3] * c + k[4] * s
    }

    /// `f'(t)` and `f''(t)`, for `|t| <= fastmath::SIN_COS_LIMIT`.
    #[inline]
    pub fn derivs(&self, t: f64) -> (f64, f64) {
        let (s, c) = sin_cos(t);
        let (s2, c2) = (2.0 * s * c, c * c - s * s);
        let k = &self.k;
        (
            -2.0 * k[1] * s2 + 2.0 * k[2] * c2 - k[3] * s + k[4] * c,
            -4.0 * k[1] * c2 - 4.0 * k[2] * s2 - k[3] * c - k[4] * s,
        )
    }

    /// `(min, max)` of `f` at 48 equally spaced parameters (no trigonometric calls), with an
    /// upper bound on the rounding error of each value.
    #[inline]
    pub fn sampled(&self) -> (f64, f64, f64) {
        let k = &self.k;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for [c, s, c2, s2] in GRID.iter() {
            let v = k[0] + k[1] * c2 + k[2] * s2 + k[3] * c + k[4] * s;
            lo = lo.min(v);
            hi = hi.max(v);
        }
        let scale = k.iter().map(|x| x.abs()).sum::<f64>();
        (lo, hi, 16.0 * f64::EPSILON * scale)
    }

    /// A bound on how far `f` between two points of the 48-point grid can fall below or rise
    /// above the chord of its values there: `h^2 / 8 max|f''|`, with
    /// `max|f''| <= 4 |(K1, K2)| + |(K3, K4)|`.
    #[inline]
    pub fn grid_slack(&self) -> f64 {
        let k = &self.k;
        let h = std::f64::consts::TAU / 48.0;
        h * h / 8.0 * (4.0 * k[1].hypot(k[2]) + k[3].hypot(k[4]))
    }

    /// `(min f, max f)` over a full turn: `f` on the 48-point grid, and at every root of `f'`
    /// bracketed by a sign change between grid points (at most four for degree 2), polished by
    /// safeguarded Newton. The grid values come from the tabulated cosines and sines; only the
    /// polishing calls `sin_cos`.
    pub fn extremes(&self) -> (f64, f64) {
        const N: usize = 48;
        let step = std::f64::consts::TAU / N as f64;
        let k = &self.k;
        let value = |[c, s, c2, s2]: [f64; 4]| k[0] + k[1] * c2 + k[2] * s2 + k[3] * c + k[4] * s;
        let slope =
            |[c, s, c2, s2]: [f64; 4]| -2.0 * k[1] * s2 + 2.0 * k[2] * c2 - k[3] * s + k[4] * c;
        let grid = &*GRID;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        let mut d_prev = slope(grid[0]);
        for i in 0..N {
            let v0 = value(grid[i]);
            lo = lo.min(v0);
            hi = hi.max(v0);
            let d1 = slope(grid[(i + 1) % N]);
            if (d_prev <= 0.0) != (d1 <= 0.0) {
                let t0 = i as f64 * step;
                let v = self.value(self.critical_point(t0, t0 + step, d_prev));
                lo = lo.min(v);
                hi = hi.max(v);
            }
            d_prev = d1;
        }
        (lo, hi)
    }

    /// A root of `f'` inside `[t0, t1]`, where `f'` changes sign (`d0 = f'(t0)`).
    fn critical_point(&self, mut t0: f64, mut t1: f64, d0: f64) -> f64 {
        let neg0 = d0 <= 0.0;
        let mut t = 0.5 * (t0 + t1);
        for _ in 0..60 {
            let (d, dd) = self.derivs(t);
            if d == 0.0 {
                return t;
            }
            if (d <= 0.0) == neg0 {
                t0 = t;
            } else {
                t1 = t;
            }
            let newton = t - d / dd;
            if dd != 0.0 && newton > t0 && newton < t1 {
                // converged when the Newton step no longer moves t (t is in [0, 2 pi])
                let done = (newton - t).abs() <= 4.0 * f64::EPSILON;
                t = newton;
                if done {
                    break;
                }
            } else {
                t = 0.5 * (t0 + t1);
            }
            if (t1 - t0).abs() < 1e-15 {
                break;
            }
        }
        t
    }
}

/// `(cos t, sin t, cos 2t, sin 2t)` at 48 equally spaced `t`.
static GRID: std::sync::LazyLock<[[f64; 4]; 48]> = std::sync::LazyLock::new(|| {
    std::array::from_fn(|i| {
        let t = i as f64 * std::f64::consts::TAU / 48.0;
        [t.cos(), t.sin(), (2.0 * t).cos(), (2.0 * t).sin()]
    })
});

/// The relation of the closed ellipses `a` and `b`. Both must be valid (see
/// [`Ellipse::validated`]).
///
/// ```
/// use geofeas::{relation, Ellipse, Relation};
/// let big = Ellipse::circle(0.0, 0.0, 10.0);
/// assert_eq!(relation(&Ellipse::circle(1.0, 1.0, 1.0), &big), Relation::AInsideB);
/// assert_eq!(relation(&big, &Ellipse::circle(30.0, 0.0, 1.0)), Relation::Disjoint);
/// ```
pub fn relation(a: &Ellipse, b: &Ellipse) -> Relation {
    if a == b {
        // identical: decided exactly, not through the rounding of the boundary function
        return Relation::AInsideB;
    }
    let fa = BoundaryFn::new(a, b);
    // Fast path: boundary points of `a` clearly inside and clearly outside `b` -> crossing.
    let (lo, hi, err) = fa.sampled();
    if lo < 1.0 - 2.0 * err && hi > 1.0 + 2.0 * err {
        // a's boundary has points certainly inside and certainly outside b
        return Relation::Crossing;
    }
    // Certified fast paths: between grid points `f` strays from the sampled values by at most
    // `h^2 / 8 max|f''|` (h = 2 pi / 48).
    let slack = fa.grid_slack() + err;
    if hi + slack < 1.0 {
        return Relation::AInsideB;
    }
    if lo - slack > 1.0 {
        // a's boundary lies strictly outside b: the boundaries do not meet, so b lies wholly
        // inside or wholly outside a, which its centre tells.
        let [u, v] = a.normalise(b.x0, b.y0);
        return if u * u + v * v < 1.0 {
            Relation::BInsideA
        } else {
            Relation::Disjoint
        };
    }
    by_extremes(a, b, &fa)
}

/// The relation from the exact extremes of both boundary functions (the slow, general path).
///
/// Certified up to the rounding of the boundary functions themselves: an extreme within the
/// rounding bound of 1 (`16 eps sum |K|`) counts as on the other boundary, so identical
/// ellipses, and ellipses equal up to the last bits of their fields, are nested rather than
/// left to a root count that rounding decides.
fn by_extremes(a: &Ellipse, b: &Ellipse, fa: &BoundaryFn) -> Relation {
    let (amin, amax) = fa.extremes();
    let tol_a = fa.sampled().2;
    if amax <= 1.0 + tol_a {
        return Relation::AInsideB;
    }
    let fb = BoundaryFn::new(b, a);
    let (bmin, bmax) = fb.extremes();
    let tol_b = fb.sampled().2;
    if bmax <= 1.0 + tol_b {
        return Relation::BInsideA;
    }
    // Neither inside the other: disjoint exactly when the boundaries do not meet, which either
    // boundary function tells (a's boundary outside b, or b's outside a). The function of the
    // smaller ellipse in the frame of the larger is asked: its coefficients are the smaller
    // (`(max axis a / min axis b)^2 < (max axis b / min axis a)^2` exactly when `a` has the
    // smaller area), so it neither cancels nor hides narrow dips between grid points. Equal
    // areas go by the fields, so both argument orders ask the same function.
    let (area_a, area_b) = (a.rx * a.ry, b.rx * b.ry);
    let in_b_frame = area_a < area_b
        || (area_a == area_b
            && a.to_row()
                .iter()
                .zip(b.to_row())
                .map(|(x, y)| x.total_cmp(&y))
                .find(|o| o.is_ne())
                .map_or(true, |o| o.is_lt()));
    let disjoint = if in_b_frame {
        amin > 1.0 + tol_a
    } else {
        bmin > 1.0 + tol_b
    };
    if disjoint {
        Relation::Disjoint
    } else {
        Relation::Crossing
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circles() {
        let a = Ellipse::circle(0.0, 0.0, 1.0);
        assert_eq!(relation(&a, &a), Relation::AInsideB);
        assert_eq!(
            relation(&a, &Ellipse::circle(2.5, 0.0, 1.0)),
            Relation::Disjoint
        );
        assert_eq!(
            relation(&a, &Ellipse::circle(1.5, 0.0, 1.0)),
            Relation::Crossing
        );
        assert_eq!(
            relation(&Ellipse::circle(0.0, 0.0, 3.0), &a),
            Relation::BInsideA
        );
    }

    #[test]
    fn boundary_fn_matches_direct_evaluation() {
        let a = Ellipse::new(1.0, -2.0, 3.0, 0.5, 0.7);
        let b = Ellipse::new(0.3, 0.2, 2.0, 1.0, -1.1);
        let f = BoundaryFn::new(&a, &b);
        for i in 0..20 {
            let t = i as f64 * 0.31;
            let p = a.point_at(t);
            let [u, v] = b.normalise(p[0], p[1]);
            assert!((f.value(t) - (u * u + v * v)).abs() < 1e-12);
        }
    }

    #[test]
    fn fast_paths_agree_with_the_extremes() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
        let mut seen = [0usize; 4];
        for i in 0..200_000 {
            let rx = rng.random_range(0.1..3.0);
            let a = Ellipse::new(0.0, 0.0, rx, rx * rng.random_range(0.05..1.0), rng.random());
            let rx = rng.random_range(0.1..3.0);
            let reach = if i % 2 == 0 { 4.0 } else { 1.0 };
            let b = Ellipse::new(
                rng.random_range(-reach..reach),
                rng.random_range(-reach..reach),
                rx,
                rx * rng.random_range(0.05..1.0),
                rng.random(),
            );
            let fast = relation(&a, &b);
            assert_eq!(
                fast,
                by_extremes(&a, &b, &BoundaryFn::new(&a, &b)),
                "{a:?} {b:?}"
            );
            seen[fast as usize] += 1;
        }
        assert!(seen.iter().all(|&n| n > 1000), "{seen:?}");
    }

    #[test]
    fn very_different_sizes_agree_both_ways() {
        // a tiny needle 1.2e-4 (relative) outside a huge ellipse: disjoint, whichever order
        let a = Ellipse::new(
            4.667457314975297e-302,
            4.27963448e-313,
            1.0368095271218181e-13,
            1.5850610584415531e-18,
            7.7455e-320,
        );
        let b = Ellipse::new(
            1.0387856152597962e-13,
            7.685082780537537e49,
            7.68463382884336e49,
            7.684632922875586e49,
            7.684632922875586e49,
        );
        assert_eq!(relation(&a, &b), Relation::Disjoint);
        assert_eq!(relation(&b, &a), Relation::Disjoint);
    }

    #[test]
    fn needle_tip_in_a_circle_is_crossing_both_ways() {
        // the tip of a needle (aspect 6.6e4) pokes 4e-5 of its area into a circle
        let a = Ellipse::new(
            4.667457314975297e-302,
            4.27963448e-313,
            1.0390299731710684e-13,
            1.5850610584415531e-18,
            2.1220281696e-314,
        );
        let b = Ellipse::new(
            1.0387854855818246e-13,
            1.0387856152602562e-13,
            1.0387866994624287e-13,
            1.0387856152602562e-13,
            -5.487353583064704e303,
        );
        assert_eq!(relation(&a, &b), Relation::Crossing);
        assert_eq!(relation(&b, &a), Relation::Crossing);
    }

    #[test]
    fn tiny_circle_off_a_huge_ellipse_is_disjoint_both_ways() {
        let a = Ellipse::new(
            7.292902054648902e-304,
            1.0387856152597962e-13,
            1.0387856131426739e-13,
            1.0387856131426739e-13,
            1.6061516385579644e-121,
        );
        let b = Ellipse::new(
            7.684632922911581e49,
            1.9521413e-317,
            7.684632922868447e49,
            7.684632922875586e49,
            1.09558642687903e-310,
        );
        assert_eq!(relation(&a, &b), Relation::Disjoint);
        assert_eq!(relation(&b, &a), Relation::Disjoint);
    }

    #[test]
    fn crossed_needles_are_crossing_not_nested() {
        let a = Ellipse::new(0.0, 0.0, 1000.0, 1.0, 0.0);
        let b = Ellipse::new(0.0, 0.0, 1000.0, 1.0, std::f64::consts::FRAC_PI_2);
        assert_eq!(relation(&a, &b), Relation::Crossing);
    }
}
