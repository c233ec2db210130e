//! Normalised overlap area (seed 000, eqs. 49-50) on polygonised ellipses.
//!
//! `g = area(S1 ∩ S2) / area(S_min)`. Each ellipse becomes a convex `n`-gon, the intersection is
//! computed by parry's convex polygon clipper (`parry2d_f64::transformation::
//! convex_polygons_intersection_points`) and measured by the shoelace formula.
//!
//! **Construction.** The `n`-gon is the affine image of a regular `n`-gon whose vertices lie on
//! the circle of radius `k_n = sqrt(2 pi / (n sin(2 pi / n)))`, chosen so that every sector
//! (centre, v_k, v_k+1) has exactly the area of the matching elliptic sector. The polygon then
//! has exactly the ellipse's area, and along every whole edge the area it gains outside the
//! ellipse equals the area it loses inside (affine maps preserve area ratios). Errors in an
//! intersection therefore only come from the partial edges at the (at most eight) ends of the
//! boundary arcs.
//!
//! **Error bound.** In each ellipse's normalised frame the boundary stays within
//! `[k_n cos(pi/n) - 1, k_n - 1] ≈ [-pi^2/(6 n^2), +pi^2/(3 n^2)]` of the unit circle, and one
//! edge spans `2 pi / n`, so each arc end contributes at most about `(pi^2 / (3 n^2)) (2 pi / n)
//! / pi = 2 pi^2 / (3 n^3)` of the normalised area. With up to four arc ends per ellipse,
//! `|g - g_true| <= (8 pi^2 / (3 n^3)) (1 + A_max / A_min)` (about `26 (1 + A_max/A_min) / n^3`).
//! At the default `n = 256` this is `1.6e-6 (1 + A_max / A_min)`, inside `1e-4` for every pair
//! whose areas differ by less than a factor 60, and the measured error on the random pairs of
//! Fig. 6 is far smaller (see the tests). Very different areas call for more vertices or the
//! exact method.
//!
//! **Speed.** Before clipping, each polygon is cut down to the oriented bounding box of the other
//! polygon (four half-planes, Sutherland-Hodgman). A box holds its polygon, so the intersection is
//! unchanged, but parry's O(n + m) walk then only visits the vertices near the overlap.
//!
//! Disjoint pairs return exactly 0 and nested or identical pairs exactly 1, decided on the true
//! ellipses by [`crate::relation`], whatever the clipper does with degenerate contacts. Each pair
//! is clipped in a frame centred on the first ellipse and scaled to the smaller one, so far-off
//! coordinates and tiny ellipses lose no digits against the clipper's absolute tolerances.

use std::cell::RefCell;

use parry2d_f64::math::Vector;
use parry2d_f64::transformation::{
    convex_polygons_intersection_points_with_tolerances, PolygonIntersectionTolerances,
};

use super::PairScore;
use crate::ellipse::Ellipse;
use crate::relation::{relation, Relation};

/// Polygon-overlap options.
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    /// Vertices of each polygon (at least 8).
    pub vertices: usize,
    /// `k_n (cos t_i, -sin t_i)`: the equal-area unit polygon, built once.
    unit: Vec<[f64; 2]>,
    /// `k_n`: the polygon of an ellipse lies in its box of half-widths `k_n rx`, `k_n ry`.
    radius: f64,
}

impl Default for Polygon {
    fn default() -> Self {
        Self::new(Self::DEFAULT_VERTICES)
    }
}

impl Polygon {
    /// Default resolution.
    pub const DEFAULT_VERTICES: usize = 256;
    /// Smallest resolution accepted.
    pub const MIN_VERTICES: usize = 8;
    /// Largest resolution accepted (16 MiB of vertices per polygon; the error bound is then
    /// below `1e-16 (1 + A_max / A_min)`).
    pub const MAX_VERTICES: usize = 1 << 20;

    /// Options for `vertices` vertices (at least [`Polygon::MIN_VERTICES`]).
    pub fn new(vertices: usize) -> Self {
        let n = vertices.clamp(Self::MIN_VERTICES, Self::MAX_VERTICES);
        let step = std::f64::consts::TAU / n as f64;
        let k = (std::f64::consts::TAU / (n as f64 * step.sin())).sqrt();
        let unit = (0..n)
            .map(|i| {
                let (s, c) = (i as f64 * step).sin_cos();
                [k * c, -k * s]
            })
            .collect();
        Self {
            vertices: n,
            unit,
            radius: k,
        }
    }

    /// The documented worst-case bound on `|g - g_true|` for an area ratio
    /// `A_max / A_min = ratio`.
    pub fn error_bound(&self, ratio: f64) -> f64 {
        let n = self.vertices as f64;
        8.0 * std::f64::consts::PI.powi(2) / (3.0 * n * n * n) * (1.0 + ratio)
    }

