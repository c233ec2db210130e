"""A Stone Soup-style adapter for the MHT trilateration tracker (seed 004).

Install with ``pip install "geofeas[stonesoup]"``. :class:`MhtStoneSoupTracker` is used like
Stone Soup's own trackers: built on a detector (any iterable of ``(timestamp, set of
Detection)``, e.g. a Stone Soup simulator or feeder), iterated for ``(timestamp, set of Track)``.

* **Detections in.** Each :class:`~stonesoup.types.detection.Detection` carries the measurement
  ``[range, range_rate]`` in its ``state_vector`` (metres, metres per second) and the index of
  the radar that made it in ``metadata[sensor_key]`` (``"sensor"`` by default). Detections of one
  yielded set are split by radar, each radar's detections being one scan at that timestamp.
  Clutter (:class:`~stonesoup.types.detection.Clutter`) needs no special handling: Reid's
  hypotheses decide what is a false alarm. A radar that scanned and saw nothing is declared with
  ``scanned``: a callable ``timestamp -> iterable of sensor indices`` (those radars get an empty
  scan at that timestamp, so the missed-detection charge ``1 - P_D`` applies).
* **Tracks out.** After each timestamp the Cartesian tracks of the most likely hypothesis, as
  :class:`~stonesoup.types.track.Track` objects whose id is ``f"mht-{id}"`` (stable across
  timestamps: the index of the detection that started the track) and whose states are
  :class:`~stonesoup.types.state.GaussianState` in Stone Soup's ``[x, vx, y, vy]`` order with
  the 4 x 4 covariance. A track that leaves the best hypothesis is dropped from the set.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from datetime import datetime
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .._core import GeofeasError
from ._mht import MhtTracker

__all__ = ["MhtStoneSoupTracker"]


_ORDER = [0, 2, 1, 3]


def _covariance(upper: np.ndarray) -> np.ndarray:
    """The symmetric 4 x 4 matrix of an upper triangle given row by row."""
    p = np.zeros((4, 4))
    p[np.triu_indices(4)] = upper
    return p + np.triu(p, 1).T


class MhtStoneSoupTracker:
    """Stone Soup-style tracker: ``for time, tracks in MhtStoneSoupTracker(detector, sensors)``.

    Parameters
    ----------
    detector : iterable of (datetime, set of Detection)
        In time order.
    sensors : array_like, shape (s, 6)
        Radar rows ``[x, y, boresight, half_beam, max_range, max_range_rate]``
        (:func:`geofeas.tracking.paper_sensors`).
    sensor_key : str
        Metadata key of a detection's radar index.
    scanned : callable, optional
        ``timestamp -> radar indices`` that scanned at that timestamp (so that radars without
        detections are charged ``1 - P_D``).
    **options
        Tracker options of :class:`geofeas.tracking.MhtTracker`.
    """

    def __init__(
        self,
        detector: Iterable[tuple[datetime, Any]],
        sensors: ArrayLike,
        /,
        *,
        sensor_key: str = "sensor",
        scanned: Callable[[datetime], Iterable[int]] | None = None,
        **options: Any,
    ) -> None:
        from stonesoup.types.track import Track  # type: ignore[import-untyped]  # noqa: F401

        self.detector = detector
        self.sensor_key = sensor_key
        self.scanned = scanned
        self._mht = MhtTracker(sensors, **options)
        self._epoch: datetime | None = None
        self._tracks: dict[int, Any] = {}
        self._current: set[Any] = set()

    @property
    def tracks(self) -> set[Any]:
        """Tracks of the most likely hypothesis after the last timestamp."""
        return set(self._current)

    @property
    def tracker(self) -> MhtTracker:
        """The underlying tracker (hypotheses, probabilities)."""
        return self._mht

    def __iter__(self) -> Iterator[tuple[datetime, set[Any]]]:
        for time, detections in self.detector:
            yield time, self._step(time, detections)

    def _step(self, time: datetime, detections: Iterable[Any]) -> set[Any]:
        from stonesoup.types.array import CovarianceMatrix, StateVector  # type: ignore[import-untyped]
        from stonesoup.types.state import GaussianState  # type: ignore[import-untyped]
        from stonesoup.types.track import Track  # type: ignore[import-untyped]

        if self._epoch is None:
            self._epoch = time
        seconds = (time - self._epoch).total_seconds()
        by_sensor: dict[int, list[list[float]]] = {}
        for k, det in enumerate(detections):
            sensor = det.metadata.get(self.sensor_key)
            if isinstance(sensor, bool) or not isinstance(sensor, (int, np.integer)):
                raise GeofeasError(
                    f"detections at {time}: detection {k}: metadata[{self.sensor_key!r}] must be "
                    f"a sensor index, got {sensor!r}"
                )
            sv = np.asarray(det.state_vector, dtype=np.float64).ravel()
            if sv.shape != (2,):
                raise GeofeasError(
                    f"detections at {time}: detection {k}: state_vector must be "
                    f"[range, range_rate], got shape {sv.shape}"
                )
            by_sensor.setdefault(int(sensor), []).append([float(sv[0]), float(sv[1])])
        if self.scanned is not None:
            for s in self.scanned(time):
                by_sensor.setdefault(int(s), [])
        for sensor in sorted(by_sensor):
            rows = np.array(by_sensor[sensor], dtype=np.float64).reshape(-1, 2)
            self._mht.process_scan(seconds, sensor, rows)
        current = set()
        for row in self._mht.estimates():
            tid = int(row[0])
            track = self._tracks.get(tid)
            if track is None:
                track = Track(id=f"mht-{tid}")
                self._tracks[tid] = track
            # [x, y, vx, vy] -> Stone Soup's [x, vx, y, vy].
            p = _covariance(row[6:16])[np.ix_(_ORDER, _ORDER)]
            state = GaussianState(
                StateVector([row[2], row[4], row[3], row[5]]),
                CovarianceMatrix(p),
                timestamp=time,
            )
            track.append(state)
            current.add(track)
        self._current = current
        return set(current)
