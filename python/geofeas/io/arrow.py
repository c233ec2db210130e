"""Reports and association results as Arrow tables and Parquet files, column by column.

Arrow in: :func:`read_reports` takes a ``pyarrow.Table`` / ``RecordBatch`` (or a Parquet path
read with ``pyarrow.parquet``) and hands its columns to :func:`geofeas.read_reports` as one
pandas frame: numeric columns convert without copies, dictionary-encoded columns (as Parquet
writers produce for repeated strings) are decoded by Arrow, timestamp columns stay timestamps.
Arrow out: :func:`pairs_table` / :func:`objects_table` and :func:`write_parquet` carry every
column of :attr:`geofeas.Association.pairs` and ``objects`` — the posterior ``p_same``, the
class, ``review_rank`` (null for pairs that are not borderline), the model's details (``llr``,
``std_error``, ``review_gain``, ``settles_same``, ``settles_different``, ``component``, null for
a pair left out of every component) and ``p_alone`` per track — with their types: missing
values stay nulls, never zeros or NaN. No step loops over rows in Python.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from .._core import GeofeasError
from ..association import Association, Reports
from ..association import associate as _associate
from ..association import read_reports as _read

__all__ = [
    "associate",
    "objects_table",
    "pairs_table",
    "read_reports",
    "to_pandas",
    "write_parquet",
]


def _pyarrow() -> Any:
    try:
        import pyarrow as pa  # type: ignore[import-untyped,unused-ignore]
    except ImportError:  # pragma: no cover - depends on the environment
        raise GeofeasError("geofeas.io.arrow needs pyarrow: pip install 'geofeas[io]'") from None
    return pa


def to_pandas(table: Any, /) -> Any:
    """An Arrow table (or record batch, or Parquet path) as a pandas frame of plain columns.

    Dictionary-encoded columns are decoded to their values by Arrow (``pyarrow.compute.cast``)
    so that ids read as strings or numbers, not as pandas categoricals.
    """
    pa = _pyarrow()
    if isinstance(table, (str, os.PathLike)):
        import pyarrow.parquet as pq  # type: ignore[import-untyped,unused-ignore]

        try:
            table = pq.read_table(Path(table))
        except (OSError, pa.ArrowInvalid) as exc:
            raise GeofeasError(f"{table}: {exc}") from None
    if isinstance(table, pa.RecordBatch):
        table = pa.Table.from_batches([table])
    if not isinstance(table, pa.Table):
        raise GeofeasError(
            f"expected a pyarrow Table or RecordBatch or a Parquet path, got {type(table).__name__}"
        )
    for i, field in enumerate(table.schema):
        if pa.types.is_dictionary(field.type):
            table = table.set_column(i, field.name, table.column(i).cast(field.type.value_type))
    return table.to_pandas()


def read_reports(table: Any, /, *, coords: str = "auto") -> Reports:
    """:func:`geofeas.read_reports` of an Arrow table, record batch or Parquet path."""
    return _read(to_pandas(table), coords=coords)


def associate(table: Any, /, *, decisions: Any = None, **options: Any) -> Association:
    """:func:`geofeas.associate` of an Arrow table, record batch or Parquet path; operator
    ``decisions`` may be one too (or anything :func:`geofeas.associate` takes)."""
    pa = _pyarrow()
    if isinstance(decisions, (pa.Table, pa.RecordBatch)):
        decisions = to_pandas(decisions)
    rep = read_reports(table, coords=options.pop("coords", "auto"))
    return _associate(rep, decisions=decisions, **options)


def pairs_table(association: Association, /) -> Any:
    """The pairs of an association (every column of :attr:`geofeas.Association.pairs`) as a
    ``pyarrow.Table``; ``review_rank`` and ``component`` are nullable integers."""
    return _pyarrow().Table.from_pandas(association.pairs, preserve_index=False)


def objects_table(association: Association, /) -> Any:
    """The objects (track id, object, source, ``p_alone``) of an association as a
    ``pyarrow.Table``."""
    return _pyarrow().Table.from_pandas(association.objects, preserve_index=False)


def write_parquet(association: Association, directory: str | os.PathLike[str], /) -> None:
    """Write ``pairs.parquet`` and ``objects.parquet`` into ``directory`` (created if absent),
    as one transaction: neither file is replaced unless both were written."""
    import pyarrow.parquet as pq  # type: ignore[import-untyped,unused-ignore]

    from .._atomic import atomic_paths

    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    with atomic_paths(out / "pairs.parquet", out / "objects.parquet") as (pairs, objects):
        pq.write_table(pairs_table(association), pairs)
        pq.write_table(objects_table(association), objects)
