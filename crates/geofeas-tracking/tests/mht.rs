//! Tests of the multiple-hypothesis trilateration tracker (seed 004).

use std::f64::consts::PI;

use geofeas::Error;
use geofeas_tracking::mht::cartesian::Cartesian;
use geofeas_tracking::mht::range_doppler::RangeDoppler;
use geofeas_tracking::mht::scenario::Leg;
use geofeas_tracking::mht::*;
use nalgebra::{Matrix2, Matrix4, Vector2, Vector4};
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;
use rand_xoshiro::Xoshiro256PlusPlus;

fn sensor_at(x: f64, y: f64, boresight: f64) -> Sensor {
    Sensor {
        position: [x, y],
        boresight,
        ..Sensor::paper(0.0, 0.5)
    }
}

fn exact_z(s: &Sensor, x: &Vector4<f64>) -> Vector2<f64> {
    // Written from the definitions r = |p - s|, r' = d r / d t, not from Sensor::measure.
    let (dx, dy) = (x[0] - s.position[0], x[1] - s.position[1]);
    let r = (dx * dx + dy * dy).sqrt();
    Vector2::new(r, (dx * x[2] + dy * x[3]) / r)
}

#[test]
fn trilateration_is_exact_on_noise_free_detections_for_arbitrary_layouts() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let mut checked = 0;
    for _ in 0..2000 {
        // Two sensors anywhere, both looking along a common random direction with 180-degree beams.
        let look: f64 = rng.random_range(-PI..PI);
        let a = sensor_at(
            rng.random_range(-50.0..50.0),
            rng.random_range(-50.0..50.0),
            look,
        );
        let b = sensor_at(
            rng.random_range(-50.0..50.0),
            rng.random_range(-50.0..50.0),
            look,
        );
        let p = [
            rng.random_range(-100.0..100.0),
            rng.random_range(-100.0..100.0),
        ];
        if !(a.in_beam(p) && b.in_beam(p)) {
            continue;
        }
        let x = Vector4::new(
            p[0],
            p[1],
            rng.random_range(-15.0..15.0),
            rng.random_range(-15.0..15.0),
        );
        let Some(t) = trilaterate(&a, exact_z(&a, &x), &b, exact_z(&b, &x)) else {
            // Only a degenerate geometry may fail: target on the baseline line.
            let base = Vector2::new(b.position[0] - a.position[0], b.position[1] - a.position[1]);
            let rel = Vector2::new(p[0] - a.position[0], p[1] - a.position[1]);
            assert!(
                (base.perp(&rel) / (base.norm() * rel.norm())).abs() < 1e-3,
                "failed at {x:?}"
            );
            continue;
        };
        // With both sensors looking the same way, the mirror image can also be in both beams;
        // then either solution reproduces the detections, so compare the measurements.
        let back_a = exact_z(&a, &t.state);
        let back_b = exact_z(&b, &t.state);
        assert!((back_a - exact_z(&a, &x)).norm() < 1e-7);
        assert!((back_b - exact_z(&b, &x)).norm() < 1e-7);
        let mirror_in_beams = {
            let base = Vector2::new(b.position[0] - a.position[0], b.position[1] - a.position[1])
                .normalize();
            let rel = Vector2::new(p[0] - a.position[0], p[1] - a.position[1]);
            let m = Vector2::new(a.position[0], a.position[1]) + base * base.dot(&rel) * 2.0 - rel;
            a.in_beam([m[0], m[1]]) && b.in_beam([m[0], m[1]])
        };
        if !mirror_in_beams && t.sin_angle > 1e-3 {
            let tol = 1e-6 / t.sin_angle;
            assert!(
                (t.state - x).norm() < tol * (1.0 + x.norm()),
                "{:?} vs {x:?}",
                t.state
            );
            checked += 1;
        }
    }
    assert!(checked > 300, "only {checked} cases checked");
}

#[test]
fn trilateration_of_the_paper_layout_matches_eqs_4_and_5() {
    // Sensors at s1 = -10, s2 = 10 on the x axis (eqs. 1-5).
    let (s1, s2) = (-10.0f64, 10.0f64);
    let a = Sensor::paper(s1, 0.5);
    let b = Sensor::paper(s2, 0.7);
    let (z1, z2) = (30.0f64, 25.0f64);
    let x = (s1 * s1 - s2 * s2 - z1 * z1 + z2 * z2) / (2.0 * (s1 - s2));
    let y = (0.5 * (z1 * z1 + z2 * z2 - (x - s1).powi(2) - (x - s2).powi(2))).sqrt();
    let t = trilaterate(&a, Vector2::new(z1, 0.0), &b, Vector2::new(z2, 0.0)).unwrap();
    assert!((t.state[0] - x).abs() < 1e-12 && (t.state[1] - y).abs() < 1e-12);
    assert!(y > 0.0);
    // Non-intersecting circles have no solution.
    assert!(trilaterate(&a, Vector2::new(3.0, 0.0), &b, Vector2::new(3.0, 0.0)).is_none());
}

