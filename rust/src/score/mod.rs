//! Geofeasibility scores and the one batch driver they all share.
//!
//! Every score implements [`PairScore`]: it prepares per-ellipse data once
//! ([`PairScore::prepare`]) and scores a prepared pair ([`PairScore::score`]). The drivers
//! [`score_pairs`] (elementwise, with length-1 broadcasting) and [`score_cdist`] (all pairs
//! between two sets, like `scipy.spatial.distance.cdist`) are written once, run on rayon in
//! chunks, and call an interrupt hook between chunks so long calls can be cancelled (Ctrl-C in
//! Python). Pair `k` of a batch (row-major `i * m + j` for all-pairs) is passed to the score as
//! its index, from which seeded scores derive their random stream, so results never depend on
//! the number of threads.

pub mod exact;
pub mod gaussian;
pub mod glr;
pub mod monte_carlo;
pub mod polygon;
pub mod spec;

use rayon::prelude::*;

use crate::ellipse::Ellipse;
use crate::error::{Error, Result};

pub use exact::{Exact, IntersectionArea};
pub use gaussian::GaussianScore;
pub use glr::Glr;
pub use monte_carlo::MonteCarlo;
pub use polygon::Polygon;
pub use spec::{Options, Score};

/// A geofeasibility score of two ellipses.
pub trait PairScore: Sync {
    /// Per-ellipse data computed once (the Gaussian, a polygon, ...).
    type Prepared: Send + Sync;
    /// Prepares one (valid) ellipse.
    fn prepare(&self, e: &Ellipse) -> Self::Prepared;
    /// The score of a prepared pair; `index` is the pair's position in its batch.
    fn score(&self, a: &Self::Prepared, b: &Self::Prepared, index: u64) -> f64;
    /// How many pairs a chunk between two interrupt checks holds (cheap scores: more).
    fn chunk_pairs(&self) -> usize {
        1 << 16
    }
    /// Scores one pair of unprepared ellipses.
    fn score_one(&self, a: &Ellipse, b: &Ellipse) -> f64 {
        self.score(&self.prepare(a), &self.prepare(b), 0)
    }
    /// Elementwise block: `out[k] = score(a[k], b[k])` for pairs `start + k`, where a side of
    /// length 1 broadcasts. Scores with a vectorised kernel override this.
    fn score_block(&self, a: &[Ellipse], b: &[Ellipse], start: usize, out: &mut [f64]) {
        let (ia, ib) = (a.len() > 1, b.len() > 1);
        for (k, slot) in out.iter_mut().enumerate() {
            let ea = &a[if ia { k } else { 0 }];
            let eb = &b[if ib { k } else { 0 }];
            *slot = self.score(&self.prepare(ea), &self.prepare(eb), (start + k) as u64);
        }
    }
    /// One row segment of an all-pairs batch: `out[k] = score(a, b[k])` for pairs `start + k`.
    fn score_row(&self, a: &Self::Prepared, b: &[Self::Prepared], start: usize, out: &mut [f64]) {
        for (k, (slot, pb)) in out.iter_mut().zip(b).enumerate() {
            *slot = self.score(a, pb, (start + k) as u64);
        }
    }
}

/// A hook called between chunks of a long computation; returning `true` stops it with
/// [`Error::Interrupted`].
pub type Interrupt<'a> = &'a mut dyn FnMut() -> bool;

/// Validates every ellipse of a batch, reporting the first bad row.
pub fn validate(ellipses: &[Ellipse]) -> Result<()> {
    for (row, e) in ellipses.iter().enumerate() {
        e.validated(row)?;
    }
    Ok(())
}

/// Length of an elementwise batch of `a` and `b`, where a length of 1 broadcasts.
pub fn broadcast_len(a: usize, b: usize) -> Result<usize> {
    match (a, b) {
        (x, y) if x == y => Ok(x),
        (1, y) => Ok(y),
        (x, 1) => Ok(x),
        (x, y) => Err(Error::LengthMismatch { left: x, right: y }),
    }
}

/// Elementwise scores: `out[k] = score(a[k], b[k])`, broadcasting a length-1 side.
///
/// Inputs are validated first; `out` must have the broadcast length.
pub fn score_pairs<S: PairScore>(
    score: &S,
    a: &[Ellipse],
    b: &[Ellipse],
    out: &mut [f64],
    interrupt: Interrupt<'_>,
) -> Result<()> {
    let n = broadcast_len(a.len(), b.len())?;
    check_out(out.len(), n)?;
    validate(a).map_err(|e| e.in_argument("a"))?;
    validate(b).map_err(|e| e.in_argument("b"))?;
    let (ia, ib) = (a.len() > 1, b.len() > 1);
    run_chunked(out, score.chunk_pairs(), interrupt, |start, block| {
        let end = start + block.len();
        let sa = if ia { &a[start..end] } else { a };
        let sb = if ib { &b[start..end] } else { b };
        score.score_block(sa, sb, start, block);
    })
}

