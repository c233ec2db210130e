//! Tests of the association pipeline with known answers: the space-time index against a brute
//! force scan on random scenes, the index never missing a pair whose AOUs touch, one ship seen by
//! two noisy sources against two ships passing at a safe distance, and geographic mode against
//! planar mode after an exact projection.

use geofeas::association::{
    self, align, candidates, geodesy, local_pair, Alignment, Coords, IndexOptions, Options, Reports,
};
use geofeas::{relation, Relation};
use proptest::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, Normal};
use rand_xoshiro::Xoshiro256PlusPlus;

/// A random scene: tracks of random walks in a `size` metre square, some with long gaps.
fn scene(seed: u64, n_tracks: usize, size: f64, geo: Option<[f64; 2]>) -> Reports {
    let (coords, (track, source, time, aou)) = scene_rows(seed, n_tracks, size, geo);
    Reports::new(coords, n_tracks, &track, &source, &time, &aou).unwrap()
}

/// The rows of [`scene`].
fn scene_rows(seed: u64, n_tracks: usize, size: f64, geo: Option<[f64; 2]>) -> (Coords, Columns) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let (mut track, mut source, mut time, mut aou) = (vec![], vec![], vec![], vec![]);
    for t in 0..n_tracks {
        let n = rng.random_range(1..15usize);
        let mut tm = rng.random_range(0.0..2000.0);
        let mut p = [rng.random_range(0.0..size), rng.random_range(0.0..size)];
        let src = rng.random_range(0..3u32);
        for _ in 0..n {
            let r = rng.random_range(10.0..400.0);
            let ry = r * rng.random_range(0.1..1.0);
            let phi: f64 = rng.random_range(-3.2..3.2);
            let row = match geo {
                None => [p[0], p[1], r, ry, phi],
                Some(c) => {
                    let (q, _) = geodesy::offset(c, [p[0] - size / 2.0, p[1] - size / 2.0]);
                    [q[0], q[1], r, ry, phi.to_degrees()]
                }
            };
            track.push(t as u32);
            source.push(src);
            time.push(tm);
            aou.push(row);
            let long = rng.random_range(0.0..1.0) < 0.15;
            let dt = if long {
                rng.random_range(300.0..1000.0)
            } else {
                rng.random_range(1.0..120.0)
            };
            tm += dt;
            // half the long gaps still (a moored ship: bridged up to max_still_gap)
            let speed = if long && rng.random_range(0.0..1.0) < 0.5 {
                0.0
            } else {
                8.0
            };
            p[0] += rng.random_range(-1.0..1.0) * speed * dt;
            p[1] += rng.random_range(-1.0..1.0) * speed * dt;
        }
    }
    let coords = if geo.is_some() {
        Coords::Geographic
    } else {
        Coords::Planar
    };
    (coords, (track, source, time, aou))
}

fn align_opts(horizon: f64) -> Alignment {
    Alignment {
        max_gap: 300.0,
        horizon,
        process_noise: 5.0,
        max_still_gap: Alignment::DEFAULT_MAX_STILL_GAP,
    }
}

