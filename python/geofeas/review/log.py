"""The operator decision log: an append-only SQLite table of every decision made at the review
station, from which the decisions file of :func:`geofeas.associate` is derived.

Every row is one action of one operator on one pair: ``same``, ``different``, ``skip``, or
``undo`` (which names the row it reverses). Rows are never updated or deleted (triggers refuse
it); the current decisions are a replay of the log. Writers take SQLite's write lock
(``BEGIN IMMEDIATE``) before reading what they check, so two connections -- two browsers, two
station processes on one file -- never lose or silently override a decision:

- a decision on a pair that already has a newer decision than the one the operator saw
  (``seen``, the log position the page was drawn at) is refused as a :class:`Conflict`;
- a decision that contradicts the current ones (the same rules as the engine: tracks declared
  the same must not be declared different, directly or through a chain of ``same``; one object
  never holds two tracks of one source whose time spans overlap) is refused as a
  :class:`Contradiction` naming the decisions involved;
- a pair already decided must be undone before it is decided otherwise.
"""

from __future__ import annotations

import csv
import os
import sqlite3
import tempfile
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import numpy as np

from .._core import GeofeasError, decisions_contradiction

__all__ = [
    "ACTIONS",
    "Conflict",
    "Contradiction",
    "DecisionLog",
    "Entry",
    "TrackSpan",
    "contradiction",
]

#: Columns of the exported decisions file (those :func:`geofeas.read_decisions` reads).
EXPORT_COLUMNS = ("track_a", "track_b", "decision", "operator", "time")
#: What an operator can do on a pair (``undo`` reverses an earlier row).
ACTIONS = ("same", "different", "skip", "undo")

_SCHEMA = """
CREATE TABLE IF NOT EXISTS decisions (
    seq      INTEGER PRIMARY KEY AUTOINCREMENT,
    time     TEXT NOT NULL,
    operator TEXT NOT NULL,
    track_a  TEXT NOT NULL,
    track_b  TEXT NOT NULL,
    action   TEXT NOT NULL CHECK (action IN ('same', 'different', 'skip', 'undo')),
    p_same   REAL,
    reverses INTEGER REFERENCES decisions (seq)
);
CREATE INDEX IF NOT EXISTS decisions_pair ON decisions (track_a, track_b);
CREATE TRIGGER IF NOT EXISTS decisions_no_update BEFORE UPDATE ON decisions
BEGIN SELECT RAISE(ABORT, 'the decision log is append-only: rows are never updated'); END;
CREATE TRIGGER IF NOT EXISTS decisions_no_delete BEFORE DELETE ON decisions
BEGIN SELECT RAISE(ABORT, 'the decision log is append-only: rows are never deleted'); END;
"""


@dataclass(frozen=True)
class Entry:
    """One row of the log."""

    seq: int
    time: str
    operator: str
    track_a: str
    track_b: str
    action: str
    p_same: float | None
    reverses: int | None

    def describe(self) -> str:
        what = f"undo of #{self.reverses}" if self.action == "undo" else repr(self.action)
        return (
            f"#{self.seq} {what} on ({self.track_a}, {self.track_b}) by {self.operator} "
            f"at {self.time}"
        )


@dataclass(frozen=True)
class TrackSpan:
    """What the contradiction rules need of a track: its source and time span (s)."""

    source: str
    start: float
    end: float

    def conflicts(self, other: TrackSpan) -> bool:
        """Two tracks of one source at overlapping times cannot be one object."""
        return self.source == other.source and self.start < other.end and other.start < self.end


class Conflict(GeofeasError):
    """A newer decision on the pair than the one the operator saw (``entry``)."""

    def __init__(self, message: str, entry: Entry) -> None:
        super().__init__(message)
        self.entry = entry


class Contradiction(GeofeasError):
    """A decision that contradicts earlier ones (``entries`` are the earlier rows involved)."""

    def __init__(self, message: str, entries: list[Entry]) -> None:
        super().__init__(message)
        self.entries = entries


def pair_key(a: str, b: str) -> tuple[str, str]:
    """The log's name of a pair: its two track ids in string order."""
    return (a, b) if a <= b else (b, a)


