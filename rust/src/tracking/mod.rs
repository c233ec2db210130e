//! Association trackers: each sub-module is one tracker with its sensors, filters and study driver.

pub mod mht;
pub mod pf;