/// Columns of reports being built: track, source, time, AOU rows.
type Columns = (Vec<u32>, Vec<u32>, Vec<f64>, Vec<[f64; 5]>);

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn merged_partials_of_any_split_hold_every_chunk_box(
        seed in 0u64..1_000_000,
        n in 1usize..40,
        parts in 1usize..4,
        window in prop_oneof![Just(0.0), 30.0..600.0f64],
        horizon in prop_oneof![Just(0.0), 1.0..120.0f64],
        halo in prop_oneof![Just(0.0), 0.0..5_000.0f64],
        geo in prop_oneof![Just(None), Just(Some([50.8, -1.1])), Just(Some([12.0, 179.97]))],
    ) {
        let (coords, (track, source, time, aou)) = scene_rows(seed, n, 20_000.0, geo);
        let whole = Reports::new(coords, n, &track, &source, &time, &aou).unwrap();
        // rows dealt to `parts` partitions at random; each partition's partials, merged
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x5eed);
        let deal: Vec<usize> = (0..track.len()).map(|_| rng.random_range(0..parts)).collect();
        let mut merged: Vec<Option<candidates::TrackPartial>> = vec![None; n];
        for part in 0..parts {
            let rows: Vec<usize> = (0..track.len()).filter(|&i| deal[i] == part).collect();
            // the partition numbers its tracks densely, as a reader of it alone does
            let mut present: Vec<u32> = rows.iter().map(|&i| track[i]).collect();
            present.sort_unstable();
            present.dedup();
            let local: Vec<u32> = rows
                .iter()
                .map(|&i| present.binary_search(&track[i]).unwrap() as u32)
                .collect();
            let sub_aou: Vec<[f64; 5]> = rows.iter().map(|&i| aou[i]).collect();
            let sub = Reports::new(
                coords,
                present.len(),
                &local,
                &rows.iter().map(|&i| source[i]).collect::<Vec<_>>(),
                &rows.iter().map(|&i| time[i]).collect::<Vec<_>>(),
                &sub_aou,
            )
            .unwrap();
            for (k, p) in candidates::TrackPartial::of(&sub, &sub_aou).iter().enumerate() {
                match &mut merged[present[k] as usize] {
                    Some(m) => m.merge(p),
                    slot => *slot = Some(p.clone()),
                }
            }
        }
        let merged: Vec<candidates::TrackPartial> = merged.into_iter().map(Option::unwrap).collect();
        // the merge is exact: the partials of the whole picture
        prop_assert_eq!(&merged, &candidates::TrackPartial::of(&whole, &aou));
        for p in &merged {
            let row = p.to_row();
            prop_assert_eq!(&candidates::TrackPartial::from_row(&row, 0).unwrap(), p);
        }
        let a = align_opts(horizon);
        let o = IndexOptions { window, same_source: true };
        for c in candidates::chunks(&whole, &a, &o) {
            let (lo, hi) = merged[c.track as usize].halo_box(&a, geo.is_some(), halo);
            for k in 0..4 {
                prop_assert!(
                    lo[k] <= c.lo[k] && c.hi[k] <= hi[k],
                    "track {} dimension {}: chunk [{}, {}] outside [{}, {}]",
                    c.track, k, c.lo[k], c.hi[k], lo[k], hi[k]
                );
            }
            for k in 0..3 {
                prop_assert!(hi[k] - lo[k] >= 2.0 * halo || (k == 2 && geo.is_none()));
            }
        }
    }

    #[test]
    fn index_returns_exactly_the_brute_force_pairs(
        seed in 0u64..1_000_000,
        n in 2usize..60,
        window in prop_oneof![Just(0.0), 30.0..600.0f64],
        horizon in prop_oneof![Just(0.0), 1.0..120.0f64],
        same_source in any::<bool>(),
        geo in prop_oneof![
            Just(None),
            Just(Some([50.8, -1.1])),
            Just(Some([12.0, 179.97])),
            Just(Some([80.0, 20.0]))
        ],
    ) {
        let r = scene(seed, n, 20_000.0, geo);
        let a = align_opts(horizon);
        let o = IndexOptions { window, same_source };
        let chunks = candidates::chunks(&r, &a, &o);
        let fast = candidates::candidate_pairs(&r, &chunks, &o);
        let slow = candidates::brute_force_pairs(&r, &chunks, &o);
        prop_assert_eq!(fast, slow);
    }

    #[test]
    fn index_never_misses_a_pair_whose_aous_touch(
        seed in 0u64..1_000_000,
        n in 2usize..40,
        horizon in prop_oneof![Just(0.0), 1.0..120.0f64],
        geo in prop_oneof![Just(None), Just(Some([-33.0, 179.99])), Just(Some([80.0, -60.0]))],
    ) {
        let r = scene(seed, n, 6_000.0, geo);
        let a = align_opts(horizon);
        let o = IndexOptions { window: 200.0, same_source: true };
        let chunks = candidates::chunks(&r, &a, &o);
        let found = candidates::candidate_pairs(&r, &chunks, &o);
        for ta in 0..n {
            for tb in ta + 1..n {
                let touching = align::common_instants(&r, ta, tb, &a).iter().any(|i| {
                    let (ea, eb) = local_pair(r.coords, &i.a, &i.b);
                    relation(&ea, &eb) != Relation::Disjoint
                });
                if touching {
                    prop_assert!(
                        found.binary_search(&(ta as u32, tb as u32)).is_ok(),
                        "pair ({}, {}) touches but is not a candidate", ta, tb
                    );
                }
            }
        }
    }
}