#[test]
fn trilateration_jacobian_matches_finite_differences() {
    let a = sensor_at(-7.0, 2.0, 1.3);
    let b = sensor_at(12.0, -3.0, 1.3);
    let x = Vector4::new(5.0, 40.0, 3.0, -8.0);
    let z = Vector4::new(
        exact_z(&a, &x)[0],
        exact_z(&a, &x)[1],
        exact_z(&b, &x)[0],
        exact_z(&b, &x)[1],
    );
    let f = |z: &Vector4<f64>| {
        trilaterate(&a, Vector2::new(z[0], z[1]), &b, Vector2::new(z[2], z[3]))
            .unwrap()
            .state
    };
    let j = trilaterate(&a, Vector2::new(z[0], z[1]), &b, Vector2::new(z[2], z[3]))
        .unwrap()
        .jacobian;
    let h = 1e-6;
    for c in 0..4 {
        let mut zp = z;
        let mut zm = z;
        zp[c] += h;
        zm[c] -= h;
        let col = (f(&zp) - f(&zm)) / (2.0 * h);
        for r in 0..4 {
            assert!(
                (col[r] - j[(r, c)]).abs() < 1e-5 * (1.0 + col[r].abs()),
                "J[{r},{c}] {} vs {}",
                j[(r, c)],
                col[r]
            );
        }
    }
}

#[test]
fn jacobian_covariance_matches_monte_carlo_propagation() {
    let a = Sensor::paper(-10.0, 0.5);
    let b = Sensor::paper(10.0, 0.7);
    let x = Vector4::new(4.0, 30.0, 6.0, -5.0);
    let (za, zb) = (exact_z(&a, &x), exact_z(&b, &x));
    let c = Matrix2::new(0.05f64.powi(2), 0.0, 0.0, 0.02f64.powi(2));
    let (_, p) = trilaterate_gaussian(&a, za, &c, &b, zb, &c).unwrap();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    let n = 200_000;
    let mut mean = Vector4::zeros();
    let mut samples = Vec::with_capacity(n);
    for _ in 0..n {
        let mut e = [0.0; 4];
        for v in &mut e {
            *v = rng.sample(StandardNormal);
        }
        let za2 = za + Vector2::new(0.05 * e[0], 0.02 * e[1]);
        let zb2 = zb + Vector2::new(0.05 * e[2], 0.02 * e[3]);
        let s = trilaterate(&a, za2, &b, zb2).unwrap().state;
        mean += s;
        samples.push(s);
    }
    mean /= n as f64;
    let mut cov = Matrix4::zeros();
    for s in &samples {
        cov += (s - mean) * (s - mean).transpose();
    }
    cov /= (n - 1) as f64;
    for i in 0..4 {
        // Standard error of a sample variance is sqrt(2 / n) ~ 0.3%; the transform is nearly linear
        // at 5 cm noise, so 3% bounds both statistical and second-order effects.
        let rel = (cov[(i, i)] - p[(i, i)]).abs() / p[(i, i)];
        assert!(
            rel < 0.03,
            "variance {i}: mc {} vs eq. 8 {}",
            cov[(i, i)],
            p[(i, i)]
        );
        for j in 0..i {
            let corr_mc = cov[(i, j)] / (cov[(i, i)] * cov[(j, j)]).sqrt();
            let corr = p[(i, j)] / (p[(i, i)] * p[(j, j)]).sqrt();
            assert!(
                (corr_mc - corr).abs() < 0.02,
                "corr {i},{j}: {corr_mc} vs {corr}"
            );
        }
    }
}

