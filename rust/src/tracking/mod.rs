//! Trackers: each sub-module is one tracker with its sensors, filters and study driver.
//! [`gospa`] is the multi-target metric both trackers' studies report beside the papers' own;
//! [`options`] declares their option sets once, with a schema the bindings expose.

pub mod gospa;
pub mod mht;
pub mod options;
pub mod pf;
