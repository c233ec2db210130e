"""Moved to :mod:`geofeas.demo.scenario` (the demo's sensor models are application code, not
library); this name is kept for old imports and warns."""

import sys
import warnings

from .demo import scenario as _moved

warnings.warn("geofeas.scenario moved to geofeas.demo.scenario", DeprecationWarning, stacklevel=2)
sys.modules[__name__] = _moved
