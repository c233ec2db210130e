//! Measurement peaks of a frame: the "locations of maximum measured intensity" `(x*_j, y*_j)` of
//! seed 003, sections III and IV.
//!
//! The paper takes the four peak intensity locations of each 256 x 256 frame without saying how
//! they are found. Here a peak is a cell that is a local maximum of its 3 x 3 neighbourhood
//! (ties broken by cell order); the local maxima are ranked by intensity and accepted greedily,
//! skipping any closer than `min_separation` pixels to one already accepted, until `count` are
//! found (default: one per target, as in the paper). With `smoothing > 0` the frame is first
//! correlated with a Gaussian of that width (the matched filter of the point spread when it equals
//! `Sigma`), which the paper does not do: by default peaks come from the raw intensities, which is
//! why Method 1 and the association collapse when noise maxima outgrow the targets
//! (below ~15 dB). Peak positions are cell centres (integer pixels).

use crate::pf::frame::Frame;
use geofeas::error::{Error, Result};

/// How peaks are extracted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeakOptions {
    /// Peaks per frame (paper: 4, one per target).
    pub count: usize,
    /// Smallest distance between two peaks, pixels.
    pub min_separation: f64,
    /// Width of the Gaussian smoothing, pixels (0: none, the paper's raw intensities).
    pub smoothing: f64,
}

impl Default for PeakOptions {
    fn default() -> Self {
        Self {
            count: 4,
            min_separation: 3.0,
            smoothing: 0.0,
        }
    }
}

impl PeakOptions {
    /// Most peaks per frame.
    pub const MAX_COUNT: usize = 4096;
    /// Widest smoothing, pixels (its kernel spans `8 smoothing + 1` pixels).
    pub const MAX_SMOOTHING: f64 = 64.0;

    /// Checks the options: `count` in `[1, 4096]`, `min_separation` finite and `>= 0`,
    /// `smoothing` in `[0, 64]` pixels.
    pub fn validated(self) -> Result<Self> {
        if !(1..=Self::MAX_COUNT).contains(&self.count) {
            return Err(Error::InvalidOption {
                name: "peaks",
                reason: format!("must be in [1, {}], got {}", Self::MAX_COUNT, self.count),
            });
        }
        if !(self.min_separation.is_finite() && self.min_separation >= 0.0) {
            return Err(Error::InvalidOption {
                name: "min_separation",
                reason: format!("must be finite and >= 0, got {}", self.min_separation),
            });
        }
        if !(self.smoothing.is_finite() && (0.0..=Self::MAX_SMOOTHING).contains(&self.smoothing)) {
            return Err(Error::InvalidOption {
                name: "smoothing",
                reason: format!(
                    "must be in [0, {}] pixels, got {}",
                    Self::MAX_SMOOTHING,
                    self.smoothing
                ),
            });
        }
        Ok(self)
    }
}

/// One measurement peak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// Column, pixels.
    pub x: f64,
    /// Row, pixels.
    pub y: f64,
    /// Intensity there (smoothed if smoothing is on).
    pub value: f64,
}

/// The frame correlated with a normalised Gaussian of width `s` (separable, truncated at 4 s,
/// zero outside the frame).
pub fn smooth(frame: &Frame, s: f64) -> Frame {
    let r = (4.0 * s).ceil() as isize;
    let mut k: Vec<f64> = (-r..=r)
        .map(|d| (-(d * d) as f64 / (2.0 * s * s)).exp())
        .collect();
    let total: f64 = k.iter().sum();
    k.iter_mut().for_each(|v| *v /= total);
    let (w, h) = (frame.width as isize, frame.height as isize);
    let mut tmp = vec![0.0; frame.data.len()];
    for j in 0..h {
        let row = &frame.data[(j * w) as usize..][..w as usize];
        for i in 0..w {
            let mut acc = 0.0;
            for (d, kv) in (-r..=r).zip(&k) {
                let ii = i + d;
                if (0..w).contains(&ii) {
                    acc += kv * row[ii as usize];
                }
            }
            tmp[(j * w + i) as usize] = acc;
        }
    }
    let mut out = vec![0.0; frame.data.len()];
    for j in 0..h {
        for (d, kv) in (-r..=r).zip(&k) {
            let jj = j + d;
            if !(0..h).contains(&jj) {
                continue;
            }
            let src = &tmp[(jj * w) as usize..][..w as usize];
            let dst = &mut out[(j * w) as usize..][..w as usize];
            for (o, s) in dst.iter_mut().zip(src) {
                *o += kv * s;
            }
        }
    }
    Frame {
        width: frame.width,
        height: frame.height,
        data: out,
    }
}

