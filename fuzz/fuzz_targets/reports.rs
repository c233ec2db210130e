//! The report reader of the association: arbitrary columns give an error or validated,
//! sorted reports; never a panic.
#![no_main]

use geofeas::association::{Coords, Reports};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    if data.len() < 2 {
        return;
    }
    let coords = if data[0] & 1 == 0 {
        Coords::Planar
    } else {
        Coords::Geographic
    };
    let n_tracks = (data[1] % 8) as usize;
    let values: Vec<f64> = common::f64s(&data[2..]).collect();
    let rows = values.len() / 6;
    let track: Vec<u32> = (0..rows)
        .map(|r| (values[6 * r].to_bits() % 9) as u32)
        .collect();
    let source: Vec<u32> = (0..rows)
        .map(|r| (values[6 * r].to_bits() >> 8) as u32 % 3)
        .collect();
    let time: Vec<f64> = (0..rows).map(|r| values[6 * r]).collect();
    let aou: Vec<[f64; 5]> = (0..rows)
        .map(|r| std::array::from_fn(|k| values[6 * r + 1 + k]))
        .collect();
    if let Ok(reports) = Reports::new(coords, n_tracks, &track, &source, &time, &aou) {
        assert_eq!(reports.len(), rows);
    }
});
