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

from .association import (
    ASSOCIATION_DEFAULTS,
    COMBINE_RULES,
    SCORES,
    associate,
    read_reports,
    write_tables,
)

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
    result = associate(
        reports,
        decisions=args.decisions,
        score=args.score,
        combine=args.combine,
        p_match=args.p_match,
        p_reject=args.p_reject,
        max_gap=args.max_gap,
        horizon=args.horizon,
        process_noise=args.process_noise,
        same_source=args.same_source,
        correlation_time=args.correlation_time,
        window=args.window,
        inflation=args.inflation if args.inflation == "auto" else float(args.inflation),
        completeness=args.completeness,
        false_tracks=args.false_tracks,
        **options,
    )
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


def add_triage_arguments(p: argparse.ArgumentParser) -> None:
    """The triage thresholds, with the defaults of :func:`geofeas.associate`."""
    defaults = ASSOCIATION_DEFAULTS
    p.add_argument(
        "--p-match",
        type=float,
        default=defaults["p_match"],
        help=f"match when p_same >= this (default {defaults['p_match']})",
    )
    p.add_argument(
        "--p-reject",
        type=float,
        default=defaults["p_reject"],
        help=f"non-match when p_same <= this (default {defaults['p_reject']})",
    )


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
    p.add_argument("--coords", choices=("auto", "planar", "geographic"), default="auto")
    p.add_argument("--score", choices=SCORES, default="glr", help="per-instant score")
    p.add_argument(
        "--combine", choices=COMBINE_RULES, default="chi2", help="combination rule (default chi2)"
    )
    p.add_argument(
        "--decisions", help="operator decisions to respect (.csv or .parquet; read only)"
    )
    add_triage_arguments(p)
    p.add_argument(
        "--completeness",
        type=float,
        default=0.95,
        help="share of the objects the most complete source holds (default 0.95)",
    )
    p.add_argument(
        "--false-tracks",
        type=float,
        default=0.05,
        help="share of each source's tracks that are false (default 0.05)",
    )
    p.add_argument(
        "--details",
        action="store_true",
        help="also write the model's columns (llr, std_error, review_gain, settles_*, component)",
    )
    p.add_argument("--max-gap", type=float, default=300.0, help="longest interpolated gap (s)")
    p.add_argument("--horizon", type=float, default=0.0, help="extrapolation horizon (s)")
    p.add_argument("--process-noise", type=float, default=2.0, help="position diffusion q (m^2/s)")
    p.add_argument(
        "--same-source", action="store_true", help="also compare tracks of the same source"
    )
    p.add_argument(
        "--correlation-time", type=float, default=60.0, help="error correlation time (s)"
    )
    p.add_argument("--window", type=float, default=300.0, help="index chunk length (s)")
    p.add_argument(
        "--threshold", action="store_true", help="thresholded GLR (same as glr_threshold)"
    )
    p.add_argument(
        "--inflation",
        default="auto",
        type=_inflation,
        help="covariance inflation: 'auto' (default) or a number",
    )
    p.add_argument(
        "--vertices",
        type=int,
        default=None,
        help="overlap by polygons of this many vertices (default: the exact overlap)",
    )
    p.add_argument("--samples", type=int, default=500, help="Monte-Carlo samples per instant")
    p.add_argument("--seed", type=int, default=0, help="Monte-Carlo seed")
    p.add_argument("--quiet", "-q", action="store_true", help="no summary on standard output")
    p.set_defaults(func=run)
