//! # geofeas-tracking
//!
//! Trackers whose estimates give AOU ellipses for the geofeas scores, with the papers' scenarios
//! and studies. Each sub-module is one tracker with its sensors, filters and study driver:
//!
//! - [`mht`]: multiple-hypothesis trilateration and tracking with distributed radars (seed 004).
//! - [`pf`]: particle-filter tracking of multiple objects on a focal-plane image (seed 003).
//!
//! [`gospa`] is the multi-target metric both trackers' studies report beside the papers' own;
//! [`options`] declares their option sets once, with a schema the bindings expose.
//!
//! The crate builds on the `geofeas` core (its [`Ellipse`](geofeas::Ellipse), seeded
//! [`rng`](geofeas::rng) streams, errors and assignment) and has no Python types.

pub mod gospa;
pub mod mht;
pub mod options;
pub mod pf;

pub use geofeas::{Error, Result};
