"""Moved to :mod:`geofeas.integrations.stonesoup` (the library inside another stack,
behind its optional extra); this name is kept for old imports and warns."""

import sys
import warnings

from .integrations import stonesoup as _moved

warnings.warn(
    "geofeas.stonesoup moved to geofeas.integrations.stonesoup", DeprecationWarning, stacklevel=2
)
sys.modules[__name__] = _moved
