//! Reports `(track, source, time, position, AOU)` stored sorted per track.
//!
//! A report is one 2-sigma area of uncertainty (seed 000, Section 1 and eqs. 56-59) of one track
//! at one time. [`Reports::new`] validates every input row (errors name the row, 0-based, in
//! the caller's order), sorts the reports by `(track, time)` and keeps, per report, the centre,
//! the covariance `R = U Lambda U^T` of eq. 58 in the report's local east/north frame, and a
//! 3-D point for the space-time index: `(x, y, 0)` in planar mode, the WGS84 Earth-centred
//! Earth-fixed (ECEF) position in geographic mode.
//!
//! Two coordinate modes:
//! - [`Coords::Planar`]: `(x, y, rx, ry, phi)`, metres east/north, `phi` in radians clockwise
//!   from north (the crate's [`Ellipse`] convention).
//! - [`Coords::Geographic`]: `(lat, lon, rx, ry, bearing)`, degrees WGS84, 2-sigma semi-axes in
//!   metres, `bearing` of the `rx` axis in degrees clockwise from true north. The covariance is
//!   held in the local east/north tangent plane of the report.

use super::geodesy;
use crate::ellipse::Ellipse;
use crate::error::{Error, Result};

/// How the five numbers of a report are to be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coords {
    /// `x, y` (metres), `rx, ry` (metres), `phi` (radians clockwise from north).
    Planar,
    /// `lat, lon` (degrees WGS84), `rx, ry` (metres), `bearing` (degrees clockwise from north).
    Geographic,
}

/// A track's centre and covariance at one time, in the local east/north frame of `pos`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// `(x, y)` metres (planar) or `(lat, lon)` degrees (geographic).
    pub pos: [f64; 2],
    /// Covariance `[xx, xy, yy]` (m^2), x east, y north.
    pub cov: [f64; 3],
}

/// Validated reports sorted by `(track, time)`.
#[derive(Debug, Clone)]
pub struct Reports {
    /// Coordinate mode.
    pub coords: Coords,
    /// Number of tracks (dense ids `0..n_tracks`).
    pub n_tracks: usize,
    /// `offsets[t]..offsets[t + 1]` are the reports of track `t`, sorted by time.
    pub offsets: Vec<usize>,
    /// Source of each track.
    pub source: Vec<u32>,
    /// Report times (seconds), sorted within each track.
    pub time: Vec<f64>,
    /// Report states.
    pub state: Vec<State>,
    /// Largest 2-sigma semi-axis of each report (metres).
    pub radius: Vec<f64>,
    /// `rx * ry` of each report (m^2): its AOU area over pi.
    pub area: Vec<f64>,
    /// The id of each track in the random streams of seeded scores (by default the track's
    /// index; a subset of a larger picture keeps the picture's ids, see
    /// [`Reports::with_stream_ids`]).
    pub stream: Vec<u32>,
    /// Index-space point of each report: `(x, y, 0)` planar, ECEF metres geographic.
    pub point: Vec<[f64; 3]>,
    /// The caller's row of each sorted report.
    pub row: Vec<usize>,
}