    /// Appends the counter-clockwise vertices of the equal-area polygon of `e` (unit axes
    /// `axes`), scaled by `scale` and shifted to `centre`.
    fn extend_vertices(
        &self,
        out: &mut Vec<Vector>,
        e: &Ellipse,
        ([e1x, e1y], [e2x, e2y]): ([f64; 2], [f64; 2]),
        centre: [f64; 2],
        scale: f64,
    ) {
        let (ax, ay) = (e.rx * e1x * scale, e.rx * e1y * scale);
        let (bx, by) = (e.ry * e2x * scale, e.ry * e2y * scale);
        out.extend(
            self.unit.iter().map(|&[u, v]| {
                Vector::new(centre[0] + u * ax + v * bx, centre[1] + u * ay + v * by)
            }),
        );
    }

    /// Counter-clockwise vertices of the equal-area polygon of `e`, relative to its centre.
    pub fn vertices_of(&self, e: &Ellipse) -> Vec<[f64; 2]> {
        // Clockwise in the (e1, e2) frame, which is left-handed: counter-clockwise in (x, y).
        let ([e1x, e1y], [e2x, e2y]) = e.axes();
        let (ax, ay) = (e.rx * e1x, e.rx * e1y);
        let (bx, by) = (e.ry * e2x, e.ry * e2y);
        self.unit
            .iter()
            .map(|&[u, v]| [u * ax + v * bx, u * ay + v * by])
            .collect()
    }
}

type Scratch = (Vec<Vector>, Vec<Vector>, Vec<Vector>, Vec<Vector>);

thread_local! {
    static SCRATCH: RefCell<Scratch> =
        const { RefCell::new((Vec::new(), Vec::new(), Vec::new(), Vec::new())) };
}

/// Cuts the convex polygon `poly` down to the box `|(p - centre) . axis_i| <= half_i`
/// (Sutherland-Hodgman, one half-plane at a time; `tmp` is scratch space). Orientation is kept.
fn clip_to_box(
    poly: &mut Vec<Vector>,
    tmp: &mut Vec<Vector>,
    centre: [f64; 2],
    axes: ([f64; 2], [f64; 2]),
    half: [f64; 2],
) {
    // a relative margin so that rounding never shaves the boxed polygon itself
    let planes = [
        (axes.0, half[0]),
        ([-axes.0[0], -axes.0[1]], half[0]),
        (axes.1, half[1]),
        ([-axes.1[0], -axes.1[1]], half[1]),
    ];
    for ([nx, ny], h) in planes {
        let d = nx * centre[0] + ny * centre[1] + h * (1.0 + 1e-9);
        let side = |p: &Vector| nx * p.x + ny * p.y - d;
        if poly.iter().all(|p| side(p) <= 0.0) {
            continue;
        }
        tmp.clear();
        let mut p = poly[poly.len() - 1];
        let mut sp = side(&p);
        for &q in poly.iter() {
            let sq = side(&q);
            if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
                tmp.push(p + (q - p) * (sp / (sp - sq)));
            }
            if sq <= 0.0 {
                tmp.push(q);
            }
            (p, sp) = (q, sq);
        }
        std::mem::swap(poly, tmp);
        if poly.len() < 3 {
            return;
        }
    }
}

/// Whether the boundary of `a`, measured in `b`'s normalised frame, stays within 1% of it
/// (nearly identical ellipses).
fn near_identical(a: &Ellipse, b: &Ellipse) -> bool {
    let (lo, hi, _) = crate::relation::BoundaryFn::new(a, b).sampled();
    lo > 0.98 && hi < 1.02
}

/// `out` = the intersection of the convex counter-clockwise polygons `pa` and `pb`, by
/// Sutherland-Hodgman clipping of `pa` against every edge of `pb` (`tmp` is scratch space).
fn clip_convex(pa: &[Vector], pb: &[Vector], out: &mut Vec<Vector>, tmp: &mut Vec<Vector>) {
    out.clear();
    out.extend_from_slice(pa);
    for k in 0..pb.len() {
        let (e0, e1) = (pb[k], pb[(k + 1) % pb.len()]);
        let (ex, ey) = (e1.x - e0.x, e1.y - e0.y);
        // > 0: left of the edge, inside a counter-clockwise polygon
        let side = |p: &Vector| ex * (p.y - e0.y) - ey * (p.x - e0.x);
        tmp.clear();
        let mut p = out[out.len() - 1];
        let mut sp = side(&p);
        for &q in out.iter() {
            let sq = side(&q);
            if (sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0) {
                tmp.push(p + (q - p) * (sp / (sp - sq)));
            }
            if sq >= 0.0 {
                tmp.push(q);
            }
            (p, sp) = (q, sq);
        }
        std::mem::swap(out, tmp);
        if out.len() < 3 {
            out.clear();
            return;
        }
    }
}

