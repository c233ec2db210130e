"""Moved to :mod:`geofeas.demo.evaluate` (the demo's evaluation against the MMSI truth); this
name is kept for old imports and warns."""

import sys
import warnings

from .demo import evaluate as _moved

warnings.warn("geofeas.evaluate moved to geofeas.demo.evaluate", DeprecationWarning, stacklevel=2)
sys.modules[__name__] = _moved