/// All-pairs scores: `out[i * m + j] = score(a[i], b[j])` for `n = a.len()`, `m = b.len()`.
pub fn score_cdist<S: PairScore>(
    score: &S,
    a: &[Ellipse],
    b: &[Ellipse],
    out: &mut [f64],
    interrupt: Interrupt<'_>,
) -> Result<()> {
    let m = b.len();
    check_out(out.len(), a.len() * m)?;
    validate(a).map_err(|e| e.in_argument("a"))?;
    validate(b).map_err(|e| e.in_argument("b"))?;
    if m == 0 {
        return Ok(());
    }
    let pa: Vec<S::Prepared> = a.par_iter().map(|e| score.prepare(e)).collect();
    let pb: Vec<S::Prepared> = b.par_iter().map(|e| score.prepare(e)).collect();
    run_chunked(out, score.chunk_pairs(), interrupt, |start, block| {
        // split the block at row boundaries
        let mut k = start;
        let mut rest = block;
        while !rest.is_empty() {
            let (i, j) = (k / m, k % m);
            let len = (m - j).min(rest.len());
            let (row, tail) = rest.split_at_mut(len);
            score.score_row(&pa[i], &pb[j..j + len], k, row);
            k += len;
            rest = tail;
        }
    })
}

/// Refuses an all-pairs output of `rows x cols` f64 values larger than `limit` bytes.
pub fn check_cdist_size(rows: usize, cols: usize, limit: u128) -> Result<()> {
    let bytes = rows as u128 * cols as u128 * 8;
    if bytes > limit {
        return Err(Error::TooLarge {
            rows,
            cols,
            bytes,
            limit,
        });
    }
    Ok(())
}

fn check_out(got: usize, want: usize) -> Result<()> {
    if got != want {
        return Err(Error::Shape {
            what: "output",
            expected: format!("({want},)"),
            got: format!("({got},)"),
        });
    }
    Ok(())
}

/// Fills `out` in parallel, chunk by chunk, calling `interrupt` between chunks; `body(start,
/// block)` fills the sub-slice of `out` that begins at pair `start`.
fn run_chunked<F>(out: &mut [f64], chunk: usize, interrupt: Interrupt<'_>, body: F) -> Result<()>
where
    F: Fn(usize, &mut [f64]) + Sync,
{
    let chunk = chunk.max(1);
    let grain = (chunk / (4 * rayon::current_num_threads())).max(64);
    for (c, block) in out.chunks_mut(chunk).enumerate() {
        if interrupt() {
            return Err(Error::Interrupted);
        }
        let base = c * chunk;
        block
            .par_chunks_mut(grain)
            .enumerate()
            .for_each(|(g, part)| body(base + g * grain, part));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn broadcasting_rules() {
        assert_eq!(broadcast_len(3, 3).unwrap(), 3);
        assert_eq!(broadcast_len(1, 4).unwrap(), 4);
        assert_eq!(broadcast_len(4, 1).unwrap(), 4);
        assert!(broadcast_len(2, 3).is_err());
    }

    #[test]
    fn interrupt_stops_the_driver() {
        let a = vec![Ellipse::circle(0.0, 0.0, 1.0); 10];
        let mut out = vec![0.0; 10];
        let err = score_pairs(&Glr::default(), &a, &a, &mut out, &mut || true).unwrap_err();
        assert_eq!(err, Error::Interrupted);
    }

    #[test]
    fn bad_row_is_reported() {
        let mut a = vec![Ellipse::circle(0.0, 0.0, 1.0); 5];
        a[3].rx = -1.0;
        let mut out = vec![0.0; 5];
        let err = score_pairs(&Glr::default(), &a, &a, &mut out, &mut || false).unwrap_err();
        assert!(err.to_string().contains("row 3"));
    }

    #[test]
    fn giant_cdist_refused() {
        assert!(check_cdist_size(1 << 20, 1 << 20, 1 << 33).is_err());
        assert!(check_cdist_size(1000, 1000, 1 << 33).is_ok());
    }
}
