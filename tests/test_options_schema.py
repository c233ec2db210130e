"""One definition of the association options (the core's ``association::schema``): the Python
signature, the defaults, the ``geofeas associate`` flags and the docs table are checked against
it, so any of them drifting fails here."""

from __future__ import annotations

import argparse
import inspect
from pathlib import Path

import pytest

import geofeas
import geofeas.integrations.dask
from geofeas._core import GeofeasError, association_options
from geofeas.association import ASSOCIATION_DEFAULTS, OPTIONS, _options_markdown
from geofeas.cli import associate as _cli_associate

DOC = Path(__file__).resolve().parents[1] / "docs" / "association.md"
BEGIN, END = "<!-- options: begin -->\n", "<!-- options: end -->"


def _schema() -> list[tuple[str, object]]:
    return [(o["name"], o["default"]) for o in association_options()]


def test_python_signature_is_the_schema():
    params = inspect.signature(geofeas.associate).parameters.values()
    kw = [(p.name, p.default) for p in params if p.kind is p.KEYWORD_ONLY and p.name != "decisions"]
    assert kw == _schema()
    # the defaults of the same type (0 is not 0.0: an int default would change the CLI's type)
    for (name, default), (_, want) in zip(kw, _schema(), strict=True):
        assert type(default) is type(want), name
    assert list(ASSOCIATION_DEFAULTS.items()) == _schema()
    assert [o["name"] for o in OPTIONS] == [n for n, _ in _schema()]


def test_dask_takes_the_schema_names_and_refuses_others():
    import pandas as pd

    one = pd.DataFrame(
        dict(track_id=["a"], source=["ais"], time=[0.0], x=[0.0], y=[0.0], rx=[10.0], ry=[5.0])
    ).assign(phi=0.0)
    with pytest.raises(TypeError, match="not_an_option"):
        geofeas.integrations.dask.associate(one, not_an_option=1)
    # every schema name is accepted (checked by the engine before any work is distributed)
    with pytest.raises(GeofeasError, match="p_match"):
        geofeas.integrations.dask.associate(one, **{**ASSOCIATION_DEFAULTS, "p_match": 0.2})


def _parser() -> argparse.ArgumentParser:
    root = argparse.ArgumentParser()
    _cli_associate.add_parser(root.add_subparsers())
    sub = next(a for a in root._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices["associate"]


def test_cli_has_one_flag_per_option_with_its_default_and_choices():
    p = _parser()
    by_dest = {a.dest: a for a in p._actions}
    for o in association_options():
        a = by_dest[o["name"]]
        assert "--" + o["name"].replace("_", "-") in a.option_strings
        assert a.default == o["default"] and type(a.default) is type(o["default"]), o["name"]
        if o["choices"]:
            assert list(a.choices) == o["choices"]
        assert a.help, o["name"]


def test_docs_table_is_rendered_from_the_schema():
    text = DOC.read_text(encoding="utf-8")
    assert BEGIN in text and END in text, "docs/association.md lost its options table markers"
    table = text.split(BEGIN, 1)[1].split(END, 1)[0]
    assert table == _options_markdown(), "run: python scripts/options_doc.py"


def test_score_names_are_the_cores():
    from geofeas.scores import _OPTIONS

    choices = next(o["choices"] for o in association_options() if o["name"] == "score")
    # the core's scores, plus the alias glr_threshold (the GLR with threshold=True)
    assert set(_OPTIONS) == set(choices) - {"glr_threshold"}
    assert "glr_threshold" in choices
