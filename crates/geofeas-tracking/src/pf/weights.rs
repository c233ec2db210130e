//! Importance weights of seed 003: Method 1 (section IV, Fig. 5) and Method 2, the
//! track-before-detect likelihood ratio (section V, Table 1).
//!
//! Both return *log* weights; [`normalise`] turns them into normalised weights with the
//! log-sum-exp shift, so no weight underflows however peaked the likelihood is.
//!
//! - Method 1: `log w_n = -(r_n / r_1)^2`, `r_n` the distance from particle `n` to the associated
//!   measurement peak (paper: `r_1 = 1` pixel).
//! - Method 2: `log W_n = sum_{(i, j) in C_n} -h(h - 2z) / (2 sigma^2)` over the `(2D + 1)^2`
//!   cells `C_n` within `+-D` of the particle's cell `floor(x + 1/2)`, `floor(y + 1/2)`
//!   (clipped to the array), with the filter's
//!   point spread `h(i, j) = A exp(-((i - x_n)^2 + (j - y_n)^2) / (2 S^2))`. In the paper the
//!   filter's `A`, `S`, `sigma` are deliberately wrong: 0.8 A, 1.5 Sigma, 1.5 sigma_Z
//!   ([`LikelihoodModel::paper`]). Since `h = A g_x(i) g_y(j)` is an outer product,
//!   `sum h z = A g_y^T Z_C g_x` (one `(2D+1) x (2D+1)` matrix-vector product) and
//!   `sum h^2 = A^2 |g_x|^2 |g_y|^2`, so a particle costs `(2D+1)^2` multiply-adds and four
//!   exponentials (each profile comes from the ratio recurrence `g(k+1) = g(k) q_k`,
//!   `q_{k+1} = q_k e^{-1/S^2}`) instead of `(2D+1)^2` exponentials.
//!   [`LikelihoodModel::log_ratio_direct`] is the cell-by-cell form, for tests.

use rayon::prelude::*;

use crate::pf::frame::{Frame, Psf};
use crate::pf::motion::Particles;
use crate::pf::peaks::Peak;
use geofeas::error::{Error, Result};
use geofeas::fastmath::exp_neg;

/// Largest box half-width `D`.
pub const MAX_HALF_BOX: usize = 32;
const MAX_LEN: usize = 2 * MAX_HALF_BOX + 1;

/// Method 1: `log w_n = -(r_n / r1)^2` for the particles `p` and the peak `peak`.
pub fn peak_distance_log_weights(p: &Particles, peak: &Peak, r1: f64, out: &mut [f64]) {
    let k = 1.0 / (r1 * r1);
    for ((o, &x), &y) in out.iter_mut().zip(&p.x).zip(&p.y) {
        let (dx, dy) = (x - peak.x, y - peak.y);
        *o = -(dx * dx + dy * dy) * k;
    }
}

/// The filter's measurement model for Method 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LikelihoodModel {
    /// Assumed amplitude `A`.
    pub amplitude: f64,
    /// Assumed blur `S`, pixels.
    pub blur: f64,
    /// Assumed noise 1-sigma.
    pub sigma: f64,
    /// Box half-width `D`, cells (paper: 10).
    pub half_box: usize,
}

impl LikelihoodModel {
    /// The paper's filter model for the true point spread `psf` and noise `sigma_z`: amplitude
    /// 0.8 A, blur 1.5 Sigma, noise 1.5 sigma_Z, D = 10 (Table 1).
    pub fn paper(psf: &Psf, sigma_z: f64) -> Self {
        Self::scaled(psf, sigma_z, [0.8, 1.5, 1.5])
    }

    /// The true model scaled by `[amplitude, blur, sigma]` factors, D = 10.
    pub fn scaled(psf: &Psf, sigma_z: f64, f: [f64; 3]) -> Self {
        Self {
            amplitude: f[0] * psf.amplitude,
            blur: f[1] * psf.blur,
            sigma: f[2] * sigma_z,
            half_box: 10,
        }
    }

