"""The trackers' option sets are declared once, in the Rust core; the Python signatures, the stubs,
the command-line flags and the docs tables must agree with that declaration."""

from __future__ import annotations

import argparse
import ast
import inspect
import typing
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import geofeas
from geofeas import _core
from geofeas._core import GeofeasError
from geofeas.cli import mht as _cli_mht
from geofeas.cli import pf as _cli_pf
from geofeas.tracking import _mht, _pf

ROOT = Path(__file__).resolve().parents[1]
STUB = Path(geofeas.__file__).with_name("_core.pyi")

#: Python wrapper -> (option sets it takes, its parameters outside the sets).
PF_FUNCTIONS = {
    _pf.pf_simulate_run: (("run", "filter"), set()),
    _pf.pf_track: (("track", "filter"), {"frames", "init", "sigma_z"}),
    _pf.pf_study: (("study",), {"ic"}),
}

MHT_FUNCTIONS = {
    _mht.mht_track: (("tracker",), {"detections", "sensors"}),
    _mht.mht_simulate_run: (("run",), set()),
    _mht.mht_study: (("study",), set()),
    _mht.mht_trilaterate: (("beam",), {"pos_a", "z_a", "cov_a", "pos_b", "z_b", "cov_b"}),
}

PYTHON_TYPES = {"int": int, "float": float, "bool": bool}


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    return type(a) is type(b) and a == b


def _specs(schema: dict[str, Any], groups: tuple[str, ...]) -> dict[str, tuple[Any, ...]]:
    return {o[0]: tuple(o[1:]) for g in groups for o in schema[g]}


def _check_signature(fn: Any, specs: dict[str, tuple[Any, ...]], outside: set[str]) -> None:
    sig = inspect.signature(fn)
    hints = typing.get_type_hints(fn)
    params = {n: p for n, p in sig.parameters.items() if n not in outside}
    assert set(params) == set(specs), (
        f"{fn.__name__}: not in the core's option sets {sorted(set(params) - set(specs))}, "
        f"missing {sorted(set(specs) - set(params))}"
    )
    for name, (kind, default, doc, choices) in specs.items():
        p = params[name]
        assert p.kind is inspect.Parameter.KEYWORD_ONLY, name
        assert _same(p.default, default), f"{fn.__name__}({name}={p.default!r}), core {default!r}"
        assert doc, f"{name}: no doc in the core"
        hint = hints[name]
        if kind == "choice":
            assert set(typing.get_args(hint)) == set(choices), f"{fn.__name__}: {name}: {hint}"
        elif kind in PYTHON_TYPES and typing.get_origin(hint) is not typing.Literal:
            assert hint is PYTHON_TYPES[kind], f"{fn.__name__}: {name}: {hint} for {kind}"


@pytest.mark.parametrize(
    ("schema", "functions", "groups"),
    [
        (_core.pf_options(), PF_FUNCTIONS, {"filter", "run", "track", "study"}),
        (_core.mht_options(), MHT_FUNCTIONS, {"tracker", "run", "study", "beam"}),
    ],
    ids=["pf", "mht"],
)
def test_python_signatures_match_the_core_option_sets(
    schema: dict[str, Any], functions: dict[Any, Any], groups: set[str]
) -> None:
    assert set(schema) == groups
    for fn, (sets, outside) in functions.items():
        _check_signature(fn, _specs(schema, sets), outside)
    # an option name shared by two sets means the same thing with the same default
    seen: dict[str, tuple[Any, ...]] = {}
    for rows in schema.values():
        for name, *rest in rows:
            if name in seen:
                assert _same(seen[name][:2], tuple(rest[:2])), name
            seen.setdefault(name, tuple(rest))


def test_the_check_fails_when_a_signature_drifts() -> None:
    schema = _core.pf_options()

    def drifted(*, snr_db: float = 15.0, method: int = 2, seed: int = 1) -> None: ...

    with pytest.raises(AssertionError):
        _check_signature(drifted, _specs(schema, ("run", "filter")), set())
    specs = _specs(schema, ("run",))
    specs["seed"] = ("int", 1, "Seed of the study.", ())
    with pytest.raises(AssertionError, match="seed"):
        _check_signature(_pf.pf_simulate_run, {**_specs(schema, ("filter",)), **specs}, set())


def test_stubs_take_the_options_from_the_core() -> None:
    tree = ast.parse(STUB.read_text())
    funcs = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    tracker = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "MhtTracker")
    funcs["MhtTracker"] = next(
        n for n in tracker.body if isinstance(n, ast.FunctionDef) and n.name == "__new__"
    )
    for name, positional in (
        ("pf_simulate_run", []),
        ("pf_track", ["frames", "init"]),
        ("pf_study", ["ic"]),
        ("mht_track", ["detections", "sensors"]),
        ("mht_simulate_run", []),
        ("mht_study", []),
        ("mht_trilaterate", ["pos_a", "z_a", "cov_a", "pos_b", "z_b", "cov_b"]),
        ("MhtTracker", ["cls", "sensors"]),
    ):
        args = funcs[name].args
        assert [a.arg for a in args.args] == positional, name
        assert args.kwarg is not None and args.kwarg.arg == "options", name
        # no option spelled out in the stub beside the core's declaration
        assert [a.arg for a in args.kwonlyargs] == (["sigma_z"] if name == "pf_track" else [])


