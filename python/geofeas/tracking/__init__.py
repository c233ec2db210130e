"""Association trackers of geofeas.

:mod:`geofeas.tracking` holds the multiple-hypothesis trilateration tracker for distributed
range / range-rate radars (seed 004, van Kleef et al.), with its simulator and the reproduction
of the paper's Tables 1 and 2.
"""

from ._mht import (
    PAPER_TABLE_1,
    PAPER_TABLE_2,
    STUDY_COLUMNS,
    paper_sensors,
    plot_run,
    simulate_run,
    study,
    track,
    track_ellipses,
    trilaterate,
)

__all__ = [
    "PAPER_TABLE_1",
    "PAPER_TABLE_2",
    "STUDY_COLUMNS",
    "paper_sensors",
    "plot_run",
    "simulate_run",
    "study",
    "track",
    "track_ellipses",
    "trilaterate",
]
