"""``python -m geofeas.cli``: the ``geofeas`` command."""

import sys

from . import main

sys.exit(main())
