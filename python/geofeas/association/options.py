"""The options of :func:`geofeas.associate`: the schema defined once in the core
(``association::schema``), the defaults derived from it, and their resolution into the engine's
options (shared by :func:`geofeas.associate`, :meth:`Association.with_decisions` and the
distributed path).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from numpy.typing import NDArray

from .. import _core
from .._core import GeofeasError
from ..scores import _OPTIONS, SCORE_DEFAULTS, SCORE_OPTIONS

__all__ = [
    "ALIGNMENT_OPTIONS",
    "ASSOCIATION_DEFAULTS",
    "COMBINE_RULES",
    "DEFAULT_UPPER",
    "OPTIONS",
    "SCORES",
]

#: The options of :func:`associate`, defined once in the core (``association::schema``): dicts
#: of ``name``, ``default``, ``choices`` and ``help``, in signature order.
OPTIONS: tuple[dict[str, Any], ...] = tuple(_core.association_options())
_CHOICES = {o["name"]: tuple(o["choices"]) for o in OPTIONS}
#: Combination rules of :func:`associate` (``"chi2"`` is the calibrated default).
COMBINE_RULES: tuple[str, ...] = _CHOICES["combine"]
#: Scores of :func:`associate` (``"glr_threshold"`` is ``"glr"`` with ``threshold=True``).
SCORES: tuple[str, ...] = _CHOICES["score"]
#: The ``"chi2"`` score of a fit like one instant 2 sigma apart (a reference on the score
#: column's scale; the classes come from the posterior).
DEFAULT_UPPER: float = _core.association_default_upper()

#: The options of the score column's score (``geofeas.scores.SCORE_OPTIONS``, from the core).
_SCORE_OPTIONS = tuple(o["name"] for o in SCORE_OPTIONS)


def _score_options(score: str, options: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    unknown = sorted(set(options) - set(_SCORE_OPTIONS))
    if unknown:
        raise TypeError(f"associate() got unexpected option(s) {', '.join(unknown)}")
    opts = dict(options)
    if score == "glr_threshold":
        score = "glr"
        opts["threshold"] = True
    if score not in SCORES:
        raise GeofeasError(f"score: unknown score {score!r} (expected one of {SCORES})")
    if opts.get("seed") is None:
        opts.pop("seed", None)
    misplaced = sorted(set(opts) - _OPTIONS[score])
    if misplaced:
        err = GeofeasError(
            f"option(s) {misplaced} do not apply to score {score!r}; "
            f"it takes {sorted(_OPTIONS[score])}"
        )
        err.argument = misplaced[0]
        raise err
    if score == "overlap" and "vertices" in opts:
        # a resolution alone asks for the polygon method, as in geofeas.overlap
        opts.setdefault("method", "polygon")
    return score, opts


#: The defaults of :func:`associate`'s options (besides the score's own), from :data:`OPTIONS`.
ASSOCIATION_DEFAULTS: dict[str, Any] = {o["name"]: o["default"] for o in OPTIONS}

#: The options of the time alignment (``association::align::Alignment`` in the core).
ALIGNMENT_OPTIONS = ("max_gap", "horizon", "process_noise", "max_still_gap")


def _alignment(options: Mapping[str, Any]) -> dict[str, float]:
    """The alignment options the core's bindings take (``alignment=``), from a mapping that holds
    them (an association's options, or keyword arguments)."""
    return {k: float(options[k]) for k in ALIGNMENT_OPTIONS}


def _options_markdown() -> str:
    """The options table of ``docs/association.md``, rendered from :data:`OPTIONS`
    (``python scripts/options_doc.py`` writes it; a test checks the page)."""
    rows = ["| option | default | `geofeas associate` | meaning |", "|---|---|---|---|"]
    for o in OPTIONS:
        flag = "--" + o["name"].replace("_", "-")
        choices = f" (one of {', '.join(o['choices'])})" if o["choices"] else ""
        rows.append(f"| `{o['name']}` | `{o['default']!r}` | `{flag}` | {o['help']}{choices} |")
    return "\n".join(rows) + "\n"


#: The score options the engine receives when the caller gives none (the core's defaults).
_SCORE_DEFAULTS: dict[str, Any] = dict(SCORE_DEFAULTS)


def _resolve_options(
    sources: NDArray[Any], options: Mapping[str, Any], score_options: dict[str, Any]
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The engine's options (a dict for ``_core``) and the options as recorded on the result,
    from :func:`associate`'s keyword arguments (shared with ``geofeas.integrations.dask``)."""
    unknown = sorted(set(options) - set(ASSOCIATION_DEFAULTS))
    if unknown:
        raise TypeError(f"associate() got unexpected option(s) {', '.join(unknown)}")
    o = {**ASSOCIATION_DEFAULTS, **options}
    name, opts = _score_options(str(o["score"]), score_options)
    inflation = o["inflation"]
    if isinstance(inflation, str):
        if inflation != "auto":
            raise GeofeasError(f"inflation: expected 'auto' or a number, got {inflation!r}")
        infl: float | None = None
    else:
        infl = float(inflation)
    ft = o["false_tracks"]
    if isinstance(ft, Mapping):
        unknown_src = [k for k in ft if k not in set(sources.tolist())]
        if unknown_src:
            raise GeofeasError(
                f"false_tracks: unknown source(s) {unknown_src} (have {list(sources)})"
            )
        false_tracks = [float(ft.get(s, 0.05)) for s in sources]
    else:
        false_tracks = [float(ft)] * len(sources)
    core = dict(
        score=name,
        combine=str(o["combine"]),
        p_match=float(o["p_match"]),
        p_reject=float(o["p_reject"]),
        max_gap=float(o["max_gap"]),
        horizon=float(o["horizon"]),
        process_noise=float(o["process_noise"]),
        max_still_gap=float(o["max_still_gap"]),
        same_source=bool(o["same_source"]),
        correlation_time=float(o["correlation_time"]),
        window=float(o["window"]),
        inflation=infl,
        completeness=float(o["completeness"]),
        false_tracks=false_tracks,
        density_cell=float(o["density_cell"]),
        exact_limit=int(o["exact_limit"]),
        chains=int(o["chains"]),
        sweeps=int(o["sweeps"]),
        posterior_seed=int(o["posterior_seed"]),
        **{**_SCORE_DEFAULTS, **opts},
    )
    recorded = {**o, **score_options}
    return core, recorded
