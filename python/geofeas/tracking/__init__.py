"""Association trackers of geofeas.

:mod:`geofeas.tracking` holds the multiple-hypothesis trilateration tracker for distributed
range / range-rate radars (seed 004, van Kleef et al.), with its simulator and the reproduction
of the paper's Tables 1 and 2; and particle-filter tracking of multiple objects on a focal-plane
image (seed 003, Ohlmeyer and Menon) with the reproduction of its Figs. 6-20 (``pf_*``).
"""

from ._mht import (
    ESTIMATE_COLUMNS,
    METRICS,
    PAPER_TABLE_1,
    PAPER_TABLE_2,
    STUDY_COLUMNS,
    TRACKERS,
    MhtTracker,
    paper_sensors,
    plot_run,
    simulate_run,
    study,
    track,
    track_ellipses,
    track_scans,
    trilaterate,
)
from ._pf import (
    PAPER_IC,
    PAPER_PCA,
    PF_CONFIGS,
    pf_ellipses,
    pf_log_weights,
    pf_peaks,
    pf_render,
    pf_simulate_run,
    pf_study,
    pf_track,
    plot_pf_run,
)

__all__ = [
    "ESTIMATE_COLUMNS",
    "METRICS",
    "MhtTracker",
    "PAPER_TABLE_1",
    "PAPER_TABLE_2",
    "STUDY_COLUMNS",
    "TRACKERS",
    "paper_sensors",
    "plot_run",
    "simulate_run",
    "study",
    "track",
    "track_ellipses",
    "track_scans",
    "trilaterate",
    "PAPER_IC",
    "PAPER_PCA",
    "PF_CONFIGS",
    "pf_ellipses",
    "pf_log_weights",
    "pf_peaks",
    "pf_render",
    "pf_simulate_run",
    "pf_study",
    "pf_track",
    "plot_pf_run",
]