    /// Checks the parameters.
    pub fn validated(self) -> Result<Self> {
        for (name, v) in [
            ("model amplitude", self.amplitude),
            ("model blur", self.blur),
            ("model sigma", self.sigma),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::InvalidOption {
                    name,
                    reason: format!("must be finite and > 0, got {v}"),
                });
            }
        }
        if self.half_box > MAX_HALF_BOX {
            return Err(Error::InvalidOption {
                name: "half_box",
                reason: format!("must be <= {MAX_HALF_BOX}, got {}", self.half_box),
            });
        }
        Ok(self)
    }

    /// The filter's intensity `h` at cell `(i, j)` for a target at `(x, y)`.
    #[inline]
    pub fn intensity(&self, i: f64, j: f64, x: f64, y: f64) -> f64 {
        let d2 = (i - x) * (i - x) + (j - y) * (j - y);
        self.amplitude * (-d2 / (2.0 * self.blur * self.blur)).exp()
    }

    /// The box `C` of a particle at `(x, y)`: first and last column, first and last row (inclusive),
    /// or `None` when it misses the frame.
    #[inline]
    pub fn cells(&self, frame: &Frame, x: f64, y: f64) -> Option<[usize; 4]> {
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        let d = self.half_box as f64;
        let (cx, cy) = ((x + 0.5).floor(), (y + 0.5).floor());
        let lo_x = (cx - d).max(0.0);
        let hi_x = (cx + d).min(frame.width as f64 - 1.0);
        let lo_y = (cy - d).max(0.0);
        let hi_y = (cy + d).min(frame.height as f64 - 1.0);
        // `!(a <= b)` also rejects NaN positions.
        if !(lo_x <= hi_x && lo_y <= hi_y) {
            return None;
        }
        Some([lo_x as usize, hi_x as usize, lo_y as usize, hi_y as usize])
    }

    /// Method 2 log weight of one particle, cell by cell (the paper's product of `l(i, j)`).
    pub fn log_ratio_direct(&self, frame: &Frame, x: f64, y: f64) -> f64 {
        let Some([i0, i1, j0, j1]) = self.cells(frame, x, y) else {
            return 0.0;
        };
        let s2 = self.sigma * self.sigma;
        let mut acc = 0.0;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let h = self.intensity(i as f64, j as f64, x, y);
                acc += -h * (h - 2.0 * frame.at(i, j)) / (2.0 * s2);
            }
        }
        acc
    }

    /// Method 2 log weight of one particle with the separable point spread.
    #[inline]
    pub fn log_ratio(&self, frame: &Frame, x: f64, y: f64) -> f64 {
        self.log_ratio_inline(frame, x, y)
    }

    #[inline(always)]
    fn log_ratio_inline(&self, frame: &Frame, x: f64, y: f64) -> f64 {
        let Some([i0, i1, j0, j1]) = self.cells(frame, x, y) else {
            return 0.0;
        };
        let c = 0.5 / (self.blur * self.blur);
        let (nx, ny) = (i1 - i0 + 1, j1 - j0 + 1);
        let (hz, gx2, gy2) = if nx == 21 && ny == 21 {
            // The paper's D = 10 away from the borders: fixed sizes, fully unrolled.
            separable_sums::<21>(frame, i0, j0, i0 as f64 - x, j0 as f64 - y, c)
        } else {
            separable_sums_dyn(frame, [i0, nx, j0, ny], i0 as f64 - x, j0 as f64 - y, c)
        };
        let a = self.amplitude;
        let s2 = self.sigma * self.sigma;
        (a * hz - 0.5 * a * a * gx2 * gy2) / s2
    }

    /// Log weights of consecutive particles. Groups of four whose `+-10` boxes lie inside the
    /// frame take the fast path: their eight profiles are built together, lane by lane, from
    /// the centre cell outwards (`g(10 + j + 1) = g(10 + j) q_j`, `q_{j+1} = q_j e^{-2c}`,
    /// likewise to the left), which needs only exponentials of negative arguments
    /// ([`exp_neg`], branch-free so the lanes vectorise), then `box_sums` gives each particle's
    /// `(g_y^T Z g_x, |g_x|^2, |g_y|^2)`; the rest use the general path.
    #[inline(always)]
    fn log_weights_inline(
        &self,
        frame: &Frame,
        xs: &[f64],
        ys: &[f64],
        out: &mut [f64],
        box_sums: impl Fn(&Frame, usize, usize, &[f64; 21], &[f64; 21]) -> (f64, f64, f64),
    ) {
        const L: usize = 21;
        let c = 0.5 / (self.blur * self.blur);
        let fast = self.half_box == 10 && c * 121.0 <= 600.0;
        let r = (-2.0 * c).exp();
        let (wmax, hmax) = (frame.width as f64 - 11.0, frame.height as f64 - 11.0);
        let a = self.amplitude;
        let inv_s2 = 1.0 / (self.sigma * self.sigma);
        let mut n = 0;
        while fast && n + 4 <= out.len() {
            let mut cx = [0.0f64; 4];
            let mut cy = [0.0f64; 4];
            let mut inside = true;
            for l in 0..4 {
                cx[l] = (xs[n + l] + 0.5).floor();
                cy[l] = (ys[n + l] + 0.5).floor();
                // Written so that NaN fails.
                inside &= cx[l] >= 10.0 && cy[l] >= 10.0 && cx[l] <= wmax && cy[l] <= hmax;
            }
            if !inside {
                for l in 0..4 {
                    out[n + l] = self.log_ratio_inline(frame, xs[n + l], ys[n + l]);
                }
                n += 4;
                continue;
            }
            let mut dx = [0.0f64; 4];
            let mut dy = [0.0f64; 4];
            for l in 0..4 {
                dx[l] = cx[l] - xs[n + l];
                dy[l] = cy[l] - ys[n + l];
            }
            let gx = centred_profiles::<L>(dx, c, r);
            let gy = centred_profiles::<L>(dy, c, r);
            for l in 0..4 {
                let (hz, sx, sy) = box_sums(
                    frame,
                    cx[l] as usize - 10,
                    cy[l] as usize - 10,
                    &gx[l],
                    &gy[l],
                );
                out[n + l] = (a * hz - 0.5 * a * a * sx * sy) * inv_s2;
            }
            n += 4;
        }
        for m in n..out.len() {
            out[m] = self.log_ratio_inline(frame, xs[m], ys[m]);
        }
    }

    fn log_weights_scalar(&self, frame: &Frame, xs: &[f64], ys: &[f64], out: &mut [f64]) {
        self.log_weights_inline(frame, xs, ys, out, box_sums_plain);
    }

    /// The same loop compiled for AVX2 + FMA (chosen at run time when the CPU has them), with
    /// the box sums in AVX2 intrinsics.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn log_weights_avx2(&self, frame: &Frame, xs: &[f64], ys: &[f64], out: &mut [f64]) {
        self.log_weights_inline(frame, xs, ys, out, |f, i0, j0, gx, gy| {
            // SAFETY: this closure only runs inside this AVX2 + FMA function.
            unsafe { box_sums_avx2(f, i0, j0, gx, gy) }
        });
    }

    fn log_weights_chunk(&self, frame: &Frame, xs: &[f64], ys: &[f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
            {
                // SAFETY: the CPU supports the features this function was compiled for.
                unsafe { self.log_weights_avx2(frame, xs, ys, out) };
                return;
            }
        }
        self.log_weights_scalar(frame, xs, ys, out);
    }

    /// Method 2 log weights of all particles into `out` (rayon over chunks when `parallel`).
    pub fn log_weights(&self, frame: &Frame, p: &Particles, out: &mut [f64], parallel: bool) {
        const CHUNK: usize = 512;
        let work = |(k, o): (usize, &mut [f64])| {
            let base = k * CHUNK;
            let n = o.len();
            self.log_weights_chunk(frame, &p.x[base..base + n], &p.y[base..base + n], o);
        };
        if parallel {
            out.par_chunks_mut(CHUNK).enumerate().for_each(work);
        } else {
            out.chunks_mut(CHUNK).enumerate().for_each(work);
        }
    }
}

