//! The generalized likelihood ratio score (seed 000, eq. 71) and its thresholded variant.
//!
//! `g_G = exp(-0.5 d^T (R1 + R2)^-1 d)` with `d = mu1 - mu2`, the GLR of "same position" against
//! "different positions" for two Gaussian reports. It never reaches 0 or 1, so the thresholded
//! variant argued for in Section 3 of the paper returns exactly 0 when the two ellipses do not
//! touch and exactly 1 when one lies inside the other, which makes it satisfy constraints 46-48.
//!
//! **Evaluation without cancellation.** With `A = rx^2/4`, `B = ry^2/4` and the axes `u1, u2`
//! of each ellipse, `d^T (R1+R2)^-1 d = d^T adj(S) d / det S` where `adj` is linear for 2x2
//! matrices, so
//! `d^T adj(S) d = B1 (u1_1.d)^2 + A1 (u2_1.d)^2 + B2 (u1_2.d)^2 + A2 (u2_2.d)^2` and
//! `det S = A1 B1 + A2 B2 + A1 (A2 sin^2 D + B2 cos^2 D) + B1 (A2 cos^2 D + B2 sin^2 D)`
//! with `D = phi2 - phi1`. Every term is non-negative, so the quadratic form keeps full relative
//! accuracy for needle-like ellipses and nearly parallel pairs, where `Sxx Syy - Sxy^2` loses
//! all its digits. The batch kernels are branch-free (see [`crate::fastmath`]) so that they
//! vectorise, with an AVX2 version selected at run time on x86-64.

use super::{Cancel, PairScore};
use crate::ellipse::{Ellipse, Gaussian};
use crate::fastmath::{exp_neg, sin_cos, SIN_COS_LIMIT};
use crate::relation::{relation, Relation};

/// GLR options.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Glr {
    /// Force 0 for disjoint ellipses and 1 for nested ones.
    pub threshold: bool,
}

/// An ellipse as the GLR kernel uses it: centre, `A = rx^2/4`, `B = ry^2/4`, `sin phi`,
/// `cos phi`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub x: f64,
    pub y: f64,
    pub a: f64,
    pub b: f64,
    pub s: f64,
    pub c: f64,
}

impl Frame {
    /// The frame of `e`; uses the branch-free `sin_cos` when `|phi|` allows it.
    #[inline(always)]
    pub fn new(e: &Ellipse) -> Self {
        let (s, c) = if e.phi.abs() <= SIN_COS_LIMIT {
            sin_cos(e.phi)
        } else {
            e.phi.sin_cos()
        };
        Self::with_sin_cos(e, s, c)
    }

    #[inline(always)]
    fn with_sin_cos(e: &Ellipse, s: f64, c: f64) -> Self {
        Self {
            x: e.x0,
            y: e.y0,
            a: 0.25 * e.rx * e.rx,
            b: 0.25 * e.ry * e.ry,
            s,
            c,
        }
    }
}

/// `d^T (R1 + R2)^-1 d` of two frames, cancellation-free (see the module docs).
#[inline(always)]
pub fn mahalanobis2(p: &Frame, r: &Frame) -> f64 {
    let dx = p.x - r.x;
    let dy = p.y - r.y;
    let p1 = dx * p.s + dy * p.c;
    let p2 = dx * p.c - dy * p.s;
    let r1 = dx * r.s + dy * r.c;
    let r2 = dx * r.c - dy * r.s;
    // Each half is written so that swapping p and r swaps exact operands: the result is
    // bit-for-bit symmetric.
    let num = (p.b * p1 * p1 + p.a * p2 * p2) + (r.b * r1 * r1 + r.a * r2 * r2);
    let sd = r.s * p.c - r.c * p.s;
    let cd = r.c * p.c + r.s * p.s;
    let (sd2, cd2) = (sd * sd, cd * cd);
    let cross = (p.a * r.a + p.b * r.b) * sd2 + (p.a * r.b + p.b * r.a) * cd2;
    let det = (p.a * p.b + r.a * r.b) + cross;
    num / det
}

/// The GLR of two Gaussians (eq. 71), from their covariance matrices.
///
/// ```
/// use geofeas::{glr, Ellipse};
/// let a = Ellipse::circle(0.0, 0.0, 2.0); // sigma 1
/// assert_eq!(glr(&a.to_gaussian(), &a.to_gaussian()), 1.0);
/// let b = Ellipse::circle(2.0, 0.0, 2.0);
/// // d = 2, R1 + R2 = 2 I: exp(-0.5 * 4 / 2)
/// assert!((glr(&a.to_gaussian(), &b.to_gaussian()) - (-1.0f64).exp()).abs() < 1e-15);
/// ```
pub fn glr(a: &Gaussian, b: &Gaussian) -> f64 {
    let dx = a.mean[0] - b.mean[0];
    let dy = a.mean[1] - b.mean[1];
    let sxx = a.cov[0] + b.cov[0];
    let sxy = a.cov[1] + b.cov[1];
    let syy = a.cov[2] + b.cov[2];
    // det(R1 + R2) = det R1 + det R2 + tr(adj(R1) R2), each positive for SPD matrices
    let det =
        a.det() + b.det() + (a.cov[2] * b.cov[0] - 2.0 * a.cov[1] * b.cov[1] + a.cov[0] * b.cov[2]);
    let q = (syy * dx * dx - 2.0 * sxy * dx * dy + sxx * dy * dy) / det;
    (-0.5 * q).exp()
}