/// A ship on a straight line: its position at t = 0 and its velocity.
struct Ship {
    start: [f64; 2],
    v: [f64; 2],
}

/// How a source sees a ship: under which track number, every `dt` seconds, with noise `sigma`.
struct Seen {
    track: u32,
    src: u32,
    dt: f64,
    sigma: f64,
}

/// Reports of `ship` as `seen` by a source, appended to `out`.
fn observe(rng: &mut Xoshiro256PlusPlus, ship: Ship, seen: Seen, out: &mut Columns) {
    let Ship { start, v } = ship;
    let Seen {
        track,
        src,
        dt,
        sigma,
    } = seen;
    let noise = Normal::new(0.0, sigma).unwrap();
    let offset = rng.random_range(0.0..dt);
    let mut t = offset;
    while t < 1200.0 {
        out.0.push(track);
        out.1.push(src);
        out.2.push(t);
        out.3.push([
            start[0] + v[0] * t + noise.sample(rng),
            start[1] + v[1] * t + noise.sample(rng),
            2.0 * sigma,
            2.0 * sigma,
            0.0,
        ]);
        t += dt;
    }
}

#[test]
fn one_ship_two_sources_scores_higher_than_two_ships_passing() {
    let mut wins = 0;
    for seed in 0..20u64 {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut d = (vec![], vec![], vec![], vec![]);
        // ship 0 seen by AIS (track 0) and radar (track 1); ship 1 passes ship 0 head-on
        // 400 m abeam (radar AOU 2-sigma 100 m, AIS 30 m: a safe distance)
        observe(
            &mut rng,
            Ship {
                start: [0.0, 0.0],
                v: [6.0, 0.0],
            },
            Seen {
                track: 0,
                src: 0,
                dt: 10.0,
                sigma: 15.0,
            },
            &mut d,
        );
        observe(
            &mut rng,
            Ship {
                start: [0.0, 0.0],
                v: [6.0, 0.0],
            },
            Seen {
                track: 1,
                src: 1,
                dt: 3.0,
                sigma: 50.0,
            },
            &mut d,
        );
        observe(
            &mut rng,
            Ship {
                start: [7200.0, 400.0],
                v: [-6.0, 0.0],
            },
            Seen {
                track: 2,
                src: 1,
                dt: 3.0,
                sigma: 50.0,
            },
            &mut d,
        );
        let r = Reports::new(Coords::Planar, 3, &d.0, &d.1, &d.2, &d.3).unwrap();
        let o = Options {
            index: IndexOptions {
                window: 300.0,
                same_source: false,
            },
            ..Options::default()
        };
        let (same, k_same) = association::score_pair(&r, 0, 1, &o);
        let (other, k_other) = association::score_pair(&r, 0, 2, &o);
        assert!(k_same > 100 && k_other > 100);
        assert!(same > other, "seed {seed}: {same} <= {other}");
        if same >= association::combine::default_upper() && other < 0.5 {
            wins += 1;
        }
        for combine in association::combine::COMBINE_NAMES {
            let o = Options {
                combine: association::Combine::from_name(combine).unwrap(),
                ..o.clone()
            };
            let (s, _) = association::score_pair(&r, 0, 1, &o);
            let (t, _) = association::score_pair(&r, 0, 2, &o);
            assert!(s > t, "seed {seed} {combine}: {s} <= {t}");
        }
        let res = association::associate(&r, &o, &[], &mut || false).unwrap();
        assert_eq!(res.object[0], res.object[1]);
        assert_ne!(res.object[0], res.object[2]);
    }
    // consistent covariances: a true pair falls below the match threshold with probability
    // 13.5 %, so 20 seeds with at most 8 failures is a loose binomial bound (P < 1e-3)
    assert!(wins >= 12, "{wins}");
}

