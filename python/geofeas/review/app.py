"""The review station's web application (Starlette): the queue, the pair view and the decision
endpoints.

Safety: the only files it touches are the picture (read once, at start) and the decision log;
its static assets are a fixed set of package files, never a path from a request. Every request
that changes state carries the station's CSRF token (``X-CSRF-Token``), every input is validated
and refused with a message the page shows, and the Host header must name the station (against
DNS rebinding).
"""

from __future__ import annotations

import html
import json
import math
import secrets
from importlib import resources
from typing import Any
from urllib.parse import urlencode

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import HTMLResponse, JSONResponse, PlainTextResponse, Response
from starlette.routing import Route

from .._core import GeofeasError
from .log import Conflict, Contradiction
from .render import distance_svg, map_svg, pair_payload
from .station import Station

__all__ = ["create_app"]

#: The static assets: URL name -> (package file, media type). Nothing else is served.
STATIC = {
    "review.js": ("review.js", "text/javascript; charset=utf-8"),
    "review.css": ("review.css", "text/css; charset=utf-8"),
}
#: Longest query filter text accepted.
MAX_FILTER = 200


def _static(name: str) -> bytes:
    return (resources.files("geofeas.review") / "static" / name).read_bytes()


def _e(x: Any) -> str:
    return html.escape(str(x), quote=True)


def _pct(p: float) -> str:
    if p < 0.001:
        return "&lt; 0.1 %"
    if p > 0.999:
        return "&gt; 99.9 %"
    return f"{100 * p:.1f} %"


def _duration(s: float) -> str:
    s = float(s)
    if s >= 3600:
        return f"{s / 3600:.1f} h"
    if s >= 60:
        return f"{s / 60:.0f} min"
    return f"{s:.0f} s"


def _page(
    station: Station, token: str, title: str, body: str, extra: str = "", status: int = 200
) -> HTMLResponse:
    op = _e(station.operator)
    return HTMLResponse(
        "<!doctype html><html lang=en><head><meta charset=utf-8>"
        f"<title>{_e(title)} - geofeas review</title>"
        f'<meta name="csrf-token" content="{token}">'
        f'<meta name="default-operator" content="{op}">'
        '<link rel="stylesheet" href="/static/review.css"></head><body>'
        '<header><a href="/" class="home">geofeas review</a>'
        '<label class="operator">operator <input id="operator" maxlength="64" '
        f'value="{op}"></label><span id="status"></span></header>'
        '<div id="message" role="alert" hidden></div>'
        f"<main>{body}</main>{extra}"
        '<script src="/static/review.js"></script></body></html>',
        status_code=status,
        headers={"Cache-Control": "no-store"},
    )


def _error(status: int, message: str) -> JSONResponse:
    return JSONResponse({"error": message}, status_code=status)


class _Filters:
    """The queue's filters from the query string, validated."""

    def __init__(self, station: Station, query: Any) -> None:
        self.sources = query.get("sources", "")
        self.area = query.get("area", "")
        if len(self.sources) > MAX_FILTER or len(self.area) > MAX_FILTER:
            raise GeofeasError("filter: too long")
        known = {str(s) for s in station.reports.sources}
        self.pair: tuple[str, str] | None = None
        if self.sources:
            parts = self.sources.split("/")
            if len(parts) != 2 or not all(p in known for p in parts):
                raise GeofeasError(
                    f"sources: expected two source names joined by '/' from {sorted(known)}, "
                    f"got {self.sources!r}"
                )
            self.pair = (parts[0], parts[1])
        self.box: tuple[float, float, float, float] | None = None
        if self.area:
            try:
                vals = [float(v) for v in self.area.split(",")]
            except ValueError:
                vals = []
            geo = station.reports.coords == "geographic"
            names = "south,west,north,east (degrees)" if geo else "ymin,xmin,ymax,xmax (metres)"
            if len(vals) != 4 or not all(math.isfinite(v) for v in vals):
                raise GeofeasError(f"area: expected four numbers {names}, got {self.area!r}")
            if not (vals[0] < vals[2] and vals[1] < vals[3]):
                raise GeofeasError(f"area: {names}: the first of each pair must be the smaller")
            self.box = (vals[0], vals[1], vals[2], vals[3])

    def apply(self, q: Any) -> Any:
        if self.pair is not None:
            s = set(self.pair)
            if len(s) == 1:
                q = q[(q["source_a"] == self.pair[0]) & (q["source_b"] == self.pair[0])]
            else:
                q = q[
                    q["source_a"].isin(s) & q["source_b"].isin(s) & (q["source_a"] != q["source_b"])
                ]
        if self.box is not None:
            south, west, north, east = self.box
            q = q[
                (q["pos0"] >= south)
                & (q["pos0"] <= north)
                & (q["pos1"] >= west)
                & (q["pos1"] <= east)
            ]
        return q


