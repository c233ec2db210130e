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
from scenes import pair_scores, straight_track, track_arrays

import geofeas
from geofeas.association import ASSOCIATION_DEFAULTS

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from association_berth import berth  # noqa: E402


@pytest.mark.parametrize("speed", [0.0, 0.05, 1.0])
def test_a_still_track_is_bridged_as_the_reference_says(rng, speed):
    # one ship: AIS every 360 s (sigma 10 m), a radar track every 3 s (sigma 40 m)
    ship = dict(start=(0.0, 0.0), velocity=(speed, 0.0), duration=1500.0)
    frame = pd.concat(
        [
            straight_track(rng, "ais", "ais", dt=360.0, sigma=10.0, t0=30.0, **ship),
            straight_track(rng, "radar", "radar", dt=3.0, sigma=40.0, **ship),
        ]
    )
    ta, ra = track_arrays(frame, "ais")
    tb, rb = track_arrays(frame, "radar")
    assert not np.isin(ta, tb).any()  # no time shared: every instant is one report's
    q = ASSOCIATION_DEFAULTS["process_noise"]
    times, m = pair_distances(ta, ra, tb, rb, max_gap=300.0, q=q, max_still_gap=900.0)
    g, k = pair_scores(frame, "ais", "radar", combine="geometric")
    assert k == len(m)
    assert -2 * math.log(g) * k == pytest.approx(m.sum(), rel=1e-9)
    _, k_plain = pair_scores(frame, "ais", "radar", combine="geometric", max_still_gap=0.0)
    # the AIS reports alone are instants without the bridge
    assert k_plain == ta.size
    if speed < 0.1:
        # still (5 cm/s moves 18 m in 6 min, within the diffusion's sqrt(9.21 q 360) = 81 m):
        # every radar report inside the AIS track's span is an instant
        inside = ((tb > ta[0]) & (tb < ta[-1])).sum()
        assert k == inside + ta.size
    else:
        # 1 m/s moves 360 m between two reports: a manoeuvre the chord does not hold
        assert k == ta.size


def test_the_bridge_is_an_option_and_refuses_bad_values():
    # AIS at 0 and 400 s, 1 m apart; one radar report at 200 s, inside the gap
    frame = pd.DataFrame(
        {
            "track_id": ["ais", "ais", "radar"],
            "source": ["ais", "ais", "radar"],
            "time": [0.0, 400.0, 200.0],
            "x": [0.0, 1.0, 0.0],
            "y": 0.0,
            "rx": [20.0, 20.0, 80.0],
            "ry": [20.0, 20.0, 80.0],
            "phi": 0.0,
        }
    )
    assert pair_scores(frame, "ais", "radar")[1] == 1
    assert pair_scores(frame, "ais", "radar", max_still_gap=300.0)[1] == 0
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
