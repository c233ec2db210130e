"""SVG drawings of the pair view, made on the server: the map (both tracks' AOU ellipses at the
common instants in a local metric frame, the rival tracks faded, the GSHHG coastline, a scale
bar and a north arrow) and the chart of the per-instant distance over time with its bands.

The map's frame is east/north metres about the pair's median position (the local tangent plane:
metres per degree of the WGS84 ellipsoid at that latitude), north up. The instant under the time
slider is drawn by the page's script from the arrays :func:`pair_payload` returns.
"""

from __future__ import annotations

import html
import math
from typing import Any, cast

import numpy as np

from ..geodesy import delta_lon, metres_per_degree
from .station import PairDetail

__all__ = ["BANDS", "distance_svg", "map_svg", "pair_payload"]

#: Distance bands in standard errors: the 95 % and 99 % points of the distance of one instant
#: of a true pair (the squared distance of two 2-D Gaussian positions is chi-square with 2
#: degrees of freedom: sqrt(-2 ln 0.05) = 2.448, sqrt(-2 ln 0.01) = 3.035).
BANDS = (
    (0.0, math.sqrt(-2 * math.log(0.05)), "agree", "#d8efd3"),
    (math.sqrt(-2 * math.log(0.05)), math.sqrt(-2 * math.log(0.01)), "doubtful", "#fbe7b5"),
    (math.sqrt(-2 * math.log(0.01)), math.inf, "disagree", "#f6cfca"),
)
COLOUR_A = "#1f5fbf"
COLOUR_B = "#d0452b"
MAP_W, MAP_H = 720, 560
#: At most this many faint ellipses per track are drawn as the trail (every k-th instant).
TRAIL = 120


def _f(x: float) -> str:
    return f"{x:.1f}"


