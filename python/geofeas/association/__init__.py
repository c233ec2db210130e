"""Track-to-track association: the library's wrapper of the engine (``docs/association.md``).

- :mod:`.reports`: :func:`read_reports`, reading and validating a picture into :class:`Reports`;
- :mod:`.options`: the options of :func:`associate`, from the schema defined once in the core;
- :mod:`.engine`: :func:`associate` (the engine's call) and its result, :class:`Association`;
- :mod:`.decisions`: :func:`~.decisions.read_decisions`, the operator's decisions the
  association takes as constraints.

The public names are re-exported by :mod:`geofeas`. The names below are those of the module
``geofeas.association`` was before it became this package; the private ones are shared with the
distributed path (:mod:`geofeas.integrations.dask`), the Stone Soup bridge and the tests.
"""

# the re-exports below are this package's interface (F401: not used here)
from .engine import (  # noqa: F401
    CLASSES,
    Association,
    associate,
    combine_instants,
    load_association,
    write_table,
    write_tables,
)
from .options import (  # noqa: F401
    ALIGNMENT_OPTIONS,
    ASSOCIATION_DEFAULTS,
    COMBINE_RULES,
    DEFAULT_UPPER,
    OPTIONS,
    SCORES,
    _alignment,
    _options_markdown,
    _resolve_options,
)
from .reports import (  # noqa: F401
    GEOGRAPHIC,
    PLANAR,
    REQUIRED,
    Reports,
    _error,
    _read_reports,
    _relabelled,
    _ReportColumns,
    _Row,
    _Where,
    read_reports,
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
