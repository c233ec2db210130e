"""The core's geodesics (``_core.geodesic_inverse`` / ``geodesic_direct``, Karney's algorithms on
WGS84) against the independent ``geographiclib`` package, and the demo's geometry through them:
range, bearing, destination, offsets and the AOU of a covariance."""

from __future__ import annotations

import numpy as np
import pytest

geographiclib = pytest.importorskip("geographiclib.geodesic")
Geodesic = geographiclib.Geodesic

from geofeas import GeofeasError, _core  # noqa: E402
from geofeas.demo import scenario  # noqa: E402


def _points(rng, n):
    lat = rng.uniform(-89.0, 89.0, n)
    lon = rng.uniform(-180.0, 180.0, n)
    return lat, lon


def _angle(a, b):
    """Difference of two azimuths (degrees), in (-180, 180]."""
    return (np.asarray(a) - np.asarray(b) + 180.0) % 360.0 - 180.0


def test_inverse_is_geographiclibs(rng):
    lat1, lon1 = _points(rng, 300)
    # far points, near points (a few km) and one pair of equal points
    lat2, lon2 = _points(rng, 300)
    lat2[:100] = lat1[:100] + rng.uniform(-0.05, 0.05, 100)
    lon2[:100] = lon1[:100] + rng.uniform(-0.05, 0.05, 100)
    lat2[-1], lon2[-1] = lat1[-1], lon1[-1]
    s12, azi1, azi2 = _core.geodesic_inverse(lat1, lon1, lat2, lon2)
    for k in range(len(lat1)):
        g = Geodesic.WGS84.Inverse(lat1[k], lon1[k], lat2[k], lon2[k])
        assert s12[k] == pytest.approx(g["s12"], abs=1e-6), k
        if g["s12"] > 0:
            assert abs(_angle(azi1[k], g["azi1"])) < 1e-9, k
            assert abs(_angle(azi2[k], g["azi2"])) < 1e-9, k
    assert s12[-1] == 0.0


def test_direct_is_geographiclibs(rng):
    lat1, lon1 = _points(rng, 300)
    azi1 = rng.uniform(-180.0, 180.0, 300)
    s12 = np.concatenate([rng.uniform(0.0, 5e3, 100), rng.uniform(0.0, 1.5e7, 200)])
    lat2, lon2, azi2 = _core.geodesic_direct(lat1, lon1, azi1, s12)
    assert np.all((lon2 >= -180.0) & (lon2 < 180.0))
    for k in range(len(lat1)):
        g = Geodesic.WGS84.Direct(lat1[k], lon1[k], azi1[k], s12[k])
        assert lat2[k] == pytest.approx(g["lat2"], abs=1e-11), k
        assert abs(_angle(lon2[k], g["lon2"])) < 1e-11, k
        assert abs(_angle(azi2[k], g["azi2"])) < 1e-9, k


def test_constants_are_wgs84():
    assert _core.WGS84_A == Geodesic.WGS84.a
    assert _core.WGS84_F == Geodesic.WGS84.f


def test_errors_name_the_row_and_column():
    z = np.zeros(3)
    bad = np.array([0.0, 91.0, 0.0])
    with pytest.raises(GeofeasError) as e:
        _core.geodesic_inverse(z, z, bad, z)
    assert (e.value.row, e.value.field) == (1, "lat2")
    nan = np.array([0.0, 0.0, np.nan])
    with pytest.raises(GeofeasError) as e:
        _core.geodesic_direct(z, z, z, nan)
    assert (e.value.row, e.value.field) == (2, "s12")
    with pytest.raises(GeofeasError, match="length"):
        _core.geodesic_direct(z, z, z, np.zeros(2))


# ------------------------------------------------------------------- the demo through the core


def test_demo_range_bearing_is_the_geodesic(rng):
    lat0, lon0 = 50.7, -1.3
    lat = lat0 + rng.uniform(-0.3, 0.3, (4, 50))
    lon = lon0 + rng.uniform(-0.5, 0.5, (4, 50))
    r, los = scenario._range_bearing(lat0, lon0, lat, lon)
    assert r.shape == los.shape == lat.shape
    assert np.all((los >= 0.0) & (los < 360.0))
    for k in np.ndindex(lat.shape):
        g = Geodesic.WGS84.Inverse(lat0, lon0, lat[k], lon[k])
        assert r[k] == pytest.approx(g["s12"], abs=1e-6)
        # the line of sight at the target, pointing away from the site
        assert abs(_angle(los[k], g["azi2"])) < 1e-9


