"""The review station's state: the picture, the decision log and the current association,
re-computed in a background thread after every decision (and whenever another process appends
to the log), so the queue and the probabilities shown are those of the decisions made so far.

The association is the engine's (:func:`geofeas.associate` with the log's decisions as hard
constraints). The pairs are scored once; each re-association recomputes only the posterior under
the decisions (:meth:`geofeas.Association.with_decisions`), off the request path, and the pages
show which log position they reflect.
"""

from __future__ import annotations

import math
import os
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .. import _core
from .._core import GeofeasError
from ..association import Association, Reports, _alignment, associate, read_reports
from ..geodesy import delta_lon, median_lon, metres_per_degree
from .coast import Coastline, coastline
from .log import DecisionLog, spans_of

__all__ = ["PairDetail", "Snapshot", "Station"]


@dataclass
class Snapshot:
    """One association of the picture under the decisions up to log position ``position``."""

    result: Association
    position: int
    version: int
    queue: pd.DataFrame
    error: str | None = None


@dataclass
class PairDetail:
    """What the pair view draws: the common instants of the two tracks in a local metric frame."""

    row: dict[str, Any]
    time: np.ndarray
    #: per instant ``(x, y, semi-major, semi-minor, angle of the major axis from east, deg ccw)``
    ell_a: np.ndarray
    ell_b: np.ndarray
    #: per instant, the distance in standard errors: ``sqrt(d^T S^-1 d / inflation)``
    sigma: np.ndarray
    inflation: float
    #: ``{track_id: (n, 5) ellipses}`` of the rival tracks inside the common time window
    rivals: dict[str, np.ndarray]
    #: ``(lat0, lon0)`` of the frame origin (``None`` for planar pictures)
    origin: tuple[float, float] | None
    #: the picture's coastline, read once when the station starts
    coast: Coastline


def ellipses(cov: np.ndarray) -> np.ndarray:
    """2-sigma ellipses ``(semi-major, semi-minor, angle from east in degrees ccw)`` of
    covariances ``[xx, xy, yy]`` (m^2, x east, y north), vectorised."""
    xx, xy, yy = cov[:, 0], cov[:, 1], cov[:, 2]
    half = 0.5 * (xx + yy)
    root = np.sqrt(np.maximum((0.5 * (xx - yy)) ** 2 + xy**2, 0.0))
    major = 2.0 * np.sqrt(np.maximum(half + root, 0.0))
    minor = 2.0 * np.sqrt(np.maximum(half - root, 0.0))
    angle = np.degrees(0.5 * np.arctan2(2.0 * xy, xx - yy))
    return np.c_[major, minor, angle]


def _aou_cov(aou: np.ndarray, geographic: bool) -> np.ndarray:
    """Covariances ``[xx, xy, yy]`` of report AOUs (2-sigma semi-axes ``rx, ry`` and the
    orientation of ``rx``: radians clockwise from north (planar), degrees (geographic))."""
    rx, ry = aou[:, 2] / 2.0, aou[:, 3] / 2.0
    th = np.radians(aou[:, 4]) if geographic else aou[:, 4]
    # rx along the unit vector (sin th, cos th) (east, north); ry perpendicular
    ux, uy = np.sin(th), np.cos(th)
    vx, vy = uy, -ux
    xx = rx**2 * ux**2 + ry**2 * vx**2
    xy = rx**2 * ux * uy + ry**2 * vx * vy
    yy = rx**2 * uy**2 + ry**2 * vy**2
    return np.c_[xx, xy, yy]


