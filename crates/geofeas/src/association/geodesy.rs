//! Geographic pairs on the WGS84 ellipsoid: the local frame in which two AOUs are compared.
//!
//! The scores of seed 000 (eqs. 49-71) are planar. A geographic pair of AOUs is brought into the
//! tangent plane of the first one by the azimuthal-equidistant (AEQD) projection centred on it,
//! computed from Karney's geodesics (`geographiclib-rs`, "Algorithms for geodesics", J. Geodesy
//! 87, 2013; round-off accurate, about 15 nm):
//!
//! - the second centre goes to `s12 (sin azi1, cos azi1)`, with `s12` the geodesic distance and
//!   `azi1` the geodesic's azimuth at the first centre. This is exact: the AEQD keeps distance
//!   and azimuth from its centre;
//! - the second covariance, given in its own east/north frame, is rotated by `azi1 - azi2` (the
//!   meridian convergence along the geodesic: `azi2` is the geodesic's forward azimuth at the
//!   second centre). This is the parallel transport of the second tangent plane along the
//!   geodesic, which keeps lengths and the angles with the geodesic, so the Mahalanobis distance
//!   `d^T (R1 + R2)^-1 d` of the pair is the same whichever AOU the frame is centred on.
//!
//! Centres and bearings are therefore exact whatever the distance, across the antimeridian and
//! at any latitude short of the poles; the only modelling choice is that each AOU is an ellipse
//! in its own tangent plane, which for a 100 km AOU differs from the ellipse drawn on the
//! ellipsoid by `(r / R)^2 / 6 < 5e-5` relative at its rim, and not at all at the centres,
//! where the score is determined. The same geodesics interpolate a track between two reports
//! (see [`interpolate`]).
//!
//! [`ecef`] gives the Earth-centred Earth-fixed point of a centre for the space-time index: a
//! straight chord is never longer than the geodesic, so a ball of radius `r` metres around the
//! ECEF point contains every point within geodesic distance `r`.

use std::sync::OnceLock;

use geographiclib_rs::{DirectGeodesic, Geodesic, InverseGeodesic};

/// WGS84 semi-major axis (m).
pub const WGS84_A: f64 = 6_378_137.0;
/// WGS84 flattening.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// The smallest radius of curvature of the WGS84 ellipsoid, `b^2 / a` (m), at the equator in
/// the meridian.
pub const MIN_CURVATURE_RADIUS: f64 = WGS84_A * (1.0 - WGS84_F) * (1.0 - WGS84_F);

fn wgs84() -> &'static Geodesic {
    static G: OnceLock<Geodesic> = OnceLock::new();
    G.get_or_init(Geodesic::wgs84)
}

/// Longitude wrapped into `[-180, 180)`.
pub fn wrap_lon(lon: f64) -> f64 {
    let w = (lon + 180.0).rem_euclid(360.0) - 180.0;
    if w >= 180.0 {
        w - 360.0
    } else {
        w
    }
}

/// The second point in the AEQD frame of the first, and the rotation (radians, clockwise) that
/// carries bearings at the second point into that frame (see the module docs).
///
/// ```
/// use geofeas::association::geodesy::log_map;
/// // 1 km due north of a point at 60 N, across nothing special
/// let ([dx, dy], rot) = log_map([60.0, 10.0], [60.0 + 1000.0 / 111_412.0, 10.0]);
/// assert!(dx.abs() < 1e-9 && (dy - 1000.0).abs() < 1.0 && rot.abs() < 1e-12);
/// ```
pub fn log_map(a: [f64; 2], b: [f64; 2]) -> ([f64; 2], f64) {
    let (s12, azi1, azi2, _a12): (f64, f64, f64, f64) = wgs84().inverse(a[0], a[1], b[0], b[1]);
    if s12 == 0.0 {
        return ([0.0, 0.0], 0.0);
    }
    let (s, c) = azi1.to_radians().sin_cos();
    ([s12 * s, s12 * c], (azi1 - azi2).to_radians())
}

/// The point at fraction `w` of the geodesic from `a` to `b`, and the rotations (radians,
/// clockwise) carrying bearings at `a` and at `b` into the east/north frame of that point.
pub fn interpolate(a: [f64; 2], b: [f64; 2], w: f64) -> ([f64; 2], f64, f64) {
    let (s12, azi1, azi2, _a12): (f64, f64, f64, f64) = wgs84().inverse(a[0], a[1], b[0], b[1]);
    if s12 == 0.0 {
        return (a, 0.0, 0.0);
    }
    let (lat, lon, azi): (f64, f64, f64) = wgs84().direct(a[0], a[1], azi1, w * s12);
    (
        [lat, wrap_lon(lon)],
        (azi - azi1).to_radians(),
        (azi - azi2).to_radians(),
    )
}

