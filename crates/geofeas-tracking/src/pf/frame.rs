//! Focal-plane frames: Gaussian point-spread function plus white noise (seed 003, section II
//! and the measurement model of section V).
//!
//! Cell `(i, j)` (column `i` = x, row `j` = y, centres at integer coordinates) of a frame holds
//! `z(i, j) = sum_t A exp(-((i - x_t)^2 + (j - y_t)^2) / (2 Sigma^2)) + sigma_Z n(i, j)` with `n`
//! standard normal and independent from cell to cell and frame to frame, and
//! `sigma_Z = A / 10^(SNR / 20)`. Frames are stored row-major: `data[j * width + i]`.
//! The point spread is separable, `exp(-(di^2 + dj^2) / 2S^2) = g(di) g(dj)`, so it is rendered
//! (and, in [`crate::pf::weights`], evaluated) as an outer product of two 1-D profiles;
//! it is truncated where it falls below `exp(-32)` (8 Sigma).

use rand::{Rng, RngExt};
use rand_distr::StandardNormal;

use geofeas::error::{Error, Result};

/// A Gaussian point spread: amplitude `A` and blur `Sigma` (pixels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Psf {
    /// Peak amplitude `A` (paper: 1).
    pub amplitude: f64,
    /// Blur parameter `Sigma`, pixels (paper: 2).
    pub blur: f64,
}

impl Default for Psf {
    fn default() -> Self {
        Self {
            amplitude: 1.0,
            blur: 2.0,
        }
    }
}

impl Psf {
    /// Checks that both parameters are finite and positive.
    pub fn validated(self, name: &'static str) -> Result<Self> {
        if !(self.amplitude.is_finite() && self.amplitude > 0.0) {
            return Err(Error::InvalidOption {
                name,
                reason: format!("amplitude must be finite and > 0, got {}", self.amplitude),
            });
        }
        if !(self.blur.is_finite() && self.blur > 0.0) {
            return Err(Error::InvalidOption {
                name,
                reason: format!("blur must be finite and > 0, got {}", self.blur),
            });
        }
        Ok(self)
    }
}

/// `sigma_Z = A / 10^(SNR / 20)`.
pub fn noise_sigma(snr_db: f64, amplitude: f64) -> f64 {
    amplitude / 10f64.powf(snr_db / 20.0)
}

/// One frame of measured intensities.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Columns (x).
    pub width: usize,
    /// Rows (y).
    pub height: usize,
    /// Row-major intensities, `data[j * width + i]`.
    pub data: Vec<f64>,
}

impl Frame {
    /// A frame from row-major data; every value must be finite.
    pub fn new(width: usize, height: usize, data: Vec<f64>) -> Result<Self> {
        if width == 0 || height == 0 || data.len() != width * height {
            return Err(Error::Shape {
                what: "frame",
                expected: format!("{height} x {width} = {} values", width * height),
                got: format!("{}", data.len()),
            });
        }
        if let Some(k) = data.iter().position(|v| !v.is_finite()) {
            return Err(Error::Invalid(format!(
                "frame: value at row {} column {} is not finite ({})",
                k / width,
                k % width,
                data[k]
            )));
        }
        Ok(Self {
            width,
            height,
            data,
        })
    }

    /// A frame of zeros.
    pub fn zeros(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            data: vec![0.0; width * height],
        }
    }

    /// The intensity of cell `(i, j)`.
    #[inline]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.data[j * self.width + i]
    }

    /// Adds `A exp(-((i - x)^2 + (j - y)^2) / (2 Sigma^2))` to every cell within 8 Sigma.
    pub fn add_psf(&mut self, x: f64, y: f64, psf: &Psf) {
        let reach = (8.0 * psf.blur).ceil();
        let Some((i0, gx)) = profile(x, reach, self.width, psf.blur) else {
            return;
        };
        let Some((j0, gy)) = profile(y, reach, self.height, psf.blur) else {
            return;
        };
        for (r, &g) in gy.iter().enumerate() {
            let row = &mut self.data[(j0 + r) * self.width + i0..][..gx.len()];
            let a = psf.amplitude * g;
            for (z, &h) in row.iter_mut().zip(&gx) {
                *z += a * h;
            }
        }
    }

    /// Adds independent `N(0, sigma^2)` noise to every cell.
    pub fn add_noise<R: Rng>(&mut self, sigma: f64, rng: &mut R) {
        for z in &mut self.data {
            *z += sigma * rng.sample::<f64, _>(StandardNormal);
        }
    }

    /// The frame of targets at `positions` seen through `psf` with noise `sigma`.
    pub fn render<R: Rng>(
        width: usize,
        height: usize,
        positions: &[[f64; 2]],
        psf: &Psf,
        sigma: f64,
        rng: &mut R,
    ) -> Self {
        let mut f = Self::zeros(width, height);
        for p in positions {
            f.add_psf(p[0], p[1], psf);
        }
        f.add_noise(sigma, rng);
        f
    }
}

