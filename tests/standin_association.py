"""A small stand-in for the association engine, used only to test the demo plumbing
(evaluation, outputs, CLI) independently of the engine: reports are binned into 30 s
instants, a track's position in an instant is its last report there, pairs of tracks of
different sources sharing instants are scored by the GLR (seed 000, eq. 71) and combined by
the mean. Not a reference for the engine's numbers."""

from types import SimpleNamespace

import numpy as np
import pandas as pd

import geofeas
from geofeas.scenario import metres_per_degree

BIN = 30.0


def read_reports(frame):
    return frame.copy()


def associate(reports, *, score="glr", combine="mean", lower=0.5, upper=0.8, **options):
    r = reports.copy()
    t = pd.to_datetime(r["time"], format="ISO8601")
    r["bin"] = ((t - t.min()) / pd.Timedelta(seconds=BIN)).astype(int)
    lat0, lon0 = r["lat"].median(), r["lon"].median()
    m_lat, m_lon = metres_per_degree(lat0)
    r["x"] = (r["lon"] - lon0) * m_lon
    r["y"] = (r["lat"] - lat0) * m_lat
    r["phi"] = np.radians(r["bearing"])
    last = r.groupby(["track_id", "bin"]).tail(1)
    j = last.merge(last, on="bin", suffixes=("_a", "_b"))
    j = j[(j["track_id_a"] < j["track_id_b"]) & (j["source_a"] != j["source_b"])]
    a = j[["x_a", "y_a", "rx_a", "ry_a", "phi_a"]].to_numpy()
    b = j[["x_b", "y_b", "rx_b", "ry_b", "phi_b"]].to_numpy()
    j = j.assign(g=geofeas.glr(a, b, **options) if len(j) else np.zeros(0))
    p = j.groupby(["track_id_a", "track_id_b"])["g"].agg(["mean", "size"]).reset_index()
    p.columns = ["track_a", "track_b", "score", "instants"]
    p["class"] = np.where(p["score"] >= upper, "match",
                          np.where(p["score"] >= lower, "borderline", "non-match"))
    ids = sorted(set(r["track_id"]))
    parent = {i: i for i in ids}

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for x, y in p.loc[p["class"] == "match", ["track_a", "track_b"]].itertuples(index=False):
        parent[find(x)] = find(y)
    roots = {i: find(i) for i in ids}
    number = {root: k for k, root in enumerate(sorted(set(roots.values())))}
    objects = pd.DataFrame({"track_id": ids, "object": [number[roots[i]] for i in ids]})
    return SimpleNamespace(pairs=p, objects=objects)
