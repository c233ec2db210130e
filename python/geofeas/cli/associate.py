"""``geofeas associate``: score the candidate track pairs of a reports file and write them.

The input (CSV or Parquet, by extension) has the columns ``track_id, source, time`` (seconds or
ISO-8601) and either ``x, y, rx, ry, phi`` (planar: metres, radians clockwise from north) or
``lat, lon, rx, ry, bearing`` (geographic: degrees WGS84, 2-sigma semi-axes in metres, bearing of
the rx axis in degrees clockwise from true north); extra columns are ignored. The output (CSV or
Parquet) has ``track_a, track_b, score, instants, class, p_same, review_rank``, one row per
candidate pair with ``track_a < track_b``: ``p_same`` is the posterior probability that the two
tracks are one object, ``class`` is ``match`` (p_same >= --p-match), ``non-match`` (p_same <=
--p-reject) or ``borderline``, and ``review_rank`` orders the borderline pairs for the operator
(1 first; empty for the others). ``--objects`` also writes ``track_id, object, source, p_alone``.
``--decisions FILE`` (CSV or Parquet: ``track_a, track_b, decision`` with ``same`` /
``different``, optionally ``operator, time``) adds operator decisions as hard constraints; the
file is only read.
"""

from __future__ import annotations

import argparse
import time
from typing import Any

from ..association import (
    OPTIONS,
    associate,
    read_reports,
    write_tables,
)
from ..scores import SCORE_DEFAULTS

#: The columns of the pairs file.
PAIR_COLUMNS = ("track_a", "track_b", "score", "instants", "class", "p_same", "review_rank")


def run(args: argparse.Namespace) -> int:
    start = time.perf_counter()
    reports = read_reports(args.reports, coords=args.coords)
    options: dict[str, Any] = {}
    if args.vertices is not None:
        # only when asked: the overlap is exact by default, polygons on request
        options["vertices"] = args.vertices
    if args.score == "monte_carlo":
        options["samples"] = args.samples
        options["seed"] = args.seed
    if args.threshold:
        options["threshold"] = True
    for o in OPTIONS:  # every option of the schema has its flag
        options[o["name"]] = getattr(args, o["name"])
    if options["inflation"] != "auto":
        options["inflation"] = float(options["inflation"])
    result = associate(reports, decisions=args.decisions, **options)
    pairs = result.pairs if args.details else result.pairs[list(PAIR_COLUMNS)]
    # one transaction: neither file is replaced unless both were written
    tables = [(pairs, args.out)]
    if args.objects:
        tables.append((result.objects, args.objects))
    write_tables(tables)
    elapsed = time.perf_counter() - start
    counts = result.pairs["class"].value_counts()
    if not args.quiet:
        print(
            f"{len(reports)} reports, {reports.n_tracks} tracks ({reports.coords}): "
            f"{len(result.pairs)} candidate pairs in {elapsed:.2f} s -> {args.out}"
        )
        print(
            "  "
            + ", ".join(
                f"{int(counts.get(c, 0))} {c}" for c in ("match", "borderline", "non-match")
            )
            + f"; {result.objects['object'].nunique()} objects"
        )
    return 0


def _inflation(text: str) -> str:
    if text != "auto":
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected 'auto' or a number, got {text!r}") from None
        if not value > 0:
            raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return text


def _option_flag(p: Any, o: dict[str, Any]) -> None:
    """The flag of one option of the schema (:data:`geofeas.association.OPTIONS`)."""
    name, default = o["name"], o["default"]
    flag = "--" + name.replace("_", "-")
    help = f"{o['help']} (default {default})"
    if isinstance(default, bool):
        p.add_argument(flag, action="store_true", default=default, help=o["help"])
    elif name == "inflation":
        p.add_argument(flag, type=_inflation, default=default, help=help)
    elif o["choices"]:
        p.add_argument(flag, choices=o["choices"], default=default, help=help)
    else:
        p.add_argument(flag, type=type(default), default=default, help=help)


def add_triage_arguments(p: argparse.ArgumentParser) -> None:
    """The triage thresholds, with the defaults of :func:`geofeas.associate`."""
    for o in OPTIONS:
        if o["name"] in ("p_match", "p_reject"):
            _option_flag(p, o)


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "associate",
        help="score the candidate track pairs of a reports file (CSV / Parquet)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("reports", help="reports file (.csv or .parquet)")
    p.add_argument("--out", "-o", required=True, help="pairs file to write (.csv or .parquet)")
    p.add_argument("--objects", help="also write the track -> object table to this file")
    p.add_argument(
        "--coords",
        choices=("auto", "planar", "geographic"),
        default="auto",
        help="how the reports' positions are read: planar x, y or geographic lat, lon "
        "(default auto: from the columns present)",
    )
    p.add_argument(
        "--decisions", help="operator decisions to respect (.csv or .parquet; read only)"
    )
    p.add_argument(
        "--details",
        action="store_true",
        help="also write the model's columns (llr, std_error, review_gain, settles_*, component)",
    )
    options = p.add_argument_group("association options (geofeas.associate's keywords)")
    for o in OPTIONS:
        _option_flag(options, o)
    scores = p.add_argument_group("options of the score column's score")
    scores.add_argument(
        "--threshold", action="store_true", help="thresholded GLR (same as glr_threshold)"
    )
    scores.add_argument(
        "--vertices",
        type=int,
        default=None,
        help="overlap by polygons of this many vertices (default: the exact overlap)",
    )
    scores.add_argument(
        "--samples",
        type=int,
        default=SCORE_DEFAULTS["samples"],
        help="Monte-Carlo samples per instant",
    )
    scores.add_argument("--seed", type=int, default=SCORE_DEFAULTS["seed"], help="Monte-Carlo seed")
    p.add_argument("--quiet", "-q", action="store_true", help="no summary on standard output")
    p.set_defaults(func=run)