impl Reports {
    /// Validates and sorts `n` reports. `track` holds dense ids `0..n_tracks`; `aou` holds one
    /// `[a, b, rx, ry, angle]` row per report, read according to `coords`.
    ///
    /// Errors name the row: non-finite values, non-positive semi-axes, a latitude outside
    /// `[-90, 90]`, a track id out of range, a track with two sources, or two reports of one
    /// track at the same time.
    pub fn new(
        coords: Coords,
        n_tracks: usize,
        track: &[u32],
        source: &[u32],
        time: &[f64],
        aou: &[[f64; 5]],
    ) -> Result<Self> {
        let n = track.len();
        for (what, len) in [
            ("source", source.len()),
            ("time", time.len()),
            ("aou", aou.len()),
        ] {
            if len != n {
                return Err(Error::Shape {
                    what,
                    expected: format!("({n},) like track"),
                    got: format!("({len},)"),
                });
            }
        }
        let names: [&'static str; 5] = match coords {
            Coords::Planar => ["x", "y", "rx", "ry", "phi"],
            Coords::Geographic => ["lat", "lon", "rx", "ry", "bearing"],
        };
        for row in 0..n {
            if track[row] as usize >= n_tracks {
                return Err(Error::Invalid(format!(
                    "report row {row}: track index {} out of range 0..{n_tracks}",
                    track[row]
                )));
            }
            if !time[row].is_finite() {
                return Err(Error::NonFinite {
                    what: "report",
                    row,
                    field: "time",
                    value: time[row],
                });
            }
            for (field, &value) in names.iter().zip(&aou[row]) {
                if !value.is_finite() {
                    return Err(Error::NonFinite {
                        what: "report",
                        row,
                        field,
                        value,
                    });
                }
            }
            for k in [2, 3] {
                if aou[row][k] <= 0.0 {
                    return Err(Error::NonPositive {
                        what: "report",
                        row,
                        field: names[k],
                        value: aou[row][k],
                    });
                }
            }
            if coords == Coords::Geographic {
                for (k, field, limit) in [(0, "lat", 90.0), (1, "lon", 180.0)] {
                    if aou[row][k].abs() > limit {
                        return Err(Error::OutOfDomain {
                            what: "report",
                            row,
                            field,
                            value: aou[row][k],
                            reason: if k == 0 {
                                "latitude must be in [-90, 90]"
                            } else {
                                "longitude must be in [-180, 180]"
                            },
                        });
                    }
                }
            }
            // the semi-axes and the planar centre feed the scores: the same domain as theirs
            let (rx, ry) = (aou[row][2], aou[row][3]);
            let domain = crate::ellipse::Ellipse::new(
                if coords == Coords::Planar {
                    aou[row][0]
                } else {
                    0.0
                },
                if coords == Coords::Planar {
                    aou[row][1]
                } else {
                    0.0
                },
                rx,
                ry,
                0.0,
            );
            if let Err(Error::OutOfDomain {
                field,
                value,
                reason,
                ..
            }) = domain.validated(row)
            {
                return Err(Error::OutOfDomain {
                    what: "report",
                    row,
                    field: names[crate::ellipse::FIELDS
                        .iter()
                        .position(|f| *f == field)
                        .unwrap_or(2)],
                    value,
                    reason,
                });
            }
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| {
            track[i]
                .cmp(&track[j])
                .then(time[i].total_cmp(&time[j]))
                .then(i.cmp(&j))
        });
        let mut offsets = vec![0usize; n_tracks + 1];
        for &t in track {
            offsets[t as usize + 1] += 1;
        }
        for t in 0..n_tracks {
            offsets[t + 1] += offsets[t];
        }
        if let Some(t) = (0..n_tracks).find(|&t| offsets[t] == offsets[t + 1]) {
            return Err(Error::Invalid(format!("track index {t} has no reports")));
        }
        let mut src = vec![u32::MAX; n_tracks];
        let mut first_row = vec![usize::MAX; n_tracks];
        for (k, &i) in order.iter().enumerate() {
            let t = track[i] as usize;
            if src[t] == u32::MAX {
                src[t] = source[i];
                first_row[t] = i;
            } else if src[t] != source[i] {
                return Err(Error::Invalid(format!(
                    "report row {i}: track has source index {} but row {} of the same track has \
                     source index {}",
                    source[i], first_row[t], src[t]
                )));
            }
            if k > 0 {
                let p = order[k - 1];
                if track[p] == track[i] && time[p] == time[i] {
                    return Err(Error::Invalid(format!(
                        "report rows {p} and {i}: two reports of one track at the same time {}",
                        time[i]
                    )));
                }
            }
        }
        let mut state = Vec::with_capacity(n);
        let mut radius = Vec::with_capacity(n);
        let mut area = Vec::with_capacity(n);
        let mut point = Vec::with_capacity(n);
        let mut times = Vec::with_capacity(n);
        for &i in &order {
            let [a, b, rx, ry, angle] = aou[i];
            let phi = match coords {
                Coords::Planar => angle,
                Coords::Geographic => angle.to_radians(),
            };
            let g = Ellipse::new(0.0, 0.0, rx, ry, phi).to_gaussian();
            let pos = match coords {
                Coords::Planar => [a, b],
                Coords::Geographic => [a, geodesy::wrap_lon(b)],
            };
            state.push(State { pos, cov: g.cov });
            radius.push(rx.max(ry));
            area.push(rx * ry);
            point.push(match coords {
                Coords::Planar => [a, b, 0.0],
                Coords::Geographic => geodesy::ecef(pos[0], pos[1]),
            });
            times.push(time[i]);
        }
        Ok(Self {
            coords,
            n_tracks,
            offsets,
            source: src,
            time: times,
            state,
            radius,
            area,
            stream: (0..n_tracks as u32).collect(),
            point,
            row: order,
        })
    }

