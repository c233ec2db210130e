"""Planar scenes and pair measures shared by the association tests."""

from __future__ import annotations

import numpy as np
import pandas as pd

import geofeas
from geofeas import _core
from geofeas.association import ASSOCIATION_DEFAULTS, _resolve_options


def straight_track(rng, track_id, source, start, velocity, dt, sigma, duration=600.0, t0=0.0):
    """Reports of a ship on a straight line seen every ``dt`` s with noise ``sigma`` (m), its
    AOU the consistent 2-sigma circle."""
    t = t0 + rng.uniform(0, dt) + np.arange(0.0, duration, dt)
    t = t[t < t0 + duration]
    x = start[0] + velocity[0] * (t - t0) + rng.normal(0, sigma, t.size)
    y = start[1] + velocity[1] * (t - t0) + rng.normal(0, sigma, t.size)
    return pd.DataFrame(
        {
            "track_id": track_id,
            "source": source,
            "time": t,
            "x": x,
            "y": y,
            "rx": 2 * sigma,
            "ry": 2 * sigma,
            "phi": 0.0,
        }
    )


def track_arrays(frame, track_id):
    """``(times, rows x, y, rx, ry, phi)`` of one track of ``frame``, sorted by time."""
    sub = frame[frame.track_id == track_id].sort_values("time")
    return sub.time.to_numpy(), sub[["x", "y", "rx", "ry", "phi"]].to_numpy()


def pair_scores(frame, a, b, **kw):
    """The engine's ``score`` column and number of common instants of tracks ``a`` and ``b``
    (inflation 1; ``kw``: association and score options)."""
    rep = geofeas.read_reports(frame)
    ids = list(rep.track_ids)
    ia = np.array([ids.index(a)], dtype=np.uint32)
    ib = np.array([ids.index(b)], dtype=np.uint32)
    engine = {k: v for k, v in kw.items() if k in ASSOCIATION_DEFAULTS}
    score = {k: v for k, v in kw.items() if k not in ASSOCIATION_DEFAULTS}
    core, _ = _resolve_options(rep.sources, {"inflation": 1.0, **engine}, score)
    st = _core.association_pair_stats(rep, ia, ib, options=core)
    return float(st.score[0]), int(st.instants[0])