/// The point reached from `a` by `(east, north)` metres along the geodesic of that azimuth and
/// length, and the rotation carrying bearings at `a` into that point's frame.
pub fn offset(a: [f64; 2], east_north: [f64; 2]) -> ([f64; 2], f64) {
    let s = east_north[0].hypot(east_north[1]);
    if s == 0.0 {
        return (a, 0.0);
    }
    let azi1 = east_north[0].atan2(east_north[1]).to_degrees();
    let (lat, lon, azi2): (f64, f64, f64) = wgs84().direct(a[0], a[1], azi1, s);
    ([lat, wrap_lon(lon)], (azi2 - azi1).to_radians())
}

/// Geographic AOU rows `[lat, lon, rx, ry, bearing]` (degrees WGS84, 2-sigma semi-axes in
/// metres, bearing of `rx` in degrees clockwise from true north) as planar rows
/// `[x, y, rx, ry, phi]` in the azimuthal-equidistant frame of `origin` (`[lat, lon]`): `x`
/// east and `y` north in metres ([`log_map`] from the origin: distance and azimuth from the
/// origin exact), `phi` in radians clockwise from the frame's north (the bearing carried into
/// the origin's frame along the geodesic, as the engine carries covariances).
///
/// Errors name the row and field: non-finite values, a latitude outside `[-90, 90]`, a longitude
/// outside `[-180, 180]`, non-positive semi-axes; an invalid origin is row `0` of `origin`.
///
/// ```
/// use geofeas::association::geodesy::project_aeqd;
/// let p = project_aeqd([50.0, -1.0], &[[50.0, -1.0, 30.0, 10.0, 90.0]]).unwrap();
/// assert_eq!(p[0][..4], [0.0, 0.0, 30.0, 10.0]);
/// assert!((p[0][4] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// ```
pub fn project_aeqd(origin: [f64; 2], rows: &[[f64; 5]]) -> crate::Result<Vec<[f64; 5]>> {
    use crate::error::Error;
    check_coordinate("origin", 0, "lat", origin[0], Some(LATITUDE))
        .map_err(|e| e.in_argument("origin"))?;
    check_coordinate("origin", 0, "lon", origin[1], Some(LONGITUDE))
        .map_err(|e| e.in_argument("origin"))?;
    let mut out = Vec::with_capacity(rows.len());
    for (row, &[lat, lon, rx, ry, bearing]) in rows.iter().enumerate() {
        check_coordinate("report", row, "lat", lat, Some(LATITUDE))?;
        check_coordinate("report", row, "lon", lon, Some(LONGITUDE))?;
        for (field, value) in [("rx", rx), ("ry", ry), ("bearing", bearing)] {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    what: "report",
                    row,
                    field,
                    value,
                });
            }
        }
        for (field, value) in [("rx", rx), ("ry", ry)] {
            if value <= 0.0 {
                return Err(Error::NonPositive {
                    what: "report",
                    row,
                    field,
                    value,
                });
            }
        }
        let (xy, rot) = log_map(origin, [lat, lon]);
        out.push([xy[0], xy[1], rx, ry, bearing.to_radians() + rot]);
    }
    Ok(out)
}

/// The geodesic from `a` to `b` (`[lat, lon]`, degrees): its length `s12` (m), its azimuth
/// `azi1` at `a` and its forward azimuth `azi2` at `b` (degrees clockwise from north, in
/// `[-180, 180]`).
pub fn inverse(a: [f64; 2], b: [f64; 2]) -> (f64, f64, f64) {
    let (s12, azi1, azi2, _a12): (f64, f64, f64, f64) = wgs84().inverse(a[0], a[1], b[0], b[1]);
    (s12, azi1, azi2)
}

/// The end `[lat, lon]` (longitude in `[-180, 180)`) of the geodesic of length `s12` metres
/// leaving `a` at azimuth `azi1` (degrees clockwise from north), and its forward azimuth there.
pub fn direct(a: [f64; 2], azi1: f64, s12: f64) -> ([f64; 2], f64) {
    let (lat, lon, azi2): (f64, f64, f64) = wgs84().direct(a[0], a[1], azi1, s12);
    ([lat, wrap_lon(lon)], azi2)
}