#[test]
fn geographic_agrees_with_planar_after_an_exact_projection() {
    // a planar scene (metres around the origin) and its image by the exact azimuthal-equidistant
    // projection centred at `c` (geodesic of length |p| and azimuth atan2(x, y), bearings
    // carried along the geodesic)
    for c in [[0.0, 179.995], [80.0, 45.0], [-80.0, -179.99], [50.8, -1.1]] {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        let mut d = (vec![], vec![], vec![], vec![]);
        observe(
            &mut rng,
            Ship {
                start: [-2000.0, -300.0],
                v: [4.0, 0.5],
            },
            Seen {
                track: 0,
                src: 0,
                dt: 10.0,
                sigma: 15.0,
            },
            &mut d,
        );
        observe(
            &mut rng,
            Ship {
                start: [-2000.0, -300.0],
                v: [4.0, 0.5],
            },
            Seen {
                track: 1,
                src: 1,
                dt: 4.0,
                sigma: 40.0,
            },
            &mut d,
        );
        observe(
            &mut rng,
            Ship {
                start: [2000.0, 200.0],
                v: [-3.0, 0.0],
            },
            Seen {
                track: 2,
                src: 1,
                dt: 6.0,
                sigma: 300.0,
            },
            &mut d,
        );
        for row in d.3.iter_mut() {
            row[4] = rng.random_range(0.0..3.0);
            row[3] = row[2] * 0.5;
        }
        let planar = Reports::new(Coords::Planar, 3, &d.0, &d.1, &d.2, &d.3).unwrap();
        let geo_rows: Vec<[f64; 5]> =
            d.3.iter()
                .map(|&[x, y, rx, ry, phi]| {
                    let (q, rot) = geodesy::offset(c, [x, y]);
                    [q[0], q[1], rx, ry, (phi + rot).to_degrees()]
                })
                .collect();
        let geo = Reports::new(Coords::Geographic, 3, &d.0, &d.1, &d.2, &geo_rows).unwrap();
        let o = Options {
            combine: association::Combine::Geometric,
            align: Alignment {
                process_noise: 0.0,
                ..Alignment::default()
            },
            ..Options::default()
        };
        for (a, b) in [(0, 1), (0, 2), (1, 2)] {
            let pp = association::pair_instants(&planar, a, b, &o);
            let pg = association::pair_instants(&geo, a, b, &o);
            assert_eq!(pp.m.len(), pg.m.len());
            for (k, (mp, mg)) in pp.m.iter().zip(&pg.m).enumerate() {
                // the scene spans about 5 km: the projection's distortion away from its centre
                // is (5 km / 6400 km)^2 / 6 ~ 1e-7 relative
                assert!(
                    (mp - mg).abs() <= 1e-6 * mp.max(1.0),
                    "{c:?} pair ({a}, {b}) instant {k}: planar {mp} geographic {mg}"
                );
            }
        }
    }
}

#[test]
fn the_density_is_looked_up_where_the_vaguer_track_is_whichever_is_named_first() {
    // a precise track along y = 0 and a vague one 3 km north of it, reported together: the
    // pair's density position is the vague track's, in both orders (the names of the tracks
    // must not decide where the picture's density is read)
    let (mut track, mut source, mut time, mut aou) = (vec![], vec![], vec![], vec![]);
    for k in 0..10 {
        let t = 10.0 * f64::from(k);
        for (id, y, r) in [(0u32, 0.0, 20.0), (1u32, 3000.0, 8000.0)] {
            track.push(id);
            source.push(id);
            time.push(t);
            aou.push([5.0 * t, y, r, r / 4.0, 0.3]);
        }
    }
    let r = Reports::new(Coords::Planar, 2, &track, &source, &time, &aou).unwrap();
    let o = Options::default();
    for (a, b) in [(0, 1), (1, 0)] {
        let s = association::pair_stat(&r, a, b, &o);
        assert!(s.instants > 0);
        assert!((s.pos[1] - 3000.0).abs() < 1e-9, "({a}, {b}): {:?}", s.pos);
    }
}