class Station:
    """The picture, its decision log and the current association.

    Parameters
    ----------
    picture : path or Reports
        The reports file (anything :func:`geofeas.read_reports` reads).
    db : path
        The SQLite decision log (created when missing).
    operator : str
        The default operator name shown on the pages.
    options : dict, optional
        Keyword options of :func:`geofeas.associate`.
    background : bool
        Re-associate in a background thread (the web application); ``False`` recomputes on
        :meth:`refresh` only.
    poll : float
        Seconds between checks of the log for rows appended by other processes.
    """

    def __init__(
        self,
        picture: Any,
        db: str | os.PathLike[str],
        *,
        operator: str = "operator",
        options: dict[str, Any] | None = None,
        background: bool = True,
        poll: float = 1.0,
    ) -> None:
        self.picture = Path(picture) if isinstance(picture, (str, os.PathLike)) else None
        saved: dict[str, Any] = {}
        if self.picture is not None and self.picture.is_dir():
            # a saved association result (Association.save): its reports and options
            import json

            for name in ("reports.parquet", "options.json"):
                if not (self.picture / name).is_file():
                    raise GeofeasError(
                        f"PICTURE: {self.picture} is a folder but not a saved association "
                        f"({name} is missing)"
                    )
            saved = json.loads((self.picture / "options.json").read_text(encoding="utf-8"))
            picture = self.picture / "reports.parquet"
        self.reports: Reports = read_reports(picture)
        self.operator = operator
        self.options = {**saved, **dict(options or {})}
        self.spans = spans_of(self.reports)
        self.log = DecisionLog(db, spans=self.spans)
        self.index = {str(t): k for k, t in enumerate(self.reports.track_ids)}
        self._ids = np.array([str(t) for t in self.reports.track_ids], dtype=object)
        n = self.reports.n_tracks
        src = np.empty(n, dtype=np.intp)
        src[self.reports.track] = self.reports.source
        self.track_source = np.array([str(self.reports.sources[s]) for s in src], dtype=object)
        start = np.full(n, np.inf)
        end = np.full(n, -np.inf)
        np.minimum.at(start, self.reports.track, self.reports.time)
        np.maximum.at(end, self.reports.track, self.reports.time)
        self.track_start, self.track_end = start, end
        self._pos = self._track_positions()
        self.coast = self._coastline()
        self._lock = threading.Lock()
        self._wake = threading.Event()
        self._stop = threading.Event()
        self._version = 0
        self.computing = False
        self.snapshot = self._compute()
        self._poll = poll
        self._thread: threading.Thread | None = None
        if background:
            self._thread = threading.Thread(target=self._run, name="geofeas-review", daemon=True)
            self._thread.start()

    # ------------------------------------------------------------------ association

    def _track_positions(self) -> np.ndarray:
        """Median ``(lat, lon)`` (or ``(x, y)``) of each track's reports, for the area filter."""
        n = self.reports.n_tracks
        out = np.zeros((n, 2))
        order = np.argsort(self.reports.track, kind="stable")
        tr = self.reports.track[order]
        bounds = np.searchsorted(tr, np.arange(n + 1))
        aou = self.reports.aou[order]
        for k in range(n):
            out[k] = np.median(aou[bounds[k] : bounds[k + 1], :2], axis=0)
        return out

    def _coastline(self) -> Coastline:
        """The GSHHG shoreline of the picture's area (read once, at start: the web requests
        never open a file), or an empty one for planar pictures."""
        if self.reports.coords != "geographic" or len(self.reports) == 0:
            return Coastline([], None)
        lat, lon = self.reports.aou[:, 0], self.reports.aou[:, 1]
        pad = 0.05
        # longitudes about their median, so that a picture across 180 degrees is one box
        lon0 = median_lon(lon)
        d = delta_lon(lon, lon0)
        return coastline(
            float(lat.min()) - pad,
            lon0 + float(d.min()) - pad,
            float(lat.max()) + pad,
            lon0 + float(d.max()) + pad,
        )

    def _compute(self) -> Snapshot:
        position = self.log.position()
        table = self.log.decisions_table()
        decisions = pd.DataFrame(table) if table else None
        self._version += 1
        try:
            # the pairs are scored once; after that only the posterior is recomputed under the
            # decisions (Association.with_decisions), and only for the components the log's
            # decisions change against the latest result: the other components are taken
            # from it as they are, which is what makes re-association cheap
            base = getattr(self, "_base", None)
            if base is None:
                base = self._base = associate(self.reports, **self.options)
            last = getattr(self, "snapshot", None)
            latest = base if last is None else last.result
            result = base if decisions is None else latest.with_decisions(decisions)
        except GeofeasError as exc:
            if self._version > 1 and hasattr(self, "snapshot"):
                old = self.snapshot
                return Snapshot(old.result, old.position, self._version, old.queue, str(exc))
            raise
        return Snapshot(result, position, self._version, self._queue(result))

    def _queue(self, result: Association) -> pd.DataFrame:
        q = result.review_queue.copy()
        pairs = result.pairs
        ia = np.array([self.index[str(t)] for t in q["track_a"]], dtype=np.intp)
        ib = np.array([self.index[str(t)] for t in q["track_b"]], dtype=np.intp)
        q["track_a"] = self._ids[ia]
        q["track_b"] = self._ids[ib]
        q["source_a"] = self.track_source[ia]
        q["source_b"] = self.track_source[ib]
        q["duration_a"] = self.track_end[ia] - self.track_start[ia]
        q["duration_b"] = self.track_end[ib] - self.track_start[ib]
        # rivals: the other pairs, not ruled out, that either track is in
        live = pairs[pairs["class"] != "non-match"]
        la = np.array([self.index[str(t)] for t in live["track_a"]], dtype=np.intp)
        lb = np.array([self.index[str(t)] for t in live["track_b"]], dtype=np.intp)
        degree = np.bincount(np.r_[la, lb], minlength=self.reports.n_tracks)
        q["rivals"] = degree[ia] + degree[ib] - 2
        q["pos0"] = (self._pos[ia, 0] + self._pos[ib, 0]) / 2
        q["pos1"] = (self._pos[ia, 1] + self._pos[ib, 1]) / 2
        return q

    def _run(self) -> None:
        while not self._stop.is_set():
            woken = self._wake.wait(self._poll)
            if self._stop.is_set():
                break
            self._wake.clear()
            try:
                changed = self.log.position() != self.snapshot.position
            except Exception:  # pragma: no cover - a transient lock; try again
                continue
            if woken or changed:
                self.computing = True
                try:
                    snap = self._compute()
                finally:
                    self.computing = False
                with self._lock:
                    self.snapshot = snap

    def notify(self) -> None:
        """Ask for a re-association (after a decision)."""
        self._wake.set()

    def refresh(self) -> Snapshot:
        """Re-associate now, in the calling thread."""
        snap = self._compute()
        with self._lock:
            self.snapshot = snap
        return snap

    def close(self) -> None:
        """Stop the background thread."""
        self._stop.set()
        self._wake.set()
        if self._thread is not None:
            self._thread.join(timeout=60)

    # ------------------------------------------------------------------ progress

    def progress(self, snap: Snapshot | None = None) -> dict[str, Any]:
        """Decided pairs, borderline pairs remaining, and the expected F1 gain of deciding the
        rest: under the posterior, the expected true / false positives and misses of the
        automatic classes now, against the same when every remaining borderline pair is
        answered truthfully."""
        s = snap or self.snapshot
        p = s.result.pairs
        prob = p["p_same"].to_numpy(dtype=np.float64)
        cls = p["class"].to_numpy()
        match = cls == "match"
        border = cls == "borderline"
        tp = float(prob[match].sum())
        fp = float((1.0 - prob[match]).sum())
        fn = float(prob[~match].sum())
        gain_tp = float(prob[border].sum())

        def f1(tp: float, fp: float, fn: float) -> float:
            return 2 * tp / (2 * tp + fp + fn) if tp > 0 else 0.0

        now = f1(tp, fp, fn)
        after = f1(tp + gain_tp, fp, fn - gain_tp)
        decided = len(self.log.decisions())
        return {
            "decided": decided,
            "remaining": int(border.sum()),
            "f1_now": now,
            "f1_gain": after - now,
            "position": s.position,
            "version": s.version,
            "log_position": self.log.position(),
            "computing": self.computing,
            "error": s.error,
        }

    # ------------------------------------------------------------------ pairs

    def track_index(self, track_id: str, what: str) -> int:
        if not isinstance(track_id, str) or track_id not in self.index:
            raise GeofeasError(f"{what}: unknown track id {track_id!r} (not in the picture)")
        return self.index[track_id]

    def pair_row(self, a: str, b: str, snap: Snapshot | None = None) -> dict[str, Any]:
        """The association's row of the candidate pair ``(a, b)`` (either order)."""
        s = snap or self.snapshot
        ia, ib = self.track_index(a, "track_a"), self.track_index(b, "track_b")
        if ia == ib:
            raise GeofeasError("track_b: a track cannot be paired with itself")
        p = s.result.pairs
        ta = p["track_a"].astype(str).to_numpy()
        tb = p["track_b"].astype(str).to_numpy()
        hit = np.flatnonzero(((ta == a) & (tb == b)) | ((ta == b) & (tb == a)))
        if hit.size == 0:
            raise GeofeasError(f"pair ({a}, {b}) is not a candidate pair of the picture")
        row = p.iloc[int(hit[0])].to_dict()
        row["track_a"], row["track_b"] = str(row["track_a"]), str(row["track_b"])
        row["source_a"] = self.track_source[self.index[row["track_a"]]]
        row["source_b"] = self.track_source[self.index[row["track_b"]]]
        rank = row.get("review_rank")
        row["review_rank"] = None if rank is None or pd.isna(rank) else int(rank)
        comp = row.get("component")
        row["component"] = None if comp is None or pd.isna(comp) else int(comp)
        return row

    def rivals(self, a: str, b: str, snap: Snapshot | None = None) -> list[str]:
        """Tracks with a live (not ``non-match``) candidate pair with ``a`` or ``b``."""
        s = snap or self.snapshot
        p = s.result.pairs
        live = p[p["class"] != "non-match"]
        ta = live["track_a"].astype(str).to_numpy()
        tb = live["track_b"].astype(str).to_numpy()
        out: set[str] = set()
        for x in (a, b):
            out.update(tb[ta == x].tolist())
            out.update(ta[tb == x].tolist())
        out.discard(a)
        out.discard(b)
        return sorted(out)

    def detail(self, a: str, b: str, snap: Snapshot | None = None) -> PairDetail:
        """The pair view's data: both tracks' aligned AOUs at every common instant, their
        distance in standard errors, and the rival tracks' AOUs over the same time window."""
        s = snap or self.snapshot
        row = self.pair_row(a, b, s)
        a, b = row["track_a"], row["track_b"]
        ia, ib = self.index[a], self.index[b]
        o = s.result.options
        rep = self.reports
        geographic = rep.coords == "geographic"
        raw = _core.association_pair_instants(
            rep,
            ia,
            ib,
            alignment=_alignment(o),
        )
        t = np.asarray(raw.time)
        sa, sb = np.asarray(raw.state_a), np.asarray(raw.state_b)
        infl = self._inflation(s.result, row["source_a"], row["source_b"])
        sigma = np.sqrt(np.asarray(raw.m) / infl)
        pos = np.r_[sa[:, :2], sb[:, :2]]
        if geographic and len(pos):
            lat0, lon0 = float(np.median(pos[:, 0])), median_lon(pos[:, 1])
            origin: tuple[float, float] | None = (lat0, lon0)
        else:
            lat0 = lon0 = 0.0
            origin = None

        def local(p: np.ndarray) -> np.ndarray:
            if origin is None:
                return p[:, :2].copy()
            m_lat, m_lon = metres_per_degree(lat0)
            return np.c_[delta_lon(p[:, 1], lon0) * m_lon, (p[:, 0] - lat0) * m_lat]

        ell_a = np.c_[local(sa), ellipses(sa[:, 2:5])]
        ell_b = np.c_[local(sb), ellipses(sb[:, 2:5])]
        rivals: dict[str, np.ndarray] = {}
        if len(t):
            t0, t1 = float(t.min()), float(t.max())
            for r in self.rivals(a, b, s):
                k = self.index[r]
                sel = (rep.track == k) & (rep.time >= t0) & (rep.time <= t1)
                if not sel.any():
                    continue
                aou = rep.aou[sel]
                rivals[r] = np.c_[local(aou), ellipses(_aou_cov(aou, geographic))]
        return PairDetail(row, t, ell_a, ell_b, sigma, infl, rivals, origin, self.coast)

    @staticmethod
    def _inflation(result: Association, sa: str, sb: str) -> float:
        for key in ((sa, sb), (sb, sa)):
            for k, v in result.inflation.items():
                if (str(k[0]), str(k[1])) == key and math.isfinite(v) and v > 0:
                    return float(v)
        infl = result.options.get("inflation", "auto")
        return float(infl) if not isinstance(infl, str) else 1.0
