"""``geofeas score``: score ellipse pairs from a CSV file and write them to a CSV file.

The input has the columns ``a_x0, a_y0, a_rx, a_ry, a_phi, b_x0, b_y0, b_rx, b_ry, b_phi``
(any order, extra columns are kept); the output repeats every input column and adds one column
per requested score.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import sys
import time
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from .._atomic import atomic_open
from .._core import GeofeasError
from ..scores import (
    SCORE_DEFAULTS,
    SCORE_NAMES,
    SCORE_OPTIONS,
    bhattacharyya,
    gaussian_product,
    glr,
    hellinger,
    monte_carlo,
    overlap,
)

FIELDS = ("x0", "y0", "rx", "ry", "phi")
COLUMNS = tuple(f"{side}_{f}" for side in "ab" for f in FIELDS)
#: Columns of a score with one option fixed: the thresholded GLR, the polygon overlap.
ALIASES = {"glr": ("glr_threshold",), "overlap": ("overlap_polygon",)}
#: The columns ``--score`` computes: the core's scores (``geofeas.scores.SCORE_NAMES``), each
#: followed by its aliases.
SCORES = tuple(c for s in SCORE_NAMES for c in (s, *ALIASES.get(s, ())))
#: The score options that are flags (``--name``), from the core's schema
#: (``geofeas.scores.SCORE_OPTIONS``); ``threshold`` is the column ``glr_threshold``.
FLAGS = tuple(o for o in SCORE_OPTIONS if o["name"] != "threshold")
#: What ``--score`` computes when it is not given.
DEFAULT_SCORES = ("glr", "glr_threshold", "overlap", "monte_carlo")


def example_path() -> Path:
    """The bundled example file of ellipse pairs."""
    return Path(str(resources.files("geofeas") / "data" / "example_pairs.csv"))


def read_pairs(path: Path) -> tuple[list[str], list[list[str]], np.ndarray]:
    """Header, raw rows and the ``(n, 10)`` float array of a pairs CSV; errors name the line."""
    with open(path, newline="", encoding="utf-8") as fh:
        reader = csv.reader(fh)
        try:
            header = [h.strip() for h in next(reader)]
        except StopIteration:
            raise GeofeasError(f"{path}: empty file, expected a header line") from None
        missing = [c for c in COLUMNS if c not in header]
        if missing:
            raise GeofeasError(f"{path}: line 1: missing column(s) {', '.join(missing)}")
        index = [header.index(c) for c in COLUMNS]
        rows: list[list[str]] = []
        values: list[list[float]] = []
        for row in reader:
            line = reader.line_num
            if not row or all(not cell.strip() for cell in row):
                continue
            if len(row) != len(header):
                raise GeofeasError(
                    f"{path}: line {line}: {len(row)} fields, header has {len(header)}"
                )
            parsed = []
            for col, i in zip(COLUMNS, index, strict=True):
                try:
                    value = float(row[i])
                except ValueError:
                    raise GeofeasError(
                        f"{path}: line {line}: column {col}: {row[i]!r} is not a number"
                    ) from None
                if not np.isfinite(value):
                    raise GeofeasError(f"{path}: line {line}: column {col}: {value} is not finite")
                if col.endswith(("_rx", "_ry")) and value <= 0:
                    raise GeofeasError(f"{path}: line {line}: column {col}: {value} must be > 0")
                parsed.append(value)
            rows.append(row)
            values.append(parsed)
    return header, rows, np.array(values, dtype=np.float64).reshape(-1, 10)


def score_all(
    data: np.ndarray,
    scores: list[str],
    vertices: int,
    samples: int,
    seed: int | None,
    method: str = SCORE_DEFAULTS["method"],
    sampler: str = SCORE_DEFAULTS["sampler"],
) -> dict[str, np.ndarray]:
    a, b = data[:, :5], data[:, 5:]
    out: dict[str, np.ndarray] = {}
    for name in scores:
        if name == "glr":
            out[name] = glr(a, b)
        elif name == "glr_threshold":
            out[name] = glr(a, b, threshold=True)
        elif name == "overlap":
            out[name] = overlap(
                a, b, method=method, vertices=vertices if method == "polygon" else None
            )
        elif name == "overlap_polygon":
            out[name] = overlap(a, b, method="polygon", vertices=vertices)
        elif name == "monte_carlo":
            out[name] = monte_carlo(a, b, samples=samples, seed=seed, sampler=sampler)
        elif name == "bhattacharyya":
            out[name] = bhattacharyya(a, b)
        elif name == "hellinger":
            out[name] = hellinger(a, b)
        else:
            out[name] = gaussian_product(a, b)
    return out


def run(args: argparse.Namespace) -> int:
    src = example_path() if args.input == "example" else Path(args.input)
    scores = args.score or list(DEFAULT_SCORES)
    start = time.perf_counter()
    header, rows, data = read_pairs(src)
    result = score_all(
        data, scores, args.vertices, args.samples, args.seed, args.method, args.sampler
    )
    elapsed = time.perf_counter() - start
    with contextlib.ExitStack() as stack:
        out_fh: Any = (
            sys.stdout
            if args.out == "-"
            else stack.enter_context(atomic_open(args.out, "w", newline=""))
        )
        writer = csv.writer(out_fh)
        writer.writerow(header + scores)
        for k, row in enumerate(rows):
            writer.writerow(row + [repr(float(result[s][k])) for s in scores])
    if args.out != "-":
        print(f"scored {len(rows)} pairs from {src} in {elapsed:.3f} s -> {args.out}")
        for s in scores:
            v = result[s]
            if len(v):
                print(f"  {s:<14} mean {np.mean(v):.4f}  >= 0.5: {int(np.sum(v >= 0.5))}")
    return 0


def _bound(v: int) -> str:
    return f"2^{v.bit_length() - 1}" if v >= 1024 and v & (v - 1) == 0 else str(v)


def options_markdown() -> str:
    """The score options table of ``README.md``, rendered from the core's schema
    (``python scripts/options_doc.py`` writes it; ``tests/test_score_schema.py`` checks it)."""
    rows = [
        "| option | default | taken by | `geofeas score` | meaning |",
        "|---|---|---|---|---|",
    ]
    for o in SCORE_OPTIONS:
        flag = "--" + o["name"].replace("_", "-") if o in FLAGS else "--score glr_threshold"
        allowed = ""
        if o["choices"]:
            allowed = f" (one of {', '.join(o['choices'])})"
        elif o["range"]:
            allowed = f" (in [{_bound(o['range'][0])}, {_bound(o['range'][1])}])"
        scores = ", ".join(f"`{s}`" for s in o["scores"])
        rows.append(
            f"| `{o['name']}` | `{o['default']!r}` | {scores} | `{flag}` | {o['help']}{allowed} |"
        )
    return "\n".join(rows) + "\n"


#: What a flag changes in the columns, beside the option's meaning.
_NOTES = {
    "method": "; of the 'overlap' column",
    "vertices": "; of overlap_polygon and of overlap with --method polygon",
}


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "score",
        help="score ellipse pairs from a CSV file",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("input", help="pairs CSV, or 'example' for the bundled example")
    p.add_argument("--out", "-o", default="-", help="output CSV (default: standard output)")
    p.add_argument(
        "--score",
        action="append",
        choices=SCORES,
        help="score to compute (repeatable; default: " + ", ".join(DEFAULT_SCORES) + ")",
    )
    options = p.add_argument_group("score options (the keywords of geofeas.overlap, .monte_carlo)")
    for o in FLAGS:
        flag = "--" + o["name"].replace("_", "-")
        note = _NOTES.get(o["name"], "")
        help = f"{o['help']}{note} (default {o['default']})"
        if o["kind"] == "bool":
            options.add_argument(flag, action="store_true", default=o["default"], help=help)
        elif o["choices"]:
            options.add_argument(flag, choices=o["choices"], default=o["default"], help=help)
        else:
            kind = int if o["kind"] == "int" else str
            options.add_argument(flag, type=kind, default=o["default"], help=help)
    p.set_defaults(func=run)
