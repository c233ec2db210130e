//! The relation of two valid ellipses: never panics, and agrees with itself when the arguments
//! are swapped (A inside B <-> B inside A; disjoint and crossing are symmetric).
#![no_main]

use geofeas::{relation, Relation};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let Some((a, b)) = common::pair(data) else {
        return;
    };
    if a.validated(0).is_err() || b.validated(1).is_err() {
        return;
    }
    let ab = relation(&a, &b);
    let ba = relation(&b, &a);
    let mirrored = match ab {
        Relation::AInsideB => Relation::BInsideA,
        Relation::BInsideA => Relation::AInsideB,
        other => other,
    };
    // identical ellipses are "A inside B" both ways round
    if !(ab == Relation::AInsideB && ba == Relation::AInsideB) {
        assert_eq!(ba, mirrored, "{a:?} {b:?}");
    }
});
