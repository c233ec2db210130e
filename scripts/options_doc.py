"""Writes the options table of docs/association.md from the core's option schema
(``geofeas._core.association_options``); tests/test_options_schema.py checks the page."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from geofeas.association import _options_markdown

DOC = Path(__file__).resolve().parents[1] / "docs" / "association.md"
BEGIN, END = "<!-- options: begin -->\n", "<!-- options: end -->"


def main() -> None:
    text = DOC.read_text(encoding="utf-8")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    fd, tmp = tempfile.mkstemp(dir=DOC.parent, suffix=".tmp")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(head + BEGIN + _options_markdown() + END + tail)
    os.replace(tmp, DOC)


if __name__ == "__main__":
    main()