def _study_parser(cli: Any, command: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser()
    cli.add_parser(parser.add_subparsers())
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[command]


@pytest.mark.parametrize(
    ("cli", "command", "schema"),
    [(_cli_pf, "pf-study", _core.pf_options()), (_cli_mht, "mht-study", _core.mht_options())],
    ids=["pf", "mht"],
)
def test_study_flags_match_the_core(cli: Any, command: str, schema: dict[str, Any]) -> None:
    specs = _specs(schema, ("study",))
    own = {"help", "out", "config", "no_figures"}
    for action in _study_parser(cli, command)._actions:
        if action.dest in own:
            continue
        assert action.dest in specs, f"--{action.dest} is not a study option of the core"
        kind, default, doc, choices = specs[action.dest]
        expected = cli.CLI_DEFAULTS.get(action.dest, default)
        assert _same(action.default, expected), action.dest
        if kind == "choice":
            assert list(action.choices or []) == list(choices), action.dest
        elif kind == "choices":
            # a comma-separated list: every name of the core is accepted, nothing else
            assert action.type(",".join(choices)) == list(choices), action.dest
            with pytest.raises(argparse.ArgumentTypeError):
                action.type("bogus")
        elif kind in ("int", "float"):
            assert action.type is PYTHON_TYPES[kind], action.dest
        assert action.help, action.dest
    # the command's own defaults are study options too
    assert set(cli.CLI_DEFAULTS) <= set(specs)


def _table(rows: list[tuple[Any, ...]]) -> str:
    def shown(v: Any) -> str:
        if isinstance(v, tuple):
            return "(" + ", ".join(shown(x) for x in v) + ")"
        return "None" if v is None else (f'"{v}"' if isinstance(v, str) else repr(v))

    lines = ["| option | default | meaning |", "|---|---|---|"]
    lines += [f"| `{n}` | `{shown(d)}` | {doc} |" for n, _, d, doc, _ in rows]
    return "\n".join(lines)


@pytest.mark.parametrize(
    ("doc", "schema", "group"),
    [("pf-study.md", _core.pf_options(), g) for g in ("filter", "run", "track", "study")]
    + [("mht-study.md", _core.mht_options(), g) for g in ("tracker", "run", "study", "beam")],
)
def test_docs_tables_match_the_core(doc: str, schema: dict[str, Any], group: str) -> None:
    text = (ROOT / "docs" / doc).read_text()
    table = _table(schema[group])
    assert table in text, f"docs/{doc}: the `{group}` options table should read\n{table}"


def test_bad_options_name_the_option() -> None:
    cases = [
        ({"particles": 2.5}, "particles"),
        ({"particles": True}, "particles"),
        ({"seed": -1}, "seed"),
        ({"model_factors": (1.0, 2.0)}, "model_factors"),
        ({"model_factors": "abc"}, "model_factors"),
        ({"snapshot_frames": [1.5]}, "snapshot_frames"),
        ({"snapshot_particles": 0}, "snapshot_particles"),
        ({"truth": "brownian"}, "truth"),
        ({"xmax": float("nan")}, "xmax"),
        ({"snr_db": "loud"}, "snr_db"),
    ]
    for kw, name in cases:
        with pytest.raises(GeofeasError, match=name):
            _pf.pf_simulate_run(particles=kw.pop("particles", 10), **kw)
    with pytest.raises(GeofeasError, match="unexpected keyword 'bogus'"):
        _core.pf_simulate_run(bogus=1)
    with pytest.raises(GeofeasError, match="snrs"):
        _pf.pf_study(runs=1, particles=10, snrs=["x"])


def test_options_reach_the_core() -> None:
    # every option changes the run it is given to (so none is read and dropped on the way)
    base = {"particles": 60, "snr_db": 6.0, "seed": 2}
    ref = _pf.pf_simulate_run(**base)
    for name, value in [
        ("association", "one-to-one"),
        ("resampling", "residual"),
        ("resample_threshold", 0.3),
        ("peaks", 6),
        ("min_separation", 6.0),
        ("smoothing", 2.0),
        ("xmax", 6.0),
        ("vmax", 1.5),
        ("sigma_w", 1.5),
        ("model_factors", (1.0, 1.0, 1.0)),
        ("half_box", 4),
        ("truth", "ncv"),
        ("run", 1),
        ("method", 1),
    ]:
        other = _pf.pf_simulate_run(**base, **{name: value})
        assert any(
            other[k].shape != ref[k].shape or not np.array_equal(other[k], ref[k], equal_nan=True)
            for k in ("truth", "estimates", "peaks", "peak")
        ), name
    r1 = _pf.pf_simulate_run(**base, method=1, r1=3.0)
    assert not np.array_equal(r1["estimates"], _pf.pf_simulate_run(**base, method=1)["estimates"])


def test_mht_bad_options_name_the_option() -> None:
    sensors = _mht.paper_sensors(2)
    for kw, name in [
        ({"max_hypotheses": 1.5}, "max_hypotheses"),
        ({"ekf_iterations": 101}, "ekf_iterations"),
        ({"single": "yes"}, "single"),
        ({"pd": float("inf")}, "pd"),
    ]:
        with pytest.raises(GeofeasError, match=name):
            _mht.MhtTracker(sensors, **kw)
    with pytest.raises(GeofeasError, match="trackers"):
        _mht.mht_study(runs=1, trackers="mht")
    with pytest.raises(GeofeasError, match="kalman"):
        _mht.mht_study(runs=1, trackers=["kalman"])
    with pytest.raises(GeofeasError, match="level"):
        _mht.mht_study(runs=1, level=1.5, one_target=[0], two_targets=[])
    with pytest.raises(GeofeasError, match="half_beam"):
        _mht.mht_trilaterate([0, 0], [20, 1], np.eye(2), [10, 0], [20, 1], np.eye(2), half_beam="x")
