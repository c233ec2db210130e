"""Track-to-track association: the library's wrapper of the engine (``docs/association.md``).

:func:`read_reports` reads and validates a picture, :func:`associate` runs the engine on it and
returns an :class:`Association`; :mod:`.decisions` reads the operator's decisions it takes as
constraints. The public names are re-exported by :mod:`geofeas`; the private helpers below are
shared with the distributed path (:mod:`geofeas.integrations.dask`) and the Stone Soup bridge.
"""

from .engine import (  # noqa: F401 (re-exported: the module's names before it became a package)
    ASSOCIATION_DEFAULTS,
    CLASSES,
    COMBINE_RULES,
    DEFAULT_UPPER,
    GEOGRAPHIC,
    OPTIONS,
    PLANAR,
    REQUIRED,
    SCORES,
    Association,
    Reports,
    _error,
    _options_markdown,
    _read_reports,
    _relabelled,
    _ReportColumns,
    _resolve_options,
    _Row,
    _Where,
    associate,
    combine_instants,
    load_association,
    read_reports,
    write_table,
    write_tables,
)

__all__ = [
    "Association",
    "COMBINE_RULES",
    "Reports",
    "associate",
    "combine_instants",
    "load_association",
    "read_reports",
]
