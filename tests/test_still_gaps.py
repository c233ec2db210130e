"""A still track's gaps longer than ``max_gap`` (a moored ship's AIS every 6 minutes): bridged
when the track stays still across them (``max_still_gap``), against the NumPy reference of the
alignment; a moving track's are not; and the berth of moored ships whose AIS reports are lone
instants, where without the bridge the triage swaps radar tracks between neighbours."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from reference_association import pair_distances

import geofeas
from geofeas import _core
from geofeas.association import ASSOCIATION_DEFAULTS, _resolve_options

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from association_berth import berth  # noqa: E402


def _track(track_id, source, t, x, y, sigma):
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


def _stats(frame, **options):
    rep = geofeas.read_reports(frame)
    ids = list(rep.track_ids)
    core, _ = _resolve_options(rep.sources, {"inflation": 1.0, **options}, {})
    st = _core.association_pair_stats(
        rep,
        np.array([ids.index("ais")], dtype=np.uint32),
        np.array([ids.index("radar")], dtype=np.uint32),
        options=core,
    )
    return int(st.instants[0]), float(st.score[0])


def _arrays(frame, track_id):
    sub = frame[frame.track_id == track_id].sort_values("time")
    return sub.time.to_numpy(), sub[["x", "y", "rx", "ry", "phi"]].to_numpy()


@pytest.mark.parametrize("speed", [0.0, 0.05, 1.0])
def test_a_still_track_is_bridged_as_the_reference_says(rng, speed):
    # AIS every 360 s (sigma 10 m), a radar track every 3 s (sigma 40 m) of the same ship
    t_ais = 31.0 + 360.0 * np.arange(5)  # no time shared with the radar scans
    t_rad = np.arange(0.0, 1500.0, 3.0)
    frame = pd.concat(
        [
            _track(
                "ais",
                "ais",
                t_ais,
                speed * t_ais + rng.normal(0, 10, t_ais.size),
                rng.normal(0, 10, t_ais.size),
                10.0,
            ),
            _track(
                "radar",
                "radar",
                t_rad,
                speed * t_rad + rng.normal(0, 40, t_rad.size),
                rng.normal(0, 40, t_rad.size),
                40.0,
            ),
        ]
    )
    ta, ra = _arrays(frame, "ais")
    tb, rb = _arrays(frame, "radar")
    q = ASSOCIATION_DEFAULTS["process_noise"]
    times, m = pair_distances(ta, ra, tb, rb, max_gap=300.0, q=q, max_still_gap=900.0)
    k, g = _stats(frame, combine="geometric")
    assert k == len(m)
    assert -2 * math.log(g) * k == pytest.approx(m.sum(), rel=1e-9)
    k_plain, _ = _stats(frame, combine="geometric", max_still_gap=0.0)
    # the AIS reports alone are instants without the bridge
    assert k_plain == t_ais.size
    if speed < 0.1:
        # still (5 cm/s moves 18 m in 6 min, within the diffusion's sqrt(9.21 q 360) = 81 m):
        # every radar report inside the AIS track's span is an instant
        inside = ((t_rad > t_ais[0]) & (t_rad < t_ais[-1])).sum()
        assert k == inside + t_ais.size
    else:
        # 1 m/s moves 360 m between two reports: a manoeuvre the chord does not hold
        assert k == t_ais.size


def test_the_bridge_is_an_option_and_refuses_bad_values():
    frame = _track("ais", "ais", [0.0, 400.0], [0.0, 1.0], [0.0, 0.0], 10.0)
    frame = pd.concat([frame, _track("radar", "radar", [200.0], [0.0], [0.0], 40.0)])
    assert _stats(frame)[0] == 1
    assert _stats(frame, max_still_gap=300.0)[0] == 0
    with pytest.raises(geofeas.GeofeasError, match="max_still_gap"):
        geofeas.associate(frame, max_still_gap=-1.0)
    with pytest.raises(geofeas.GeofeasError, match="max_still_gap"):
        geofeas.associate(frame, max_still_gap=float("nan"))


@pytest.mark.parametrize("seed", [5, 9])
def test_a_berth_of_lone_instants_does_not_swap_radar_tracks(seed):
    # ten ships 10 m apart, AIS every 6 minutes, a radar track (a scan every 3 s, 16 x 20 m
    # errors) and aircraft tracks of each: without the bridge, these pictures lose true AIS-radar
    # pairs to `non-match` and (seed 9) merge a radar track onto the neighbour's AIS track
    pairs = geofeas.associate(berth(np.random.default_rng(seed), 10, 10.0, 360.0)).pairs
    a = pairs.track_a.str.split("-")
    b = pairs.track_b.str.split("-")
    same = np.array([x[1] == z[1] for x, z in zip(a, b, strict=True)])
    kind = np.array([f"{x[0]}-{z[0]}" for x, z in zip(a, b, strict=True)])
    cls = pairs["class"].to_numpy()
    ais_radar = kind == "ais-radar"
    assert ais_radar.sum() > 10
    assert not (same & ais_radar & (cls == "non-match")).any()
    assert not (~same & (cls == "match")).any()
    # the true pairs are at least even odds: ten ships 10 m apart under a radar's 16 x 20 m
    # errors are told apart by their 6-minute reports over 20 minutes, not by one lone instant
    assert pairs.p_same[same & ais_radar].min() > 0.5