/// Latitudes in `[-90, 90]` and longitudes in `[-180, 180]`, with the reason given when refused.
const LATITUDE: (f64, &str) = (90.0, "latitude must be in [-90, 90]");
const LONGITUDE: (f64, &str) = (180.0, "longitude must be in [-180, 180]");

/// `value` of `field` in row `row` of `what`: finite, and within `[-bound, bound]` when a bound
/// is given (refused with its reason).
fn check_coordinate(
    what: &'static str,
    row: usize,
    field: &'static str,
    value: f64,
    bound: Option<(f64, &'static str)>,
) -> crate::Result<()> {
    use crate::error::Error;
    if !value.is_finite() {
        return Err(Error::NonFinite {
            what,
            row,
            field,
            value,
        });
    }
    match bound {
        Some((limit, reason)) if value.abs() > limit => Err(Error::OutOfDomain {
            what,
            row,
            field,
            value,
            reason,
        }),
        _ => Ok(()),
    }
}

/// Checks the columns of a batch of points: equal lengths, finite values, latitudes in
/// `[-90, 90]`; errors name the row and the column.
fn check_columns(what: &'static str, columns: [(&'static str, &[f64]); 4]) -> crate::Result<()> {
    use crate::error::Error;
    let n = columns[0].1.len();
    if columns.iter().any(|(_, c)| c.len() != n) {
        return Err(Error::Shape {
            what,
            expected: "four columns of one length".into(),
            got: format!("{:?}", columns.map(|(_, c)| c.len())),
        });
    }
    for (field, column) in columns {
        let bound = field.starts_with("lat").then_some(LATITUDE);
        for (row, &value) in column.iter().enumerate() {
            check_coordinate(what, row, field, value, bound)?;
        }
    }
    Ok(())
}

/// [`inverse`] of every row `k` of the columns: `[s12, azi1, azi2]` of the geodesic from
/// `(lat1[k], lon1[k])` to `(lat2[k], lon2[k])`, computed in parallel.
pub fn inverse_rows(
    lat1: &[f64],
    lon1: &[f64],
    lat2: &[f64],
    lon2: &[f64],
) -> crate::Result<Vec<[f64; 3]>> {
    use rayon::prelude::*;
    check_columns(
        "points",
        [
            ("lat1", lat1),
            ("lon1", lon1),
            ("lat2", lat2),
            ("lon2", lon2),
        ],
    )?;
    Ok((0..lat1.len())
        .into_par_iter()
        .with_min_len(256)
        .map(|k| {
            let (s12, azi1, azi2) = inverse([lat1[k], lon1[k]], [lat2[k], lon2[k]]);
            [s12, azi1, azi2]
        })
        .collect())
}

/// [`direct`] of every row `k` of the columns: `[lat2, lon2, azi2]` at the end of the geodesic
/// of length `s12[k]` leaving `(lat1[k], lon1[k])` at azimuth `azi1[k]`, computed in parallel.
pub fn direct_rows(
    lat1: &[f64],
    lon1: &[f64],
    azi1: &[f64],
    s12: &[f64],
) -> crate::Result<Vec<[f64; 3]>> {
    use rayon::prelude::*;
    check_columns(
        "points",
        [("lat1", lat1), ("lon1", lon1), ("azi1", azi1), ("s12", s12)],
    )?;
    Ok((0..lat1.len())
        .into_par_iter()
        .with_min_len(256)
        .map(|k| {
            let ([lat, lon], azi2) = direct([lat1[k], lon1[k]], azi1[k], s12[k]);
            [lat, lon, azi2]
        })
        .collect())
}

/// WGS84 Earth-centred Earth-fixed coordinates (m) of a point at height 0.
pub fn ecef(lat: f64, lon: f64) -> [f64; 3] {
    let e2 = WGS84_F * (2.0 - WGS84_F);
    let (sp, cp) = lat.to_radians().sin_cos();
    let (sl, cl) = lon.to_radians().sin_cos();
    let n = WGS84_A / (1.0 - e2 * sp * sp).sqrt();
    [n * cp * cl, n * cp * sl, n * (1.0 - e2) * sp]
}