def contradiction(
    decisions: Iterable[Entry], spans: Mapping[str, TrackSpan] | None = None
) -> tuple[str, list[Entry]] | None:
    """The first contradiction among active ``same`` / ``different`` decisions, as
    ``(reason, rows involved)``, or ``None``, by the engine's own check
    (``geofeas._core.decisions_contradiction``): a ``different`` between two tracks a chain of
    ``same`` joins; a chain of ``same`` that puts two tracks of one source at overlapping times
    into one object (when ``spans`` gives the tracks' sources and spans). The rows involved are
    the shortest such chain (and the ``different``)."""
    rows = [e for e in decisions if e.action in ("same", "different")]
    ids: dict[str, int] = {}
    for e in rows:
        for t in (e.track_a, e.track_b):
            ids.setdefault(t, len(ids))
    codes: dict[str, int] = {}
    source = np.zeros(len(ids), np.uint32)
    start = np.zeros(len(ids), np.float64)
    end = np.zeros(len(ids), np.float64)
    for t, k in ids.items():
        span = spans.get(t) if spans else None
        # a track without a span gets a source of its own: it conflicts with none
        key = span.source if span is not None else f"\0{t}"
        source[k] = codes.setdefault(key, len(codes))
        if span is not None:
            start[k], end[k] = span.start, span.end
    found = decisions_contradiction(
        source,
        start,
        end,
        np.array([ids[e.track_a] for e in rows], np.uint32),
        np.array([ids[e.track_b] for e in rows], np.uint32),
        np.array([e.action == "same" for e in rows], np.bool_),
    )
    if found is None:
        return None
    # the log refuses a pair of a track with itself before, so the chain is one of the two
    chain = [rows[k] for k in found[0]]
    if chain[-1].action == "different":
        e, involved = chain[-1], chain[:-1]
        return (
            f"({e.track_a}, {e.track_b}) declared different, but "
            + "; ".join(x.describe() for x in involved)
            + " make them one object",
            [e, *involved],
        )
    # the chain's two ends are the two tracks of one source
    x, y = _chain_ends(chain)
    kind = spans[x].source if spans else ""
    return (
        f"tracks {x} and {y} are both {kind} tracks at overlapping times, so they cannot be "
        "one object, but " + "; ".join(e.describe() for e in chain) + " join them",
        chain,
    )


def _chain_ends(chain: list[Entry]) -> tuple[str, str]:
    """The two tracks a chain of decisions (each sharing a track with the next) joins."""
    first = (chain[0].track_a, chain[0].track_b)
    if len(chain) == 1:
        return first
    nxt = {chain[1].track_a, chain[1].track_b}
    head = first[0] if first[1] in nxt else first[1]
    last = (chain[-1].track_a, chain[-1].track_b)
    prev = {chain[-2].track_a, chain[-2].track_b}
    tail = last[0] if last[1] in prev else last[1]
    return head, tail


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds").replace("+00:00", "Z")