/// The GLR of two ellipses (eq. 71).
#[inline(always)]
pub fn glr_ellipses(a: &Ellipse, b: &Ellipse) -> f64 {
    exp_neg(-0.5 * mahalanobis2(&Frame::new(a), &Frame::new(b)))
}

/// Exactly 0 / 1 for disjoint / nested ellipses, otherwise `g`.
#[inline]
fn thresholded(a: &Ellipse, b: &Ellipse, g: f64) -> f64 {
    let (dx, dy) = (a.x0 - b.x0, a.y0 - b.y0);
    let d2 = dx * dx + dy * dy;
    let (ra, rb) = (a.rx.max(a.ry), b.rx.max(b.ry));
    if d2 > (ra + rb) * (ra + rb) {
        return 0.0;
    }
    match relation(a, b) {
        Relation::Disjoint => 0.0,
        Relation::AInsideB | Relation::BInsideA => 1.0,
        Relation::Crossing => g,
    }
}

/// Pairs handled together by the vectorised kernels.
const TILE: usize = 64;

/// Frames of up to [`TILE`] ellipses, one array per field, so that loops over them vectorise.
struct FrameTile {
    x: [f64; TILE],
    y: [f64; TILE],
    a: [f64; TILE],
    b: [f64; TILE],
    s: [f64; TILE],
    c: [f64; TILE],
}

impl FrameTile {
    fn new() -> Self {
        Self {
            x: [0.0; TILE],
            y: [0.0; TILE],
            a: [0.0; TILE],
            b: [0.0; TILE],
            s: [0.0; TILE],
            c: [0.0; TILE],
        }
    }

    /// Fills the tile from ellipses (one ellipse broadcasts to `n` slots).
    #[inline(always)]
    fn load(&mut self, es: &[Ellipse], n: usize) {
        let n = n.min(TILE);
        let mut phi = [0.0; TILE];
        for i in 0..n {
            let e = &es[if es.len() == 1 { 0 } else { i }];
            self.x[i] = e.x0;
            self.y[i] = e.y0;
            self.a[i] = 0.25 * e.rx * e.rx;
            self.b[i] = 0.25 * e.ry * e.ry;
            phi[i] = e.phi;
        }
        for ((p, s), c) in phi[..n].iter().zip(&mut self.s[..n]).zip(&mut self.c[..n]) {
            (*s, *c) = sin_cos(*p);
        }
    }

    /// Fills the tile from frames (one frame broadcasts to `n` slots).
    #[inline(always)]
    fn load_frames(&mut self, fs: &[&Frame], n: usize) {
        let n = n.min(TILE);
        for i in 0..n {
            let f = fs[if fs.len() == 1 { 0 } else { i }];
            self.x[i] = f.x;
            self.y[i] = f.y;
            self.a[i] = f.a;
            self.b[i] = f.b;
            self.s[i] = f.s;
            self.c[i] = f.c;
        }
    }
}

/// `out[i] = exp(-0.5 d^T (R1+R2)^-1 d)` for the first `out.len()` slots of two tiles.
#[inline(always)]
fn glr_tile(p: &FrameTile, r: &FrameTile, out: &mut [f64]) {
    let n = out.len().min(TILE);
    let out = &mut out[..n];
    for (i, o) in out.iter_mut().enumerate() {
        let fp = Frame {
            x: p.x[i],
            y: p.y[i],
            a: p.a[i],
            b: p.b[i],
            s: p.s[i],
            c: p.c[i],
        };
        let fr = Frame {
            x: r.x[i],
            y: r.y[i],
            a: r.a[i],
            b: r.b[i],
            s: r.s[i],
            c: r.c[i],
        };
        *o = exp_neg(-0.5 * mahalanobis2(&fp, &fr));
    }
}

#[inline(always)]
fn block_kernel(a: &[Ellipse], b: &[Ellipse], out: &mut [f64]) {
    let (mut ta, mut tb) = (FrameTile::new(), FrameTile::new());
    for (t, o) in out.chunks_mut(TILE).enumerate() {
        let n = o.len();
        let range = t * TILE..t * TILE + n;
        ta.load(if a.len() == 1 { a } else { &a[range.clone()] }, n);
        tb.load(if b.len() == 1 { b } else { &b[range] }, n);
        glr_tile(&ta, &tb, o);
    }
}