/// The covariance `[xx, xy, yy]` with every bearing turned clockwise by `delta` radians:
/// `M C M^T`, `M = [[cos, sin], [-sin, cos]]`.
pub fn rotate_cov(cov: [f64; 3], delta: f64) -> [f64; 3] {
    if delta == 0.0 {
        return cov;
    }
    let (s, c) = delta.sin_cos();
    let [xx, xy, yy] = cov;
    // rows of M: (c, s), (-s, c)
    let nxx = c * c * xx + 2.0 * c * s * xy + s * s * yy;
    let nyy = s * s * xx - 2.0 * c * s * xy + c * c * yy;
    let nxy = -c * s * xx + (c * c - s * s) * xy + c * s * yy;
    [nxx, nxy, nyy]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ellipse::Ellipse;

    #[test]
    fn rotation_turns_bearings_clockwise() {
        // rx axis pointing north (phi = 0) turned by 90 degrees points east.
        let c = Ellipse::new(0.0, 0.0, 4.0, 2.0, 0.0).to_gaussian().cov;
        let want = Ellipse::new(0.0, 0.0, 4.0, 2.0, 0.3 + 1.0)
            .to_gaussian()
            .cov;
        let got = rotate_cov(Ellipse::new(0.0, 0.0, 4.0, 2.0, 0.3).to_gaussian().cov, 1.0);
        for k in 0..3 {
            assert!((got[k] - want[k]).abs() < 1e-12, "{got:?} {want:?}");
        }
        let r = rotate_cov(c, std::f64::consts::FRAC_PI_2);
        assert!((r[0] - 4.0).abs() < 1e-12 && (r[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn log_map_is_symmetric_and_crosses_the_antimeridian() {
        let a = [10.0, 179.99];
        let b = [10.05, -179.97];
        let (d1, r1) = log_map(a, b);
        let (d2, r2) = log_map(b, a);
        let l1 = d1[0].hypot(d1[1]);
        let l2 = d2[0].hypot(d2[1]);
        assert!((l1 - l2).abs() < 1e-8 && l1 < 10_000.0 && d1[0] > 0.0);
        assert!((r1 + r2).abs() < 1e-12);
    }

    #[test]
    fn offset_then_log_map_round_trips() {
        for &(lat, lon) in &[(0.0, 0.0), (80.0, 30.0), (-80.0, -179.9), (45.0, 179.95)] {
            for &en in &[[1000.0, 0.0], [-3000.0, 2000.0], [50_000.0, -70_000.0]] {
                let (p, _) = offset([lat, lon], en);
                let (d, _) = log_map([lat, lon], p);
                assert!((d[0] - en[0]).abs() < 1e-6 && (d[1] - en[1]).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn direct_inverts_inverse_in_rows() {
        let (lat1, lon1) = ([50.0, -33.0, 0.0], [-1.0, 179.5, 10.0]);
        let (lat2, lon2) = ([50.2, -33.4, 0.0], [-0.7, -179.8, 10.0]);
        let inv = inverse_rows(&lat1, &lon1, &lat2, &lon2).unwrap();
        assert_eq!(inv[2][0], 0.0);
        let azi: Vec<f64> = inv.iter().map(|r| r[1]).collect();
        let s: Vec<f64> = inv.iter().map(|r| r[0]).collect();
        let dir = direct_rows(&lat1, &lon1, &azi, &s).unwrap();
        for k in 0..3 {
            assert!((dir[k][0] - lat2[k]).abs() < 1e-12, "{k}");
            assert!(wrap_lon(dir[k][1] - lon2[k]).abs() < 1e-12, "{k}");
            if k < 2 {
                assert!((dir[k][2] - inv[k][2]).abs() < 1e-9, "{k}");
            }
        }
        // on the equator, due east: a quarter of the equator is a quarter of 2 pi a
        let ([lat, lon], azi2) = direct([0.0, 0.0], 90.0, std::f64::consts::FRAC_PI_2 * WGS84_A);
        assert!(lat.abs() < 1e-12 && (lon - 90.0).abs() < 1e-9 && (azi2 - 90.0).abs() < 1e-12);
        let bad = inverse_rows(&[91.0], &[0.0], &[0.0], &[0.0]).unwrap_err();
        assert_eq!((bad.row(), bad.field()), (Some(0), Some("lat1")));
        let bad = direct_rows(&[0.0, 0.0], &[0.0, 0.0], &[0.0, 0.0], &[1.0, f64::NAN]);
        assert_eq!(bad.unwrap_err().field(), Some("s12"));
        assert!(direct_rows(&[0.0], &[0.0, 1.0], &[0.0], &[0.0]).is_err());
    }

    #[test]
    fn wrap() {
        assert_eq!(wrap_lon(180.0), -180.0);
        assert_eq!(wrap_lon(-190.0), 170.0);
        assert_eq!(wrap_lon(10.0), 10.0);
    }
}