/// Profiles `g[l][h + j] = exp(-c (d_l + j)^2)`, `j = -h..=h`, `L = 2h + 1`, of four particles
/// with `|d_l| <= 1/2`, from the centre outwards with `r = exp(-2c)`.
#[inline(always)]
fn centred_profiles<const L: usize>(d: [f64; 4], c: f64, r: f64) -> [[f64; L]; 4] {
    let h = L / 2;
    let mut g = [[0.0f64; L]; 4];
    let mut mid = [0.0f64; 4];
    let mut qr = [0.0f64; 4];
    let mut ql = [0.0f64; 4];
    for l in 0..4 {
        mid[l] = exp_neg(-c * d[l] * d[l]);
        qr[l] = exp_neg(-c * (2.0 * d[l] + 1.0));
        ql[l] = exp_neg(-c * (1.0 - 2.0 * d[l]));
        g[l][h] = mid[l];
    }
    let (mut vr, mut vl) = (mid, mid);
    for j in 1..=h {
        for l in 0..4 {
            vr[l] *= qr[l];
            vl[l] *= ql[l];
            qr[l] *= r;
            ql[l] *= r;
            g[l][h + j] = vr[l];
            g[l][h - j] = vl[l];
        }
    }
    g
}

/// `(g_y^T Z g_x, |g_x|^2, |g_y|^2)` over the 21 x 21 box at `(i0, j0)`, plain arithmetic.
#[inline(always)]
fn box_sums_plain(
    frame: &Frame,
    i0: usize,
    j0: usize,
    gx: &[f64; 21],
    gy: &[f64; 21],
) -> (f64, f64, f64) {
    let mut acc = [0.0f64; 21];
    for (r, &g) in gy.iter().enumerate() {
        let row = &frame.data[(j0 + r) * frame.width + i0..][..21];
        for (a, &z) in acc.iter_mut().zip(row) {
            *a += g * z;
        }
    }
    let hz: f64 = gx.iter().zip(&acc).map(|(a, b)| a * b).sum();
    let sx: f64 = gx.iter().map(|v| v * v).sum();
    let sy: f64 = gy.iter().map(|v| v * v).sum();
    (hz, sx, sy)
}

