//! Criterion benchmarks of the score kernels through the shared batch drivers.
//!
//! `cargo bench -p geofeas-benches --bench scores`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use geofeas::score::monte_carlo::Sampler;
use geofeas::score::{score_cdist, score_pairs, Exact, GaussianScore, Glr, MonteCarlo, Polygon};
use geofeas::Ellipse;
use rand::{RngExt, SeedableRng};

fn random_pairs(n: usize, seed: u64) -> (Vec<Ellipse>, Vec<Ellipse>) {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut gen = |x: f64, y: f64| {
        let rx = rng.random_range(0.5..3.0);
        Ellipse::new(
            x + rng.random_range(-1.0..1.0),
            y + rng.random_range(-1.0..1.0),
            rx,
            rx * rng.random_range(0.2..1.0),
            rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
        )
    };
    let a: Vec<Ellipse> = (0..n).map(|_| gen(0.0, 0.0)).collect();
    let b: Vec<Ellipse> = (0..n).map(|_| gen(1.0, 0.5)).collect();
    (a, b)
}

fn bench_pairs(c: &mut Criterion) {
    let mut group = c.benchmark_group("pairs");
    let n = 20_000;
    let (a, b) = random_pairs(n, 1);
    let mut out = vec![0.0; n];
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function("glr", |bench| {
        bench.iter(|| score_pairs(&Glr::default(), &a, &b, black_box(&mut out), &mut || false))
    });
    group.bench_function("glr_threshold", |bench| {
        bench.iter(|| {
            score_pairs(
                &Glr { threshold: true },
                &a,
                &b,
                black_box(&mut out),
                &mut || false,
            )
        })
    });
    for vertices in [64, 256] {
        group.bench_with_input(
            BenchmarkId::new("polygon", vertices),
            &vertices,
            |bench, &v| {
                bench.iter(|| {
                    score_pairs(&Polygon::new(v), &a, &b, black_box(&mut out), &mut || false)
                })
            },
        );
    }
    group.bench_function("exact", |bench| {
        bench.iter(|| score_pairs(&Exact, &a, &b, black_box(&mut out), &mut || false))
    });
    group.bench_function("bhattacharyya", |bench| {
        bench.iter(|| {
            score_pairs(
                &GaussianScore::Bhattacharyya,
                &a,
                &b,
                black_box(&mut out),
                &mut || false,
            )
        })
    });
    group.bench_function("monte_carlo_sobol_64", |bench| {
        bench.iter(|| {
            score_pairs(
                &MonteCarlo {
                    samples: 64,
                    seed: 0,
                    sampler: Sampler::Sobol,
                },
                &a,
                &b,
                black_box(&mut out),
                &mut || false,
            )
        })
    });
    group.bench_function("monte_carlo_500", |bench| {
        bench.iter(|| {
            score_pairs(
                &MonteCarlo::default(),
                &a,
                &b,
                black_box(&mut out),
                &mut || false,
            )
        })
    });
    group.finish();
}

fn bench_cdist(c: &mut Criterion) {
    let mut group = c.benchmark_group("cdist");
    let (a, b) = random_pairs(1000, 2);
    let mut out = vec![0.0; a.len() * b.len()];
    group.throughput(Throughput::Elements(out.len() as u64));
    group.bench_function("glr_1000x1000", |bench| {
        bench.iter(|| score_cdist(&Glr::default(), &a, &b, black_box(&mut out), &mut || false))
    });
    group.bench_function("exact_1000x1000", |bench| {
        bench.iter(|| score_cdist(&Exact, &a, &b, black_box(&mut out), &mut || false))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench_pairs, bench_cdist
}
criterion_main!(benches);
