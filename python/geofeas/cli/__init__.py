"""The ``geofeas`` command line. Each sub-command lives in its own module of this package
(``geofeas.cli.<name>``) that provides ``add_parser(subparsers)``; list it in
:data:`SUBCOMMANDS` to enable it."""

from __future__ import annotations

import argparse
import importlib
import re
import sys
from collections.abc import Sequence

from .._core import GeofeasError, __version__

#: Modules providing sub-commands, in the order ``--help`` lists them.
SUBCOMMANDS = ["score", "demo", "associate", "mht", "pf", "figures", "review"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="geofeas",
        description="Geofeasibility scores for track-to-track association.",
    )
    parser.add_argument("--version", action="version", version=f"geofeas {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in SUBCOMMANDS:
        importlib.import_module(f"geofeas.cli.{name}").add_parser(sub)
    for command in sub.choices.values():  # the modules' docstrings, as a terminal shows them
        if command.description:
            command.description = plain(command.description)
        for action in command._actions:
            if action.help:
                action.help = plain(action.help)
    return parser


#: The project's names of its specification papers, as a reader of ``--help`` knows them.
_PAPERS = {
    "000": "the geofeasibility paper",
    "003": "the particle-filter paper",
    "004": "the distributed-radar MHT paper",
}


def plain(text: str) -> str:
    """Help text without reStructuredText markup (````x```` and ``:func:`x```` become ``x``)
    and with the papers named instead of numbered."""
    text = re.sub(r"(?::\w+:)?`+([^`]+)`+", r"\1", text)
    text = re.sub(r"seeds? (000|003|004)", lambda m: _PAPERS[m.group(1)], text)
    return text


#: Exit code of a run refused for its input (bad data, options or files); 1 is kept for
#: unexpected failures, 130 for Ctrl-C.
EXIT_INPUT = 2


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; every failure is one line on stderr and a nonzero exit code:
    2 for input errors (bad data, options, unreadable or unwritable files), 130 for Ctrl-C,
    1 for anything else."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code = args.func(args)
    except (GeofeasError, OSError, UnicodeError, OverflowError) as exc:
        print(f"geofeas {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print(f"geofeas {args.command}: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001 - the command line never shows a traceback
        print(
            f"geofeas {args.command}: internal error: {type(exc).__name__}: {_one_line(exc)}",
            file=sys.stderr,
        )
        return 1
    return int(code or 0)


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text or type(exc).__name__