#[test]
fn ekf_jacobian_matches_finite_differences_and_shows_the_eq_21_typo() {
    let s = sensor_at(3.0, -2.0, 1.0);
    let x = Vector4::new(-4.0, 25.0, 7.0, -3.0);
    let h = s.jacobian(&x);
    let eps = 1e-6;
    for c in 0..4 {
        let mut xp = x;
        let mut xm = x;
        xp[c] += eps;
        xm[c] -= eps;
        let col = (exact_z(&s, &xp) - exact_z(&s, &xm)) / (2.0 * eps);
        for r in 0..2 {
            assert!(
                (col[r] - h[(r, c)]).abs() < 1e-7,
                "H[{r},{c}] {} vs {}",
                h[(r, c)],
                col[r]
            );
        }
    }
    // Eq. 21 as printed, for a sensor at the origin: H[1,0] = y (x' - x y') / r^3 differs.
    let o = Sensor::paper(0.0, 0.5);
    let hx = o.jacobian(&x);
    let r = x[0].hypot(x[1]);
    let printed = x[1] * (x[2] - x[0] * x[3]) / r.powi(3);
    let corrected = x[1] * (x[1] * x[2] - x[0] * x[3]) / r.powi(3);
    assert!((hx[(1, 0)] - corrected).abs() < 1e-12);
    assert!((hx[(1, 0)] - printed).abs() > 1e-3);
    // The printed H[1,1] is right.
    assert!((hx[(1, 1)] - x[0] * (x[0] * x[3] - x[1] * x[2]) / r.powi(3)).abs() < 1e-12);
}

#[test]
fn ekf_update_of_an_exact_measurement_moves_towards_it() {
    let s = Sensor::paper(0.0, 0.5);
    let truth = Vector4::new(1.0, 30.0, 2.0, -1.0);
    let est = Cartesian {
        time: 0.0,
        x: truth + Vector4::new(0.5, -0.4, 0.3, 0.2),
        p: Matrix4::identity(),
    };
    let r = Noise::default().covariance();
    let z = exact_z(&s, &truth);
    let (upd, _, d2) = est.update(&s, z, &r).unwrap();
    assert!(d2 > 0.0);
    let before = (s.measure(&est.x) - z).norm();
    let after = (s.measure(&upd.x) - z).norm();
    assert!(after < 0.2 * before, "{after} vs {before}");
    assert!(upd.p.trace() < est.p.trace());
}

#[test]
fn range_doppler_filter_follows_eqs_10_to_15() {
    let est = RangeDoppler {
        time: 1.0,
        x: Vector2::new(20.0, -2.0),
        p: Matrix2::new(0.01, 0.0, 0.0, 0.04),
    };
    let q = 3.0;
    let p = est.predict(1.5, q);
    let dt = 0.5;
    assert!((p.x[0] - (20.0 - 2.0 * dt)).abs() < 1e-12);
    // P = F P F^T + G q^2 G^T by hand.
    let p00 = 0.01 + dt * dt * 0.04 + q * q * dt.powi(4) / 4.0;
    let p01 = dt * 0.04 + q * q * dt.powi(3) / 2.0;
    let p11 = 0.04 + q * q * dt * dt;
    assert!(
        (p.p[(0, 0)] - p00).abs() < 1e-12
            && (p.p[(0, 1)] - p01).abs() < 1e-12
            && (p.p[(1, 1)] - p11).abs() < 1e-12
    );
    let r = Matrix2::new(0.0025, 0.0, 0.0, 0.0004);
    let z = Vector2::new(19.2, -1.9);
    let (u, ll, d2) = p.update(z, &r).unwrap();
    let s = p.p + r;
    let e = z - p.x;
    let sinv = s.try_inverse().unwrap();
    assert!((d2 - (e.transpose() * sinv * e)[(0, 0)]).abs() < 1e-9);
    let ll_ref = -0.5 * d2 - (2.0 * PI * (s.determinant()).sqrt()).ln();
    assert!((ll - ll_ref).abs() < 1e-9);
    assert!((u.x - (p.x + p.p * sinv * e)).norm() < 1e-12);
}

fn det(sensor: usize, time: f64, range: f64, range_rate: f64) -> Detection {
    Detection {
        time,
        sensor,
        scan: 0,
        range,
        range_rate,
        target: None,
    }
}

fn small_config() -> MhtConfig {
    MhtConfig {
        pd: 0.8,
        false_alarm_density: 1e-3,
        new_target_density: 2e-4,
        accel_sigma: 2.0,
        ..MhtConfig::default()
    }
}