    /// The same reports with `ids` as the tracks' ids in the random streams of seeded scores
    /// (one per track): a tile of a larger picture scores its pairs with the picture's streams.
    pub fn with_stream_ids(mut self, ids: &[u32]) -> Result<Self> {
        if ids.len() != self.n_tracks {
            return Err(Error::Invalid(format!(
                "stream ids: expected one per track ({}), got {}",
                self.n_tracks,
                ids.len()
            )));
        }
        self.stream = ids.to_vec();
        Ok(self)
    }

    /// The smallest and largest `rx * ry` of the reports of track `t` (`(0, 0)` without reports).
    pub fn area_range(&self, t: usize) -> (f64, f64) {
        self.area[self.offsets[t]..self.offsets[t + 1]]
            .iter()
            .fold(None, |acc: Option<(f64, f64)>, &x| {
                Some(acc.map_or((x, x), |(lo, hi)| (lo.min(x), hi.max(x))))
            })
            .unwrap_or((0.0, 0.0))
    }

    /// Number of reports.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// Whether there are no reports.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// The range of report indices of track `t`.
    pub fn range(&self, t: usize) -> std::ops::Range<usize> {
        self.offsets[t]..self.offsets[t + 1]
    }

    /// Report times of track `t`.
    pub fn times(&self, t: usize) -> &[f64] {
        &self.time[self.range(t)]
    }

    /// First and last report time of track `t`.
    pub fn span(&self, t: usize) -> (f64, f64) {
        let ts = self.times(t);
        (ts[0], ts[ts.len() - 1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorted_per_track_and_rows_kept() {
        let track = [1, 0, 1, 0];
        let source = [0, 1, 0, 1];
        let time = [5.0, 3.0, 1.0, 2.0];
        let aou = [[0.0, 0.0, 1.0, 1.0, 0.0]; 4];
        let r = Reports::new(Coords::Planar, 2, &track, &source, &time, &aou).unwrap();
        assert_eq!(r.times(0), &[2.0, 3.0]);
        assert_eq!(r.times(1), &[1.0, 5.0]);
        assert_eq!(r.row, vec![3, 1, 2, 0]);
        assert_eq!(r.source, vec![1, 0]);
    }

    #[test]
    fn errors_name_the_row() {
        let aou = [[0.0, 0.0, 1.0, 1.0, 0.0]; 3];
        let e = Reports::new(
            Coords::Planar,
            1,
            &[0, 0, 0],
            &[0; 3],
            &[1.0, 2.0, 1.0],
            &aou,
        )
        .unwrap_err();
        assert!(e.to_string().contains("rows 0 and 2"), "{e}");
        let mut bad = aou;
        bad[1][3] = 0.0;
        let e = Reports::new(
            Coords::Planar,
            1,
            &[0, 0, 0],
            &[0; 3],
            &[1.0, 2.0, 3.0],
            &bad,
        )
        .unwrap_err();
        assert!(e.to_string().contains("row 1") && e.to_string().contains("ry"));
        let e = Reports::new(
            Coords::Planar,
            1,
            &[0, 0, 0],
            &[0, 1, 0],
            &[1.0, 2.0, 3.0],
            &aou,
        )
        .unwrap_err();
        assert!(e.to_string().contains("row 1"), "{e}");
        let mut geo = aou;
        geo[2][0] = 91.0;
        let e = Reports::new(
            Coords::Geographic,
            1,
            &[0, 0, 0],
            &[0; 3],
            &[1.0, 2.0, 3.0],
            &geo,
        )
        .unwrap_err();
        assert!(e.to_string().contains("row 2") && e.to_string().contains("lat"));
    }
}
