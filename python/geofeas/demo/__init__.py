"""The end-to-end demo: a simulated multi-source picture over a real AIS recording, associated and
scored against the MMSI ground truth (``geofeas demo``).

:func:`run` reads and cleans the recording (:mod:`geofeas.io.ais`), simulates the sources
(:mod:`geofeas.demo.scenario`), associates the reports with the default configuration (and with any
score and combination rule asked for), scores the association against the truth
(:mod:`geofeas.demo.evaluate`): the triage, the calibration of ``p_same`` (reliability diagram,
expected calibration error) and an operator who answers the review queue truthfully.
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

from .._atomic import atomic_path, save_figure, write_text
from .._core import GeofeasError
from ..association import COMBINE_RULES, associate, read_reports
from ..geodesy import delta_lon, median_lon, metres_per_degree, wrap_lon
from ..io.ais import AisRecording, read_ais
from .evaluate import (
    Metrics,
    evaluate,
    labels,
    oracle_borderline,
    reliability,
    simulate_operator,
    track_table,
)
from .scenario import SENSORS, HfDf, Scenario, simulate

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
    association: Any = None


@dataclass
class DemoResult:
    """Everything :func:`run` produced."""

    recording: AisRecording
    scenario: Scenario
    tracks: pd.DataFrame
    default: Run
    runs: list[Run] = field(default_factory=list)
    #: Reliability table of the default association's ``p_same`` (see
    #: :func:`geofeas.demo.evaluate.reliability`) and its expected calibration error.
    calibration: pd.DataFrame | None = None
    ece: float = math.nan
    #: F1 after each number of truthful operator decisions (:func:`simulate_operator`).
    operator: pd.DataFrame | None = None
    #: With one HF DF source: the fewest borderline HF DF pairs any triage can leave (by an
    #: oracle that judges each fix track alone) while it
    #: loses at most 1 % of the true pairs (:func:`geofeas.demo.evaluate.oracle_borderline`).
    oracle_borderline: float = math.nan

    def summary(self) -> dict[str, float]:
        """The operator's view of the default association: ``operator_load`` (borderline pairs
        per true duplicate pair), ``merge_precision`` (share of the automatic merges that are
        right), ``lost`` (share of the true pairs classed ``non-match``), ``ece`` and
        ``oracle_load`` (:attr:`oracle_borderline` per true pair; NaN without one HF DF
        source)."""
        pairs = self.default.pairs
        y = labels(pairs, self.tracks)
        cls = pairs["class"].to_numpy()
        n_true = max(self.default.metrics.true_pairs, 1)
        match = cls == "match"
        return dict(
            operator_load=float((cls == "borderline").sum() / n_true),
            merge_precision=float(y[match].mean()) if match.any() else math.nan,
            lost=float((y & (cls == "non-match")).sum() / n_true),
            ece=self.ece,
            oracle_load=self.oracle_borderline / n_true,
        )

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
    metrics = evaluate(tracks, pairs, objects=objects, seconds=seconds)
    return Run(score, combine or default_combine(), metrics, pairs, objects, result)


def run(
    ais: str | Path = "solent",
    /,
    *,
    sensors: Sequence[Any] = ("ais", "radar", "aircraft", "hfdf"),
    seed: int = 0,
    minutes: float | None = None,
    scores: Sequence[str] = (),
    combines: Sequence[str] = (),
    options: dict[str, Any] | None = None,
    operator: Sequence[int] | None = (0, 25, 50, 100, 200),
    operator_batch: int = 25,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
) -> DemoResult:
    """Run the demo pipeline.

    Parameters
    ----------
    ais : str or Path
        A bundled recording name (:data:`RECORDINGS`) or the path of an AIS CSV file.
    sensors, seed, minutes
        Passed to :func:`geofeas.demo.scenario.simulate`.
    scores, combines : sequence of str
        Further associations for a comparison table of the ``score`` column's configurations
        (keys of :data:`SCORES`, and combination rules, each with the other's default). The
        classes come from the posterior, which does not depend on them.
    options : dict, optional
        Further keyword options of every ``associate`` call (``p_match``, ``p_reject``, ...).
    operator : sequence of int, optional
        Decision counts at which the simulated operator's F1 is recorded (``None``: no
        simulation).
    operator_batch : int
        Decisions the simulated operator answers between two recomputations of the
        association (:func:`simulate_operator`'s ``batch``; a review station recomputes after
        every decision, ``1``, at a recomputation's cost each).
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
    for s in scores:
        if s not in SCORES:
            raise GeofeasError(f"unknown score {s!r}; expected one of {list(SCORES)}")
    for c in combines:
        if c not in COMBINE_RULES:
            raise GeofeasError(f"unknown combination rule {c!r}; expected one of {COMBINE_RULES}")
    dflt = default_combine()
    configs = [(s, dflt) for s in scores] + [("glr", c) for c in combines]
    configs = [c for k, c in enumerate(configs) if c not in configs[:k] and c != ("glr", dflt)]
    steps = 1 + len(configs) + (1 if operator is not None else 0)
    bar = Progress(steps, "demo") if progress else None
    say(f"associating {len(sc.reports)} reports")
    default = _associate(reports, tracks, "glr", None, opts)
    if bar:
        bar.step(f"glr / {dflt} (default)")
    table, ece = reliability(default.pairs["p_same"], labels(default.pairs, tracks))
    specs = [SENSORS[s] if isinstance(s, str) else s for s in sensors]
    df_names = [spec.name for spec in specs if isinstance(spec, HfDf)]
    bound = math.nan
    if len(df_names) == 1:
        bound = oracle_borderline(sc, rec, default.pairs, tracks, source=df_names[0])
    runs = []
    for s, c in configs:
        runs.append(_associate(reports, tracks, s, c, opts))
        if bar:
            bar.step(f"{s} / {c}")
    op = None
    if operator is not None:
        op = simulate_operator(
            default.association, tracks, checkpoints=operator, batch=operator_batch
        )
        if bar:
            bar.step("simulated operator")
    return DemoResult(rec, sc, tracks, default, runs, table, ece, op, bound)


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
    lat0, lon0 = float(np.median(snap["lat"])), median_lon(snap["lon"])
    m_lat, m_lon = metres_per_degree(lat0)
    x = delta_lon(snap["lon"].to_numpy(), lon0) * m_lon
    y = (snap["lat"].to_numpy() - lat0) * m_lat
    inside = (np.abs(x[:, None] - x[None, :]) <= size / 2) & (
        np.abs(y[:, None] - y[None, :]) <= size / 2
    )
    k = int(np.argmax(inside.sum(axis=1)))
    return (
        lat0 + y[k] / m_lat,
        float(wrap_lon(lon0 + x[k] / m_lon)),
        float(sec.min() + (best + 1) * window),
    )


def plot_map(
    result: DemoResult,
    path: str | Path,
    /,
    *,
    size: float = 4000.0,
    window: float = 60.0,
) -> Path:
    """Write a PNG map of the busiest area: the latest AOU of every track within ``window``
    seconds on the coastline (GSHHG from Debian's ``gmt-gshhg-*`` files when installed), a scale
    bar and a north arrow. Each object the default association merged has its own colour
    (cycled through a qualitative palette with a second line style, so no two objects nearby look
    alike); tracks left alone are grey. The truth is in the key: an object holding tracks of two
    vessels is a false merge (thick red outline), a track whose vessel's other tracks were merged
    without it is a miss (thick orange outline). AIS reports are drawn as their 20 m circles with
    a dot at the centre so they stay visible at the map's scale. Needs matplotlib
    (``pip install "geofeas[plot]"``)."""
    plt = _pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Ellipse

    from ..review.coast import Coastline, coastline

    sc = result.scenario
    rep, sec = sc.reports, sc.seconds
    lat_c, lon_c, t_c = busy_window(rep, sec, size=size, window=window)
    m_lat, m_lon = metres_per_degree(lat_c)
    sel = (sec > t_c - window) & (sec <= t_c)
    snap = rep[sel].assign(t=sec[sel])
    snap = snap.sort_values("t").groupby("track_id").tail(1)
    x = delta_lon(snap["lon"].to_numpy(), lon_c) * m_lon
    y = (snap["lat"].to_numpy() - lat_c) * m_lat
    half = size / 2 * 1.2
    objects = result.default.objects
    obj: dict[str, int] = {}
    if objects is not None:
        sizes = objects.groupby("object")["track_id"].transform("size")
        grouped = np.where(sizes > 1, objects["object"], -1)
        obj = dict(zip(objects["track_id"].astype(str), grouped.tolist(), strict=True))
    mmsi = result.tracks["mmsi"]
    # the truth behind each merged object: its vessels; a false merge holds two
    members: dict[int, set[int]] = {}
    for tid, o in obj.items():
        if o != -1 and tid in mmsi.index and mmsi[tid] >= 0:
            members.setdefault(o, set()).add(int(mmsi[tid]))
    false_merge = {o for o, v in members.items() if len(v) > 1}
    # a miss: a track of a vessel whose other tracks form an object it is not in
    vessel_objects: dict[int, set[int]] = {}
    for tid, o in obj.items():
        if o != -1 and tid in mmsi.index and mmsi[tid] >= 0:
            vessel_objects.setdefault(int(mmsi[tid]), set()).add(o)
    palette = list(plt.get_cmap("tab10").colors) + list(plt.get_cmap("Dark2").colors)
    ids = sorted({v for v in obj.values() if v != -1})
    style_of = {
        o: (palette[k % len(palette)], "-" if (k // len(palette)) % 2 == 0 else "--")
        for k, o in enumerate(ids)
    }
    fig, ax = plt.subplots(figsize=(9, 9))
    west, east = lon_c - half / m_lon, lon_c + half / m_lon
    south, north = lat_c - half / m_lat, lat_c + half / m_lat
    try:
        coast = coastline(south - 0.05, west - 0.05, north + 0.05, east + 0.05)
        lines = coast.clip(south - 0.02, west - 0.02, north + 0.02, east + 0.02)
    except ImportError:  # the coastline reader (h5py, shapely) is in the "review" extra
        coast, lines = Coastline([], None), []
    for line in lines:
        ax.plot(
            delta_lon(line[:, 0], lon_c) * m_lon / 1000,
            (line[:, 1] - lat_c) * m_lat / 1000,
            color="#8a6d3b",
            lw=1.0,
        )
    n_false = n_miss = 0
    for (_, r), xi, yi in zip(snap.iterrows(), x, y, strict=True):
        tid = str(r["track_id"])
        o = obj.get(tid, -1)
        colour, ls = style_of.get(o, ((0.55, 0.55, 0.55), ":"))
        vessel = int(mmsi[tid]) if tid in mmsi.index else -1
        missed = o == -1 and vessel >= 0 and bool(vessel_objects.get(vessel))
        wrong = o in false_merge
        n_false += int(wrong)
        n_miss += int(missed)
        if wrong or missed:
            ax.add_patch(
                Ellipse(
                    (xi / 1000, yi / 1000),
                    2 * r["rx"] / 1000,
                    2 * r["ry"] / 1000,
                    angle=90.0 - r["bearing"],
                    fill=False,
                    lw=3.2,
                    ec="red" if wrong else "orange",
                    alpha=0.5,
                )
            )
        ax.add_patch(
            Ellipse(
                (xi / 1000, yi / 1000),
                2 * r["rx"] / 1000,
                2 * r["ry"] / 1000,
                angle=90.0 - r["bearing"],
                fill=r["source"] == "ais",
                fc=(*colour[:3], 0.35) if r["source"] == "ais" else "none",
                lw=1.3 if r["source"] != "hfdf" else 0.8,
                ls=ls,
                ec=colour,
            )
        )
        if r["source"] == "ais":
            ax.plot(xi / 1000, yi / 1000, marker="o", ms=2.5, color=colour)
    ax.set_xlim(-half / 1000, half / 1000)
    ax.set_ylim(-half / 1000, half / 1000)
    ax.set_aspect("equal")
    ax.set_xlabel(f"east of {lon_c:.4f}°, km")
    ax.set_ylabel(f"north of {lat_c:.4f}°, km")
    # scale bar and north arrow
    bar = 1.0 if half > 1500 else 0.2
    x0, y0 = -half / 1000 * 0.92, -half / 1000 * 0.92
    ax.plot([x0, x0 + bar], [y0, y0], color="k", lw=3)
    ax.text(x0 + bar / 2, y0 + 0.04 * half / 1000, f"{bar:g} km", ha="center", fontsize=9)
    ax.annotate(
        "N",
        xy=(half / 1000 * 0.9, half / 1000 * 0.9),
        xytext=(half / 1000 * 0.9, half / 1000 * 0.72),
        ha="center",
        fontsize=11,
        arrowprops=dict(arrowstyle="-|>", color="k"),
    )
    stamp = pd.Timestamp(t_c, unit="s").strftime("%Y-%m-%d %H:%M:%S")
    ax.set_title(
        f"AOUs (2-sigma) of the tracks reporting in the {window:g} s before {stamp} UTC: "
        f"{len(ids)} objects merged,\n{n_false} tracks in false merges, {n_miss} missed tracks "
        f"(by the truth); coastline: {'GSHHG' if coast.source else 'not installed'}"
    )
    handles = [
        Line2D(
            [],
            [],
            color="0.3",
            marker="o",
            ms=6,
            ls="",
            mfc=(0.3, 0.3, 0.3, 0.35),
            label="AIS (20 m circle, dot at centre)",
        ),
        Line2D([], [], color="0.3", ls="-", label="radar / aircraft / HF DF AOU"),
        Line2D([], [], color=palette[0], ls="-", label="one colour per merged object"),
        Line2D([], [], color=(0.55, 0.55, 0.55), ls=":", label="left alone (no partner)"),
        Line2D([], [], color="red", lw=3.2, alpha=0.5, label="false merge (two vessels)"),
        Line2D([], [], color="orange", lw=3.2, alpha=0.5, label="missed: not with its vessel"),
        Line2D([], [], color="#8a6d3b", label="coastline (GSHHG)"),
    ]
    ax.legend(handles=handles, loc="upper left", fontsize=8)
    ax.grid(alpha=0.25)
    out = Path(path)
    save_figure(fig, out, dpi=130, bbox_inches="tight")
    plt.close(fig)
    return out


def write_outputs(
    result: DemoResult, out: str | Path, *, map_png: bool = True, figures: bool = True
) -> list[Path]:
    """Write ``reports.csv`` (the simulated reports, every value exactly as associated),
    ``pairs.csv`` (default association, with the truth), ``metrics.csv``,
    ``metrics.md`` (the table in Markdown), ``metrics_by_sources.csv``, ``calibration.csv``
    and ``operator.csv`` (when the result has them) into ``out``, and with ``figures`` (they
    need matplotlib) ``calibration.png``, ``operator.png`` and, with ``map_png`` too,
    ``map.png``; returns the paths written."""
    d = Path(out)
    d.mkdir(parents=True, exist_ok=True)
    written = []
    p = d / "reports.csv"
    with atomic_path(p) as tmp:
        # every float as the shortest text that reads back to the same double: the file is the
        # picture the demo associated, so `geofeas associate reports.csv` gives its pairs
        result.scenario.reports.to_csv(tmp, index=False)
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
    if result.calibration is not None:
        p = d / "calibration.csv"
        with atomic_path(p) as tmp:
            result.calibration.to_csv(tmp, index=False, float_format="%.5f")
        written.append(p)
    if result.operator is not None:
        p = d / "operator.csv"
        with atomic_path(p) as tmp:
            result.operator.to_csv(tmp, index=False, float_format="%.4f")
        written.append(p)
    if figures:
        if map_png:
            written.append(plot_map(result, d / "map.png"))
        if result.calibration is not None:
            written.append(plot_reliability(result, d / "calibration.png"))
        if result.operator is not None:
            written.append(plot_operator(result, d / "operator.png"))
    return written


def _name(result: DemoResult) -> str:
    return Path(result.recording.source).name if result.recording.source else "recording"


def _pyplot() -> Any:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise GeofeasError(
            'the figures need matplotlib: pip install "geofeas[plot]" (or use --no-figures)'
        ) from None
    return plt


def plot_reliability(result: DemoResult, path: str | Path, /) -> Path:
    """The reliability diagram of the default association: observed frequency of true
    duplicate-track pairs against the predicted ``p_same``, per bin, with Wilson 95 % intervals
    and the number of pairs per bin."""
    plt = _pyplot()
    t = result.calibration
    if t is None:
        raise GeofeasError("no calibration table: run the demo first")
    fig, (ax, hist) = plt.subplots(
        2, 1, figsize=(6, 7), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    ax.plot([0, 1], [0, 1], color="0.6", lw=1, label="perfect calibration")
    yerr = np.vstack([t["observed"] - t["observed_lo"], t["observed_hi"] - t["observed"]])
    ax.errorbar(
        t["predicted"],
        t["observed"],
        yerr=yerr,
        fmt="o-",
        color="C0",
        capsize=3,
        label="observed (Wilson 95 %)",
    )
    ax.set_ylabel("observed frequency of true duplicates")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left")
    ax.set_title(
        f"Reliability of p_same ({_name(result)})\n"
        f"expected calibration error {result.ece:.4f}, {int(t['n'].sum())} pairs"
    )
    hist.bar((t["lo"] + t["hi"]) / 2, t["n"], width=t["hi"] - t["lo"], color="C0", alpha=0.6)
    hist.set_yscale("log")
    hist.set_xlabel("predicted P(same object)")
    hist.set_ylabel("pairs")
    out = Path(path)
    save_figure(fig, out, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return out


def plot_operator(result: DemoResult, path: str | Path, /) -> Path:
    """F1 of the association after each number of truthful operator decisions in review
    order."""
    plt = _pyplot()
    t = result.operator
    if t is None:
        raise GeofeasError("no operator simulation: run the demo with operator checkpoints")
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(t["decisions"], t["f1"], "o-", label="F1")
    ax.plot(t["decisions"], t["object_f1"], "D:", label="F1 of the objects' pairs", alpha=0.7)
    ax.plot(t["decisions"], t["precision"], "s--", label="precision", alpha=0.7)
    ax.plot(t["decisions"], t["recall"], "^--", label="recall", alpha=0.7)
    ax.set_xlabel("operator decisions (review order)")
    ax.set_ylabel("duplicate-track pairs")
    lowest = float(t[["f1", "object_f1", "precision", "recall"]].min().min())
    ax.set_ylim(min(0.8, lowest - 0.02), 1.0)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right")
    ax.set_title(f"A truthful operator in review order ({_name(result)})")
    out = Path(path)
    save_figure(fig, out, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return out


def markdown_table(result: DemoResult) -> str:
    """The comparison table (one row per score and combination rule) in Markdown."""
    lines = [
        "| score | combine | precision | recall | F1 | match | borderline | non-match | time (s) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in [result.default, *result.runs]:
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
