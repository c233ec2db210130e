"""Moved to :mod:`geofeas.integrations.dask` (the library inside another stack, behind
its optional extra); this name is kept for old imports and warns."""

import sys
import warnings

from .integrations import dask as _moved

warnings.warn("geofeas.dask moved to geofeas.integrations.dask", DeprecationWarning, stacklevel=2)
sys.modules[__name__] = _moved
