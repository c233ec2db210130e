//! The core's boundary (ARCHITECTURE.md): no Python. The bindings crate is the only one with
//! pyo3 and numpy, so the core builds and tests without an interpreter. (Cargo already keeps the
//! core from depending on the tracking or bindings crates: that would be a cycle.)

#[test]
fn the_core_depends_on_no_python() {
    let manifest = include_str!("../Cargo.toml");
    for name in ["pyo3", "numpy"] {
        assert!(
            !manifest.lines().any(|l| l.trim_start().starts_with(name)),
            "the core's Cargo.toml names {name}"
        );
    }
}
