"""The ``geofeas`` command line. Each sub-command lives in its own ``_cli_<name>`` module that
provides ``add_parser(subparsers)``; list it in :data:`SUBCOMMANDS` to enable it."""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from ._core import GeofeasError, __version__

#: Modules providing sub-commands, in the order ``--help`` lists them.
SUBCOMMANDS = [
    "_cli_score",
    "_cli_demo",
    "_cli_associate",
    "_cli_mht",
    "_cli_pf",
    "_cli_figures",
    "_cli_review",
]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="geofeas",
        description="Geofeasibility scores for track-to-track association.",
    )
    parser.add_argument("--version", action="version", version=f"geofeas {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in SUBCOMMANDS:
        importlib.import_module(f"geofeas.{name}").add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code = args.func(args)
    except (GeofeasError, OSError) as exc:
        print(f"geofeas {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"geofeas {args.command}: interrupted", file=sys.stderr)
        return 130
    return int(code or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
