"""The demo's simulated picture does not depend on where on the Earth's longitudes it lies: the
same recording moved across the antimeridian gives the same sensors, tracks and reports, and
the oracle the same posterior. Also the longitude helpers they use, by hand."""

import dataclasses

import numpy as np
import pytest

from geofeas.demo import bundled
from geofeas.demo.evaluate import emitter_posterior
from geofeas.demo.scenario import simulate
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
    np.testing.assert_allclose(rb["lat"], ra["lat"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(
        delta_lon(rb["lon"].to_numpy(), ra["lon"].to_numpy()), wrap_lon(shift), rtol=0, atol=1e-9
    )
    for c in ("rx", "ry", "bearing"):
        np.testing.assert_allclose(rb[c], ra[c], rtol=1e-9, atol=1e-6)
    assert (rb["lon"].abs() <= 180).all()
    orbit_a, orbit_b = a.geometry["aircraft_orbit"], b.geometry["aircraft_orbit"]
    assert orbit_b["radius"] == pytest.approx(orbit_a["radius"], rel=1e-9)


def test_the_oracle_is_the_same_across_the_antimeridian(both):
    rec, moved, a, b, _ = both
    qa = emitter_posterior(a, rec).sort_values(["track_id", "mmsi"]).reset_index(drop=True)
    qb = emitter_posterior(b, moved).sort_values(["track_id", "mmsi"]).reset_index(drop=True)
    assert len(qa) > 0
    assert (qa[["track_id", "mmsi"]].to_numpy() == qb[["track_id", "mmsi"]].to_numpy()).all()
    np.testing.assert_allclose(qb["q"], qa["q"], rtol=1e-6, atol=1e-9)
