"""Moved to :mod:`geofeas.io.arrow` (the Arrow / Parquet I/O of the association, apart
from the library core); this name is kept for old imports and warns."""

import sys
import warnings

from .io import arrow as _moved

warnings.warn("geofeas.arrow moved to geofeas.io.arrow", DeprecationWarning, stacklevel=2)
sys.modules[__name__] = _moved