def create_app(
    station: Station, *, token: str | None = None, hosts: list[str] | None = None
) -> Starlette:
    """The Starlette application of a :class:`Station`."""
    csrf = token or secrets.token_urlsafe(32)

    def check_token(request: Request) -> JSONResponse | None:
        sent = request.headers.get("x-csrf-token", "")
        if not sent or not secrets.compare_digest(sent, csrf):
            return _error(403, "refused: missing or wrong CSRF token (reload the page)")
        return None

    async def body_of(request: Request) -> dict[str, Any]:
        if request.headers.get("content-type", "").split(";")[0].strip() != "application/json":
            raise GeofeasError("request: expected a JSON body (Content-Type: application/json)")
        raw = await request.body()
        if len(raw) > 10_000:
            raise GeofeasError("request: body too large")
        try:
            data = json.loads(raw)
        except ValueError as exc:
            raise GeofeasError(f"request: the body is not JSON ({exc})") from None
        if not isinstance(data, dict):
            raise GeofeasError("request: expected a JSON object")
        return data

    def field(data: dict[str, Any], name: str, kind: type, *, required: bool = True) -> Any:
        v = data.get(name)
        if v is None:
            if required:
                raise GeofeasError(f"{name}: missing")
            return None
        if kind is int:
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise GeofeasError(f"{name}: expected a non-negative integer, got {v!r}")
            return v
        if not isinstance(v, kind):
            raise GeofeasError(f"{name}: expected {kind.__name__}, got {type(v).__name__}")
        return v

    # ------------------------------------------------------------------ pages

    def queue(request: Request) -> Response:
        snap = station.snapshot
        try:
            flt = _Filters(station, request.query_params)
        except GeofeasError as exc:
            flt = None
            message = str(exc)
        else:
            message = ""
        q = snap.queue if flt is None else flt.apply(snap.queue)
        prog = station.progress(snap)
        rows = []
        for r in q.itertuples(index=False):
            link = "/pair?" + urlencode({"a": r.track_a, "b": r.track_b})
            rows.append(
                f'<tr data-a="{_e(r.track_a)}" data-b="{_e(r.track_b)}">'
                f"<td>{int(r.review_rank)}</td>"
                f'<td><a href="{_e(link)}">{_e(r.track_a)} / {_e(r.track_b)}</a></td>'
                f'<td class="p">{_pct(float(r.p_same))}</td>'
                f"<td>{_e(r.source_a)} / {_e(r.source_b)}</td>"
                f"<td>{_duration(r.duration_a)} / {_duration(r.duration_b)}</td>"
                f"<td>{int(r.instants)}</td><td>{int(r.rivals)}</td></tr>"
            )
        srcs = sorted({str(s) for s in station.reports.sources})
        options = ['<option value="">all</option>'] + [
            f'<option value="{_e(a)}/{_e(b)}"{" selected" if flt and flt.pair == (a, b) else ""}>'
            f"{_e(a)} / {_e(b)}</option>"
            for i, a in enumerate(srcs)
            for b in srcs[i:]
        ]
        geo = station.reports.coords == "geographic"
        area_hint = "south,west,north,east" if geo else "ymin,xmin,ymax,xmax"
        error = f'<p class="error" id="filter-error">{_e(message)}</p>' if message else ""
        body = (
            '<section class="progress" id="progress">'
            f'<span><b id="decided">{prog["decided"]}</b> decided</span>'
            f'<span><b id="remaining">{prog["remaining"]}</b> borderline pairs remaining</span>'
            f"<span>estimated F1 gain if all are decided: <b>{prog['f1_gain']:+.3f}</b> "
            f"(F1 now {prog['f1_now']:.3f}, expected under the model)</span></section>"
            '<form class="filters" method="get" action="/">'
            f'<label>sources <select name="sources">{"".join(options)}</select></label>'
            f'<label>area <input name="area" placeholder="{area_hint}" '
            f'value="{_e(flt.area if flt else "")}" size="34"></label>'
            f'<button type="submit">filter</button></form>{error}'
            f'<p class="hint">{len(q)} pairs shown, in review order: the first settles the most. '
            "Open a pair to decide it.</p>"
            '<table id="queue"><thead><tr><th>#</th><th>tracks</th><th>P(same ship)</th>'
            "<th>sources</th><th>durations</th><th>instants</th><th>rivals</th></tr></thead>"
            f"<tbody>{''.join(rows)}</tbody></table>"
        )
        extra = (
            f'<script id="state" type="application/json">'
            f"{json.dumps({'page': 'queue', 'version': snap.version})}</script>"
        )
        return _page(station, csrf, "queue", body, extra)

    def pair(request: Request) -> Response:
        a, b = request.query_params.get("a", ""), request.query_params.get("b", "")
        snap = station.snapshot
        try:
            d = station.detail(a, b, snap)
        except GeofeasError as exc:
            body = (
                f'<p class="error" id="pair-error">{_e(exc)}</p>'
                '<p><a href="/">back to the queue</a></p>'
            )
            return _page(station, csrf, "pair", body, status=400)
        row = d.row
        a, b = row["track_a"], row["track_b"]
        position = station.log.position()
        current = station.log.current().get((a, b) if a <= b else (b, a))
        decided = ""
        if current is not None and current.action in ("same", "different"):
            decided = (
                f'<p class="decided" id="decided-by">Decided <b>{_e(current.action)}</b> by '
                f"{_e(current.operator)} at {_e(current.time)} (#{current.seq}).</p>"
            )
        k = len(d.time)
        outside = int((d.sigma > 3.035).sum())
        doubtful = int(((d.sigma > 2.448) & (d.sigma <= 3.035)).sum())
        plain = (
            f"At {k - outside - doubtful} of {k} common instants the two positions agree within "
            f"their uncertainties; at {doubtful} they are doubtful and at {outside} they disagree "
            "(fewer than 1 in 100 instants of one ship would be that far apart)."
        )
        rank = row["review_rank"]
        cls = row["class"]
        body = (
            f'<h1>{_e(a)} <span class="src">({_e(row["source_a"])})</span> and {_e(b)} '
            f'<span class="src">({_e(row["source_b"])})</span></h1>'
            f'<section class="posterior"><p class="p-same">Probability they are one ship: '
            f'<b id="p-same">{_pct(float(row["p_same"]))}</b> ({_e(cls)}'
            f"{f', review #{rank}' if rank else ''})</p>"
            f"<p>Confirming <b>same</b> settles {int(row['settles_same'])} other pairs; "
            f"<b>different</b> settles {int(row['settles_different'])}.</p>"
            f'<p class="plain">{plain}</p>{decided}</section>'
            '<section class="actions">'
            '<button id="same" data-action="same"><kbd>s</kbd> same ship</button>'
            '<button id="different" data-action="different"><kbd>d</kbd> different ships</button>'
            '<button id="skip" data-action="skip"><kbd>k</kbd> skip</button>'
            '<button id="undo" data-action="undo"><kbd>u</kbd> undo my last</button></section>'
            '<section class="view"><div class="legend">'
            f'<span class="key key-a"></span>{_e(a)} '
            f'<span class="key key-b"></span>{_e(b)} '
            '<span class="key key-rival"></span>rival tracks '
            "- ellipses: where each source says the ship is (95 % of the time inside)</div>"
            f"{map_svg(d)}"
            '<div class="slider"><input type="range" id="slider" min="0" '
            f'max="{max(k - 1, 0)}" value="{k // 2}" aria-label="instant">'
            '<span id="instant"></span></div>'
            f"<h2>How far apart, at each instant</h2>{distance_svg(d)}</section>"
        )
        state = {
            "page": "pair",
            "a": a,
            "b": b,
            "p_same": float(row["p_same"]),
            "seen": position,
            "version": snap.version,
            "payload": pair_payload(d),
        }
        extra = f'<script id="state" type="application/json">{_json_script(state)}</script>'
        return _page(station, csrf, f"{a} / {b}", body, extra)

    # ------------------------------------------------------------------ API

    def api_state(request: Request) -> Response:
        return JSONResponse(station.progress())

    def api_pair(request: Request) -> Response:
        a, b = request.query_params.get("a", ""), request.query_params.get("b", "")
        try:
            row = station.pair_row(a, b)
        except GeofeasError as exc:
            return _error(400, str(exc))
        key = (row["track_a"], row["track_b"])
        cur = station.log.current().get(key if key[0] <= key[1] else (key[1], key[0]))
        return JSONResponse(
            {
                "p_same": float(row["p_same"]),
                "class": row["class"],
                "review_rank": row["review_rank"],
                "decision": None if cur is None else cur.action,
                "operator": None if cur is None else cur.operator,
                "seq": None if cur is None else cur.seq,
                "version": station.snapshot.version,
            }
        )

    def next_pair(a: str, b: str) -> str:
        q = station.snapshot.queue
        key = {a, b}
        decided = station.log.current()
        for r in q.itertuples(index=False):
            pk = (r.track_a, r.track_b) if r.track_a <= r.track_b else (r.track_b, r.track_a)
            if {r.track_a, r.track_b} == key or pk in decided:
                continue
            return "/pair?" + urlencode({"a": r.track_a, "b": r.track_b})
        return "/"

    async def api_decide(request: Request) -> Response:
        bad = check_token(request)
        if bad is not None:
            return bad
        try:
            data = await body_of(request)
            a = field(data, "track_a", str)
            b = field(data, "track_b", str)
            action = field(data, "decision", str)
            operator = field(data, "operator", str)
            seen = field(data, "seen", int)
            shown = data.get("p_same")
            if shown is not None and (
                isinstance(shown, bool)
                or not isinstance(shown, (int, float))
                or not 0.0 <= shown <= 1.0
            ):
                raise GeofeasError(f"p_same: expected the probability shown, got {shown!r}")

            def write() -> Any:
                row = station.pair_row(a, b)  # a candidate pair of the picture
                # the probability the operator saw; the current one when the page sent none
                p = float(shown) if shown is not None else float(row["p_same"])
                return station.log.decide(operator, a, b, action, p_same=p, seen=seen)

            entry = await run_in_threadpool(write)
        except Conflict as exc:
            return JSONResponse({"error": str(exc), "conflict": True}, status_code=409)
        except Contradiction as exc:
            return JSONResponse({"error": str(exc), "contradiction": True}, status_code=409)
        except GeofeasError as exc:
            return _error(400, str(exc))
        station.notify()
        nxt = await run_in_threadpool(next_pair, a, b)
        return JSONResponse(
            {"ok": True, "seq": entry.seq, "message": entry.describe(), "next": nxt}
        )

    async def api_undo(request: Request) -> Response:
        bad = check_token(request)
        if bad is not None:
            return bad
        try:
            data = await body_of(request)
            operator = field(data, "operator", str)
            seq = field(data, "seq", int, required=False)
            seen = field(data, "seen", int, required=False)
            entry = await run_in_threadpool(station.log.undo, operator, seq=seq, seen=seen)
        except Conflict as exc:
            return JSONResponse({"error": str(exc), "conflict": True}, status_code=409)
        except GeofeasError as exc:
            return _error(400, str(exc))
        station.notify()
        return JSONResponse(
            {
                "ok": True,
                "seq": entry.seq,
                "message": entry.describe(),
                "pair": "/pair?" + urlencode({"a": entry.track_a, "b": entry.track_b}),
            }
        )

    def decisions_csv(request: Request) -> Response:
        import csv
        import io

        from .log import EXPORT_COLUMNS

        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=list(EXPORT_COLUMNS))
        w.writeheader()
        w.writerows(station.log.decisions_table())
        return PlainTextResponse(buf.getvalue(), media_type="text/csv; charset=utf-8")

    def static(request: Request) -> Response:
        name = request.path_params["name"]
        if name not in STATIC:
            return PlainTextResponse("not found", status_code=404)
        file, media = STATIC[name]
        return Response(_static(file), media_type=media, headers={"Cache-Control": "no-cache"})

    routes = [
        Route("/", queue),
        Route("/pair", pair),
        Route("/api/state", api_state),
        Route("/api/pair", api_pair),
        Route("/api/decide", api_decide, methods=["POST"]),
        Route("/api/undo", api_undo, methods=["POST"]),
        Route("/decisions.csv", decisions_csv),
        Route("/static/{name}", static),
    ]
    allowed = hosts or ["127.0.0.1", "localhost", "testserver"]
    app = Starlette(
        routes=routes, middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=allowed)]
    )
    app.state.csrf = csrf
    app.state.station = station
    return app


def _json_script(obj: Any) -> str:
    """JSON safe inside a ``<script>`` element."""
    return json.dumps(obj).replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")