def test_demo_destination_and_offset_are_the_geodesic(rng):
    la, lo = scenario._destination(50.7, -1.3, 135.0, 20_000.0)
    g = Geodesic.WGS84.Direct(50.7, -1.3, 135.0, 20_000.0)
    assert (la, lo) == pytest.approx((g["lat2"], g["lon2"]), abs=1e-11)
    lat = rng.uniform(40.0, 60.0, 100)
    lon = rng.uniform(-10.0, 10.0, 100)
    de, dn = rng.normal(0.0, 3000.0, 100), rng.normal(0.0, 3000.0, 100)
    pla, plo = scenario._offset(lat, lon, de, dn)
    s12, azi1, _ = _core.geodesic_inverse(lat, lon, pla, plo)
    # to the round-off of the geodesics, about 15 nm
    np.testing.assert_allclose(s12, np.hypot(de, dn), rtol=0, atol=2e-8)
    np.testing.assert_allclose(_angle(azi1, np.degrees(np.arctan2(de, dn))), 0.0, atol=1e-9)
    # and the small-offset form of metres_per_degree agrees to second order: the meridians
    # converge, by about d^2 tan(lat) / R over an offset of d metres
    m_lat, m_lon = scenario.metres_per_degree(lat)
    bound = 2 * (de**2 + dn**2) * (1 + np.tan(np.radians(lat))) / 6.3e6
    assert np.all(np.abs((pla - lat) * m_lat - dn) <= bound)
    assert np.all(np.abs((plo - lon) * m_lon - de) <= bound)


def _eigen_aou(cov):
    """The demo's former AOU of a covariance: a NumPy eigen-decomposition (the reference)."""
    w, vec = np.linalg.eigh(cov)
    major = vec[..., :, 1]
    bearing = np.degrees(np.arctan2(major[..., 0], major[..., 1])) % 180.0
    return 2 * np.sqrt(w[..., 1]), 2 * np.sqrt(np.maximum(w[..., 0], 0.0)), bearing


def test_aou_from_covariance_is_the_eigen_decomposition(rng):
    a = rng.normal(0.0, 1.0, (500, 2, 2)) * rng.uniform(1.0, 1e3, (500, 1, 1))
    cov = a @ np.swapaxes(a, -1, -2) + 1e-3 * np.eye(2)
    rx, ry, b = scenario.aou_from_covariance(cov)
    rx0, ry0, b0 = _eigen_aou(cov)
    np.testing.assert_allclose(rx, rx0, rtol=1e-9)
    np.testing.assert_allclose(ry, ry0, rtol=1e-7)
    assert np.all((b >= 0.0) & (b < 180.0)) and np.all(rx >= ry)
    # bearings agree modulo 180 where the axes are distinct (a circle has none)
    distinct = rx > ry * (1 + 1e-6)
    assert np.abs(_angle(2 * b[distinct], 2 * b0[distinct])).max() < 1e-6
    # shapes (..., 2, 2) and no rows
    rx2, ry2, b2 = scenario.aou_from_covariance(cov[:6].reshape(2, 3, 2, 2))
    assert rx2.shape == (2, 3) and np.array_equal(rx2.ravel(), rx[:6])
    assert scenario.aou_from_covariance(np.zeros((0, 2, 2)))[0].shape == (0,)


def test_library_geodesy_broadcasts_and_is_geographiclibs(rng):
    from geofeas import geodesy

    # one point against a (2, 3) grid of points: the shape follows NumPy broadcasting and every
    # value is geographiclib's
    lat2, lon2 = rng.uniform(40, 60, (2, 3)), rng.uniform(-10, 10, (2, 3))
    s12, azi1, azi2 = geodesy.inverse(50.0, 0.0, lat2, lon2)
    assert s12.shape == azi1.shape == azi2.shape == (2, 3)
    for k in np.ndindex(2, 3):
        g = Geodesic.WGS84.Inverse(50.0, 0.0, lat2[k], lon2[k])
        assert s12[k] == pytest.approx(g["s12"], abs=1e-6)
        assert _angle(azi2[k], g["azi2"]) == pytest.approx(0.0, abs=1e-9)
    # direct undoes inverse, on strided (non-contiguous) input columns
    la, lo, _ = geodesy.direct(np.full((3, 2), 50.0).T, 0.0, azi1, s12)
    assert np.allclose(la, lat2, atol=1e-9) and np.allclose(lo, lon2, atol=1e-9)
    with pytest.raises(GeofeasError, match="lat2"):
        geodesy.inverse(0.0, 0.0, [10.0, 91.0], 0.0)


def test_metres_per_degree_is_the_geodesic_length_of_a_small_step():
    from geofeas import geodesy

    lat = np.array([0.0, 35.0, 50.7, 70.0])
    m_lat, m_lon = geodesy.metres_per_degree(lat)
    step = 1e-4
    s_north, _, _ = geodesy.inverse(lat - step / 2, 0.0, lat + step / 2, 0.0)
    s_east, _, _ = geodesy.inverse(lat, 0.0, lat, step)
    assert np.allclose(m_lat * step, s_north, rtol=1e-7)
    assert np.allclose(m_lon * step, s_east, rtol=1e-7)