#[inline(always)]
fn row_kernel(a: &Frame, b: &[(Ellipse, Frame)], out: &mut [f64]) {
    let (mut ta, mut tb) = (FrameTile::new(), FrameTile::new());
    ta.load_frames(&[a], TILE);
    let mut refs: [&Frame; TILE] = [a; TILE];
    for (o, pb) in out.chunks_mut(TILE).zip(b.chunks(TILE)) {
        let n = o.len();
        for (slot, p) in refs.iter_mut().zip(pb) {
            *slot = &p.1;
        }
        tb.load_frames(&refs[..n.max(2)], n);
        glr_tile(&ta, &tb, o);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn block_kernel_avx2(a: &[Ellipse], b: &[Ellipse], out: &mut [f64]) {
    block_kernel(a, b, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn row_kernel_avx2(a: &Frame, b: &[(Ellipse, Frame)], out: &mut [f64]) {
    row_kernel(a, b, out)
}

#[inline]
fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

impl PairScore for Glr {
    type Prepared = (Ellipse, Frame);

    fn prepare(&self, e: &Ellipse) -> Self::Prepared {
        (*e, Frame::new(e))
    }

    #[inline]
    fn score(&self, a: &Self::Prepared, b: &Self::Prepared, _index: u64) -> f64 {
        let g = exp_neg(-0.5 * mahalanobis2(&a.1, &b.1));
        if self.threshold {
            thresholded(&a.0, &b.0, g)
        } else {
            g
        }
    }

    fn score_block(
        &self,
        a: &[Ellipse],
        b: &[Ellipse],
        _start: usize,
        out: &mut [f64],
        _cancel: &Cancel,
    ) {
        let fast = a.iter().chain(b).all(|e| e.phi.abs() <= SIN_COS_LIMIT);
        if !fast {
            let (ia, ib) = (a.len() > 1, b.len() > 1);
            for (k, o) in out.iter_mut().enumerate() {
                *o = glr_ellipses(&a[if ia { k } else { 0 }], &b[if ib { k } else { 0 }]);
            }
        } else if has_avx2() {
            // SAFETY: the CPU supports AVX2 and FMA (checked at run time just above).
            #[cfg(target_arch = "x86_64")]
            unsafe {
                block_kernel_avx2(a, b, out)
            }
        } else {
            block_kernel(a, b, out)
        }
        if self.threshold {
            let (ia, ib) = (a.len() > 1, b.len() > 1);
            for (k, o) in out.iter_mut().enumerate() {
                *o = thresholded(&a[if ia { k } else { 0 }], &b[if ib { k } else { 0 }], *o);
            }
        }
    }

    fn score_row(
        &self,
        a: &Self::Prepared,
        b: &[Self::Prepared],
        start: usize,
        out: &mut [f64],
        _cancel: &Cancel,
    ) {
        if self.threshold {
            for (k, (o, pb)) in out.iter_mut().zip(b).enumerate() {
                *o = self.score(a, pb, (start + k) as u64);
            }
            return;
        }
        if has_avx2() {
            // SAFETY: the CPU supports AVX2 and FMA (checked at run time just above).
            #[cfg(target_arch = "x86_64")]
            unsafe {
                row_kernel_avx2(&a.1, b, out)
            }
        } else {
            row_kernel(&a.1, b, out)
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
    fn kernel_agrees_with_covariance_formula() {
        let pairs = [
            (
                Ellipse::new(1.0, 2.0, 3.0, 1.0, 0.3),
                Ellipse::new(2.5, 1.0, 2.0, 2.5, 1.3),
            ),
            (
                Ellipse::new(0.0, 0.0, 1000.0, 1.0, 0.2),
                Ellipse::new(3.0, 1.0, 900.0, 2.0, 0.21),
            ),
            (
                Ellipse::new(0.0, 0.0, 1.0, 1.0, 0.0),
                Ellipse::new(0.5, 0.1, 1.0, 1.0, 7.0),
            ),
        ];
        for (a, b) in pairs {
            let g1 = glr(&a.to_gaussian(), &b.to_gaussian());
            let g2 = glr_ellipses(&a, &b);
            assert!((g1 - g2).abs() <= 1e-12 * g1.max(1e-300), "{g1} vs {g2}");
        }
        // a huge bearing takes the std path and agrees
        let a = Ellipse::new(0.0, 0.0, 3.0, 1.0, 1e7);
        let b = Ellipse::new(1.0, 0.0, 2.0, 1.0, 0.0);
        let g = glr(&a.to_gaussian(), &b.to_gaussian());
        assert!((glr_ellipses(&a, &b) - g).abs() < 1e-12);
    }

    #[test]
    fn blocks_rows_and_pairs_agree() {
        let es: Vec<Ellipse> = (0..37)
            .map(|i| {
                let t = i as f64;
                Ellipse::new(t.sin(), t.cos() * 2.0, 1.0 + (t * 0.3).sin().abs(), 0.5, t)
            })
            .collect();
        let s = Glr::default();
        let mut out = vec![0.0; es.len()];
        s.score_block(&es, &es[..1], 0, &mut out, Cancel::never());
        let prepared: Vec<_> = es.iter().map(|e| s.prepare(e)).collect();
        let mut row = vec![0.0; es.len()];
        s.score_row(&prepared[0], &prepared, 0, &mut row, Cancel::never());
        for k in 0..es.len() {
            let direct = s.score_one(&es[k], &es[0]);
            assert_eq!(out[k], direct);
            assert_eq!(row[k], s.score_one(&es[0], &es[k]));
        }
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
