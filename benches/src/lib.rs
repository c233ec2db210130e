//! Criterion benchmarks for geofeas live in `benches/`.
