//! Geofeasibility scores and the one batch driver they all share.
//!
//! Every score implements [`PairScore`]: it prepares per-ellipse data once
//! ([`PairScore::prepare`]) and scores a prepared pair ([`PairScore::score`]). The drivers
//! [`score_pairs`] (elementwise, with length-1 broadcasting) and [`score_cdist`] (all pairs
//! between two sets, like `scipy.spatial.distance.cdist`) are written once, run on rayon in
//! chunks, and call an interrupt hook between chunks so long calls can be cancelled (Ctrl-C in
//! Python). While a chunk runs on the pool the calling thread keeps polling the hook; when it
//! fires the driver raises a [`Cancel`] flag that the pair loops check, so even one long pair
//! (a Monte-Carlo pair with billions of samples) stops promptly. Pair `k` of a batch (row-major `i * m + j` for all-pairs) is passed to the score as
//! its index, from which seeded scores derive their random stream, so results never depend on
//! the number of threads.

pub mod dd;
pub mod exact;
pub mod gaussian;
pub mod glr;
pub mod monte_carlo;
pub mod polygon;
pub mod schema;
pub mod spec;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

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
    /// [`PairScore::score`] for a driver that may cancel the call: a score whose one pair can
    /// run long checks `cancel` inside its loop and returns early (any value: the driver then
    /// discards the whole output and reports [`Error::Interrupted`]).
    fn score_cancellable(
        &self,
        a: &Self::Prepared,
        b: &Self::Prepared,
        index: u64,
        cancel: &Cancel,
    ) -> f64 {
        let _ = cancel;
        self.score(a, b, index)
    }
    /// Whether one pair may run long (beyond about ten milliseconds): the driver then always
    /// runs the pairs on the pool and polls the interrupt hook from the calling thread.
    fn long_pairs(&self) -> bool {
        false
    }
    /// How many pairs a chunk between two interrupt checks holds (cheap scores: more).
    fn chunk_pairs(&self) -> usize {
        1 << 16
    }
    /// Scores one pair of unprepared ellipses.
    fn score_one(&self, a: &Ellipse, b: &Ellipse) -> f64 {
        self.score(&self.prepare(a), &self.prepare(b), 0)
    }
    /// Elementwise block: `out[k] = score(a[k], b[k])` for pairs `start + k`, where a side of
    /// length 1 broadcasts; stops early once `cancel` is raised. Scores with a vectorised
    /// kernel override this.
    fn score_block(
        &self,
        a: &[Ellipse],
        b: &[Ellipse],
        start: usize,
        out: &mut [f64],
        cancel: &Cancel,
    ) {
        let (ia, ib) = (a.len() > 1, b.len() > 1);
        for (k, slot) in out.iter_mut().enumerate() {
            if cancel.is_raised() {
                return;
            }
            let ea = &a[if ia { k } else { 0 }];
            let eb = &b[if ib { k } else { 0 }];
            let (pa, pb) = (self.prepare(ea), self.prepare(eb));
            *slot = self.score_cancellable(&pa, &pb, (start + k) as u64, cancel);
        }
    }
    /// One row segment of an all-pairs batch: `out[k] = score(a, b[k])` for pairs `start + k`;
    /// stops early once `cancel` is raised.
    fn score_row(
        &self,
        a: &Self::Prepared,
        b: &[Self::Prepared],
        start: usize,
        out: &mut [f64],
        cancel: &Cancel,
    ) {
        for (k, (slot, pb)) in out.iter_mut().zip(b).enumerate() {
            if cancel.is_raised() {
                return;
            }
            *slot = self.score_cancellable(a, pb, (start + k) as u64, cancel);
        }
    }
}

/// A hook called between chunks of a long computation; returning `true` stops it with
/// [`Error::Interrupted`].
pub type Interrupt<'a> = &'a mut dyn FnMut() -> bool;

/// The cancellation flag of one driver call: raised by the calling thread when its interrupt
/// hook fires, read by the pair loops on the pool (a relaxed load, cheap enough to check every
/// few thousand samples).
#[derive(Debug, Default)]
pub struct Cancel(AtomicBool);

