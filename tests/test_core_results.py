"""The result types the bindings return: the stub lists exactly the attributes each class has at
run time, with the types the values have, and every result names its type in its repr."""

from __future__ import annotations

import ast
import inspect
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import geofeas
from geofeas import _core
from geofeas.association import _resolve_options
from geofeas.association.decisions import Decisions
from geofeas.tracking import paper_sensors

STUB = ast.parse(Path(geofeas.__file__).with_name("_core.pyi").read_text())


def _stub_classes() -> dict[str, dict[str, str]]:
    """Class name -> {property name: its return annotation} of every class in the stub."""
    out: dict[str, dict[str, str]] = {}
    for node in STUB.body:
        if isinstance(node, ast.ClassDef):
            out[node.name] = {
                f.name: ast.unparse(f.returns) if f.returns else ""
                for f in node.body
                if isinstance(f, ast.FunctionDef)
                and any(ast.unparse(d) == "property" for d in f.decorator_list)
            }
    return out


STUB_CLASSES = _stub_classes()
#: The classes defined in Rust: every class of the module but the exception (which has plain
#: attributes) and the stub's private protocols.
PYCLASSES = sorted(
    n for n, v in vars(_core).items() if isinstance(v, type) and not issubclass(v, BaseException)
)


def test_stub_lists_every_class() -> None:
    assert set(PYCLASSES) <= set(STUB_CLASSES)


def _runtime_attributes(cls: type) -> set[str]:
    return {
        n
        for n, v in vars(cls).items()
        if (inspect.isgetsetdescriptor(v) or inspect.ismemberdescriptor(v))
        and not n.startswith("__")
    }


@pytest.mark.parametrize("name", PYCLASSES)
def test_stub_lists_exactly_the_runtime_attributes(name: str) -> None:
    cls = getattr(_core, name)
    assert set(STUB_CLASSES[name]) == _runtime_attributes(cls), name


def _tiny_pf_frames() -> tuple[np.ndarray, np.ndarray]:
    init = np.array([[10.0, 12.0, 1.0, 0.0], [30.0, 25.0, 0.0, -1.0]])
    frames = np.stack(
        [
            _core.pf_render(init[:, :2] + k * init[:, 2:], width=48, height=40, seed=k)
            for k in range(3)
        ]
    )
    return frames, init


def _reports() -> Any:
    """Two sources seeing two ships, one seen by both."""
    t = np.arange(0.0, 300.0, 10.0)
    rows = [
        (track, source, t, x0 + 5.0 * t, 100.0 + 0.0 * t)
        for track, source, x0 in (("a1", "A", 0.0), ("b1", "B", 20.0), ("b2", "B", 9000.0))
    ]
    frame = {
        "track_id": np.concatenate([np.full(t.size, r[0]) for r in rows]),
        "source": np.concatenate([np.full(t.size, r[1]) for r in rows]),
        "time": np.concatenate([r[2] for r in rows]),
        "x": np.concatenate([r[3] for r in rows]),
        "y": np.concatenate([r[4] for r in rows]),
        "rx": 50.0,
        "ry": 30.0,
        "phi": 0.0,
    }
    import pandas as pd

    return geofeas.read_reports(pd.DataFrame(frame))


def _association() -> Any:
    return geofeas.associate(_reports())


ALIGNMENT = {"max_gap": 60.0, "horizon": 30.0, "process_noise": 0.1, "max_still_gap": 900.0}


def _track_boxes() -> Any:
    rep = _reports()
    partials = _core.association_track_partials(rep)
    track = np.arange(rep.n_tracks, dtype=np.uint32)
    return _core.association_track_boxes(
        partials, track, rep.n_tracks, geographic=False, alignment=ALIGNMENT
    )


