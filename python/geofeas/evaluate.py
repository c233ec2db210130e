"""Moved to :mod:`geofeas.demo.evaluate` (the demo's evaluation against the MMSI truth); this
name is kept for old imports and warns."""

import importlib
import sys
import warnings

# the module, not the function geofeas.demo.evaluate (which the package's attribute is)
_moved = importlib.import_module(".demo.evaluate", __package__)

warnings.warn("geofeas.evaluate moved to geofeas.demo.evaluate", DeprecationWarning, stacklevel=2)
sys.modules[__name__] = _moved
