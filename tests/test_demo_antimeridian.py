"""The demo's simulated picture does not depend on where on the Earth's longitudes it lies: the
same recording moved across the antimeridian gives the same sensors, tracks and reports, and
the oracle the same posterior. Also the longitude helpers they use, by hand."""

import dataclasses

import numpy as np
import pytest

from geofeas.demo import bundled
from geofeas.demo.evaluate import emitter_posterior
from geofeas.demo.scenario import Truth, simulate
from geofeas.geodesy import delta_lon, median_lon, wrap_lon
from geofeas.io.ais import read_ais


def test_longitude_helpers_by_hand():
    assert wrap_lon(180.0) == -180.0
    np.testing.assert_allclose(wrap_lon([190.0, -190.0, 540.0, 0.5]), [-170.0, 170.0, -180.0, 0.5])
    np.testing.assert_allclose(delta_lon(179.9, -179.9), -0.2, atol=1e-12)
    np.testing.assert_allclose(delta_lon(-179.9, 179.9), 0.2, atol=1e-12)
    np.testing.assert_allclose(delta_lon(10.0, 5.0), 5.0)
    assert median_lon([179.8, -179.9, 179.95]) == pytest.approx(179.95)
    assert median_lon([179.9, -179.8, -179.9]) == pytest.approx(-179.9)
    assert median_lon([1.0, 2.0, 3.0]) == pytest.approx(2.0)


def test_away_from_the_antimeridian_the_helpers_change_nothing(rng):
    """A picture that does not straddle 180 degrees simulates to the bit as it did before the
    helpers: wrapping is the identity there, the median the plain one, a path its longitudes."""
    lon = rng.uniform(-179.0, 179.0, 1000)
    assert (wrap_lon(lon) == lon).all()
    lon = rng.uniform(-1.5, -1.0, 1001)
    assert median_lon(lon) == np.median(lon)
    truth = Truth.from_recording(read_ais(bundled("solent")))
    assert (truth._path_lon == truth.lon).all()


def test_the_truth_crosses_the_antimeridian_by_hand():
    # vessel 1 crosses eastwards at t = 5 s and back at t = 25 s; vessel 2 never crosses
    t = Truth(
        np.array([1, 2]),
        np.array([0, 4, 6]),
        np.array([0.0, 10.0, 20.0, 30.0, 0.0, 10.0]),
        np.zeros(6),
        np.array([179.99, -179.99, -179.98, 179.98, 5.0, 5.1]),
    )
    np.testing.assert_allclose(t._path_lon, [179.99, 180.01, 180.02, 179.98, 5.0, 5.1])
    _, lon, known = t.vessel(0, np.array([5.0, 15.0, 25.0]))
    assert known.all()
    np.testing.assert_allclose(lon, [-180.0, -179.985, -180.0], atol=1e-9)
    _, lon, _ = t.vessel(1, np.array([5.0]))
    np.testing.assert_allclose(lon, [5.05])


@pytest.fixture(scope="module")
def both():
    rec = read_ais(bundled("solent"))
    shift = 180.0 - float(np.median(rec.tracks["lon"]))
    moved = dataclasses.replace(
        rec, tracks=rec.tracks.assign(lon=wrap_lon(rec.tracks["lon"].to_numpy() + shift))
    )
    lon = moved.tracks["lon"].to_numpy()
    assert (lon > 179).any() and (lon < -179).any(), "the moved recording straddles 180"
    a = simulate(rec, seed=3, minutes=12)
    b = simulate(moved, seed=3, minutes=12)
    return rec, moved, a, b, shift


def test_the_simulation_is_the_same_across_the_antimeridian(both):
    _, _, a, b, shift = both
    ra, rb = a.reports, b.reports
    assert len(ra) == len(rb)
    assert (ra["track_id"].to_numpy() == rb["track_id"].to_numpy()).all()
    assert (ra["mmsi"].to_numpy() == rb["mmsi"].to_numpy()).all()
    np.testing.assert_array_equal(a.seconds, b.seconds)
    # to rounding: 1e-11 degrees is a millimetre
    np.testing.assert_allclose(rb["lat"], ra["lat"], rtol=0, atol=1e-11)
    np.testing.assert_allclose(
        delta_lon(rb["lon"].to_numpy(), ra["lon"].to_numpy()), wrap_lon(shift), rtol=0, atol=1e-11
    )
    for c in ("rx", "ry", "bearing"):
        np.testing.assert_allclose(rb[c], ra[c], rtol=1e-10, atol=1e-7)
    assert (rb["lon"].abs() <= 180).all()
    orbit_a, orbit_b = a.geometry["aircraft_orbit"], b.geometry["aircraft_orbit"]
    assert orbit_b["radius"] == pytest.approx(orbit_a["radius"], rel=1e-9)


def test_the_oracle_is_the_same_across_the_antimeridian(both):
    rec, moved, a, b, _ = both
    qa = emitter_posterior(a, rec).sort_values(["track_id", "mmsi"]).reset_index(drop=True)
    qb = emitter_posterior(b, moved).sort_values(["track_id", "mmsi"]).reset_index(drop=True)
    assert len(qa) > 0
    assert (qa[["track_id", "mmsi"]].to_numpy() == qb[["track_id", "mmsi"]].to_numpy()).all()
    np.testing.assert_allclose(qb["q"], qa["q"], rtol=1e-9, atol=1e-12)
