"""Moved to :mod:`geofeas.io.ais` (a reader of an outside format: I/O, apart
from the library core); this name is kept for old imports and warns."""

import sys
import warnings

from .io import ais as _moved

warnings.warn("geofeas.ais moved to geofeas.io.ais", DeprecationWarning, stacklevel=2)
sys.modules[__name__] = _moved
