//! Property tests of the scores: range, symmetry, translation and rotation invariance, closed
//! forms, and agreement between the batch drivers and single-pair calls.

use geofeas::score::{score_cdist, score_pairs, Glr, MonteCarlo, PairScore, Polygon, Score};
use geofeas::{relation, Ellipse, Relation};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

fn ellipse() -> impl Strategy<Value = Ellipse> {
    (
        -5.0..5.0f64,
        -5.0..5.0f64,
        0.2..4.0f64,
        0.05..1.0f64,
        -PI..PI,
    )
        .prop_map(|(x, y, rx, k, phi)| Ellipse::new(x, y, rx, rx * k, phi))
}

/// Rotates about the origin, clockwise by `alpha` (bearings grow by `alpha`).
fn rotated(e: &Ellipse, alpha: f64) -> Ellipse {
    let (s, c) = alpha.sin_cos();
    Ellipse::new(
        e.x0 * c + e.y0 * s,
        -e.x0 * s + e.y0 * c,
        e.rx,
        e.ry,
        e.phi + alpha,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn scores_in_unit_interval_and_symmetric(a in ellipse(), b in ellipse()) {
        let glr = Glr::default();
        let thr = Glr { threshold: true };
        let poly = Polygon::new(64);
        for g in [glr.score_one(&a, &b), thr.score_one(&a, &b), poly.score_one(&a, &b),
                  MonteCarlo { samples: 64, seed: 1, ..MonteCarlo::default() }.score_one(&a, &b)] {
            prop_assert!((0.0..=1.0).contains(&g), "g = {g}");
        }
        prop_assert_eq!(glr.score_one(&a, &b), glr.score_one(&b, &a));
        prop_assert_eq!(thr.score_one(&a, &b), thr.score_one(&b, &a));
        prop_assert!((poly.score_one(&a, &b) - poly.score_one(&b, &a)).abs() < 1e-12);
    }

    #[test]
    fn invariant_under_translation_and_rotation(a in ellipse(), b in ellipse(), alpha in -PI..PI,
                                                dx in -1e6..1e6f64, dy in -1e6..1e6f64) {
        let glr = Glr::default();
        let poly = Polygon::new(64);
        let (ta, tb) = (a.shifted(dx, dy), b.shifted(dx, dy));
        prop_assert!((glr.score_one(&ta, &tb) - glr.score_one(&a, &b)).abs() < 1e-8);
        prop_assert!((poly.score_one(&ta, &tb) - poly.score_one(&a, &b)).abs() < 1e-8);
        let (ra, rb) = (rotated(&a, alpha), rotated(&b, alpha));
        prop_assert!((glr.score_one(&ra, &rb) - glr.score_one(&a, &b)).abs() < 1e-12);
        prop_assert!((poly.score_one(&ra, &rb) - poly.score_one(&a, &b)).abs() < 1e-9);
    }

    #[test]
    fn relation_agrees_with_point_tests(a in ellipse(), b in ellipse()) {
        // boundary points of a tell inside / outside b
        let inside = (0..720).filter(|i| {
            let p = a.point_at(*i as f64 * PI / 360.0);
            b.contains(p[0], p[1])
        }).count();
        match relation(&a, &b) {
            Relation::AInsideB => prop_assert_eq!(inside, 720),
            Relation::Disjoint => prop_assert_eq!(inside, 0),
            Relation::BInsideA => prop_assert_eq!(inside, 0),
            Relation::Crossing => {}
        }
    }
}

#[test]
fn crossed_ellipses_closed_form() {
    for (a, b) in [(3.0, 1.0), (2.0, 1.5), (50.0, 1.0)] {
        let e1 = Ellipse::new(7.0, -2.0, a, b, 0.3);
        let e2 = Ellipse::new(7.0, -2.0, a, b, 0.3 + FRAC_PI_2);
        let truth = 4.0 * a * b * (b / a).atan() / (PI * a * b);
        let p = Polygon::new(4096);
        let g = p.score_one(&e1, &e2);
        assert!(
            (g - truth).abs() <= p.error_bound(1.0),
            "{a}x{b}: {g} vs {truth}"
        );
    }
}

#[test]
fn circle_lens_closed_form() {
    let lens = |r: f64, d: f64| {
        2.0 * r * r * (d / (2.0 * r)).acos() - 0.5 * d * (4.0 * r * r - d * d).sqrt()
    };
    for d in [0.1, 0.5, 1.0, 1.5, 1.9] {
        let a = Ellipse::circle(0.0, 0.0, 1.0);
        let b = Ellipse::circle(d, 0.0, 1.0);
        let truth = lens(1.0, d) / PI;
        let p = Polygon::default();
        assert!((p.score_one(&a, &b) - truth).abs() <= p.error_bound(1.0));
    }
}

#[test]
fn drivers_agree_with_single_pairs() {
    let es: Vec<Ellipse> = (0..50)
        .map(|i| {
            let t = i as f64;
            Ellipse::new(
                t.sin() * 2.0,
                t.cos(),
                1.0 + (0.7 * t).sin().abs(),
                0.6,
                t * 0.37,
            )
        })
        .collect();
    for name in ["glr", "overlap", "monte_carlo"] {
        let score = Score::from_name(name, &Default::default()).unwrap();
        let mut pairs = vec![0.0; 49];
        score
            .pairs(&es[..49], &es[1..], &mut pairs, &mut || false)
            .unwrap();
        let mut all = vec![0.0; 50 * 50];
        score.cdist(&es, &es, &mut all, &mut || false).unwrap();
        for k in 0..49 {
            assert_eq!(
                pairs[k],
                score.one(&es[k], &es[k + 1], k as u64),
                "{name} pair {k}"
            );
            let (i, j) = (k, k + 1);
            assert_eq!(
                all[i * 50 + j],
                score.one(&es[i], &es[j], (i * 50 + j) as u64)
            );
        }
    }
    // broadcasting one ellipse
    let mut out = vec![0.0; 50];
    score_pairs(&Glr::default(), &es[..1], &es, &mut out, &mut || false).unwrap();
    let mut row = vec![0.0; 50];
    score_cdist(&Glr::default(), &es[..1], &es, &mut row, &mut || false).unwrap();
    assert_eq!(out, row);
}

#[test]
fn monte_carlo_converges_to_lens() {
    let a = Ellipse::circle(0.0, 0.0, 2.0);
    let b = Ellipse::circle(2.0, 0.0, 2.0);
    let truth = (8.0 * (0.5f64).acos() - 12f64.sqrt()) / (4.0 * PI);
    let mc = MonteCarlo {
        samples: 1_000_000,
        seed: 3,
        ..MonteCarlo::default()
    };
    // standard error ~ 0.5 / sqrt(1e6)
    assert!((mc.score_one(&a, &b) - truth).abs() < 3e-3);
}
