"""Reading real AIS recordings into clean per-vessel trajectories.

Two schemas are recognised from the header: the Solent recording of dstl/Stone-Soup (``Time,
MMSI, Latitude_degrees, Longitude_degrees, COG_degrees, SOG_knots``) and the NOAA MarineCadastre
broadcast-point schema (``MMSI, BaseDateTime, LAT, LON, SOG, COG, Heading, ...``); other files are
read when their columns match :data:`FIELD_ALIASES` (e.g. MarineCadastre's newer snake-case names
or the Danish Maritime Authority's export). The defects that
real recordings have are handled and every removal or correction is reported (count and reason),
never silent:

- position "not available" (latitude 91 / longitude 181, ITU-R M.1371) or outside the globe:
  row removed;
- exact duplicate reports (same MMSI, time, position, SOG and COG; untrustworthy columns such as
  MarineCadastre's ``ETA`` are ignored): all but the first removed;
- several different positions for one vessel at one instant: all but the first removed;
- physically impossible jumps: per vessel, the trajectory is cut where the implied speed between
  consecutive reports exceeds ``max_speed`` (plus a GPS tolerance); the largest consistent part is
  kept and every other part that cannot be reached from it is removed (this finds a corrupt
  longitude anywhere in the file without knowing the row);
- COG: 360 means "not available" (set to NaN); negative values are a signed 12-bit wrap of the
  0.1-degree field (409.6 added; -49.6 then means 360, "not available"); SOG 102.3 means "not
  available" (NaN).

Malformed files (missing columns, unparseable numbers or times) raise :class:`GeofeasError`
naming the line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .. import geodesy
from .._core import GeofeasError

__all__ = ["AIS_SCHEMAS", "FIELD_ALIASES", "AisRecording", "read_ais"]

#: Column names of each recognised schema: mmsi, time, lat, lon, sog, cog.
AIS_SCHEMAS: dict[str, dict[str, str]] = {
    "solent": {
        "mmsi": "MMSI",
        "time": "Time",
        "lat": "Latitude_degrees",
        "lon": "Longitude_degrees",
        "sog": "SOG_knots",
        "cog": "COG_degrees",
    },
    "marinecadastre": {
        "mmsi": "MMSI",
        "time": "BaseDateTime",
        "lat": "LAT",
        "lon": "LON",
        "sog": "SOG",
        "cog": "COG",
    },
}

KNOT = 1852.0 / 3600.0  # m/s


@dataclass
class AisRecording:
    """A cleaned AIS recording.

    Attributes
    ----------
    tracks : pandas.DataFrame
        Columns ``mmsi`` (int64), ``time`` (float64, seconds since the Unix epoch, UTC), ``lat``,
        ``lon`` (degrees WGS84), ``sog`` (knots, NaN if not available), ``cog`` (degrees in
        ``[0, 360)``, NaN if not available); sorted by ``mmsi`` then ``time``, strictly increasing
        time per vessel.
    removed : pandas.DataFrame
        The rows removed: ``line`` (1-based line of the file, the header is line 1), ``mmsi`` and
        ``reason``.
    corrected : dict[str, int]
        Counts of values corrected or marked not available, by reason.
    schema : str
        ``"solent"`` or ``"marinecadastre"``.
    source : str
        Where the recording was read from.
    """

    tracks: pd.DataFrame
    removed: pd.DataFrame
    corrected: dict[str, int] = field(default_factory=dict)
    schema: str = ""
    source: str = ""

    @property
    def start(self) -> float:
        """First report time, seconds since the Unix epoch."""
        return float(self.tracks["time"].min())

    @property
    def end(self) -> float:
        """Last report time, seconds since the Unix epoch."""
        return float(self.tracks["time"].max())

    def summary(self) -> str:
        """One line per removal / correction reason, for the user."""
        t = self.tracks
        lines = [
            f"{self.source}: {self.schema} schema, {len(t)} reports of {t['mmsi'].nunique()} "
            f"vessels over {(self.end - self.start) / 60:.1f} min"
            if len(t)
            else f"{self.source}: {self.schema} schema, no usable reports"
        ]
        for reason, n in self.removed["reason"].value_counts(sort=False).items():
            lines.append(f"  removed {n} row(s): {reason}")
        for reason, n in self.corrected.items():
            if n:
                lines.append(f"  {reason}: {n} row(s)")
        return "\n".join(lines)


#: Accepted column names of each field (case-insensitive), beyond the two schemas above: the
#: MarineCadastre 2024+ snake-case names and the Danish Maritime Authority's export.
FIELD_ALIASES: dict[str, tuple[str, ...]] = {
    "mmsi": ("MMSI",),
    "time": ("Time", "BaseDateTime", "base_date_time", "# Timestamp", "Timestamp", "datetime"),
    "lat": ("Latitude_degrees", "LAT", "Latitude"),
    "lon": ("Longitude_degrees", "LON", "Longitude", "long"),
    "sog": ("SOG_knots", "SOG", "speed"),
    "cog": ("COG_degrees", "COG", "course"),
}
_REQUIRED = ("mmsi", "time", "lat", "lon")


def _detect_schema(columns: list[str], source: str) -> tuple[str, dict[str, str | None]]:
    for name, cols in AIS_SCHEMAS.items():
        if all(c in columns for c in cols.values()):
            return name, dict(cols)
    lower = {c.lower(): c for c in columns}
    found: dict[str, str | None] = {}
    for key, aliases in FIELD_ALIASES.items():
        found[key] = next((lower[a.lower()] for a in aliases if a.lower() in lower), None)
    missing = [k for k in _REQUIRED if found[k] is None]
    if missing:
        expected = "; ".join(f"{k}: {', '.join(v.values())}" for k, v in AIS_SCHEMAS.items())
        raise GeofeasError(
            f"{source}: line 1: not a recognised AIS schema (columns {', '.join(columns)}): "
            f"no column for {', '.join(missing)}; expected the columns of one of {expected}"
        )
    t = str(found["time"]).lower()
    name = "marinecadastre" if t in ("basedatetime", "base_date_time") else "generic"
    return (name if t != "# timestamp" else "dma"), found


def _numeric(frame: pd.DataFrame, column: str, source: str, *, integer: bool = False) -> np.ndarray:
    raw = frame[column]
    values = pd.to_numeric(raw, errors="coerce")
    bad = np.flatnonzero(values.isna().to_numpy() & raw.notna().to_numpy())
    if integer:
        bad = np.union1d(bad, np.flatnonzero(raw.isna().to_numpy()))
    if len(bad):
        k = int(bad[0])
        raise GeofeasError(
            f"{source}: line {k + 2}: column {column}: {raw.iloc[k]!r} is not a number"
            + (f" ({len(bad)} such rows)" if len(bad) > 1 else "")
        )
    out = values.to_numpy(dtype=np.float64)
    if integer:
        if not np.all(out == np.round(out)):
            k = int(np.flatnonzero(out != np.round(out))[0])
            raise GeofeasError(f"{source}: line {k + 2}: column {column}: {raw.iloc[k]!r}")
        return out.astype(np.int64)
    return out


def _times(frame: pd.DataFrame, column: str, source: str) -> np.ndarray:
    """Seconds since the Unix epoch: numbers are taken as such, text as ISO-8601 (or, if that
    fails, day-first ``dd/mm/yyyy HH:MM:SS`` as in the Danish Maritime Authority's files)."""
    raw = frame[column].astype(str).str.strip()
    numeric = pd.to_numeric(raw, errors="coerce")
    if numeric.notna().all():
        return numeric.to_numpy(np.float64)
    parsed = pd.to_datetime(raw, format="ISO8601", errors="coerce", utc=True)
    if parsed.isna().any():
        dayfirst = pd.to_datetime(raw, format="%d/%m/%Y %H:%M:%S", errors="coerce", utc=True)
        if dayfirst.notna().all():
            parsed = dayfirst
    bad = np.flatnonzero(parsed.isna().to_numpy())
    if len(bad):
        k = int(bad[0])
        raise GeofeasError(
            f"{source}: line {k + 2}: column {column}: {raw.iloc[k]!r} is not an ISO-8601 time"
        )
    epoch = pd.Timestamp("1970-01-01", tz="UTC")
    return ((parsed - epoch) / pd.Timedelta(seconds=1)).to_numpy(dtype=np.float64)


def _reachable(
    lat: np.ndarray, lon: np.ndarray, t: np.ndarray, i: int, j: int, vmax: float, slack: float
) -> bool:
    d = float(geodesy.inverse(lat[i], lon[i], lat[j], lon[j])[0])
    return d <= vmax * abs(t[j] - t[i]) + slack


def _consistent(
    lat: np.ndarray, lon: np.ndarray, t: np.ndarray, vmax: float, slack: float
) -> np.ndarray:
    """Mask of the reports of one vessel (sorted by time) kept by the impossible-jump test.

    The trajectory is cut into runs between jumps faster than ``vmax`` (with ``slack`` metres of
    tolerance); the run with the most reports is the anchor, and runs are joined outwards from it
    when their first (or last) report is reachable from the kept trajectory's end.
    """
    n = len(t)
    keep = np.ones(n, dtype=bool)
    if n < 2:
        return keep
    d, _, _ = geodesy.inverse(lat[:-1], lon[:-1], lat[1:], lon[1:])
    jump = d > vmax * np.diff(t) + slack
    if not jump.any():
        return keep
    cuts = np.flatnonzero(jump) + 1
    starts = np.concatenate([[0], cuts])
    ends = np.concatenate([cuts, [n]])
    anchor = int(np.argmax(ends - starts))
    keep[:] = False
    keep[starts[anchor] : ends[anchor]] = True
    last = ends[anchor] - 1
    for k in range(anchor + 1, len(starts)):
        if _reachable(lat, lon, t, last, starts[k], vmax, slack):
            keep[starts[k] : ends[k]] = True
            last = ends[k] - 1
    first = starts[anchor]
    for k in range(anchor - 1, -1, -1):
        if _reachable(lat, lon, t, ends[k] - 1, first, vmax, slack):
            keep[starts[k] : ends[k]] = True
            first = starts[k]
    return keep


def read_ais(
    source: str | Path,
    /,
    *,
    max_speed: float = 60.0,
    gps_tolerance: float = 200.0,
) -> AisRecording:
    """Read an AIS recording (Solent or MarineCadastre schema) and clean it.

    Parameters
    ----------
    source : str or Path
        CSV file.
    max_speed : float, optional
        Fastest plausible vessel speed in knots for the impossible-jump test (60 kn is above any
        high-speed craft in a harbour; search-and-rescue aircraft, MMSI ``111...``, are allowed
        ten times as much).
    gps_tolerance : float, optional
        Distance in metres always allowed between consecutive reports (GPS noise, time-stamp
        jitter of a few seconds).

    Returns
    -------
    AisRecording
        Clean trajectories, the removed rows with their reasons, and the correction counts.

    Raises
    ------
    GeofeasError
        Unknown schema, unparseable number or time (naming the line), or no usable report.
    """
    path = Path(source)
    name = str(source)
    if not max_speed > 0 or not gps_tolerance >= 0:
        raise GeofeasError(
            f"max_speed must be > 0 and gps_tolerance >= 0, got {max_speed}, {gps_tolerance}"
        )
    try:
        frame = pd.read_csv(path, dtype=str, keep_default_na=False, na_values=[""])
    except pd.errors.EmptyDataError:
        raise GeofeasError(f"{name}: empty file, expected a header line") from None
    except pd.errors.ParserError as exc:
        raise GeofeasError(f"{name}: malformed CSV: {exc}") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    schema, cols = _detect_schema(list(frame.columns), name)
    mmsi = _numeric(frame, str(cols["mmsi"]), name, integer=True)
    t = _times(frame, str(cols["time"]), name)
    lat = _numeric(frame, str(cols["lat"]), name)
    lon = _numeric(frame, str(cols["lon"]), name)
    nan = np.full(len(frame), np.nan)
    sog = nan.copy() if cols["sog"] is None else _numeric(frame, cols["sog"], name)
    cog = nan.copy() if cols["cog"] is None else _numeric(frame, cols["cog"], name)
    cog_given = np.isfinite(cog)
    line = np.arange(len(frame), dtype=np.int64) + 2

    reasons = np.full(len(frame), "", dtype=object)

    def drop(mask: np.ndarray, why: str) -> None:
        mask = mask & (reasons == "")
        reasons[mask] = why

    drop(~np.isfinite(lat) | ~np.isfinite(lon), "position missing")
    drop(
        (lat == 91) | (lon == 181),
        "position not available (latitude 91 / longitude 181)",
    )
    drop(np.abs(lat) > 90, "latitude outside [-90, 90]")
    drop(np.abs(lon) > 180, "longitude outside [-180, 180]")

    corrected: dict[str, int] = {}
    wrapped = np.isfinite(cog) & (cog < 0) & (cog >= -409.6)
    corrected["COG negative (signed 12-bit wrap), 409.6 added"] = int(wrapped.sum())
    cog = np.where(wrapped, cog + 409.6, cog)
    cog = np.round(cog, 1)
    na_cog = ~np.isfinite(cog) | (cog >= 360.0) | (cog < 0)
    corrected["COG not available (360 or out of range), set to NaN"] = int(
        (na_cog & cog_given).sum()
    )
    cog = np.where(na_cog, np.nan, cog)
    na_sog = np.isfinite(sog) & ((sog >= 102.25) | (sog < 0))
    corrected["SOG not available (102.3 or negative), set to NaN"] = int(na_sog.sum())
    sog = np.where(na_sog, np.nan, sog)

    # order by vessel and time (stable: equal keys keep file order, so "first" is the file's first)
    order = np.lexsort((line, t, mmsi))
    mmsi, t, lat, lon, sog, cog, line = (a[order] for a in (mmsi, t, lat, lon, sog, cog, line))
    reasons = reasons[order]

    ok = reasons == ""
    key = pd.DataFrame({"m": mmsi, "t": t, "la": lat, "lo": lon, "s": sog, "c": cog})
    dup = np.zeros(len(t), dtype=bool)
    dup[ok] = key[ok].duplicated(keep="first").to_numpy()
    drop(dup, "exact duplicate of an earlier report (same MMSI, time, position, SOG, COG)")
    ok = reasons == ""
    same_t = np.zeros(len(t), dtype=bool)
    same_t[ok] = key[ok].duplicated(subset=["m", "t"], keep="first").to_numpy()
    drop(same_t, "second, different position of one vessel at one instant")

    ok = reasons == ""
    idx = np.flatnonzero(ok)
    bounds = np.flatnonzero(np.diff(mmsi[idx])) + 1
    jump = np.zeros(len(t), dtype=bool)
    for part in np.split(idx, bounds):
        if len(part) < 2:
            continue
        vmax = max_speed * KNOT * (10.0 if 111_000_000 <= mmsi[part[0]] < 112_000_000 else 1.0)
        keep = _consistent(lat[part], lon[part], t[part], vmax, gps_tolerance)
        jump[part[~keep]] = True
    drop(
        jump,
        f"physically impossible jump (faster than {max_speed:g} kn + {gps_tolerance:g} m "
        "from the vessel's consistent trajectory)",
    )

    ok = reasons == ""
    if not ok.any():
        raise GeofeasError(f"{name}: no usable AIS report")
    tracks = pd.DataFrame(
        {
            "mmsi": mmsi[ok],
            "time": t[ok],
            "lat": lat[ok],
            "lon": lon[ok],
            "sog": sog[ok],
            "cog": cog[ok],
        }
    ).reset_index(drop=True)
    gone = ~ok
    removed = (
        pd.DataFrame({"line": line[gone], "mmsi": mmsi[gone], "reason": reasons[gone].astype(str)})
        .sort_values("line", kind="stable")
        .reset_index(drop=True)
    )
    return AisRecording(tracks, removed, corrected, schema, name)