#[test]
fn hypothesis_probabilities_are_reid_s_on_a_hand_checked_case() {
    let cfg = small_config();
    let mut mht = Mht::new(vec![Sensor::paper(0.0, 0.5)], cfg).unwrap();
    let d0 = det(0, 0.0, 20.0, -1.0);
    mht.process_scan(0.0, 0, &[(0, d0)]).unwrap();
    let (bfa, bnt, pd) = (1e-3f64, 2e-4f64, 0.8f64);
    let h = mht.hypotheses();
    assert_eq!(h.len(), 2);
    assert!((h[0].probability() - bfa / (bfa + bnt)).abs() < 1e-12);
    assert!(h[0].tracks.is_empty());
    assert!((h[1].probability() - bnt / (bfa + bnt)).abs() < 1e-12);

    // Second scan, one detection near the prediction.
    let d1 = det(0, 0.5, 19.6, -0.9);
    mht.process_scan(0.5, 0, &[(1, d1)]).unwrap();
    // By hand: predicted (r, r') and S for the track started by d0.
    let dt = 0.5f64;
    let (r0, rr0) = (20.0 - dt, -1.0);
    let (vr, vv) = (0.05f64.powi(2), 0.02f64.powi(2));
    let q = 4.0f64;
    let s00 = vr + dt * dt * vv + q * dt.powi(4) / 4.0 + vr;
    let s01 = dt * vv + q * dt.powi(3) / 2.0;
    let s11 = vv + q * dt * dt + vv;
    let detm = s00 * s11 - s01 * s01;
    let (e0, e1) = (19.6 - r0, -0.9 - rr0);
    let d2 = (s11 * e0 * e0 - 2.0 * s01 * e0 * e1 + s00 * e1 * e1) / detm;
    let lik = (-0.5 * d2).exp() / (2.0 * PI * detm.sqrt());
    // Children: of H_FA (w bfa): FA, New. Of H_New (w bnt): FA + miss, New + miss, Update.
    let w = [
        bfa * bfa,
        bfa * bnt,
        bnt * bfa * (1.0 - pd),
        bnt * bnt * (1.0 - pd),
        bnt * pd * lik,
    ];
    let total: f64 = w.iter().sum();
    let mut expected: Vec<f64> = w.iter().map(|v| v / total).collect();
    expected.sort_by(|a, b| b.total_cmp(a));
    let got: Vec<f64> = mht
        .hypotheses()
        .iter()
        .map(Hypothesis::probability)
        .collect();
    assert_eq!(got.len(), 5);
    for (g, e) in got.iter().zip(&expected) {
        assert!((g - e).abs() < 1e-9, "{got:?} vs {expected:?}");
    }
    assert!((got.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    // The update hypothesis is the most likely and holds one track with both contacts.
    assert_eq!(mht.best().tracks.len(), 1);
    assert_eq!(mht.best().tracks[0].detections(), vec![0, 1]);
}

#[test]
fn pruning_keeps_the_most_likely_hypotheses_renormalised() {
    let sensors = vec![Sensor::paper(-10.0, 0.5), Sensor::paper(10.0, 0.5)];
    let scans: Vec<(f64, usize, Vec<Detection>)> = vec![
        (
            0.0,
            0,
            vec![
                det(0, 0.0, 30.0, -1.0),
                det(0, 0.0, 45.0, 2.0),
                det(0, 0.0, 60.0, 0.5),
            ],
        ),
        (
            0.0,
            1,
            vec![det(1, 0.0, 28.0, -1.2), det(1, 0.0, 50.0, 1.0)],
        ),
    ];
    let run = |n: usize, upto: usize| {
        let mut m = Mht::new(
            sensors.clone(),
            MhtConfig {
                max_hypotheses: n,
                ..small_config()
            },
        )
        .unwrap();
        let mut k = 0;
        for (t, s, ds) in &scans[..upto] {
            let batch: Vec<(usize, Detection)> = ds
                .iter()
                .map(|d| {
                    k += 1;
                    (k - 1, *d)
                })
                .collect();
            m.process_scan(*t, *s, &batch).unwrap();
            let total: f64 = m.hypotheses().iter().map(Hypothesis::probability).sum();
            assert!((total - 1.0).abs() < 1e-9, "probabilities sum to {total}");
        }
        m
    };
    let key = |h: &Hypothesis| {
        let mut v: Vec<Vec<usize>> = h.tracks.iter().map(|t| t.detections()).collect();
        v.sort();
        v
    };
    // Scan 1: three detections of one sensor, no track can take two of them: 2^3 hypotheses.
    let full = run(1_000_000, 1);
    assert_eq!(full.hypotheses().len(), 8);
    // Pruned to 4 after each detection: after the second detection 4 children, all kept; after
    // the third, 8 children, keep 4. The weights are beta_FA^(3-k) beta_NT^k for k new tracks, so
    // the 4 kept are the unique top 4 of the 8 (k = 0 and the three k = 1), renormalised.
    let pruned = run(4, 1);
    assert_eq!(pruned.hypotheses().len(), 4);
    let top: f64 = full.hypotheses()[..4]
        .iter()
        .map(Hypothesis::probability)
        .sum();
    for p in pruned.hypotheses() {
        assert!(p.tracks.len() <= 1);
        let f = full.hypotheses().iter().find(|f| key(f) == key(p)).unwrap();
        assert!((p.probability() - f.probability() / top).abs() < 1e-12);
    }
    // Scan 2: every kept hypothesis of the pruned tracker is a hypothesis of the full one with
    // the same weight relative to the best, and the full best is kept.
    let full = run(1_000_000, 2);
    let pruned = run(4, 2);
    assert_eq!(key(&pruned.hypotheses()[0]), key(&full.hypotheses()[0]));
    let base = pruned.hypotheses()[0].log_weight - full.hypotheses()[0].log_weight;
    for p in pruned.hypotheses() {
        let f = full
            .hypotheses()
            .iter()
            .find(|f| key(f) == key(p))
            .expect("kept hypothesis exists");
        assert!((p.log_weight - f.log_weight - base).abs() < 1e-9);
    }
    // The best explains the two sensors' detections as two trilaterated tracks is not required,
    // but the kept hypotheses are sorted by probability.
    let w: Vec<f64> = pruned.hypotheses().iter().map(|h| h.log_weight).collect();
    assert!(w.windows(2).all(|p| p[0] >= p[1]));
}

#[test]
fn with_no_false_alarms_the_true_tracks_are_found() {
    let opts = StudyOptions {
        runs: 1,
        seed: 11,
        ..StudyOptions::default()
    };
    for targets in [1, 2] {
        for run in 0..3 {
            let cell = Cell {
                targets,
                sensors: 3,
                tracker: TrackerKind::Mht,
                false_alarms: 0,
            };
            let out = run_one(&cell, &opts, run).unwrap();
            let m = out.tally.metrics();
            assert!(m.t_pd > 0.9, "targets {targets} run {run}: {m:?}");
            assert_eq!(m.t_far, 0.0, "targets {targets} run {run}: {m:?}");
            assert!(m.pos_err < 1.5, "targets {targets} run {run}: {m:?}");
            // Every Cartesian track of the final best hypothesis holds contacts of one target only.
            for t in out
                .best
                .all_tracks()
                .iter()
                .filter(|t| t.is_cartesian() && t.contacts >= 3)
            {
                let ids = t.detections();
                let first = out.detections[ids[0]].target;
                assert!(first.is_some());
                assert!(
                    ids.iter().all(|&k| out.detections[k].target == first),
                    "mixed track {ids:?}"
                );
            }
        }
    }
}

#[test]
fn paper_scenario_flies_in_front_of_the_sensors_at_constant_speed() {
    let sc = Scenario::paper(2, 3, 2).unwrap().validated().unwrap();
    for tr in &sc.targets {
        let total: f64 = tr
            .legs
            .iter()
            .map(|l| match *l {
                Leg::Straight(s) => s,
                Leg::Turn(a) => a.abs() * tr.speed / tr.turn_acceleration,
            })
            .sum();
        assert!((total - 20.0).abs() < 1e-9);
        let mut prev = tr.state(0.0);
        for k in 1..=2000 {
            let t = k as f64 * 0.01;
            let s = tr.state(t);
            assert!((s[2].hypot(s[3]) - 10.0).abs() < 1e-9);
            // Position is the integral of velocity: the step length is speed * dt.
            let step = (s[0] - prev[0]).hypot(s[1] - prev[1]);
            assert!(step <= 0.1 + 1e-9 && step > 0.099, "t {t}: step {step}");
            for sensor in &sc.sensors {
                assert!(sensor.sees([s[0], s[1]]), "target leaves the beam at {t}");
            }
            prev = s;
        }
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
    let dets = sc.simulate(&mut rng);
    let scans = sc.scan_times();
    // 41 + 34 + 29 scans in [0, 20] s.
    assert_eq!(scans.len(), 41 + 34 + 29);
    assert_eq!(dets.len(), scans.len() * (2 + 2));
    assert!(dets
        .windows(2)
        .all(|w| w[0].time <= w[1].time && w[0].scan <= w[1].scan));
    let fa = dets.iter().filter(|d| d.target.is_none()).count();
    assert_eq!(fa, scans.len() * 2);
    for d in dets.iter().filter(|d| d.target.is_none()) {
        assert!((0.0..=100.0).contains(&d.range) && d.range_rate.abs() <= 15.0);
    }
}

#[test]
fn study_is_reproducible_whatever_the_thread_count() {
    let cells = [
        Cell {
            targets: 2,
            sensors: 3,
            tracker: TrackerKind::Mht,
            false_alarms: 2,
        },
        Cell {
            targets: 1,
            sensors: 2,
            tracker: TrackerKind::Single,
            false_alarms: 2,
        },
    ];
    let opts = StudyOptions {
        runs: 3,
        seed: 5,
        max_hypotheses: 20,
        ..StudyOptions::default()
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let a = one.install(|| study(&cells, &opts)).unwrap();
    let b = two.install(|| study(&cells, &opts)).unwrap();
    for ((_, x), (_, y)) in a.iter().zip(&b) {
        assert_eq!(format!("{x:?}"), format!("{y:?}"));
    }
}

#[test]
fn track_covariance_becomes_a_geofeas_ellipse() {
    let opts = StudyOptions::default();
    let cell = Cell {
        targets: 1,
        sensors: 3,
        tracker: TrackerKind::Mht,
        false_alarms: 0,
    };
    let out = run_one(&cell, &opts, 0).unwrap();
    let t = out
        .best
        .tracks
        .iter()
        .find(|t| t.is_cartesian())
        .expect("a Cartesian track");
    let c = t.cartesian().unwrap();
    let e = t.ellipse().unwrap().validated(0).unwrap();
    let g = e.to_gaussian();
    assert!((g.mean[0] - c.x[0]).abs() < 1e-12 && (g.mean[1] - c.x[1]).abs() < 1e-12);
    let scale = c.p[(0, 0)].max(c.p[(1, 1)]);
    assert!((g.cov[0] - c.p[(0, 0)]).abs() < 1e-9 * scale);
    assert!((g.cov[1] - c.p[(0, 1)]).abs() < 1e-9 * scale);
    assert!((g.cov[2] - c.p[(1, 1)]).abs() < 1e-9 * scale);
    // The true position lies inside the 2-sigma ellipse for a well-tracked target (most of the time).
    let inside = out
        .best
        .all_tracks()
        .iter()
        .filter_map(|t| t.ellipse().map(|e| (t.last_time, e)))
        .filter(|(time, e)| {
            let s = out.scenario.targets[0].state(*time);
            e.contains(s[0], s[1])
        })
        .count();
    assert!(inside >= 1);
    // A range-Doppler track has no ellipse.
    let d = det(0, 0.0, 10.0, 0.0);
    assert!(Track::start(0, &d, &Noise::default().covariance())
        .ellipse()
        .is_none());
}

#[test]
fn bad_input_gives_clear_errors() {
    let s = vec![Sensor::paper(0.0, 0.5)];
    assert!(matches!(
        Mht::new(
            s.clone(),
            MhtConfig {
                pd: 1.0,
                ..MhtConfig::default()
            }
        ),
        Err(Error::InvalidOption { name: "pd", .. })
    ));
    assert!(matches!(
        Mht::new(
            s.clone(),
            MhtConfig {
                max_hypotheses: 0,
                ..MhtConfig::default()
            }
        ),
        Err(Error::InvalidOption {
            name: "max_hypotheses",
            ..
        })
    ));
    let bad_sensor = Sensor {
        period: f64::NAN,
        ..Sensor::paper(0.0, 0.5)
    };
    assert!(matches!(
        Mht::new(vec![bad_sensor], MhtConfig::default()),
        Err(Error::NonFinite {
            field: "period",
            ..
        })
    ));
    let mut m = Mht::new(s, MhtConfig::default()).unwrap();
    let nan = det(0, 1.0, f64::NAN, 0.0);
    let e = m.process_scan(1.0, 0, &[(4, nan)]).unwrap_err();
    assert!(
        e.to_string().contains("row 4") && e.to_string().contains("range"),
        "{e}"
    );
    m.process_scan(1.0, 0, &[]).unwrap();
    assert!(m
        .process_scan(0.5, 0, &[])
        .unwrap_err()
        .to_string()
        .contains("time order"));
    assert!(m.process_scan(2.0, 3, &[]).is_err());
    assert!(m
        .process_scan(2.0, 0, &[(0, det(0, 2.5, 1.0, 0.0))])
        .is_err());
    assert!(Scenario::paper(3, 3, 0).is_err());
    assert!(Scenario::paper(1, 4, 0).is_err());
    assert!(study(
        &paper_cells(),
        &StudyOptions {
            runs: 0,
            ..StudyOptions::default()
        }
    )
    .is_err());
}

/// A Cartesian track `id` at `(x, y)` at `time` whose `n` contacts are the detections `dets`.
fn cartesian_track(id: usize, time: f64, x: f64, y: f64, dets: &[usize]) -> std::sync::Arc<Track> {
    use geofeas_tracking::mht::track::{Contact, Estimate};
    let mut history: Option<std::sync::Arc<Contact>> = None;
    for &k in dets {
        history = Some(std::sync::Arc::new(Contact {
            detection: k,
            time,
            state: Some([x, y, 10.0, 0.0]),
            prev: history,
        }));
    }
    std::sync::Arc::new(Track {
        id,
        estimate: Estimate::Cartesian(Cartesian {
            time,
            x: Vector4::new(x, y, 10.0, 0.0),
            p: Matrix4::identity(),
        }),
        last_scan: 0,
        last_time: time,
        contacts: dets.len(),
        sensor_mask: 0b11,
        history: history.unwrap(),
    })
}

#[test]
fn scorer_counts_identity_switches_fragmentation_and_gospa() {
    // One target flying along +x at 10 m/s from the origin; detections 0-9 are its, 10-19 false.
    let truth = vec![Trajectory {
        start: [0.0, 20.0],
        heading: 0.0,
        speed: 10.0,
        turn_acceleration: 1.0,
        legs: vec![],
    }];
    let mut detections = Vec::new();
    for k in 0..20 {
        detections.push(Detection {
            target: (k < 10).then_some(0),
            ..det(0, 0.0, 1.0, 0.0)
        });
    }
    let mut scorer = Scorer::new(Evaluation::default());
    let mut tally = Tally::default();
    let hyp = |tracks: Vec<std::sync::Arc<Track>>| Hypothesis {
        log_weight: 0.0,
        tracks,
        closed: None,
    };
    let at = |t: f64| 10.0 * t;
    // t = 0, 1: held by track 100 (exact); t = 2: nothing; t = 3, 4: held by track 200 (1 m off);
    // t = 5: track 100 again, plus a false track far away.
    let outputs: Vec<(f64, Vec<std::sync::Arc<Track>>)> = vec![
        (
            0.0,
            vec![cartesian_track(100, 0.0, at(0.0), 20.0, &[0, 1, 2])],
        ),
        (
            1.0,
            vec![cartesian_track(100, 1.0, at(1.0), 20.0, &[0, 1, 2])],
        ),
        (2.0, vec![]),
        (
            3.0,
            vec![cartesian_track(200, 3.0, at(3.0) + 1.0, 20.0, &[3, 4, 5])],
        ),
        (
            4.0,
            vec![cartesian_track(200, 4.0, at(4.0) + 1.0, 20.0, &[3, 4, 5])],
        ),
        (
            5.0,
            vec![
                cartesian_track(100, 5.0, at(5.0), 20.0, &[0, 1, 2]),
                cartesian_track(300, 5.0, 0.0, 90.0, &[10, 11, 12]),
            ],
        ),
    ];
    for (t, tracks) in outputs {
        scorer.observe(&mut tally, &[hyp(tracks)], &detections, &truth, t, 1.0);
    }
    let m = tally.metrics();
    // 200 replaces 100 after a gap (one switch, one fragmentation); 100 returns (one switch).
    assert_eq!(tally.id_switches, 2.0);
    assert_eq!(tally.fragmentations, 1.0);
    assert_eq!(m.id_switches, 2.0);
    assert_eq!(tally.false_tracks, 1.0);
    assert!((m.t_pd - 5.0 / 6.0).abs() < 1e-12);
    // GOSPA (c = 5, p = 2): 0, 0, c / sqrt(2) (missed), 1, 1, sqrt(c^2 / 2) (one false) -> mean.
    let c = 5.0f64;
    let expected = (0.0 + 0.0 + (c * c / 2.0).sqrt() + 1.0 + 1.0 + (c * c / 2.0).sqrt()) / 6.0;
    assert!(
        (m.gospa - expected).abs() < 1e-9,
        "{} vs {expected}",
        m.gospa
    );
    assert!((m.gospa_missed - 1.0 / 6.0).abs() < 1e-12);
    assert!((m.gospa_false - 1.0 / 6.0).abs() < 1e-12);
    assert!((m.gospa_loc - 2.0 / 6.0).abs() < 1e-12);
    // Velocity errors: every true output has velocity (10, 0), the truth's.
    assert!(m.vel_err.abs() < 1e-12 && m.speed_err.abs() < 1e-12);
}

#[test]
fn confirmation_stage_waits_for_the_track_probability() {
    let truth = vec![Trajectory {
        start: [0.0, 20.0],
        heading: 0.0,
        speed: 10.0,
        turn_acceleration: 1.0,
        legs: vec![],
    }];
    let detections: Vec<Detection> = (0..3)
        .map(|_| Detection {
            target: Some(0),
            ..det(0, 0.0, 1.0, 0.0)
        })
        .collect();
    let track = cartesian_track(7, 0.0, 0.0, 20.0, &[0, 1, 2]);
    let with = |p: f64| Hypothesis {
        log_weight: p.ln(),
        tracks: vec![track.clone()],
        closed: None,
    };
    let without = |p: f64| Hypothesis {
        log_weight: p.ln(),
        tracks: vec![],
        closed: None,
    };
    let eval = Evaluation {
        confirm_probability: 0.9,
        ..Evaluation::default()
    };
    let mut scorer = Scorer::new(eval);
    let mut tally = Tally::default();
    // Best hypothesis holds the track, but only 0.6 + 0.2 of the mass: not confirmed.
    let hs = [with(0.6), without(0.2), with(0.2)];
    scorer.observe(&mut tally, &hs, &detections, &truth, 0.0, 1.0);
    assert_eq!(tally.in_track, 0.0);
    // 0.95: confirmed, and it stays confirmed when the mass falls again.
    scorer.observe(
        &mut tally,
        &[with(0.95), without(0.05)],
        &detections,
        &truth,
        0.0,
        1.0,
    );
    scorer.observe(&mut tally, &hs, &detections, &truth, 0.0, 1.0);
    assert_eq!(tally.in_track, 2.0);
    // Without a confirmation stage the first output already counts.
    let mut scorer = Scorer::new(Evaluation::default());
    let mut tally = Tally::default();
    scorer.observe(&mut tally, &hs, &detections, &truth, 0.0, 1.0);
    assert_eq!(tally.in_track, 1.0);
}

/// Pooled metrics of `runs` runs of a cell.
fn cell_metrics(cell: Cell, opts: &StudyOptions) -> (Metrics, ([f64; 12], [f64; 12])) {
    let per = study_runs(&[cell], opts, &mut || false).unwrap();
    (pool(&per[0]).metrics(), bootstrap(&per[0], 400, 0.95, 1))
}

#[test]
fn mht_false_track_rate_is_far_below_the_single_hypothesis_baseline() {
    // One target, three sensors, four false alarms per sensor per scan (Table 1's column): the
    // paper's "without multiple hypotheses ... large false track rates".
    let opts = StudyOptions {
        runs: 6,
        seed: 3,
        ..StudyOptions::default()
    };
    let cell = |tracker| Cell {
        targets: 1,
        sensors: 3,
        tracker,
        false_alarms: 4,
    };
    let (mht, _) = cell_metrics(cell(TrackerKind::Mht), &opts);
    let (single, (lo, _)) = cell_metrics(cell(TrackerKind::Single), &opts);
    assert!(lo[1] > 10.0, "single-hypothesis T_FAR {single:?}");
    assert!(
        mht.t_far < 0.5 && 20.0 * mht.t_far < single.t_far,
        "MHT {mht:?} vs single {single:?}"
    );
    assert!(
        mht.gospa < 0.5 * single.gospa,
        "GOSPA {mht:?} vs {single:?}"
    );
}

#[test]
fn paper_faithful_t_pd_falls_with_false_alarms() {
    // Table 2's trend: T_PD 0.65 -> 0.33 from 0 to 4 false alarms per sensor per scan (two
    // targets, three sensors): the true tracks compete with hypotheses that call their contacts
    // false alarms, the more so the more false alarms there are.
    let opts = StudyOptions {
        runs: 8,
        seed: 4,
        ..StudyOptions::default()
    };
    let cell = |false_alarms| Cell {
        targets: 2,
        sensors: 3,
        tracker: TrackerKind::MhtPaper,
        false_alarms,
    };
    let (clean, (clean_lo, _)) = cell_metrics(cell(0), &opts);
    let (busy, (_, busy_hi)) = cell_metrics(cell(4), &opts);
    assert!(
        busy_hi[0] < clean_lo[0] && clean.t_pd - busy.t_pd > 0.15,
        "T_PD {} [{}, ..] at 0 FA vs {} [.., {}] at 4 FA",
        clean.t_pd,
        clean_lo[0],
        busy.t_pd,
        busy_hi[0]
    );
}

/// The MHT modules depend one way, `config` <- `track` <- `hypothesis`: a track never names the
/// hypotheses that hold it, and the options name neither.
#[test]
fn tracks_do_not_depend_on_hypotheses() {
    let sources = [
        (
            "track.rs",
            include_str!("../src/mht/track.rs"),
            &["hypothesis"][..],
        ),
        (
            "config.rs",
            include_str!("../src/mht/config.rs"),
            &["hypothesis", "track"][..],
        ),
    ];
    for (file, text, forbidden) in sources {
        for line in text.lines().filter(|l| l.trim_start().starts_with("use ")) {
            for module in forbidden {
                assert!(
                    !line.contains(&format!("{module}::")),
                    "{file} uses {module}: {line}"
                );
            }
        }
    }
}