/// The 1-D Gaussian profile `exp(-(c - x)^2 / (2 s^2))` over the cells `c` within `reach` of `x`
/// (clipped to `0..n`): first cell and values, or `None` when no cell is in reach.
pub fn profile(x: f64, reach: f64, n: usize, s: f64) -> Option<(usize, Vec<f64>)> {
    let lo = (x - reach).ceil().max(0.0);
    let hi = (x + reach).floor().min(n as f64 - 1.0);
    if lo.is_nan() || hi.is_nan() || lo > hi {
        return None;
    }
    let c = 0.5 / (s * s);
    let (lo, hi) = (lo as usize, hi as usize);
    Some((
        lo,
        (lo..=hi)
            .map(|i| {
                let d = i as f64 - x;
                (-c * d * d).exp()
            })
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geofeas::rng::stream;

    #[test]
    fn psf_is_the_paper_gaussian() {
        let mut f = Frame::zeros(64, 48);
        let psf = Psf::default();
        f.add_psf(20.3, 30.6, &psf);
        for j in 0..48 {
            for i in 0..64 {
                let d2 = (i as f64 - 20.3).powi(2) + (j as f64 - 30.6).powi(2);
                let want = (-d2 / 8.0).exp();
                let want = if d2.sqrt() > 16.0 { 0.0 } else { want };
                assert!((f.at(i, j) - want).abs() < 1e-12, "{i} {j}");
            }
        }
        // Sum over the plane = 2 pi Sigma^2 A.
        let s: f64 = f.data.iter().sum();
        assert!((s - 2.0 * std::f64::consts::PI * 4.0).abs() < 1e-6, "{s}");
    }

    #[test]
    fn psf_clipped_at_the_border_and_outside() {
        let mut f = Frame::zeros(16, 16);
        f.add_psf(-3.0, 5.0, &Psf::default());
        assert!((f.at(0, 5) - (-9.0f64 / 8.0).exp()).abs() < 1e-12);
        let mut g = Frame::zeros(16, 16);
        g.add_psf(-100.0, 5.0, &Psf::default());
        assert!(g.data.iter().all(|&v| v == 0.0));
    }

    #[test]
    fn noise_has_the_snr_sigma() {
        assert!((noise_sigma(20.0, 1.0) - 0.1).abs() < 1e-15);
        assert!((noise_sigma(0.0, 2.0) - 2.0).abs() < 1e-15);
        let s = noise_sigma(6.0, 1.0);
        let f = Frame::render(256, 256, &[], &Psf::default(), s, &mut stream(3, 0));
        let n = f.data.len() as f64;
        let mean = f.data.iter().sum::<f64>() / n;
        let var = f.data.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        // 65536 cells: sd of the sample sd ~ s / sqrt(2n) = 0.28% of s.
        assert!((var.sqrt() / s - 1.0).abs() < 0.012, "{}", var.sqrt() / s);
        assert!(mean.abs() < 4.0 * s / n.sqrt());
    }

    #[test]
    fn bad_frames_are_rejected() {
        assert!(Frame::new(2, 2, vec![0.0; 3]).is_err());
        let e = Frame::new(2, 2, vec![0.0, 0.0, f64::NAN, 0.0])
            .unwrap_err()
            .to_string();
        assert!(e.contains("row 1 column 0"), "{e}");
    }
}