#: One small call of every function that returns a result type.
CALLS: dict[str, Callable[[], Any]] = {
    "pf_track": lambda: _core.pf_track(*_tiny_pf_frames(), sigma_z=0.1, particles=50, peaks=3),
    "pf_simulate_run": lambda: _core.pf_simulate_run(
        particles=20, snapshot_frames=[0, 5], snapshot_particles=3, keep_frames=[1]
    ),
    "pf_study": lambda: _core.pf_study(np.array([[3.0, 0.5]]), runs=1, particles=20, snrs=[6.0]),
    "mht_track": lambda: _core.mht_track(
        np.array([[0.0, 0, 50.0, -1.0], [0.0, 1, 51.0, -1.2]]), paper_sensors(3)
    ),
    "mht_simulate_run": lambda: _core.mht_simulate_run(targets=1, sensors=2, seed=1),
    "mht_study": lambda: _core.mht_study(
        runs=1, max_hypotheses=5, one_target=(0,), two_targets=(), resamples=10
    ),
    # the engine keeps what the bindings returned
    "associate": lambda: _association()._raw,
    "association_finish": lambda: _association().with_decisions(Decisions.empty())._raw,
    "association_pair_instants": lambda: _core.association_pair_instants(
        _reports(), 0, 1, alignment=ALIGNMENT
    ),
    "association_states_at": lambda: _core.association_states_at(
        _reports(), np.array([15.0, 100.0, 250.0]), alignment=ALIGNMENT
    ),
    "association_track_boxes": _track_boxes,
    "association_track_summary": lambda: _core.association_track_summary(
        _reports(), options=_resolve_options(np.array(["A", "B"], dtype=object), {}, {})[0]
    ),
    "association_pair_stats": lambda: _core.association_pair_stats(
        _reports(),
        np.array([0], dtype=np.uint32),
        np.array([1], dtype=np.uint32),
        options=_resolve_options(np.array(["A", "B"], dtype=object), {}, {})[0],
    ),
}


def _check_value(where: str, value: Any, annotation: str) -> None:
    if annotation.startswith("NDArray["):
        dtype = annotation[len("NDArray[np.") : -1]
        assert isinstance(value, np.ndarray), (where, type(value))
        assert annotation == "NDArray[Any]" or value.dtype == np.dtype(dtype), (where, value.dtype)
    elif annotation in STUB_CLASSES:
        assert type(value) is getattr(_core, annotation), where
        _check_result(value)
    else:
        simple = {"float": float, "int": int, "bool": bool, "str": str}
        origin = annotation.split("[", 1)[0]
        expected = simple.get(origin) or {"list": list, "dict": dict, "tuple": tuple}[origin]
        assert isinstance(value, expected), (where, type(value), annotation)
        if origin == "tuple":
            items = [a.strip() for a in annotation[len("tuple[") : -1].split(",")]
            assert len(value) == len(items), where
            for k, (v, item) in enumerate(zip(value, items, strict=True)):
                _check_value(f"{where}[{k}]", v, item)
        if origin == "list":
            item = simple[annotation[len("list[") : -1]]
            assert all(isinstance(v, item) for v in value), where
        if origin == "dict":
            key, val = (a.strip() for a in annotation[len("dict[") : -1].split(",", 1))
            for k, v in value.items():
                assert isinstance(k, simple[key]), where
                if val != "Any":
                    _check_value(f"{where}[{k!r}]", v, val)


def _check_result(result: Any) -> None:
    name = type(result).__name__
    assert repr(result).startswith(f"{name}("), repr(result)
    for attribute, annotation in STUB_CLASSES[name].items():
        _check_value(f"{name}.{attribute}", getattr(result, attribute), annotation)


@pytest.mark.parametrize("function", sorted(CALLS))
def test_results_have_the_stub_types(function: str) -> None:
    returns = next(
        ast.unparse(n.returns)
        for n in STUB.body
        if isinstance(n, ast.FunctionDef) and n.name == function and n.returns
    )
    _check_value(function, CALLS[function](), returns)


def test_results_are_frozen() -> None:
    r = CALLS["mht_track"]()
    with pytest.raises(AttributeError):
        r.probability = 0.5
