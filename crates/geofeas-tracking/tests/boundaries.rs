//! The tracking crate's boundary (ARCHITECTURE.md): no Python. The bindings crate is the only
//! one with pyo3 and numpy, so the trackers build and test without an interpreter.

#[test]
fn the_trackers_depend_on_no_python() {
    let manifest = include_str!("../Cargo.toml");
    for name in ["pyo3", "numpy"] {
        assert!(
            !manifest.lines().any(|l| l.trim_start().starts_with(name)),
            "the tracking crate's Cargo.toml names {name}"
        );
    }
}
