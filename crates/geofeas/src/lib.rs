//! # geofeas
//!
//! Geofeasibility scores that tell a multi-sensor fusion centre which tracks are the same object,
//! from the 2-sigma areas of uncertainty (AOU) of their reports (seed 000: Coates et al.,
//! "Recognized Maritime Picture: Geofeasibility Scores").
//!
//! - [`Ellipse`] / [`Gaussian`]: an AOU and its Gaussian (eqs. 56-59).
//! - [`score::Glr`]: the generalized likelihood ratio (eq. 71), optionally thresholded.
//! - [`score::Polygon`]: the normalised overlap area (eqs. 49-50) on polygonised ellipses.
//! - [`score::MonteCarlo`]: the importance-sampling estimator of eq. 55.
//! - [`score::Exact`]: the exact normalised overlap (eqs. 49-50) from the boundary crossings,
//!   and [`score::exact::intersection_area`].
//! - [`score::GaussianScore`]: Bhattacharyya, Hellinger and the normalised Gaussian product.
//! - [`score::score_pairs`] / [`score::score_cdist`]: the parallel batch drivers shared by all.
//! - [`rng`]: the seeded per-item random streams every randomised computation draws from.
//! - [`association`]: track-to-track association at scale: reports, time alignment, the
//!   calibrated combination of per-instant scores, a space-time candidate index and grouping.
//!
//! The crate has no Python types and no paper studies: the trackers (seeds 003 and 004), whose
//! estimates give AOU ellipses for the scores, are the `geofeas-tracking` crate, and the PyO3
//! bindings the `geofeas-python` crate.
//!
//! ```
//! use geofeas::{score::{PairScore, Polygon}, Ellipse};
//! let a = Ellipse::circle(0.0, 0.0, 1.0);
//! let b = Ellipse::circle(0.5, 0.0, 1.0);
//! let g = Polygon::default().score_one(&a, &b);
//! assert!(g > 0.6 && g < 0.7);
//! ```

pub mod association;
pub mod ellipse;
pub mod error;
pub mod fastmath;
pub mod relation;
pub mod rng;
pub mod score;

pub use ellipse::{Ellipse, Gaussian};
pub use error::{Error, Result};
pub use relation::{relation, Relation};
pub use score::glr::glr;
