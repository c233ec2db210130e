"""``geofeas review``: the operator's review station for the borderline pairs of a picture.

``geofeas review PICTURE --db DECISIONS.sqlite`` serves the station (queue, pair view,
decisions) on http://127.0.0.1:PORT/ and prints that address on a line of its own once it is
serving; every decision is appended to the SQLite log at once. ``geofeas review --db
DECISIONS.sqlite --export DECISIONS.csv`` writes the log's current decisions as the file
``geofeas associate --decisions`` reads (atomically).
"""

from __future__ import annotations

import argparse
import getpass
from pathlib import Path

from .._core import GeofeasError


def _operator() -> str:
    try:
        return getpass.getuser() or "operator"
    except (KeyError, OSError):  # pragma: no cover - no user database
        return "operator"


def main(args: argparse.Namespace) -> int:
    db = Path(args.db)
    if args.export is not None:
        from ..review.log import DecisionLog

        if not db.is_file():
            raise GeofeasError(f"--db: {db}: no such decision log")
        out = DecisionLog(db).export(args.export)
        print(f"wrote {out}")
        return 0
    if args.picture is None:
        raise GeofeasError(
            "PICTURE: the reports file or saved association to review is required (or use --export)"
        )
    if not (0 <= args.port <= 65535):
        raise GeofeasError(f"--port: {args.port} is not a port number (0 takes a free port)")
    try:
        from ..review import serve
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise GeofeasError(
            f"review needs its extra: pip install 'geofeas[review]' ({exc})"
        ) from None
    try:
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError as exc:
        raise GeofeasError(
            f"review needs its extra: pip install 'geofeas[review]' ({exc})"
        ) from None
    serve(args.picture, str(db), host=args.host, port=args.port, operator=args.operator)
    return 0


def review_demo(out: str | Path, *, host: str = "127.0.0.1", port: int = 0) -> None:
    """Serve the review station on the picture ``geofeas demo`` wrote into ``out``
    (``reports.csv``), with the decision log ``out/decisions.sqlite``."""
    folder = Path(out)
    picture = folder / "reports.csv"
    if not picture.is_file():
        raise GeofeasError(f"--review: {picture}: the demo's reports are missing")
    from ..review import serve

    serve(picture, str(folder / "decisions.sqlite"), host=host, port=port, operator=_operator())


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "review",
        help="the operator's review station for borderline pairs (web, local)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "picture",
        nargs="?",
        metavar="PICTURE",
        help="reports file (.csv / .parquet), or a saved association (a folder written by "
        "Association.save)",
    )
    p.add_argument("--db", required=True, metavar="DECISIONS.sqlite", help="the decision log")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (127.0.0.1)")
    p.add_argument("--port", type=int, default=0, help="port (0: a free port)")
    p.add_argument("--operator", default=_operator(), help="default operator name")
    p.add_argument(
        "--export",
        metavar="DECISIONS.csv",
        default=None,
        help="write the current decisions as the file associate(decisions=...) reads, and exit",
    )
    p.set_defaults(func=main)
