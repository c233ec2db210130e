"""Trackers of geofeas.

:mod:`geofeas.tracking` holds the multiple-hypothesis trilateration tracker for distributed
range / range-rate radars (seed 004, van Kleef et al.), with its simulator and the reproduction
of the paper's Tables 1 and 2 (``mht_*``, :class:`MhtTracker`); and particle-filter tracking of
multiple objects on a focal-plane image (seed 003, Ohlmeyer and Menon) with the reproduction of
its Figs. 6-20 (``pf_*``).

The MHT functions were first published without their ``mht_`` prefix (``track``,
``track_scans``, ``simulate_run``, ``study``, ``trilaterate``, ``track_ellipses``, ``plot_run``);
those names still work and warn with a :class:`DeprecationWarning`.
"""

import warnings
from typing import Any

from ._mht import (
    ESTIMATE_COLUMNS,
    METRICS,
    PAPER_TABLE_1,
    PAPER_TABLE_2,
    STUDY_COLUMNS,
    TRACKERS,
    MhtTracker,
    mht_ellipses,
    mht_simulate_run,
    mht_study,
    mht_track,
    mht_track_scans,
    mht_trilaterate,
    paper_sensors,
    plot_mht_run,
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
    "mht_ellipses",
    "mht_simulate_run",
    "mht_study",
    "mht_track",
    "mht_track_scans",
    "mht_trilaterate",
    "paper_sensors",
    "plot_mht_run",
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

#: Former names of the MHT functions -> their names now.
DEPRECATED_NAMES: dict[str, str] = {
    "track": "mht_track",
    "track_scans": "mht_track_scans",
    "simulate_run": "mht_simulate_run",
    "study": "mht_study",
    "trilaterate": "mht_trilaterate",
    "track_ellipses": "mht_ellipses",
    "plot_run": "plot_mht_run",
}


def __getattr__(name: str) -> Any:
    new = DEPRECATED_NAMES.get(name)
    if new is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(
        f"geofeas.tracking.{name} is deprecated; use geofeas.tracking.{new}",
        DeprecationWarning,
        stacklevel=2,
    )
    return globals()[new]