/// Shoelace area of a simple polygon.
pub fn shoelace(points: &[Vector]) -> f64 {
    let n = points.len();
    if n < 3 {
        return 0.0;
    }
    let mut twice = 0.0;
    for i in 0..n {
        let p = points[i];
        let q = points[(i + 1) % n];
        twice += p.x * q.y - q.x * p.y;
    }
    0.5 * twice.abs()
}

impl PairScore for Polygon {
    /// The ellipse and its unit axes (no allocation per ellipse: the vertices are generated
    /// straight into per-thread scratch space).
    type Prepared = (Ellipse, ([f64; 2], [f64; 2]));

    fn prepare(&self, e: &Ellipse) -> Self::Prepared {
        (*e, e.axes())
    }

    fn score(&self, a: &Self::Prepared, b: &Self::Prepared, _index: u64) -> f64 {
        let (ea, eb) = (&a.0, &b.0);
        let (dx, dy) = (eb.x0 - ea.x0, eb.y0 - ea.y0);
        let reach = ea.rx.max(ea.ry) + eb.rx.max(eb.ry);
        if dx * dx + dy * dy > reach * reach {
            return 0.0;
        }
        match relation(ea, eb) {
            Relation::Disjoint => return 0.0,
            Relation::AInsideB | Relation::BInsideA => return 1.0,
            Relation::Crossing => {}
        }
        let small = if ea.area() <= eb.area() { ea } else { eb };
        let scale = (small.rx * small.ry).sqrt();
        let inv = 1.0 / scale;
        SCRATCH.with(|cell| {
            let (pa, pb, out, tmp) = &mut *cell.borrow_mut();
            pa.clear();
            pb.clear();
            out.clear();
            self.extend_vertices(pa, ea, a.1, [0.0, 0.0], inv);
            self.extend_vertices(pb, eb, b.1, [dx * inv, dy * inv], inv);
            let k = self.radius * inv;
            clip_to_box(pa, tmp, [dx * inv, dy * inv], b.1, [k * eb.rx, k * eb.ry]);
            clip_to_box(pb, tmp, [0.0, 0.0], a.1, [k * ea.rx, k * ea.ry]);
            if pa.len() < 3 || pb.len() < 3 {
                return 0.0;
            }
            let area = if near_identical(ea, eb) {
                // boundaries within 1% of each other all the way round: edges of the two
                // polygons nearly coincide, which the clipper's walk does not survive; clip
                // by every edge instead (O(n m), exact for convex polygons)
                clip_convex(pa, pb, out, tmp);
                shoelace(out)
            } else {
                // no collinearity tolerance: where two thin ellipses cross at a shallow
                // angle, their polygons' edges are nearly parallel over many vertices, and
                // the default (100 ulp) took them for collinear and walked the wrong chain
                // (`a_shallow_double_crossing_of_thin_ellipses`: 2.5e-4 off)
                convex_polygons_intersection_points_with_tolerances(
                    pa,
                    pb,
                    PolygonIntersectionTolerances {
                        collinearity_epsilon: 0.0,
                    },
                    out,
                );
                shoelace(out)
            };
            let small_area = std::f64::consts::PI * small.rx * inv * small.ry * inv;
            (area / small_area).clamp(0.0, 1.0)
        })
    }

    fn chunk_pairs(&self) -> usize {
        (1 << 22) / self.vertices.max(Self::MIN_VERTICES)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polygon_area_equals_ellipse_area() {
        let e = Ellipse::new(0.0, 0.0, 3.0, 1.5, 0.4);
        for n in [8, 64, 255] {
            let p = Polygon::new(n);
            let v: Vec<Vector> = p
                .vertices_of(&e)
                .iter()
                .map(|q| Vector::new(q[0], q[1]))
                .collect();
            assert!((shoelace(&v) - e.area()).abs() < 1e-12 * e.area());
            // counter-clockwise: positive signed area
            let signed: f64 = (0..v.len())
                .map(|i| {
                    let (p, q) = (v[i], v[(i + 1) % v.len()]);
                    p.x * q.y - q.x * p.y
                })
                .sum();
            assert!(signed > 0.0);
        }
    }

    #[test]
    fn crossed_ellipses_closed_form() {
        // Centred a x b ellipse and its 90-degree rotation: intersection 4ab atan(b/a).
        let (a, b) = (3.0f64, 1.0f64);
        let e1 = Ellipse::new(0.0, 0.0, a, b, 0.2);
        let e2 = Ellipse::new(0.0, 0.0, a, b, 0.2 + std::f64::consts::FRAC_PI_2);
        let truth = 4.0 * a * b * (b / a).atan() / (std::f64::consts::PI * a * b);
        let p = Polygon::default();
        let g = p.score_one(&e1, &e2);
        assert!((g - truth).abs() <= p.error_bound(1.0), "{g} vs {truth}");
    }
}
