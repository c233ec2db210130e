"""The end-to-end demo: a simulated multi-source picture over a real AIS recording, associated and
scored against the MMSI ground truth (``geofeas demo``).

:func:`run` reads and cleans the recording (:mod:`geofeas.ais`), simulates the sources
(:mod:`geofeas.scenario`), associates the reports with the default configuration and with every
score and combination rule asked for, and scores each association (:mod:`geofeas.evaluate`).
:func:`plot_map` draws the AOUs of a busy area coloured by associated object.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, TextIO

import numpy as np
import pandas as pd

from ._atomic import atomic_path, save_figure, write_text
from ._core import GeofeasError
from .ais import AisRecording, read_ais
from .association import COMBINE_RULES, associate, read_reports
from .evaluate import Metrics, evaluate, track_table
from .scenario import Scenario, metres_per_degree, simulate

__all__ = ["RECORDINGS", "SCORES", "DemoResult", "Progress", "bundled", "plot_map", "run"]

#: Bundled AIS recordings by short name.
RECORDINGS = {
    "solent": "solent_ais_20160112.csv",
    "nyharbor": "nyharbor_ais_20200630.csv",
}

#: The scores of the comparison table: name -> (engine score, score options).
SCORES: dict[str, tuple[str, dict[str, Any]]] = {
    "glr": ("glr", {}),
    "glr_threshold": ("glr", {"threshold": True}),
    "overlap": ("overlap", {}),
    "monte_carlo": ("monte_carlo", {"seed": 0}),
}

REPORT_COLUMNS = ["track_id", "source", "time", "lat", "lon", "rx", "ry", "bearing"]


def bundled(name: str) -> Path:
    """Path of a bundled AIS recording (``"solent"`` or ``"nyharbor"``)."""
    if name not in RECORDINGS:
        raise GeofeasError(
            f"unknown bundled recording {name!r}; expected one of {sorted(RECORDINGS)}"
        )
    return Path(str(resources.files("geofeas") / "data" / RECORDINGS[name]))


class Progress:
    """A minimal progress bar on a stream (stderr by default): redrawn in place on a terminal,
    one line per step otherwise; with elapsed time and an estimate of the time left."""

    def __init__(self, total: int, label: str, stream: TextIO | None = None, width: int = 30):
        self.total, self.label, self.width = max(int(total), 1), label, width
        self.stream = stream if stream is not None else sys.stderr
        self.done = 0
        self.start = time.perf_counter()
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def step(self, what: str = "") -> None:
        """Mark one step done (``what`` names it)."""
        self.done = min(self.done + 1, self.total)
        elapsed = time.perf_counter() - self.start
        left = elapsed / self.done * (self.total - self.done)
        fill = int(self.width * self.done / self.total)
        bar = "#" * fill + "-" * (self.width - fill)
        msg = (
            f"{self.label} [{bar}] {self.done}/{self.total} {elapsed:5.1f} s"
            f" (~{left:.0f} s left) {what}"
        )
        if self.tty:
            end = "\n" if self.done == self.total else ""
            self.stream.write("\r" + msg.ljust(100)[:100] + end)
        else:
            self.stream.write(msg + "\n")
        self.stream.flush()


@dataclass
class Run:
    """One association of the comparison: its configuration, pairs, objects and metrics."""

    score: str
    combine: str
    metrics: Metrics
    pairs: pd.DataFrame
    objects: pd.DataFrame | None


@dataclass
class DemoResult:
    """Everything :func:`run` produced."""

    recording: AisRecording
    scenario: Scenario
    tracks: pd.DataFrame
    default: Run
    runs: list[Run] = field(default_factory=list)

    def metrics_table(self) -> pd.DataFrame:
        """One row per association (the default first): score, combine and the metrics."""
        rows = []
        for k, r in enumerate([self.default, *self.runs]):
            row = {"config": "default" if k == 0 else "", "score": r.score, "combine": r.combine}
            row.update(r.metrics.row())
            rows.append(row)
        return pd.DataFrame(rows)


def default_combine() -> str:
    """Name of the engine's default combination rule (from ``associate``'s signature)."""
    import inspect

    return str(inspect.signature(associate).parameters["combine"].default)


def _associate(
    reports: Any,
    tracks: pd.DataFrame,
    score: str,
    combine: str | None,
    options: dict[str, Any],
) -> Run:
    kwargs: dict[str, Any] = dict(options)
    name, extra = SCORES[score]
    kwargs.update(extra)
    if combine is not None:
        kwargs["combine"] = combine
    t0 = time.perf_counter()
    result = associate(reports, score=name, **kwargs)
    seconds = time.perf_counter() - t0
    pairs = result.pairs
    objects = getattr(result, "objects", None)
    upper = getattr(result, "options", {}).get("upper")
    metrics = evaluate(tracks, pairs, objects=objects, seconds=seconds, upper=upper)
    return Run(score, combine or default_combine(), metrics, pairs, objects)


def run(
    ais: str | Path = "solent",
    /,
    *,
    sensors: Sequence[Any] = ("ais", "radar", "aircraft", "hfdf"),
    seed: int = 0,
    minutes: float | None = None,
    scores: Sequence[str] | None = None,
    combines: Sequence[str] | None = None,
    grid: bool = False,
    options: dict[str, Any] | None = None,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
) -> DemoResult:
    """Run the demo pipeline.

    Parameters
    ----------
    ais : str or Path
        A bundled recording name (:data:`RECORDINGS`) or the path of an AIS CSV file.
    sensors, seed, minutes
        Passed to :func:`geofeas.scenario.simulate`.
    scores : sequence of str, optional
        Scores of the comparison table (keys of :data:`SCORES`; default all).
    combines : sequence of str, optional
        Combination rules of the table (default: all the engine offers).
    grid : bool
        Table over every score x rule; by default each score with the default rule and each rule
        with the default score (``glr``).
    options : dict, optional
        Further keyword options of every ``associate`` call (``lower``, ``upper``, ...).
    progress : bool
        Show a progress bar on stderr over the associations.
    log : callable, optional
        Receives the progress messages of the stages (default: silent).

    Returns
    -------
    DemoResult
    """
    say = log or (lambda _msg: None)
    path = bundled(str(ais)) if str(ais) in RECORDINGS else Path(ais)
    rec = read_ais(path)
    say(rec.summary())
    sc = simulate(rec, sensors=sensors, seed=seed, minutes=minutes)
    tracks = track_table(sc.reports, sc.seconds)
    reports = read_reports(sc.reports[REPORT_COLUMNS])
    opts = dict(options or {})
    scores = list(scores) if scores is not None else list(SCORES)
    for s in scores:
        if s not in SCORES:
            raise GeofeasError(f"unknown score {s!r}; expected one of {list(SCORES)}")
    combines = list(combines) if combines is not None else list(COMBINE_RULES)
    for c in combines:
        if c not in COMBINE_RULES:
            raise GeofeasError(f"unknown combination rule {c!r}; expected one of {COMBINE_RULES}")
    dflt = default_combine()
    if grid:
        configs = [(s, c) for s in scores for c in combines]
    else:
        configs = [(s, dflt) for s in scores] + [("glr", c) for c in combines]
        configs = [c for k, c in enumerate(configs) if c not in configs[:k]]
    todo = [c for c in configs if c != ("glr", dflt)]
    bar = Progress(1 + len(todo), "associate") if progress else None
    say(f"associating {len(sc.reports)} reports: {1 + len(todo)} configurations")
    default = _associate(reports, tracks, "glr", None, opts)
    if bar:
        bar.step(f"glr / {dflt} (default)")
    runs = []
    for s, c in configs:
        if (s, c) == ("glr", dflt):
            runs.append(default)
            continue
        runs.append(_associate(reports, tracks, s, c, opts))
        if bar:
            bar.step(f"{s} / {c}")
    return DemoResult(rec, sc, tracks, default, runs)


# ------------------------------------------------------------------------------------ map


def busy_window(
    reports: pd.DataFrame, seconds: np.ndarray, *, size: float = 4000.0, window: float = 60.0
) -> tuple[float, float, float]:
    """Centre ``(lat, lon)`` and end time of the busiest ``size``-metre square and
    ``window``-second interval: the interval with the most tracks reporting, and in it the square
    centred on a report that holds the most tracks."""
    sec = np.asarray(seconds, dtype=np.float64)
    bins = np.floor((sec - sec.min()) / window).astype(np.int64)
    per_bin = pd.DataFrame({"b": bins, "track": reports["track_id"].to_numpy()})
    best = int(per_bin.drop_duplicates().groupby("b").size().idxmax())
    sel = bins == best
    snap = reports[sel]
    lat0, lon0 = float(np.median(snap["lat"])), float(np.median(snap["lon"]))
    m_lat, m_lon = metres_per_degree(lat0)
    x = (snap["lon"].to_numpy() - lon0) * m_lon
    y = (snap["lat"].to_numpy() - lat0) * m_lat
    inside = (np.abs(x[:, None] - x[None, :]) <= size / 2) & (
        np.abs(y[:, None] - y[None, :]) <= size / 2
    )
    k = int(np.argmax(inside.sum(axis=1)))
    return lat0 + y[k] / m_lat, lon0 + x[k] / m_lon, float(sec.min() + (best + 1) * window)


def plot_map(
    result: DemoResult,
    path: str | Path,
    /,
    *,
    size: float = 4000.0,
    window: float = 60.0,
) -> Path:
    """Write a PNG map of the busiest area: the latest AOU of every track within ``window``
    seconds, coloured by the object the default association put it in (grey: alone), with the
    true vessel positions. Needs matplotlib (``pip install "geofeas[plot]"``)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.lines import Line2D
        from matplotlib.patches import Ellipse
    except ImportError:
        raise GeofeasError(
            'the map needs matplotlib: pip install "geofeas[plot]" (or use --no-map)'
        ) from None
    sc = result.scenario
    rep, sec = sc.reports, sc.seconds
    lat_c, lon_c, t_c = busy_window(rep, sec, size=size, window=window)
    m_lat, m_lon = metres_per_degree(lat_c)
    snap = rep[(sec > t_c - window) & (sec <= t_c)].assign(
        t=sec[(sec > t_c - window) & (sec <= t_c)]
    )
    snap = snap.sort_values("t").groupby("track_id").tail(1)
    x = (snap["lon"].to_numpy() - lon_c) * m_lon
    y = (snap["lat"].to_numpy() - lat_c) * m_lat
    half = size / 2 * 1.2
    objects = result.default.objects
    obj = {}
    if objects is not None:
        sizes = objects.groupby("object")["track_id"].transform("size")
        grouped = np.where(sizes > 1, objects["object"], -1)
        obj = dict(zip(objects["track_id"].astype(str), grouped, strict=True))
    cmap = plt.get_cmap("tab20")
    styles = {"ais": "-", "radar": "--", "aircraft": ":", "hfdf": "-."}
    fig, ax = plt.subplots(figsize=(9, 9))
    ids = sorted({v for v in obj.values() if v != -1})
    colour_of = {o: cmap(k % 20) for k, o in enumerate(ids)}
    for (_, r), xi, yi in zip(snap.iterrows(), x, y, strict=True):
        o = obj.get(str(r["track_id"]), -1)
        colour = colour_of.get(o, (0.5, 0.5, 0.5, 1.0))
        ax.add_patch(
            Ellipse(
                (xi / 1000, yi / 1000),
                2 * r["rx"] / 1000,
                2 * r["ry"] / 1000,
                angle=90.0 - r["bearing"],
                fill=False,
                lw=1.2 if r["source"] != "hfdf" else 0.8,
                ls=styles.get(r["source"], "-"),
                ec=colour,
            )
        )
    truth = rep[(rep["source"] == "ais") & (sec > t_c - window) & (sec <= t_c)]
    ax.plot(
        (truth["lon"] - lon_c) * m_lon / 1000,
        (truth["lat"] - lat_c) * m_lat / 1000,
        "k.",
        ms=2,
    )
    ax.set_xlim(-half / 1000, half / 1000)
    ax.set_ylim(-half / 1000, half / 1000)
    ax.set_aspect("equal")
    ax.set_xlabel(f"east of {lon_c:.4f}°, km")
    ax.set_ylabel(f"north of {lat_c:.4f}°, km")
    stamp = pd.Timestamp(t_c, unit="s").strftime("%Y-%m-%d %H:%M:%S")
    ax.set_title(
        f"AOUs (2-sigma) of the tracks reporting in the {window:g} s before {stamp} UTC,\n"
        "coloured by associated object (grey: alone); "
        f"{result.default.score} / {result.default.combine}"
    )
    handles = [Line2D([], [], color="k", ls=ls, label=s) for s, ls in styles.items()]
    handles.append(Line2D([], [], color="k", marker=".", ls="", label="AIS report"))
    ax.legend(handles=handles, loc="upper right")
    ax.grid(alpha=0.3)
    out = Path(path)
    save_figure(fig, out, dpi=130, bbox_inches="tight")
    plt.close(fig)
    return out