/// [`box_sums_plain`] with AVX2 + FMA intrinsics: five 4-wide accumulators and one scalar per
/// row of the box.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn box_sums_avx2(
    frame: &Frame,
    i0: usize,
    j0: usize,
    gx: &[f64; 21],
    gy: &[f64; 21],
) -> (f64, f64, f64) {
    use std::arch::x86_64::*;
    let mut a = [_mm256_setzero_pd(); 5];
    let mut a20 = 0.0f64;
    for (r, &g) in gy.iter().enumerate() {
        let row: &[f64] = &frame.data[(j0 + r) * frame.width + i0..][..21];
        let p = row.as_ptr();
        let gv = _mm256_set1_pd(g);
        for (k, acc) in a.iter_mut().enumerate() {
            // SAFETY: `row` has 21 elements, so lanes 4k..4k+4 (k < 5) are in bounds.
            *acc = _mm256_fmadd_pd(gv, unsafe { _mm256_loadu_pd(p.add(4 * k)) }, *acc);
        }
        a20 = g.mul_add(row[20], a20);
    }
    let px = gx.as_ptr();
    let py = gy.as_ptr();
    let mut hz = _mm256_setzero_pd();
    let mut sx = _mm256_setzero_pd();
    let mut sy = _mm256_setzero_pd();
    for (k, acc) in a.iter().enumerate() {
        // SAFETY: the profiles have 21 elements.
        let (xv, yv) = unsafe {
            (
                _mm256_loadu_pd(px.add(4 * k)),
                _mm256_loadu_pd(py.add(4 * k)),
            )
        };
        hz = _mm256_fmadd_pd(xv, *acc, hz);
        sx = _mm256_fmadd_pd(xv, xv, sx);
        sy = _mm256_fmadd_pd(yv, yv, sy);
    }
    let sum = |v: __m256d| {
        let mut t = [0.0f64; 4];
        // SAFETY: `t` holds four doubles.
        unsafe { _mm256_storeu_pd(t.as_mut_ptr(), v) };
        (t[0] + t[1]) + (t[2] + t[3])
    };
    (
        gx[20].mul_add(a20, sum(hz)),
        gx[20].mul_add(gx[20], sum(sx)),
        gy[20].mul_add(gy[20], sum(sy)),
    )
}

/// `(g_y^T Z g_x, |g_x|^2, |g_y|^2)` over the `L x L` box at `(i0, j0)`, `u`, `v` the offsets of
/// its first column / row from the particle.
#[inline(always)]
fn separable_sums<const L: usize>(
    frame: &Frame,
    i0: usize,
    j0: usize,
    u: f64,
    v: f64,
    c: f64,
) -> (f64, f64, f64) {
    let mut gx = [0.0f64; L];
    let mut gy = [0.0f64; L];
    fill_profile(&mut gx, u, c);
    fill_profile(&mut gy, v, c);
    let mut acc = [0.0f64; L];
    for (r, &g) in gy.iter().enumerate() {
        let row: &[f64; L] = frame.data[(j0 + r) * frame.width + i0..][..L]
            .try_into()
            .expect("box inside the frame");
        for k in 0..L {
            acc[k] += g * row[k];
        }
    }
    let mut hz = 0.0;
    let (mut sx, mut sy) = (0.0, 0.0);
    for k in 0..L {
        hz += gx[k] * acc[k];
        sx += gx[k] * gx[k];
        sy += gy[k] * gy[k];
    }
    (hz, sx, sy)
}

