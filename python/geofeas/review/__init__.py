"""``geofeas review``: the operator's review station for the borderline pairs of an association.

- :mod:`.log`: the append-only SQLite decision log (conflicts, contradictions, undo, export);
- :mod:`.station`: the picture, the log and the association kept current in the background;
- :mod:`.coast`: GSHHG coastlines from the system's offline files;
- :mod:`.render`: the pair view's SVG map and distance chart;
- :mod:`.app`: the Starlette web application; :func:`serve` runs it with uvicorn.

The web parts need the ``review`` extra (``pip install 'geofeas[review]'``).
"""

from __future__ import annotations

from .log import Conflict, Contradiction, DecisionLog, Entry, TrackSpan, contradiction, spans_of

__all__ = [
    "Conflict",
    "Contradiction",
    "DecisionLog",
    "Entry",
    "TrackSpan",
    "contradiction",
    "serve",
    "spans_of",
]


def serve(
    picture: object,
    db: str,
    *,
    host: str = "127.0.0.1",
    port: int = 0,
    operator: str = "operator",
    options: dict[str, object] | None = None,
    on_ready: object = None,
) -> None:
    """Run the station until interrupted; prints ``http://HOST:PORT/`` on a line of its own once
    the socket is listening (``port=0`` takes a free port). ``on_ready(url)`` is called then."""
    import socket

    import uvicorn

    from .app import create_app
    from .station import Station

    station = Station(picture, db, operator=operator, options=dict(options or {}))
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
    except OSError as exc:
        sock.close()
        station.close()
        raise OSError(f"cannot listen on {host}:{port}: {exc.strerror or exc}") from None
    sock.listen(128)
    bound = sock.getsockname()[1]
    shown = f"[{host}]" if ":" in host else host
    url = f"http://{shown}:{bound}/"
    hosts = ["*"] if host in ("0.0.0.0", "::") else [host, "127.0.0.1", "localhost", "::1"]
    app = create_app(station, hosts=hosts)
    config = uvicorn.Config(app, log_level="warning", lifespan="off")
    server = uvicorn.Server(config)

    async def started() -> None:
        import asyncio

        while not server.started:
            await asyncio.sleep(0.01)
        print(url, flush=True)
        if callable(on_ready):
            on_ready(url)

    import asyncio

    async def main() -> None:
        task = asyncio.ensure_future(started())
        await server.serve(sockets=[sock])
        task.cancel()

    try:
        asyncio.run(main())
    finally:
        station.close()
        sock.close()
