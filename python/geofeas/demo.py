"""The end-to-end demo: a simulated multi-source picture over a real AIS recording, associated and
scored against the MMSI ground truth (``geofeas demo``)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from ._core import GeofeasError

#: Bundled AIS recordings by short name.
RECORDINGS = {
    "solent": "solent_ais_20160112.csv",
    "nyharbor": "nyharbor_ais_20200630.csv",
}


def bundled(name: str) -> Path:
    """Path of a bundled AIS recording (``"solent"`` or ``"nyharbor"``)."""
    if name not in RECORDINGS:
        raise GeofeasError(
            f"unknown bundled recording {name!r}; expected one of {sorted(RECORDINGS)}"
        )
    return Path(str(resources.files("geofeas") / "data" / RECORDINGS[name]))