/// [`separable_sums`] for a clipped box `[i0, nx, j0, ny]`.
#[inline(always)]
fn separable_sums_dyn(frame: &Frame, b: [usize; 4], u: f64, v: f64, c: f64) -> (f64, f64, f64) {
    let [i0, nx, j0, ny] = b;
    let mut gx = [0.0f64; MAX_LEN];
    let mut gy = [0.0f64; MAX_LEN];
    let gx = &mut gx[..nx];
    let gy = &mut gy[..ny];
    fill_profile(gx, u, c);
    fill_profile(gy, v, c);
    let mut acc = [0.0f64; MAX_LEN];
    let acc = &mut acc[..nx];
    for (r, &g) in gy.iter().enumerate() {
        let row = &frame.data[(j0 + r) * frame.width + i0..][..nx];
        for (a, &z) in acc.iter_mut().zip(row) {
            *a += g * z;
        }
    }
    let hz: f64 = gx.iter().zip(acc.iter()).map(|(a, b)| a * b).sum();
    let gx2: f64 = gx.iter().map(|v| v * v).sum();
    let gy2: f64 = gy.iter().map(|v| v * v).sum();
    (hz, gx2, gy2)
}

/// `g[k] = exp(-c (u + k)^2)` as `exp(-c u^2) exp(-c k^2) (exp(-2 c u))^k`: three exponentials
/// (the middle factor has no data dependence and is hoisted by the compiler when `g` has a fixed
/// length), and powers by a short product tree; directly when the factors could overflow.
#[inline(always)]
fn fill_profile(g: &mut [f64], u: f64, c: f64) {
    let n = g.len() as f64;
    if c * (u.abs() + n) * (u.abs() + n) > 600.0 {
        for (k, v) in g.iter_mut().enumerate() {
            let d = u + k as f64;
            *v = (-c * d * d).exp();
        }
        return;
    }
    // g[k+1] = g[k] q_k with q_k = exp(-c (2 (u + k) + 1)) = q_0 r^k, r = exp(-2c).
    let mut v = (-c * u * u).exp();
    let mut q = (-c * (2.0 * u + 1.0)).exp();
    let r = (-2.0 * c).exp();
    for x in g.iter_mut() {
        *x = v;
        v *= q;
        q *= r;
    }
}

