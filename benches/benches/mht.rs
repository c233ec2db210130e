//! Criterion benchmarks of the MHT trilateration tracker (seed 004).
//!
//! One 20 s two-target scenario of the paper with 4 false alarms per sensor per scan and three
//! sensors (412 detections), tracked by the MHT with 50 hypotheses, and, as the baseline measured
//! in the same run, by the single-hypothesis tracker. Simulation is outside the timed loop.
//!
//! `cargo bench -p geofeas-benches --bench mht`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use geofeas::rng::stream;
use geofeas_tracking::mht::{Mht, MhtConfig, Scenario};

fn bench_scenario(c: &mut Criterion) {
    let scenario = Scenario::paper(2, 3, 4).unwrap();
    let detections = scenario.simulate(&mut stream(0, 0));
    let scans = scenario.scan_times();
    let mht = MhtConfig::for_scenario(&scenario);
    let mut group = c.benchmark_group("mht_two_targets_4fa");
    group.sample_size(20);
    for (name, config) in [("mht50", mht), ("single", mht.single_hypothesis())] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut t = Mht::new(scenario.sensors.clone(), config).unwrap();
                t.run(&scans, black_box(&detections), |_, _, _| {}).unwrap();
                black_box(t.best().tracks.len())
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_scenario);
criterion_main!(benches);
