"""Adversarial inputs: every case gives the right value or a GeofeasError (a ValueError) that
names the argument, row and field; nothing panics, aborts, hangs or returns NaN; outputs are
written atomically and ids are kept as given."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys

import numpy as np
import pytest

import geofeas
from geofeas import GeofeasError
from geofeas.cli import main
from geofeas.tracking import (
    mht_simulate_run,
    mht_trilaterate,
    pf_peaks,
    pf_render,
    pf_simulate_run,
)

# ---------------------------------------------------------------------------------------------
# wrong answers


THIN_INTERNAL = (
    [
        -0.5051807090518174,
        -0.7816121396483737,
        1.8203731844787696,
        0.045556928976155354,
        0.9906815718245982,
    ],
    [
        1.213524591913347,
        -0.12074190277397812,
        0.3948377786793643,
        0.06252637189172866,
        -0.5514741753330439,
    ],
    # 50-digit reference (independently: tests/exact_reference.py)
    0.002293877603833476,
)


def test_thin_pair_near_internal_tangency():
    a, b, truth = THIN_INTERNAL
    assert abs(geofeas.overlap(a, b) - truth) < 1e-11
    assert abs(geofeas.overlap(b, a) - truth) < 1e-11


def test_polygon_one_ulp_apart_far_from_origin():
    a = [620227.6, 5622995.9, 20, 20, 0]
    b = [620227.6000000001, 5622995.9, 20, 20, 0]
    g = geofeas.overlap(a, b, method="polygon")
    assert abs(g - 1.0) < 1e-6
    assert abs(geofeas.overlap(a, b) - 1.0) < 1e-11


def test_polygon_identical_far_from_origin():
    e = [-7639.937097257161, -5702.316114342645, 1.5874326894015702, 4.127125803748774]
    e.append(5.399315697346241)
    assert geofeas.overlap(e, e, vertices=1024) == 1.0
    rng = np.random.default_rng(5)
    for _ in range(30):
        e = np.concatenate(
            [rng.uniform(-1e4, 1e4, 2), rng.uniform(0.5, 5, 2), rng.uniform(0, 2 * np.pi, 1)]
        )
        assert geofeas.overlap(e, e, vertices=1024) == 1.0
        assert geofeas.overlap(e, e) == 1.0


@pytest.mark.parametrize(
    "call",
    [
        lambda: geofeas.glr([0, 0, 2e77, 2e77, 0], [0, 0, 2e77, 2e77, 0]),
        lambda: geofeas.hellinger([0, 0, 2e77, 2e77, 0], [1e77, 0, 2e77, 2e77, 0]),
        lambda: geofeas.overlap([0, 0, 1e300, 1, 0], [0, 0, 1, 1e300, 0]),
        lambda: geofeas.intersection_area([0, 0, 1e12, 1, 0], [0, 0, 1, 1e12, 0]),
        lambda: geofeas.to_gaussian([0, 0, 1, 2.7e154, 0]),
    ],
)
def test_outside_the_domain_is_refused(call):
    with pytest.raises(GeofeasError) as info:
        call()
    assert info.value.argument in ("a", "b", "e")
    assert info.value.row == 0
    assert info.value.field in ("rx", "ry")


def test_scores_at_the_edges_of_the_domain_are_right():
    # scale invariance: the same configuration at 1e-49 .. 1e49 gives the same scores
    base_a = np.array([0.0, 0.0, 2.0, 1.0, 0.3])
    base_b = np.array([1.0, 0.5, 1.5, 1.2, 1.1])
    ref = {f: getattr(geofeas, f)(base_a, base_b) for f in ("glr", "hellinger", "overlap")}
    for scale in (1e-49, 1e-20, 1e20, 1e49):
        a, b = base_a.copy(), base_b.copy()
        a[:4] *= scale
        b[:4] *= scale
        for f, v in ref.items():
            assert getattr(geofeas, f)(a, b) == pytest.approx(v, rel=1e-12, abs=1e-15), (f, scale)
    # aspect 1e8 at the limit: two crossed needles, 4 ab atan(b / a) / (pi ab)
    a = [0, 0, 1e4, 1e-4, 0]
    b = [0, 0, 1e4, 1e-4, math.pi / 2]
    assert geofeas.overlap(a, b) == pytest.approx(4 / math.pi * math.atan(1e-8), rel=1e-9)
    with pytest.raises(GeofeasError, match="aspect"):
        geofeas.overlap([0, 0, 1e5, 1e-4, 0], b)


def test_combine_instants_domain():
    with pytest.raises(GeofeasError) as info:
        geofeas.combine_instants([2.0, 0.5])
    assert (info.value.argument, info.value.row) == ("g", 0)
    with pytest.raises(GeofeasError, match="no instants"):
        geofeas.combine_instants([])
    with pytest.raises(GeofeasError):
        geofeas.combine_instants([0.5, np.nan])
    with pytest.raises(GeofeasError) as info:
        geofeas.combine_instants([0.5, 0.5], None, [1.0, 1.0])
    assert info.value.argument == "time"
    assert 0.0 <= geofeas.combine_instants([0.5, 0.9]) <= 1.0


@pytest.mark.parametrize(
    "cov",
    [
        [[-1.0, 0.0], [0.0, -1.0]],  # negative definite
        [[1.0, 2.0], [2.0, 1.0]],  # indefinite
        [[1.0, 0.5], [0.0, 1.0]],  # asymmetric
        [[0.0, 0.0], [0.0, 1.0]],  # singular
    ],
)
def test_trilaterate_refuses_bad_covariances(cov):
    good = np.diag([0.05**2, 0.02**2])
    args = ([0.0, 0.0], [10.0, 0.1], good, [5.0, 0.0], [10.0, 0.1], good)
    mht_trilaterate(*args)
    for k in (2, 5):
        bad = list(args)
        bad[k] = cov
        with pytest.raises(GeofeasError) as info:
            mht_trilaterate(*bad)
        assert info.value.argument == ("cov_a" if k == 2 else "cov_b")


# ---------------------------------------------------------------------------------------------
# crashes and hangs


E = [0.0, 0.0, 2.0, 1.0, 0.3]


@pytest.mark.parametrize(
    "call, argument",
    [
        (lambda: geofeas.overlap(E, E, vertices=2**62), "vertices"),
        (lambda: geofeas.overlap(E, E, vertices=10**9), "vertices"),
        (lambda: geofeas.cdist([E], [E], score="overlap", vertices=10**9), "vertices"),
        (lambda: geofeas.monte_carlo(E, E, samples=10**10, seed=1), "samples"),
        (lambda: geofeas.monte_carlo(E, E, samples=2**64, seed=1), "samples"),
        (lambda: geofeas.monte_carlo(E, E, samples=2**32 + 1, sampler="sobol"), "samples"),
        (lambda: pf_peaks(np.zeros((8, 8)), smoothing=1e300), "smoothing"),
        (lambda: pf_peaks(np.zeros((8, 8)), count=10**9), "peaks"),
        (lambda: pf_render(np.zeros((1, 2)), width=2**40, height=2**40), None),
        (lambda: pf_simulate_run(peaks=10**7), "peaks"),
        (lambda: pf_simulate_run(smoothing=1e6), "smoothing"),
        (lambda: mht_simulate_run(false_alarms=2**62), "false_alarms"),
        (lambda: mht_simulate_run(false_alarms=10**5), "false_alarms"),
    ],
)
def test_no_panic_no_abort(call, argument):
    with pytest.raises(GeofeasError) as info:
        call()
    if argument is not None:
        assert info.value.argument == argument


_ONE_LONG_PAIR = """
import signal, sys
# a runner may start us with SIGINT ignored (inherited); Python's handler must be in place
signal.signal(signal.SIGINT, signal.default_int_handler)
import geofeas
a, b = [0.0, 0.0, 2.0, 1.0, 0.3], [0.5, 0.0, 2.0, 1.0, 0.0]
print("ready", flush=True)
try:
    # one pair of 2**32 samples: minutes of work on one pool thread unless cancelled
    geofeas.monte_carlo(a, b, samples=2**32, seed=1, sampler=sys.argv[1])
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(0)
print("finished", flush=True)
sys.exit(3)
"""


@pytest.mark.parametrize("sampler", geofeas.scores.SAMPLERS)
def test_ctrl_c_stops_one_long_monte_carlo_pair(sampler):
    child = subprocess.Popen(
        [sys.executable, "-c", _ONE_LONG_PAIR, sampler],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline().strip() == "ready"
        # let the call start (the child prints "ready" just before it)
        try:
            child.wait(timeout=1.0)
        except subprocess.TimeoutExpired:
            pass
        child.send_signal(signal.SIGINT)
        # a pair that ignored the interrupt would run for minutes: the bound only keeps a
        # failing run from hanging the suite
        out, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    assert out.strip() == "interrupted", (out, err)
    assert child.returncode == 0


def test_cdist_guard_cannot_be_raised_past_memory():
    a = np.tile(E, (10**6, 1))
    with pytest.raises(GeofeasError, match="exceeds"):
        geofeas.cdist(a, a, max_bytes=2**100)


def test_memory_limit_respects_rlimit():
    resource = pytest.importorskip("resource")
    from geofeas.scores import _memory_limit

    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = 1 << 40
    if hard != resource.RLIM_INFINITY and hard < limit:
        pytest.skip("hard address-space limit below the test value")
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    try:
        assert _memory_limit() <= limit // 2
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


# ---------------------------------------------------------------------------------------------
# silently coerced inputs


@pytest.mark.parametrize(
    "value, words",
    [
        (np.ma.masked_array([E], mask=[[0, 1, 0, 0, 0]]), "masked"),
        (np.array([E], dtype=complex), "complex"),
        (np.ones((1, 5), dtype=bool), "bool"),
        (np.array([["0", "0", "1", "1", "0"]]), "dtype"),
        (np.array([["2024-01-01"] * 5], dtype="datetime64[D]"), "dtype"),
        (np.array([[0, 0, 1, 1, "x"]], dtype=object), "not a real number"),
    ],
)
def test_refused_array_kinds(value, words):
    with pytest.raises(GeofeasError, match=words) as info:
        geofeas.glr(value, E)
    assert info.value.argument == "a"


def test_misaligned_buffer_is_copied():
    raw = np.zeros(5 * 8 + 1, dtype=np.uint8)
    arr = np.frombuffer(raw.data, dtype=np.float64, count=5, offset=1).reshape(1, 5)
    assert not arr.flags.aligned
    # an unwritable, misaligned view of [0, 0, 0, 0, 0]: filled through a copy
    buf = bytearray(41)
    view = np.frombuffer(buf, dtype=np.float64, count=5, offset=1)
    view_w = np.ndarray((5,), dtype=np.float64, buffer=buf, offset=1)
    view_w[:] = E
    assert not view.flags.aligned
    assert geofeas.glr(view, E) == 1.0


def test_errors_name_argument_row_and_field():
    b = np.array([E, E, [0, 0, -1.0, 1, 0]])
    with pytest.raises(GeofeasError) as info:
        geofeas.overlap(E, b)
    err = info.value
    assert (err.argument, err.row, err.field) == ("b", 2, "rx")
    assert "argument 'b'" in str(err) and "row 2" in str(err)


# ---------------------------------------------------------------------------------------------
# data lost or mangled


REPORTS = """track_id,source,time,x,y,rx,ry,phi
007,ais,0,0,0,50,50,0
007,ais,10,10,0,50,50,0
7,radar,0,5,0,80,60,0
7,radar,10,15,0,80,60,0
"""


def test_ids_are_kept_as_given(tmp_path):
    path = tmp_path / "reports.csv"
    path.write_text(REPORTS)
    reports = geofeas.read_reports(path)
    assert reports.n_tracks == 2
    assert sorted(reports.track_ids) == ["007", "7"]
    out = tmp_path / "pairs.csv"
    assert main(["associate", str(path), "--out", str(out), "--quiet"]) == 0
    text = out.read_text()
    assert "007" in text


def test_reader_refusals(tmp_path):
    dup = tmp_path / "dup.csv"
    dup.write_text("track_id,source,time,x,y,rx,ry,phi,x\n1,a,0,0,0,1,1,0,5\n")
    with pytest.raises(GeofeasError, match="more than once") as info:
        geofeas.read_reports(dup)
    assert info.value.field == "x"
    header = tmp_path / "header.csv"
    header.write_text("track_id,source,time,x,y,rx,ry,phi\n")
    assert len(geofeas.read_reports(header)) == 0  # no rows: an empty picture, no IndexError
    lon = tmp_path / "lon.csv"
    lon.write_text("track_id,source,time,lat,lon,rx,ry,bearing\nt,a,0,50,200,10,10,0\n")
    with pytest.raises(GeofeasError, match="lon") as info:
        geofeas.read_reports(lon)
    assert (info.value.argument, info.value.row, info.value.field) == ("reports", 0, "lon")


def test_cli_input_errors_exit_2_in_one_line(tmp_path, capsys):
    header = tmp_path / "header.csv"
    header.write_text("track_id,source,time,x,y,rx,ry,phi\n")
    binary = tmp_path / "binary.csv"
    binary.write_bytes(b"track_id,source\xff\xfe,time\n\x00\x81\n")
    for path in (binary, tmp_path / "absent.csv", tmp_path / "o.txt"):
        code = main(["associate", str(path), "--out", str(tmp_path / "o.csv")])
        err = capsys.readouterr().err
        assert code == 2, err
        assert err.count("\n") == 1 and "Traceback" not in err


def test_associate_outputs_are_one_transaction(tmp_path):
    path = tmp_path / "reports.csv"
    path.write_text(REPORTS)
    out, objects = tmp_path / "pairs.csv", tmp_path / "objects.csv"
    out.write_text("previous pairs\n")
    objects.write_text("previous objects\n")
    # the objects file cannot be written (its folder does not exist): nothing is replaced
    bad = tmp_path / "missing" / "objects.csv"
    code = main(["associate", str(path), "--out", str(out), "--objects", str(bad), "--quiet"])
    assert code == 2
    assert out.read_text() == "previous pairs\n"
    assert sorted(os.listdir(tmp_path)) == ["objects.csv", "pairs.csv", "reports.csv"]
    assert main(["associate", str(path), "--out", str(out), "--objects", str(objects), "-q"]) == 0
    assert out.read_text().startswith("track_a")
    assert objects.read_text().startswith("track_id")


def test_options_that_do_not_apply_are_refused(tmp_path, capsys):
    path = tmp_path / "reports.csv"
    path.write_text(REPORTS)
    with pytest.raises(GeofeasError, match="do not apply") as info:
        geofeas.associate(geofeas.read_reports(path), score="overlap", threshold=True)
    assert info.value.argument == "threshold"
    out = str(tmp_path / "o.csv")
    assert main(["associate", str(path), "--out", out, "--score", "overlap", "--threshold"]) == 2
    assert "do not apply" in capsys.readouterr().err
    assert main(["associate", str(path), "--out", out, "--score", "glr", "--vertices", "64"]) == 2