/// Normalises `log_w` into `w` (`w_n = exp(log_w_n - max) / sum`); returns `log sum exp(log_w)`.
/// Non-finite log weights (a particle off every model) get zero weight; if none is finite the
/// weights are uniform and the result is NaN.
pub fn normalise(log_w: &[f64], w: &mut [f64]) -> f64 {
    let m = log_w
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !m.is_finite() {
        let u = 1.0 / w.len().max(1) as f64;
        w.iter_mut().for_each(|v| *v = u);
        return f64::NAN;
    }
    let mut total = 0.0;
    for (o, &l) in w.iter_mut().zip(log_w) {
        *o = if l.is_finite() { (l - m).exp() } else { 0.0 };
        total += *o;
    }
    w.iter_mut().for_each(|v| *v /= total);
    m + total.ln()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geofeas::rng::stream;

    #[test]
    fn separable_equals_direct() {
        let psf = Psf::default();
        let f = Frame::render(
            64,
            40,
            &[[20.0, 20.0], [50.5, 3.0]],
            &psf,
            0.3,
            &mut stream(1, 0),
        );
        for model in [
            LikelihoodModel::paper(&psf, 0.3),
            LikelihoodModel {
                blur: 0.3,
                ..LikelihoodModel::paper(&psf, 0.3)
            },
            LikelihoodModel {
                half_box: 3,
                ..LikelihoodModel::paper(&psf, 0.3)
            },
        ] {
            for &(x, y) in &[
                (20.2, 19.7),
                (0.1, 0.4),
                (63.4, 39.6),
                (-5.0, 10.0),
                (52.0, 2.5),
                (-30.0, 10.0),
                (30.49, 30.51),
            ] {
                let a = model.log_ratio(&f, x, y);
                let b = model.log_ratio_direct(&f, x, y);
                assert!((a - b).abs() <= 1e-10 * (1.0 + b.abs()), "{x} {y}: {a} {b}");
            }
        }
    }

    #[test]
    fn batched_weights_equal_direct() {
        let psf = Psf::default();
        let f = Frame::render(80, 60, &[[40.0, 30.0]], &psf, 0.5, &mut stream(2, 0));
        let mut rng = stream(2, 1);
        let n = 1003;
        let mut p = Particles::uniform(n, [40.0, 30.0, 0.0, 0.0], 45.0, 0.0, &mut rng);
        p.x[7] = f64::NAN;
        p.y[500] = 10.5; // a rounding tie
        p.x[501] = 69.5;
        for model in [
            LikelihoodModel::paper(&psf, 0.5),
            LikelihoodModel {
                half_box: 4,
                ..LikelihoodModel::paper(&psf, 0.5)
            },
        ] {
            for parallel in [false, true] {
                let mut out = vec![0.0; n];
                model.log_weights(&f, &p, &mut out, parallel);
                for (k, &got) in out.iter().enumerate() {
                    let want = model.log_ratio_direct(&f, p.x[k], p.y[k]);
                    assert!(
                        (got - want).abs() <= 1e-10 * (1.0 + want.abs()),
                        "{k}: ({}, {}) {got} {want}",
                        p.x[k],
                        p.y[k]
                    );
                }
            }
        }
    }

    #[test]
    fn scalar_path_equals_the_dispatched_one() {
        // where the CPU has AVX2 + FMA, the dispatched path is the vector one: the portable
        // scalar path (what other CPUs run) must give the same weights
        let psf = Psf::default();
        let f = Frame::render(80, 60, &[[40.0, 30.0]], &psf, 0.5, &mut stream(3, 0));
        let mut rng = stream(3, 1);
        let n = 517;
        let p = Particles::uniform(n, [40.0, 30.0, 0.0, 0.0], 45.0, 0.0, &mut rng);
        let model = LikelihoodModel::paper(&psf, 0.5);
        let (mut scalar, mut dispatched) = (vec![0.0; n], vec![0.0; n]);
        model.log_weights_scalar(&f, &p.x, &p.y, &mut scalar);
        model.log_weights_chunk(&f, &p.x, &p.y, &mut dispatched);
        for k in 0..n {
            let (a, b) = (scalar[k], dispatched[k]);
            assert!((a - b).abs() <= 1e-11 * (1.0 + a.abs()), "{k}: {a} {b}");
        }
    }

    #[test]
    fn noise_free_ratio_has_the_closed_form() {
        // z = h exactly: log W = sum h^2 / (2 sigma^2) = A^2 pi S^2 / (2 sigma^2) for a large box.
        let psf = Psf {
            amplitude: 1.0,
            blur: 1.5,
        };
        let mut f = Frame::zeros(101, 101);
        f.add_psf(50.3, 49.8, &psf);
        let m = LikelihoodModel {
            amplitude: 1.0,
            blur: 1.5,
            sigma: 0.5,
            half_box: 20,
        };
        let want = std::f64::consts::PI * 1.5 * 1.5 / (2.0 * 0.25);
        assert!((m.log_ratio(&f, 50.3, 49.8) - want).abs() < 1e-6);
        // The true position maximises the ratio.
        assert!(m.log_ratio(&f, 50.3, 49.8) > m.log_ratio(&f, 50.8, 49.8));
    }

    #[test]
    fn method_one_and_normalisation() {
        let p = Particles {
            x: vec![0.0, 1.0, 3.0],
            y: vec![0.0, 0.0, 4.0],
            vx: vec![0.0; 3],
            vy: vec![0.0; 3],
        };
        let mut lw = [0.0; 3];
        peak_distance_log_weights(
            &p,
            &Peak {
                x: 0.0,
                y: 0.0,
                value: 1.0,
            },
            1.0,
            &mut lw,
        );
        assert_eq!(lw, [0.0, -1.0, -25.0]);
        let mut w = [0.0; 3];
        let lse = normalise(&lw, &mut w);
        let z = 1.0 + (-1.0f64).exp() + (-25.0f64).exp();
        assert!((lse - z.ln()).abs() < 1e-15);
        assert!((w[1] - (-1.0f64).exp() / z).abs() < 1e-15);
        // Far-away peaks underflow naive exponentials but not the normalised weights.
        let lw2 = [-2000.0, -2001.0, f64::NAN];
        normalise(&lw2, &mut w);
        assert!((w[0] - 1.0 / (1.0 + (-1.0f64).exp())).abs() < 1e-15 && w[2] == 0.0);
    }
}