def _nice(length: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above ``length``."""
    if length <= 0:
        return 1.0
    p = 10 ** math.floor(math.log10(length))
    for m in (5, 2, 1):
        if m * p <= length:
            return m * p
    return p


class Frame:
    """Metres to SVG pixels: the view box ``(x0, y0, x1, y1)`` (metres) fitted into the map."""

    def __init__(self, x0: float, y0: float, x1: float, y1: float) -> None:
        w, h = max(x1 - x0, 1.0), max(y1 - y0, 1.0)
        self.scale = min((MAP_W - 40) / w, (MAP_H - 40) / h)
        self.cx, self.cy = (x0 + x1) / 2, (y0 + y1) / 2

    def x(self, v: Any) -> Any:
        return MAP_W / 2 + (np.asarray(v) - self.cx) * self.scale

    def y(self, v: Any) -> Any:
        return MAP_H / 2 - (np.asarray(v) - self.cy) * self.scale

    def metres(self) -> tuple[float, float, float, float]:
        hw, hh = MAP_W / 2 / self.scale, MAP_H / 2 / self.scale
        return self.cx - hw, self.cy - hh, self.cx + hw, self.cy + hh


def _extent(d: PairDetail) -> tuple[float, float, float, float]:
    e = np.r_[d.ell_a, d.ell_b]
    if not len(e):
        return -1000.0, -1000.0, 1000.0, 1000.0
    r = e[:, 2]
    x0, x1 = float(np.min(e[:, 0] - r)), float(np.max(e[:, 0] + r))
    y0, y1 = float(np.min(e[:, 1] - r)), float(np.max(e[:, 1] + r))
    pad = 0.1 * max(x1 - x0, y1 - y0, 200.0)
    return x0 - pad, y0 - pad, x1 + pad, y1 + pad


def _ellipse(fr: Frame, e: np.ndarray, cls: str, extra: str = "") -> str:
    return (
        f'<ellipse class="{cls}" cx="{_f(fr.x(e[0]))}" cy="{_f(fr.y(e[1]))}" '
        f'rx="{_f(max(e[2] * fr.scale, 0.5))}" ry="{_f(max(e[3] * fr.scale, 0.5))}" '
        f'transform="rotate({_f(-e[4])} {_f(fr.x(e[0]))} {_f(fr.y(e[1]))})"{extra}/>'
    )


def _path(fr: Frame, xy: np.ndarray) -> str:
    pts = " ".join(f"{_f(x)},{_f(y)}" for x, y in zip(fr.x(xy[:, 0]), fr.y(xy[:, 1]), strict=True))
    return pts


def map_svg(d: PairDetail) -> str:
    """The map of the pair view as an SVG element."""
    fr = Frame(*_extent(d))
    x0, y0, x1, y1 = fr.metres()
    out = [
        f'<svg id="map" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {MAP_W} {MAP_H}" '
        f'width="{MAP_W}" height="{MAP_H}" role="img" aria-label="map of the two tracks">',
        f'<rect class="sea" x="0" y="0" width="{MAP_W}" height="{MAP_H}"/>',
    ]
    coast_note = "planar picture: no coastline"
    if d.origin is not None:
        lat0, lon0 = d.origin
        m_lat, m_lon = (float(v) for v in metres_per_degree(lat0))
        c = d.coast
        if c.source is None:
            coast_note = "no coastline: install gmt-gshhg-high (GSHHG)"
        else:
            coast_note = "coastline: GSHHG 2.3"
            box = (lat0 + y0 / m_lat, lon0 + x0 / m_lon, lat0 + y1 / m_lat, lon0 + x1 / m_lon)
            for line in c.clip(*box):
                xy = np.c_[delta_lon(line[:, 0], lon0) * m_lon, (line[:, 1] - lat0) * m_lat]
                out.append(f'<polyline class="coast" points="{_path(fr, xy)}"/>')
    # rival tracks, faded
    for name, e in d.rivals.items():
        step = max(1, len(e) // 40)
        out.append(f'<g class="rival" data-track="{html.escape(name)}">')
        for row in e[::step]:
            out.append(_ellipse(fr, row, "rival-aou"))
        out.append(f'<polyline class="rival-path" points="{_path(fr, e[:, :2])}"/>')
        last = e[-1]
        out.append(
            f'<text class="rival-label" x="{_f(fr.x(last[0]) + 4)}" y="{_f(fr.y(last[1]) - 4)}">'
            f"{html.escape(name)}</text></g>"
        )
    # trails of the two tracks: every k-th instant faint, and the centre paths
    for cls, e in (("a", d.ell_a), ("b", d.ell_b)):
        step = max(1, math.ceil(len(e) / TRAIL))
        out.append(f'<g class="trail trail-{cls}">')
        for k in range(0, len(e), step):
            out.append(_ellipse(fr, e[k], f"aou aou-{cls}", f' data-k="{k}"'))
        out.append(f'<polyline class="path path-{cls}" points="{_path(fr, e[:, :2])}"/></g>')
    # the instant under the slider (moved by the page's script)
    k = len(d.time) // 2
    if len(d.time):
        out.append(_ellipse(fr, d.ell_a[k], "now now-a", ' id="now-a"'))
        out.append(_ellipse(fr, d.ell_b[k], "now now-b", ' id="now-b"'))
    # scale bar
    bar = _nice((x1 - x0) / 5)
    px = bar * fr.scale
    label = f"{bar / 1000:g} km" if bar >= 1000 else f"{bar:g} m"
    out.append(
        f'<g class="scale"><rect x="16" y="{MAP_H - 30}" width="{_f(px)}" height="6"/>'
        f'<text x="16" y="{MAP_H - 36}">{label}</text></g>'
    )
    # north arrow (north is up in the local frame)
    out.append(
        f'<g class="north" transform="translate({MAP_W - 30} 44)">'
        '<path d="M0,-24 L8,4 L0,-2 L-8,4 Z"/><text x="0" y="18" text-anchor="middle">N</text></g>'
    )
    out.append(
        f'<text class="note" x="{MAP_W - 8}" y="{MAP_H - 8}" text-anchor="end">'
        f"{html.escape(coast_note)}</text>"
    )
    out.append("</svg>")
    return "".join(out)


CHART_W, CHART_H = 720, 190
CHART_TOP = 6.0  # standard errors at the top of the chart


def distance_svg(d: PairDetail) -> str:
    """The distance of the two positions in standard errors at every common instant, over
    time, on the bands of :data:`BANDS`."""
    left, right, top, bottom = 44, 10, 10, 28
    w, h = CHART_W - left - right, CHART_H - top - bottom
    out = [
        f'<svg id="chart" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {CHART_W} {CHART_H}" '
        f'width="{CHART_W}" height="{CHART_H}" role="img" aria-label="distance over time">'
    ]

    def yv(v: Any) -> Any:
        return top + h - np.minimum(np.asarray(v), CHART_TOP) / CHART_TOP * h

    for lo, hi, name, colour in BANDS:
        y_hi, y_lo = yv(min(hi, CHART_TOP)), yv(lo)
        out.append(
            f'<rect class="band band-{name}" x="{left}" y="{_f(y_hi)}" width="{w}" '
            f'height="{_f(y_lo - y_hi)}" fill="{colour}"/>'
            f'<text class="band-label" x="{left + 4}" y="{_f(y_hi + 12)}">{name}</text>'
        )
    for v in range(0, int(CHART_TOP) + 1, 2):
        out.append(
            f'<text class="tick" x="{left - 6}" y="{_f(yv(v) + 4)}" text-anchor="end">{v}</text>'
        )
    t = d.time
    if len(t):
        t0, t1 = float(t.min()), float(t.max())
        span = max(t1 - t0, 1.0)
        xs = left + (t - t0) / span * w
        pts = " ".join(f"{_f(x)},{_f(y)}" for x, y in zip(xs, yv(d.sigma), strict=True))
        out.append(f'<polyline class="distance" points="{pts}"/>')
        out.append(
            f'<text class="tick" x="{left}" y="{CHART_H - 8}">0 s</text>'
            f'<text class="tick" x="{left + w}" y="{CHART_H - 8}" text-anchor="end">'
            f"{span:.0f} s</text>"
        )
        k = len(t) // 2
        out.append(
            f'<line id="cursor" x1="{_f(xs[k])}" x2="{_f(xs[k])}" y1="{top}" y2="{top + h}"/>'
        )
    out.append(
        f'<text class="axis" x="12" y="{top + h / 2}" transform="rotate(-90 12 {top + h / 2})" '
        'text-anchor="middle">apart (std. errors)</text></svg>'
    )
    return "".join(out)


def pair_payload(d: PairDetail) -> dict[str, Any]:
    """The arrays the page's script needs to move the instant under the time slider: per
    instant, both ellipses in SVG pixels and the chart cursor's x."""
    fr = Frame(*_extent(d))
    left, w = 44, CHART_W - 44 - 10
    t = d.time
    span = max(float(t.max() - t.min()), 1.0) if len(t) else 1.0

    def pix(e: np.ndarray) -> list[list[float]]:
        if not len(e):
            return []
        arr = np.c_[
            fr.x(e[:, 0]),
            fr.y(e[:, 1]),
            np.maximum(e[:, 2] * fr.scale, 0.5),
            np.maximum(e[:, 3] * fr.scale, 0.5),
            -e[:, 4],
        ]
        return cast("list[list[float]]", np.round(arr, 1).tolist())

    return {
        "t": np.round(t - (t.min() if len(t) else 0.0), 1).tolist(),
        "a": pix(d.ell_a),
        "b": pix(d.ell_b),
        "sigma": np.round(d.sigma, 2).tolist(),
        "cursor": np.round(left + (t - (t.min() if len(t) else 0.0)) / span * w, 1).tolist(),
    }
