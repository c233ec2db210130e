//! Every score on one pair of ellipses, through the validating driver (as the bindings call
//! it): an error, or a score in its documented range; never a panic, NaN or out-of-range value.
#![no_main]

use geofeas::score::{Options, Score};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let Some((a, b)) = common::pair(data) else {
        return;
    };
    let polygon = Options {
        method: "polygon".into(),
        vertices: 64,
        ..Options::default()
    };
    let mc = Options {
        samples: 64,
        seed: 7,
        ..Options::default()
    };
    for (name, options) in [
        ("glr", Options::default()),
        (
            "glr",
            Options {
                threshold: true,
                ..Options::default()
            },
        ),
        ("overlap", Options::default()),
        ("overlap", polygon),
        ("monte_carlo", mc),
        ("bhattacharyya", Options::default()),
        ("hellinger", Options::default()),
        ("gaussian_product", Options::default()),
    ] {
        let score = Score::from_name(name, &options).expect("valid options");
        let mut out = [0.0];
        if score.pairs(&[a], &[b], &mut out, &mut || false).is_ok() {
            assert!(
                (0.0..=1.0).contains(&out[0]),
                "{name} {options:?}: {a:?} {b:?} -> {}",
                out[0]
            );
        }
    }
    let mut area = [0.0];
    if geofeas::score::score_pairs(
        &geofeas::score::IntersectionArea,
        &[a],
        &[b],
        &mut area,
        &mut || false,
    )
    .is_ok()
    {
        let small = a.area().min(b.area());
        assert!(
            area[0] >= 0.0 && area[0] <= small * (1.0 + 1e-12),
            "{a:?} {b:?} -> {}",
            area[0]
        );
    }
});
