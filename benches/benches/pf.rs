//! Criterion benchmarks of the particle-filter focal-plane tracker (seed 003).
//!
//! One full 10 s scenario of the paper (101 frames of 256 x 256, four filters of 10,000
//! particles, SNR 6 dB, frames simulated inside the timed loop) tracked with Method 2 and, as the
//! baseline measured in the same run, with Method 1; plus the Method-2 weight kernel alone
//! (separable point spread) against the cell-by-cell likelihood ratio of the paper on the same
//! 10,000 particles.
//!
//! `cargo bench -p geofeas-benches --bench pf`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use geofeas::rng::stream;
use geofeas_tracking::pf::{track_run, LikelihoodModel, Method, Particles, PfConfig, RunSpec};

fn bench_scenario(c: &mut Criterion) {
    let spec = RunSpec::paper(6.0, 0, 0);
    let mut group = c.benchmark_group("pf_scenario_4x10000");
    group.sample_size(10);
    for (name, method) in [
        ("method2", Method::LikelihoodRatio),
        ("method1", Method::PeakDistance),
    ] {
        let cfg = PfConfig::paper(method, &spec.psf, spec.sigma_z());
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut x = 0.0;
                track_run(
                    &spec,
                    &[cfg],
                    |_, _, _, s, _| x += s.filters[0].estimate.mean[0],
                    &mut || false,
                )
                .unwrap();
                black_box(x)
            })
        });
    }
    group.finish();
}

fn bench_weights(c: &mut Criterion) {
    let spec = RunSpec::paper(6.0, 0, 0);
    let truth = spec.truth();
    let frame = spec.frame(&truth, 50);
    let p = Particles::uniform(
        10_000,
        truth.states[50][0].xv(),
        2.0,
        0.0,
        &mut stream(1, 0),
    );
    let model = LikelihoodModel::paper(&spec.psf, spec.sigma_z());
    let mut out = vec![0.0; p.len()];
    let mut group = c.benchmark_group("pf_method2_weights_10000");
    group.bench_function("separable", |b| {
        b.iter(|| {
            model.log_weights(&frame, &p, &mut out, false);
            black_box(out[0])
        })
    });
    group.bench_function("cell_by_cell", |b| {
        b.iter(|| {
            for (o, (&x, &y)) in out.iter_mut().zip(p.x.iter().zip(&p.y)) {
                *o = model.log_ratio_direct(&frame, x, y);
            }
            black_box(out[0])
        })
    });
    group.finish();
}

criterion_group!(benches, bench_scenario, bench_weights);
criterion_main!(benches);