class DecisionLog:
    """The decision log in an SQLite file (created when missing).

    Parameters
    ----------
    path : path
        The database file.
    spans : mapping, optional
        ``{track_id: TrackSpan}`` of the picture, for the same-source rule; with it, decisions
        on unknown tracks are refused.
    timeout : float
        Seconds a writer waits for another writer's lock.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        *,
        spans: Mapping[str, TrackSpan] | None = None,
        timeout: float = 30.0,
    ) -> None:
        self.path = Path(path)
        self.spans = dict(spans) if spans is not None else None
        self._timeout = timeout
        try:
            with self._connect() as con:
                con.executescript(_SCHEMA)
                cols = [r[1] for r in con.execute("PRAGMA table_info(decisions)")]
        except sqlite3.DatabaseError as exc:
            raise GeofeasError(f"db: {self.path}: not a decision log ({exc})") from None
        expected = ["seq", "time", "operator", "track_a", "track_b", "action", "p_same", "reverses"]
        if cols != expected:
            raise GeofeasError(
                f"db: {self.path}: table 'decisions' has columns {cols}, expected {expected}"
            )

    def _connect(self) -> sqlite3.Connection:
        con = sqlite3.connect(self.path, timeout=self._timeout, isolation_level=None)
        con.execute("PRAGMA journal_mode=WAL")
        con.execute("PRAGMA synchronous=FULL")
        return con

    # ------------------------------------------------------------------ reading

    def entries(self, con: sqlite3.Connection | None = None) -> list[Entry]:
        """Every row, oldest first."""
        own = con is None
        c = self._connect() if con is None else con
        try:
            rows = c.execute(
                "SELECT seq, time, operator, track_a, track_b, action, p_same, reverses "
                "FROM decisions ORDER BY seq"
            ).fetchall()
        finally:
            if own:
                c.close()
        return [Entry(*r) for r in rows]

    def position(self) -> int:
        """The log position: the last row's ``seq`` (0 when empty)."""
        con = self._connect()
        try:
            return int(con.execute("SELECT COALESCE(MAX(seq), 0) FROM decisions").fetchone()[0])
        finally:
            con.close()

    @staticmethod
    def replay(entries: Iterable[Entry]) -> dict[tuple[str, str], Entry]:
        """The active row of each pair (its last ``same`` / ``different`` / ``skip`` not undone)."""
        rows = list(entries)
        undone = {e.reverses for e in rows if e.action == "undo"}
        active: dict[tuple[str, str], Entry] = {}
        for e in rows:
            key = pair_key(e.track_a, e.track_b)
            if e.action == "undo":
                if active.get(key) is not None and active[key].seq == e.reverses:
                    del active[key]
            elif e.seq not in undone:
                active[key] = e
        return active

    def current(self) -> dict[tuple[str, str], Entry]:
        """The active decision (or skip) of every pair."""
        return self.replay(self.entries())

    def decisions(self) -> list[Entry]:
        """The active ``same`` / ``different`` decisions, oldest first."""
        return sorted(
            (e for e in self.current().values() if e.action in ("same", "different")),
            key=lambda e: e.seq,
        )

    # ------------------------------------------------------------------ writing

    def _write(self, fn: Callable[[sqlite3.Connection, list[Entry]], Entry]) -> Entry:
        con = self._connect()
        try:
            con.execute("BEGIN IMMEDIATE")
            try:
                entry = fn(con, self.entries(con))
                con.execute("COMMIT")
            except BaseException:
                con.execute("ROLLBACK")
                raise
            return entry
        finally:
            con.close()

    @staticmethod
    def _insert(
        con: sqlite3.Connection,
        operator: str,
        a: str,
        b: str,
        action: str,
        p_same: float | None,
        reverses: int | None,
    ) -> Entry:
        t = _now()
        cur = con.execute(
            "INSERT INTO decisions (time, operator, track_a, track_b, action, p_same, reverses) "
            "VALUES (?, ?, ?, ?, ?, ?, ?)",
            (t, operator, a, b, action, p_same, reverses),
        )
        return Entry(int(cur.lastrowid or 0), t, operator, a, b, action, p_same, reverses)

    @staticmethod
    def _check_operator(operator: str) -> None:
        if not isinstance(operator, str) or not operator.strip() or len(operator) > 64:
            raise GeofeasError("operator: a name of 1 to 64 characters is required")
        if not operator.isprintable():
            raise GeofeasError("operator: the name must be printable text")

    def _check_names(self, operator: str, a: str, b: str) -> None:
        self._check_operator(operator)
        for what, t in (("track_a", a), ("track_b", b)):
            if not isinstance(t, str) or not t:
                raise GeofeasError(f"{what}: a track id is required")
            if self.spans is not None and t not in self.spans:
                raise GeofeasError(f"{what}: unknown track id {t!r} (not in the picture)")
        if a == b:
            raise GeofeasError("track_b: a track cannot be paired with itself")

    def decide(
        self,
        operator: str,
        track_a: str,
        track_b: str,
        action: str,
        *,
        p_same: float | None = None,
        seen: int | None = None,
    ) -> Entry:
        """Append a decision (``same``, ``different`` or ``skip``) on a pair.

        ``seen`` is the log position the operator's page showed; a newer row on this pair
        raises :class:`Conflict`. A decision contradicting the active ones raises
        :class:`Contradiction`; deciding a pair that already has an active decision raises
        :class:`Contradiction` too (undo it first). Returns the new row.
        """
        if action not in ACTIONS[:3]:
            raise GeofeasError(f"decision: expected 'same', 'different' or 'skip', got {action!r}")
        self._check_names(operator, track_a, track_b)
        if p_same is not None and not (0.0 <= p_same <= 1.0):
            raise GeofeasError(f"p_same: {p_same} is not a probability")
        key = pair_key(track_a, track_b)

        def write(con: sqlite3.Connection, rows: list[Entry]) -> Entry:
            on_pair = [e for e in rows if pair_key(e.track_a, e.track_b) == key]
            if seen is not None:
                newer = [e for e in on_pair if e.seq > seen]
                if newer:
                    e = newer[-1]
                    raise Conflict(
                        f"pair ({key[0]}, {key[1]}) changed since this page was drawn: "
                        f"{e.describe()}",
                        e,
                    )
            active = self.replay(rows)
            prev = active.get(key)
            if prev is not None and prev.action in ("same", "different"):
                raise Contradiction(
                    f"pair ({key[0]}, {key[1]}) is already decided: {prev.describe()}; "
                    "undo it first",
                    [prev],
                )
            if action in ("same", "different"):
                new = Entry(0, "", operator, key[0], key[1], action, p_same, None)
                decided = [e for e in active.values() if e.action in ("same", "different")]
                found = contradiction([*decided, new], self.spans)
                if found is not None:
                    reason, involved = found
                    raise Contradiction(f"refused: {reason}", [e for e in involved if e is not new])
            return self._insert(con, operator, key[0], key[1], action, p_same, None)

        return self._write(write)

    def undo(self, operator: str, *, seq: int | None = None, seen: int | None = None) -> Entry:
        """Append the reversal of row ``seq`` (default: ``operator``'s last active row).

        Refused when the row is not active (already undone, or replaced) or, with ``seen``,
        when its pair has a newer row than the operator saw."""
        self._check_operator(operator)

        def write(con: sqlite3.Connection, rows: list[Entry]) -> Entry:
            active = self.replay(rows)
            live = {e.seq: e for e in active.values()}
            if seq is None:
                mine = [e for e in live.values() if e.operator == operator]
                if not mine:
                    raise GeofeasError(f"undo: {operator} has no decision to undo")
                target = max(mine, key=lambda e: e.seq)
            elif seq in live:
                target = live[seq]
            else:
                raise GeofeasError(f"undo: row #{seq} is not an active decision")
            key = pair_key(target.track_a, target.track_b)
            if seen is not None:
                newer = [e for e in rows if pair_key(e.track_a, e.track_b) == key and e.seq > seen]
                if newer:
                    raise Conflict(
                        f"pair ({key[0]}, {key[1]}) changed since this page was drawn: "
                        f"{newer[-1].describe()}",
                        newer[-1],
                    )
            return self._insert(con, operator, key[0], key[1], "undo", None, target.seq)

        return self._write(write)

    # ------------------------------------------------------------------ export

    def decisions_table(self) -> list[dict[str, str]]:
        """The active decisions as rows of the decisions file (``track_a, track_b, decision,
        operator, time``)."""
        return [
            {
                "track_a": e.track_a,
                "track_b": e.track_b,
                "decision": e.action,
                "operator": e.operator,
                "time": e.time,
            }
            for e in self.decisions()
        ]

    def export(self, path: str | os.PathLike[str]) -> Path:
        """Write the decisions file :func:`geofeas.associate` reads (CSV), atomically: a
        temporary file in the destination folder, renamed over the target."""
        out = Path(path)
        if out.suffix.lower() != ".csv":
            raise GeofeasError(f"export: {out}: the decisions file is written as .csv")
        rows = self.decisions_table()
        fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent or ".")
        try:
            with os.fdopen(fd, "w", newline="", encoding="utf-8") as fh:
                w = csv.DictWriter(fh, fieldnames=list(EXPORT_COLUMNS))
                w.writeheader()
                w.writerows(rows)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, out)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise
        return out


def spans_of(reports: Any) -> dict[str, TrackSpan]:
    """``{track_id: TrackSpan}`` of validated :class:`geofeas.Reports` (ids as strings)."""
    import numpy as np

    n = reports.n_tracks
    start = np.full(n, np.inf)
    end = np.full(n, -np.inf)
    np.minimum.at(start, reports.track, reports.time)
    np.maximum.at(end, reports.track, reports.time)
    src = np.empty(n, dtype=np.intp)
    src[reports.track] = reports.source
    return {
        str(t): TrackSpan(str(reports.sources[src[k]]), float(start[k]), float(end[k]))
        for k, t in enumerate(reports.track_ids)
    }
