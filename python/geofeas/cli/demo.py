"""``geofeas demo``: the whole pipeline on a real AIS recording.

Reads and cleans the recording (reporting every removed row and corrected value), simulates
several sources observing its vessels (AIS self-reports, a coastal radar, a patrol aircraft, an
HF direction-finding net; each with its own track numbers, dropouts and false tracks), associates
their reports and scores the association against the MMSI ground truth: precision, recall and F1
of the duplicate-track pairs, the candidate pairs per triage class and the time taken, for the
default association: the operator load (borderline pairs per true duplicate), the precision of
the automatic merges, the true pairs lost to non-match, the calibration of p_same (expected
calibration error), the F1 a truthful operator reaches after 0, 25, 50, 100 and 200
decisions in review order, and, with HF DF, the fewest borderline HF DF pairs any triage can
leave while losing at most 1 % of the true pairs (an oracle's bound, each fix judged alone:
what geometry cannot decide). Writes into ``--out``: ``reports.csv`` (the simulated reports, with
the truth column ``mmsi``; ``geofeas associate`` reads it), ``pairs.csv`` (the default
association's candidate pairs with the truth), ``metrics.csv`` and ``metrics.md``,
``metrics_by_sources.csv``, ``calibration.csv`` and ``calibration.png`` (the reliability
diagram), ``operator.csv`` and ``operator.png`` (F1 against decisions) and ``map.png`` (AOUs of
a busy area coloured by associated object); the figures need matplotlib (--no-map: no map.png,
--no-figures: none).
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

from .._core import GeofeasError
from ..association import COMBINE_RULES
from .associate import add_triage_arguments

# the names only (the modules need pandas, imported when the command runs); tests check that
# they match geofeas.demo.scenario.SENSORS, geofeas.demo.SCORES and geofeas.demo.RECORDINGS
SENSORS = ("ais", "radar", "aircraft", "hfdf")
SCORES = ("glr", "glr_threshold", "overlap", "monte_carlo")
RECORDINGS = ("solent", "nyharbor")


def _sensors(text: str) -> list[str]:
    names = [s.strip() for s in text.split(",") if s.strip()]
    bad = [s for s in names if s not in SENSORS]
    if bad or not names:
        raise argparse.ArgumentTypeError(
            f"unknown sensor(s) {', '.join(bad) or '(none)'}; choose from {', '.join(SENSORS)}"
        )
    return names


def _count(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {n}")
    return n


def main(args: argparse.Namespace) -> int:
    try:
        from ..demo import fmt, run, write_outputs
    except ImportError as exc:
        raise GeofeasError(f"demo needs pandas: pip install 'geofeas[io]' ({exc})") from None
    options: dict[str, Any] = {"p_match": args.p_match, "p_reject": args.p_reject}
    result = run(
        args.ais,
        sensors=args.sensors,
        seed=args.seed,
        minutes=args.minutes,
        scores=args.score or (),
        combines=args.combine or (),
        options=options,
        operator=None if args.no_operator else (0, 25, 50, 100, 200),
        operator_batch=args.operator_batch,
        progress=not args.no_progress,
        log=print,
    )
    sc = result.scenario
    print(f"\nsimulated sources (seed {args.seed}):")
    counts = sc.counts()
    med = sc.reports.groupby("source")[["rx", "ry"]].median()
    print(
        f"  {'source':<9}{'reports':>9}{'tracks':>8}{'false':>7}{'vessels':>9}"
        f"   median 2-sigma AOU (m)"
    )
    for s, row in counts.iterrows():
        print(
            f"  {s:<9}{row['reports']:>9}{row['tracks']:>8}{row['false_tracks']:>7}"
            f"{row['vessels']:>9}   {med.loc[s, 'rx']:.0f} x {med.loc[s, 'ry']:.0f}"
        )
    d = result.default
    m = d.metrics
    print(f"\ndefault association (score {d.score}, combine {d.combine}): {m.seconds:.2f} s")
    print(
        f"  candidate pairs: {m.classes['match']} match, {m.classes['borderline']} borderline, "
        f"{m.classes['non-match']} non-match"
    )
    print(
        f"  true duplicate-track pairs: {m.true_pairs}; of them {m.true_in_class['match']} "
        f"match, {m.true_in_class['borderline']} borderline, "
        f"{m.true_in_class['non-match']} non-match, {m.true_not_candidates} not candidates"
    )
    print(
        f"  precision {fmt(m.precision)}  recall {fmt(m.recall)}  F1 {fmt(m.f1)}  "
        f"({m.tp} TP, {m.fp} FP of which {m.fp_with_false_track} with a false track, "
        f"{m.fn} FN)"
    )
    summ = result.summary()
    print(
        f"  operator load: {summ['operator_load']:.3f} borderline pairs per true duplicate; "
        f"automatic merges {fmt(summ['merge_precision'])} correct; "
        f"{summ['lost']:.2%} of the true pairs lost to non-match"
    )
    print(f"  calibration of p_same: expected calibration error {summ['ece']:.4f}")
    if not math.isnan(summ["oracle_load"]):
        print(
            f"  HF DF, what geometry cannot decide: an oracle knowing every vessel's true path "
            f"leaves at least {result.oracle_borderline:.0f} borderline HF DF pairs "
            f"({summ['oracle_load']:.3f} per true duplicate) to lose at most 1% of the true pairs"
        )
    if result.operator is not None:
        steps = "  ".join(f"{int(r.decisions)}: {fmt(r.f1)}" for r in result.operator.itertuples())
        print(
            f"  F1 after truthful decisions in review order (recomputed every "
            f"{args.operator_batch}): {steps}"
        )
        steps = "  ".join(
            f"{int(r.decisions)}: {fmt(r.object_f1)}" for r in result.operator.itertuples()
        )
        print(f"    of the pairs the objects imply: {steps}")
    if m.object_f1 == m.object_f1:
        print(
            f"  pairs implied by the objects: precision {fmt(m.object_precision)}  "
            f"recall {fmt(m.object_recall)}  F1 {fmt(m.object_f1)}"
        )
    if m.by_sources is not None and len(m.by_sources):
        print("  by source pair:")
        for _, r in m.by_sources.iterrows():
            print(
                f"    {r['sources']:<16} true {r['true_pairs']:>5}  predicted "
                f"{r['predicted']:>5}  P {fmt(r['precision'])}  R {fmt(r['recall'])}  "
                f"F1 {fmt(r['f1'])}"
            )
    if result.runs:
        print("\nper score and combination rule:")
        print(
            f"  {'score':<14}{'combine':<14}{'precision':>10}{'recall':>8}{'F1':>7}"
            f"{'match':>8}{'border':>8}{'non':>8}{'time s':>8}"
        )
        for one in result.runs:
            x = one.metrics
            print(
                f"  {one.score:<14}{one.combine:<14}{fmt(x.precision):>10}{fmt(x.recall):>8}"
                f"{fmt(x.f1):>7}{x.classes['match']:>8}{x.classes['borderline']:>8}"
                f"{x.classes['non-match']:>8}{x.seconds:>8.2f}"
            )
    written = write_outputs(result, args.out, map_png=not args.no_map, figures=not args.no_figures)
    print(f"\nwrote {', '.join(str(p) for p in written)}")
    if args.review:
        from .review import review_demo

        review_demo(args.out)
    return 0


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "demo",
        help="simulate sources over a real AIS recording, associate, score against the truth",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--ais",
        default="solent",
        metavar="PATH",
        help=f"AIS CSV (Solent or MarineCadastre schema) or a bundled one: "
        f"{', '.join(RECORDINGS)} (default solent)",
    )
    p.add_argument(
        "--sensors",
        type=_sensors,
        default=list(SENSORS),
        help=f"comma-separated sources (default {','.join(SENSORS)})",
    )
    p.add_argument("--seed", type=int, default=0, help="simulation seed (default 0)")
    p.add_argument("--minutes", type=float, default=None, help="use only the first minutes")
    p.add_argument("--out", "-o", default="demo", help="output directory (default demo/)")
    p.add_argument(
        "--score",
        action="append",
        choices=list(SCORES),
        help="also associate with this score for the comparison table (repeatable)",
    )
    p.add_argument(
        "--combine",
        action="append",
        choices=list(COMBINE_RULES),
        help="also associate with this rule for the comparison table (repeatable)",
    )
    add_triage_arguments(p)
    p.add_argument("--no-operator", action="store_true", help="do not simulate the operator")
    p.add_argument(
        "--operator-batch",
        type=_count,
        default=25,
        metavar="N",
        help="decisions the simulated operator answers between two recomputations of the "
        "association (default 25; a review station recomputes after every decision: 1)",
    )
    p.add_argument("--no-map", action="store_true", help="do not draw map.png")
    p.add_argument(
        "--no-figures",
        action="store_true",
        help="draw no figure (map.png, calibration.png, operator.png: they need matplotlib)",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    p.add_argument(
        "--review",
        action="store_true",
        help="then open the review station on the simulated picture (decisions in "
        "OUT/decisions.sqlite)",
    )
    p.set_defaults(func=main)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(0)
