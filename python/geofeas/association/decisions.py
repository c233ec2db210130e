"""Operator decisions on track pairs: the evidence an operator adds to the association.

A decisions table has the columns ``track_a``, ``track_b`` and ``decision`` (``"same"`` or
``"different"``), and optionally ``operator`` and ``time``; it is read from CSV, Parquet or a
pandas DataFrame and never written by the engine. :func:`geofeas.associate` takes the decisions
as hard constraints: tracks declared the same are one object, tracks declared different never
are, and the posterior of every other pair of their components is recomputed under them
(``docs/association.md``, "Operator decisions").
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._core import GeofeasError

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .reports import Reports

__all__ = ["DECISION_COLUMNS", "DECISIONS", "Decisions", "read_decisions"]

#: Columns of a decisions table (``operator`` and ``time`` are optional).
DECISION_COLUMNS = ("track_a", "track_b", "decision", "operator", "time")
#: The decisions an operator can make on a pair.
DECISIONS = ("same", "different")


class Decisions:
    """Decisions resolved against a picture: the table as read (every column kept) and, per
    row, the two tracks' indices and whether they were declared the same."""

    def __init__(
        self,
        frame: pd.DataFrame,
        a: NDArray[np.uint32],
        b: NDArray[np.uint32],
        same: NDArray[np.bool_],
        name: str = "decisions",
    ) -> None:
        self.frame = frame
        self.a = a
        self.b = b
        self.same = same
        #: where the table came from: a file's path, or ``"decisions"`` for a DataFrame
        self.name = name

    def where(self, row: int) -> str:
        """Row ``row`` (0-based) as the user sees it: the file line of a CSV file (the header
        is line 1), else the table row."""
        return _where(self.name, row)

    @contextmanager
    def naming_rows(self) -> Iterator[None]:
        """Re-raise the engine's errors about several decisions (contradictions) naming them as
        the user wrote them: ``d.csv: line 2 (A same B), line 4 (A different B): ...``. The
        error keeps the 0-based ``rows``."""
        try:
            yield
        except GeofeasError as exc:
            rows = getattr(exc, "rows", None)
            if not rows:
                raise
            track_a, track_b, decision = (self.frame[c] for c in DECISION_COLUMNS[:3])
            named = ", ".join(
                f"{self.where(r)} ({track_a.iat[r]} {decision.iat[r]} {track_b.iat[r]})"
                for r in rows
            )
            err = GeofeasError(f"{self.name}: {named}: {exc.reason}")
            err.rows = list(rows)
            err.reason = exc.reason
            raise err from None

    def __len__(self) -> int:
        return int(self.a.shape[0])

    @staticmethod
    def empty() -> Decisions:
        import pandas as pd

        return Decisions(
            pd.DataFrame({c: [] for c in DECISION_COLUMNS[:3]}),
            np.zeros(0, np.uint32),
            np.zeros(0, np.uint32),
            np.zeros(0, np.bool_),
        )


def _where(name: str, row: int) -> str:
    return f"line {row + 2}" if name.lower().endswith(".csv") else f"row {row}"


def _table(source: Any) -> tuple[pd.DataFrame, str]:
    import pandas as pd

    if isinstance(source, pd.DataFrame):
        return source, "decisions"
    if isinstance(source, (str, Path)):
        path = Path(source)
        suffix = path.suffix.lower()
        try:
            if suffix == ".csv":
                # ids are names: read every column as text, never as numbers
                return pd.read_csv(path, dtype=str, keep_default_na=False), str(path)
            if suffix in (".parquet", ".pq"):
                return pd.read_parquet(path), str(path)
        except (OSError, ValueError, UnicodeDecodeError) as exc:
            raise GeofeasError(f"decisions: cannot read {path}: {exc}") from None
        raise GeofeasError(
            f"decisions: {path}: unknown file type {suffix!r} (expected .csv or .parquet)"
        )
    raise GeofeasError(
        f"decisions: expected a path or a pandas DataFrame, got {type(source).__name__}"
    )


def read_decisions(source: Any, reports: Reports) -> Decisions:
    """Read operator decisions and resolve their track ids against ``reports``.

    Errors name the row (the file line for CSV files) and the column: a missing column, an
    unknown track id, a pair of one track with itself, a decision other than ``same`` /
    ``different`` (read without regard to case or surrounding spaces; the table keeps the words
    as written). Contradictions between decisions are found by the engine: the error names
    the decisions involved (file lines or rows, with their tracks; :meth:`Decisions.naming_rows`).
    """
    frame, name = _table(source)

    def where(row: int) -> str:
        return f"{name}: {_where(name, row)}"

    missing = [c for c in DECISION_COLUMNS[:3] if c not in frame.columns]
    if missing:
        raise GeofeasError(
            f"{name}: missing column(s) {', '.join(missing)} (have {list(frame.columns)})"
        )
    index = {str(t): k for k, t in enumerate(reports.track_ids)}
    n = len(frame)
    a = np.zeros(n, np.uint32)
    b = np.zeros(n, np.uint32)
    same = np.zeros(n, np.bool_)
    for row, (ta, tb, d) in enumerate(
        zip(frame["track_a"], frame["track_b"], frame["decision"], strict=True)
    ):
        for col, t, out in (("track_a", ta, a), ("track_b", tb, b)):
            key = str(t)
            if key not in index:
                raise GeofeasError(
                    f"{where(row)}: column {col}: unknown track id {t!r} (not in the reports)"
                )
            out[row] = index[key]
        if a[row] == b[row]:
            raise GeofeasError(f"{where(row)}: column track_b: a track is paired with itself")
        word = str(d).strip().lower()
        if word not in DECISIONS:
            raise GeofeasError(
                f"{where(row)}: column decision: expected 'same' or 'different', got {d!r}"
            )
        same[row] = word == "same"
    return Decisions(frame, a, b, same, name)
