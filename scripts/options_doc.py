"""Writes the options tables of the docs from the core's option schemas: the association's in
docs/association.md (``geofeas._core.association_options``) and the scores' in README.md
(``geofeas._core.score_options``); tests/test_options_schema.py and tests/test_score_schema.py
check the pages."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path

from geofeas.association import _options_markdown
from geofeas.cli.score import options_markdown as _score_options_markdown

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "association.md"
BEGIN, END = "<!-- options: begin -->\n", "<!-- options: end -->"
SCORE_DOC = ROOT / "README.md"
SCORE_BEGIN, SCORE_END = "<!-- score options: begin -->\n", "<!-- score options: end -->"


def write(doc: Path, begin: str, end: str, render: Callable[[], str]) -> None:
    """Replaces the text between ``begin`` and ``end`` in ``doc`` by ``render()`` (atomically)."""
    text = doc.read_text(encoding="utf-8")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    fd, tmp = tempfile.mkstemp(dir=doc.parent, suffix=".tmp")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(head + begin + render() + end + tail)
    os.replace(tmp, doc)


def main() -> None:
    write(DOC, BEGIN, END, _options_markdown)
    write(SCORE_DOC, SCORE_BEGIN, SCORE_END, _score_options_markdown)


if __name__ == "__main__":
    main()