/// The peaks of `frame`, strongest first (fewer than `count` only if the frame has fewer local
/// maxima far enough apart).
pub fn find_peaks(frame: &Frame, opts: &PeakOptions) -> Vec<Peak> {
    let smoothed;
    let f = if opts.smoothing > 0.0 {
        smoothed = smooth(frame, opts.smoothing);
        &smoothed
    } else {
        frame
    };
    let (w, h) = (f.width, f.height);
    let z = &f.data;
    let mut maxima: Vec<(f64, usize)> = Vec::new();
    // Strictly greater than earlier cells, >= later ones: one maximum per plateau.
    let is_max = |i: usize, j: usize| -> bool {
        let c = j * w + i;
        let v = z[c];
        for dj in -1isize..=1 {
            for di in -1isize..=1 {
                if di == 0 && dj == 0 {
                    continue;
                }
                let (ii, jj) = (i as isize + di, j as isize + dj);
                if ii < 0 || jj < 0 || ii >= w as isize || jj >= h as isize {
                    continue;
                }
                let n = jj as usize * w + ii as usize;
                if (n < c && z[n] >= v) || (n > c && z[n] > v) {
                    return false;
                }
            }
        }
        true
    };
    for j in 0..h {
        let row = &z[j * w..(j + 1) * w];
        for i in 0..w {
            // Most cells fail against their row neighbours; test those first.
            let v = row[i];
            if (i > 0 && row[i - 1] >= v) || (i + 1 < w && row[i + 1] > v) {
                continue;
            }
            if is_max(i, j) {
                maxima.push((v, j * w + i));
            }
        }
    }
    let order = |a: &(f64, usize), b: &(f64, usize)| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1));
    let sep2 = opts.min_separation * opts.min_separation;
    let accept = |cands: &[(f64, usize)]| -> Vec<Peak> {
        let mut out: Vec<Peak> = Vec::with_capacity(opts.count);
        for &(v, c) in cands {
            if out.len() == opts.count {
                break;
            }
            let (x, y) = ((c % w) as f64, (c / w) as f64);
            if out
                .iter()
                .all(|p| (p.x - x).powi(2) + (p.y - y).powi(2) >= sep2)
            {
                out.push(Peak { x, y, value: v });
            }
        }
        out
    };
    // Usually the strongest few dozen maxima suffice; sort everything only when they do not.
    let m = (16 * opts.count).max(64);
    if maxima.len() > m {
        maxima.select_nth_unstable_by(m - 1, order);
        let mut top = maxima[..m].to_vec();
        top.sort_by(order);
        let out = accept(&top);
        if out.len() == opts.count {
            return out;
        }
    }
    maxima.sort_by(order);
    accept(&maxima)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pf::frame::Psf;
    use geofeas::rng::stream;

    #[test]
    fn four_clear_targets_give_their_cells() {
        let pos = [[20.2, 30.7], [100.0, 100.0], [101.0, 190.4], [240.6, 5.0]];
        let f = Frame::render(256, 256, &pos, &Psf::default(), 0.02, &mut stream(1, 0));
        let peaks = find_peaks(&f, &PeakOptions::default());
        assert_eq!(peaks.len(), 4);
        for p in &pos {
            assert!(
                peaks
                    .iter()
                    .any(|q| q.x == p[0].round() && q.y == p[1].round()),
                "{p:?} not in {peaks:?}"
            );
        }
        assert!(peaks.windows(2).all(|w| w[0].value >= w[1].value));
    }

    #[test]
    fn separation_and_plateaus() {
        let mut f = Frame::zeros(10, 10);
        f.data[22] = 5.0;
        f.data[23] = 5.0; // plateau: one maximum
        f.data[44] = 4.0; // (4, 4): within 3 px of the first
        f.data[88] = 3.0;
        let p = find_peaks(
            &f,
            &PeakOptions {
                count: 3,
                ..Default::default()
            },
        );
        assert_eq!(p.len(), 2, "{p:?}");
        assert_eq!((p[0].x, p[0].y), (2.0, 2.0));
        assert_eq!((p[1].x, p[1].y), (8.0, 8.0));
    }

    #[test]
    fn smoothing_recovers_a_weak_target() {
        // 3 dB: a raw maximum is usually noise, the matched filter finds the target.
        let sigma = crate::pf::frame::noise_sigma(3.0, 1.0);
        let mut hits = (0, 0);
        for k in 0..10 {
            let f = Frame::render(
                128,
                128,
                &[[64.0, 64.0]],
                &Psf::default(),
                sigma,
                &mut stream(9, k),
            );
            let one = |s| {
                let p = find_peaks(
                    &f,
                    &PeakOptions {
                        count: 1,
                        smoothing: s,
                        ..Default::default()
                    },
                )[0];
                (p.x - 64.0).hypot(p.y - 64.0) <= 2.0
            };
            hits.0 += one(0.0) as usize;
            hits.1 += one(2.0) as usize;
        }
        assert!(hits.1 >= 9 && hits.0 <= 5, "{hits:?}");
    }

    #[test]
    fn smoothing_preserves_a_constant_interior() {
        let f = Frame {
            width: 40,
            height: 40,
            data: vec![2.0; 1600],
        };
        let s = smooth(&f, 1.5);
        assert!((s.at(20, 20) - 2.0).abs() < 1e-12);
    }
}
