"""Atomic file output: every file geofeas writes goes to a temporary file in the destination
folder first and is renamed over the destination only once it is complete, so a failed or
interrupted write leaves the previous file untouched and never a truncated one.

:func:`atomic_paths` writes several files as one transaction: none of the destinations is
replaced unless every file was written.
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

from ._core import GeofeasError

__all__ = ["atomic_open", "atomic_path", "atomic_paths", "save_figure", "write_text"]


def _temporary(dest: Path) -> Path:
    # same folder (so the rename never crosses file systems), same suffix (so writers that pick
    # a format from the extension, like matplotlib, still do), a hidden unique name
    return dest.with_name(f".{dest.stem}.{secrets.token_hex(6)}.tmp{dest.suffix}")


@contextmanager
def atomic_paths(*paths: str | os.PathLike[str]) -> Iterator[list[Path]]:
    """Temporary paths to write ``paths`` to; on a clean exit all of them are moved over their
    destinations, on an exception none is and the temporaries are removed."""
    dests = [Path(p) for p in paths]
    if len({d.resolve() for d in dests}) != len(dests):
        raise GeofeasError(f"the same output file is given twice: {[str(d) for d in dests]}")
    temps = [_temporary(d) for d in dests]
    try:
        yield temps
        for t in temps:
            if not t.exists():
                raise OSError(f"{t}: nothing was written for {dests[temps.index(t)]}")
            _fsync(t)
    except BaseException:
        for t in temps:
            t.unlink(missing_ok=True)
        raise
    for t, d in zip(temps, dests, strict=True):
        os.replace(t, d)


@contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A temporary path to write ``path`` to, moved over it on a clean exit."""
    with atomic_paths(path) as (tmp,):
        yield tmp


@contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w", **kwargs: Any) -> Iterator[IO[Any]]:
    """``open(path, mode)`` writing to a temporary file that replaces ``path`` on a clean
    exit."""
    if not any(c in mode for c in "wx"):
        raise GeofeasError(f"atomic_open writes a new file; mode {mode!r} is not a write mode")
    with atomic_path(path) as tmp, open(tmp, mode, **kwargs) as fh:
        yield fh


def _fsync(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - unreadable temporary (odd permissions)
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - file systems without fsync
        pass
    finally:
        os.close(fd)


def write_text(path: str | os.PathLike[str], text: str, encoding: str = "utf-8") -> None:
    """``Path(path).write_text(text)``, atomically."""
    with atomic_open(path, "w", encoding=encoding) as fh:
        fh.write(text)


def save_figure(fig: Any, path: str | os.PathLike[str], **kwargs: Any) -> None:
    """``fig.savefig(path, **kwargs)``, atomically (the format follows ``path``'s suffix)."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, **kwargs)