def write_outputs(result: DemoResult, out: str | Path, *, map_png: bool = True) -> list[Path]:
    """Write ``reports.csv``, ``pairs.csv`` (default association, with the truth), ``metrics.csv``,
    ``metrics.md`` (the table in Markdown), ``metrics_by_sources.csv`` and ``map.png`` into
    ``out``; returns the paths written."""
    d = Path(out)
    d.mkdir(parents=True, exist_ok=True)
    written = []
    p = d / "reports.csv"
    with atomic_path(p) as tmp:
        result.scenario.reports.to_csv(tmp, index=False, float_format="%.7f")
    written.append(p)
    pairs = result.default.pairs.copy()
    t = result.tracks
    a, b = pairs["track_a"].astype(str), pairs["track_b"].astype(str)
    ma, mb = t["mmsi"].reindex(a).to_numpy(), t["mmsi"].reindex(b).to_numpy()
    from .evaluate import true_pairs

    truth = true_pairs(t)
    pairs["true_pair"] = [((x, y) if x < y else (y, x)) in truth for x, y in zip(a, b, strict=True)]
    pairs["mmsi_a"], pairs["mmsi_b"] = ma, mb
    p = d / "pairs.csv"
    with atomic_path(p) as tmp:
        pairs.to_csv(tmp, index=False)
    written.append(p)
    p = d / "metrics.csv"
    with atomic_path(p) as tmp:
        result.metrics_table().to_csv(tmp, index=False, float_format="%.4f")
    written.append(p)
    p = d / "metrics.md"
    write_text(p, markdown_table(result), encoding="utf-8")
    written.append(p)
    if result.default.metrics.by_sources is not None:
        p = d / "metrics_by_sources.csv"
        with atomic_path(p) as tmp:
            result.default.metrics.by_sources.to_csv(tmp, index=False, float_format="%.4f")
        written.append(p)
    if map_png:
        written.append(plot_map(result, d / "map.png"))
    return written


def markdown_table(result: DemoResult) -> str:
    """The comparison table (one row per score and combination rule) in Markdown."""
    lines = [
        "| score | combine | precision | recall | F1 | match | borderline | non-match | time (s) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in result.runs or [result.default]:
        m = r.metrics
        name = f"**{r.score}**" if r is result.default else r.score
        rule = f"**{r.combine}**" if r is result.default else r.combine
        lines.append(
            f"| {name} | {rule} | {fmt(m.precision)} | {fmt(m.recall)} | {fmt(m.f1)} | "
            f"{m.classes['match']} | {m.classes['borderline']} | {m.classes['non-match']} | "
            f"{m.seconds:.1f} |"
        )
    return "\n".join(lines) + "\n"


def fmt(v: float) -> str:
    """A metric for a table."""
    return "-" if isinstance(v, float) and math.isnan(v) else f"{v:.3f}"