impl Cancel {
    /// A flag that is never raised, for scoring outside a driver.
    pub fn never() -> &'static Cancel {
        static NEVER: Cancel = Cancel(AtomicBool::new(false));
        &NEVER
    }

    /// Raises the flag.
    pub fn raise(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether the flag is raised.
    #[inline]
    pub fn is_raised(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

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
    let chunk = score.chunk_pairs();
    run_chunked(
        out,
        chunk,
        score.long_pairs(),
        interrupt,
        |start, block, cancel| {
            let end = start + block.len();
            let sa = if ia { &a[start..end] } else { a };
            let sb = if ib { &b[start..end] } else { b };
            score.score_block(sa, sb, start, block, cancel);
        },
    )
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
    let chunk = score.chunk_pairs();
    run_chunked(
        out,
        chunk,
        score.long_pairs(),
        interrupt,
        |start, block, cancel| {
            // split the block at row boundaries
            let mut k = start;
            let mut rest = block;
            while !rest.is_empty() {
                let (i, j) = (k / m, k % m);
                let len = (m - j).min(rest.len());
                let (row, tail) = rest.split_at_mut(len);
                score.score_row(&pa[i], &pb[j..j + len], k, row, cancel);
                k += len;
                rest = tail;
            }
        },
    )
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

/// How often the calling thread polls the interrupt hook while a chunk runs on the pool.
const POLL: Duration = Duration::from_millis(20);

/// Fills `out` in parallel, chunk by chunk; `body(start, block, cancel)` fills the sub-slice of
/// `out` that begins at pair `start`. The interrupt hook is called before every chunk and, while
/// a chunk runs on the pool (always when `long_pairs`, otherwise when the chunk is split across
/// threads), every [`POLL`] from the calling thread; once it fires the chunk is cancelled and the
/// call returns [`Error::Interrupted`].
fn run_chunked<F>(
    out: &mut [f64],
    chunk: usize,
    long_pairs: bool,
    interrupt: Interrupt<'_>,
    body: F,
) -> Result<()>
where
    F: Fn(usize, &mut [f64], &Cancel) + Sync,
{
    let chunk = chunk.max(1);
    let grain = (chunk / (4 * rayon::current_num_threads())).max(64);
    // a pool thread cannot wait for the pool (with one thread it would wait for itself)
    let may_watch = rayon::current_thread_index().is_none();
    let cancel = Cancel::default();
    for (c, block) in out.chunks_mut(chunk).enumerate() {
        if interrupt() {
            return Err(Error::Interrupted);
        }
        let base = c * chunk;
        let watch = may_watch && (long_pairs || block.len() > grain);
        let work = |block: &mut [f64]| {
            block
                .par_chunks_mut(grain)
                .enumerate()
                .for_each(|(g, part)| body(base + g * grain, part, &cancel));
        };
        if watch {
            watched(&cancel, &mut *interrupt, || work(block));
        } else {
            work(block);
        }
        if cancel.is_raised() {
            return Err(Error::Interrupted);
        }
    }
    Ok(())
}

/// Runs `work` on the pool while the calling thread polls `interrupt`, raising `cancel` when it
/// fires; returns when `work` has returned.
fn watched<W: FnOnce() + Send>(cancel: &Cancel, interrupt: Interrupt<'_>, work: W) {
    struct Done<'a>(&'a (Mutex<bool>, Condvar));
    impl Drop for Done<'_> {
        // also on unwinding, so the watcher never waits for a job that is gone
        fn drop(&mut self) {
            *self.0 .0.lock().unwrap_or_else(|e| e.into_inner()) = true;
            self.0 .1.notify_all();
        }
    }
    let done = (Mutex::new(false), Condvar::new());
    rayon::in_place_scope(|scope| {
        scope.spawn(|_| {
            let _done = Done(&done);
            work();
        });
        loop {
            let guard = done.0.lock().unwrap_or_else(|e| e.into_inner());
            let (guard, _) = done
                .1
                .wait_timeout_while(guard, POLL, |finished| !*finished)
                .unwrap_or_else(|e| e.into_inner());
            if *guard {
                break;
            }
            drop(guard);
            if !cancel.is_raised() && interrupt() {
                cancel.raise();
            }
        }
    });
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
