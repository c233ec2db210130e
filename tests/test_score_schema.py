"""One definition of the score options (the core's ``score::schema``): the keyword defaults of
the score functions, the options each score takes, the options the association passes to its
score, the flags of ``geofeas score`` and the README's table are checked against it, so any of
them drifting fails here."""

from __future__ import annotations

import argparse
import inspect
import typing
from pathlib import Path

import pytest

import geofeas
from geofeas import _core, scores
from geofeas.association import options as association_options
from geofeas.cli import associate as cli_associate
from geofeas.cli import score as cli_score

README = Path(__file__).resolve().parents[1] / "README.md"
BEGIN, END = "<!-- score options: begin -->\n", "<!-- score options: end -->"

#: The score functions of ``geofeas.scores``, by score name.
FUNCTIONS = {
    "glr": scores.glr,
    "overlap": scores.overlap,
    "monte_carlo": scores.monte_carlo,
    "bhattacharyya": scores.bhattacharyya,
    "hellinger": scores.hellinger,
    "gaussian_product": scores.gaussian_product,
}
#: Keyword defaults that are not the core's on purpose: ``None`` resolves to it (``overlap``:
#: the exact method, or the polygon method when ``vertices`` is given; ``monte_carlo``: a fresh
#: random seed).
RESOLVED = {("overlap", "method"), ("overlap", "vertices"), ("monte_carlo", "seed")}


def _schema() -> list[dict[str, typing.Any]]:
    return _core.score_options()


def _taken_by(score: str) -> list[tuple[str, object]]:
    return [(o["name"], o["default"]) for o in _schema() if score in o["scores"]]


def test_score_names_are_the_cores():
    names = _core.score_names()
    assert list(FUNCTIONS) == names
    assert list(scores.SCORE_NAMES) == names
    assert list(typing.get_args(scores.ScoreName)) == names
    assert list(scores._OPTIONS) == names
    for o in _schema():
        assert set(o["scores"]) <= set(names), o["name"]
        assert o["kind"] in ("bool", "int", "text")
        assert o["help"], o["name"]


@pytest.mark.parametrize("score", list(FUNCTIONS))
def test_function_keywords_are_the_schema(score):
    params = inspect.signature(FUNCTIONS[score]).parameters.values()
    kw = [(p.name, p.default) for p in params if p.kind is p.KEYWORD_ONLY]
    want = _taken_by(score)
    assert sorted(n for n, _ in kw) == sorted(n for n, _ in want)
    assert scores._OPTIONS[score] == {n for n, _ in want}
    defaults = dict(want)
    for name, default in kw:
        if (score, name) in RESOLVED:
            assert default is None, name
            continue
        # the same value of the same type (False is not 0, 500 is not 500.0)
        assert default == defaults[name] and type(default) is type(defaults[name]), name


def test_resolved_defaults_are_the_schema():
    d = scores.SCORE_DEFAULTS
    # overlap() with neither option: the core's method, and the core's resolution when polygons
    assert scores._options("overlap", {"method": None, "vertices": None}) == {"method": d["method"]}
    assert geofeas.overlap(_E, _F, method="polygon") == geofeas.overlap(
        _E, _F, method="polygon", vertices=d["vertices"]
    )
    assert geofeas.overlap(_E, _F) == geofeas.overlap(_E, _F, method=d["method"])
    # monte_carlo(seed=None) draws a seed; the engine's own default is the schema's
    assert isinstance(scores._options("monte_carlo", {})["seed"], int)
    assert repr(_core.ScoreOptions()) == repr(_core.ScoreOptions(**d))


_E = [0.0, 0.0, 3.0, 1.0, 0.2]
_F = [1.0, 0.5, 2.0, 1.5, 1.0]


def test_module_constants_are_the_schema():
    by_name = {o["name"]: o for o in _schema()}
    assert scores.SCORE_OPTIONS == tuple(_schema())
    assert scores.SCORE_DEFAULTS == {o["name"]: o["default"] for o in _schema()}
    assert geofeas.DEFAULT_VERTICES == by_name["vertices"]["default"]
    assert list(geofeas.SAMPLERS) == by_name["sampler"]["choices"]
    assert list(scores._METHODS) == by_name["method"]["choices"]
    # the Python checks refuse below the core's lower bounds, the core above its upper ones
    for name, score in (("vertices", "overlap"), ("samples", "monte_carlo")):
        lo, hi = by_name[name]["range"]
        opts = {"method": "polygon"} if score == "overlap" else {}
        with pytest.raises(geofeas.GeofeasError, match=name):
            scores._options(score, {**opts, name: lo - 1})
        assert scores._options(score, {**opts, name: lo})[name] == lo
        with pytest.raises(geofeas.GeofeasError, match=name):
            _core.score_pairs(
                scores.as_ellipses(_E, "a")[0],
                scores.as_ellipses(_F, "b")[0],
                score,
                _core.ScoreOptions(**{**opts, name: hi + 1}),
            )


def test_association_passes_the_schemas_options():
    assert association_options._SCORE_OPTIONS == tuple(o["name"] for o in _schema())
    assert association_options._SCORE_DEFAULTS == {o["name"]: o["default"] for o in _schema()}
    p = _subparser(cli_associate, "associate")
    by_dest = {a.dest: a for a in p._actions}
    for name in ("samples", "seed"):
        want = scores.SCORE_DEFAULTS[name]
        assert by_dest[name].default == want and type(by_dest[name].default) is type(want)


def _subparser(module: typing.Any, name: str) -> argparse.ArgumentParser:
    root = argparse.ArgumentParser()
    module.add_parser(root.add_subparsers())
    sub = next(a for a in root._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[name]


def test_score_cli_has_one_flag_per_option_with_its_default_and_choices():
    p = _subparser(cli_score, "score")
    by_dest = {a.dest: a for a in p._actions}
    for o in _schema():
        if o["name"] == "threshold":
            # the thresholded GLR is a column of its own
            assert "glr_threshold" in by_dest["score"].choices
            continue
        a = by_dest[o["name"]]
        assert "--" + o["name"].replace("_", "-") in a.option_strings
        assert a.default == o["default"] and type(a.default) is type(o["default"]), o["name"]
        assert list(a.choices or []) == o["choices"], o["name"]
        if a.type is not None:  # a value typed on the command line is read as the core's kind
            typed = a.type(str(o["default"]))
            assert typed == o["default"] and type(typed) is type(o["default"]), o["name"]
        assert a.help and o["help"] in a.help, o["name"]
    # every score of the core is a column, beside the aliases
    columns = set(by_dest["score"].choices)
    assert columns - {"glr_threshold", "overlap_polygon"} == set(_core.score_names())
    assert set(cli_score.DEFAULT_SCORES) <= columns
    # score_all's own defaults are the schema's
    params = inspect.signature(cli_score.score_all).parameters
    for name in ("method", "sampler"):
        assert params[name].default == scores.SCORE_DEFAULTS[name], name


def test_readme_table_is_rendered_from_the_schema():
    text = README.read_text(encoding="utf-8")
    assert BEGIN in text and END in text, "README.md lost its score options table markers"
    table = text.split(BEGIN, 1)[1].split(END, 1)[0]
    assert table == cli_score.options_markdown(), "run: python scripts/options_doc.py"
    for o in _schema():
        assert f"| `{o['name']}` | `{o['default']!r}` |" in table, o["name"]
