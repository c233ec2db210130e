"""geofeas: geofeasibility scores for track-to-track association.

Scores of how feasible it is, geographically, that two reports with 2-sigma area-of-uncertainty
ellipses come from one object (Coates et al., "Recognized Maritime Picture: Geofeasibility
Scores"), computed in a Rust core.
"""

from ._core import GeofeasError, __version__
from .association import (
    Association,
    Reports,
    associate,
    combine_instants,
    load_association,
    read_reports,
)
from .association.decisions import read_decisions
from .scores import (
    DEFAULT_VERTICES,
    SAMPLERS,
    bhattacharyya,
    cdist,
    from_gaussian,
    gaussian_product,
    glr,
    hellinger,
    intersection_area,
    monte_carlo,
    overlap,
    to_gaussian,
)

__all__ = [
    "Association",
    "Reports",
    "associate",
    "combine_instants",
    "load_association",
    "read_decisions",
    "read_reports",
    "DEFAULT_VERTICES",
    "GeofeasError",
    "SAMPLERS",
    "__version__",
    "bhattacharyya",
    "cdist",
    "from_gaussian",
    "gaussian_product",
    "glr",
    "hellinger",
    "intersection_area",
    "monte_carlo",
    "overlap",
    "to_gaussian",
]
