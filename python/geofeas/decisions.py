"""Moved to :mod:`geofeas.association.decisions` (the operator's decisions are read for the
association, so they are part of its package); this name is kept for old imports and warns."""

import sys
import warnings

from .association import decisions as _moved

warnings.warn(
    "geofeas.decisions moved to geofeas.association.decisions", DeprecationWarning, stacklevel=2
)
sys.modules[__name__] = _moved
