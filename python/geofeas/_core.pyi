"""Typed stub of the Rust extension module ``geofeas._core``."""

from collections.abc import Mapping
from typing import Any, Protocol, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "GeofeasError",
    "WGS84_A",
    "WGS84_F",
    "__version__",
    "assign_one_to_one",
    "associate",
    "AssociationOutput",
    "association_candidates",
    "association_default_upper",
    "association_finish",
    "association_pair_instants",
    "association_options",
    "association_pair_stats",
    "association_states_at",
    "association_track_boxes",
    "association_track_partials",
    "association_track_summary",
    "combine_instants",
    "from_gaussian",
    "geodesic_direct",
    "geodesic_inverse",
    "intersection_area",
    "MhtRun",
    "PairInstants",
    "PairStats",
    "PictureCounts",
    "MhtStudy",
    "MhtTrack",
    "MhtTracker",
    "mht_metric_names",
    "mht_options",
    "mht_simulate_run",
    "mht_study",
    "mht_track",
    "mht_tracker_names",
    "mht_trilaterate",
    "PfBankMetrics",
    "PfMetrics",
    "PfRun",
    "PfStudy",
    "PfTrack",
    "pf_log_weights",
    "pf_options",
    "pf_peaks",
    "pf_render",
    "pf_simulate_run",
    "pf_study",
    "pf_track",
    "polygon_error_bound",
    "project_aeqd",
    "ScoreOptions",
    "StatesAt",
    "score_cdist",
    "score_names",
    "score_options",
    "score_pairs",
    "TimeCover",
    "to_gaussian",
    "TrackBoxes",
    "validate_ellipses",
]

__version__: str

class _ReportColumns(Protocol):
    """What the association bindings read of ``geofeas.Reports`` (or ``ReportColumns``)."""

    @property
    def track(self) -> NDArray[np.uint32]: ...
    @property
    def source(self) -> NDArray[np.uint32]: ...
    @property
    def time(self) -> NDArray[np.float64]: ...
    @property
    def aou(self) -> NDArray[np.float64]: ...
    @property
    def n_tracks(self) -> int: ...
    @property
    def coords(self) -> str: ...

class _DecisionColumns(Protocol):
    """What the association bindings read of ``geofeas.Decisions``."""

    @property
    def a(self) -> NDArray[np.uint32]: ...
    @property
    def b(self) -> NDArray[np.uint32]: ...
    @property
    def same(self) -> NDArray[np.bool_]: ...

class GeofeasError(ValueError):
    """Invalid input or options for a geofeas computation (a ValueError)."""

    argument: str | None
    row: int | None
    field: str | None
    #: the rows (0-based) of an error about several rows of one table, and what is wrong
    rows: list[int] | None
    reason: str | None

@final
class ScoreOptions:
    def __new__(
        cls,
        *,
        threshold: bool | None = None,
        method: str | None = None,
        vertices: int | None = None,
        samples: int | None = None,
        seed: int | None = None,
        sampler: str | None = None,
    ) -> ScoreOptions: ...

def score_names() -> list[str]: ...
def score_options() -> list[dict[str, Any]]: ...
def score_pairs(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    score: str,
    options: ScoreOptions | None = None,
) -> NDArray[np.float64]: ...
def score_cdist(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    score: str,
    options: ScoreOptions | None = None,
    *,
    max_bytes: int,
) -> NDArray[np.float64]: ...
def intersection_area(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]: ...
def to_gaussian(
    e: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def from_gaussian(mean: NDArray[np.float64], cov: NDArray[np.float64]) -> NDArray[np.float64]: ...
def validate_ellipses(e: NDArray[np.float64]) -> None: ...
def polygon_error_bound(vertices: int, ratio: float) -> float: ...
def mht_options() -> dict[str, list[tuple[str, str, Any, str, tuple[str, ...]]]]: ...
def mht_trilaterate(
    pos_a: NDArray[np.float64],
    z_a: NDArray[np.float64],
    cov_a: NDArray[np.float64],
    pos_b: NDArray[np.float64],
    z_b: NDArray[np.float64],
    cov_b: NDArray[np.float64],
    **options: Any,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def mht_track(
    detections: NDArray[np.float64],
    sensors: NDArray[np.float64],
    **options: Any,
) -> MhtTrack: ...
def mht_simulate_run(**options: Any) -> MhtRun: ...
def mht_study(**options: Any) -> MhtStudy: ...
def mht_metric_names() -> list[str]: ...
def mht_tracker_names() -> list[str]: ...

@final
class MhtTrack:
    @property
    def tracks(self) -> NDArray[np.float64]: ...
    @property
    def ellipses(self) -> NDArray[np.float64]: ...
    @property
    def track_of_detection(self) -> NDArray[np.float64]: ...
    @property
    def probability(self) -> float: ...

@final
class MhtRun:
    @property
    def detections(self) -> NDArray[np.float64]: ...
    @property
    def tracks(self) -> NDArray[np.float64]: ...
    @property
    def ellipses(self) -> NDArray[np.float64]: ...
    @property
    def truth(self) -> NDArray[np.float64]: ...
    @property
    def sensors(self) -> NDArray[np.float64]: ...
    @property
    def metrics(self) -> NDArray[np.float64]: ...
    @property
    def duration(self) -> float: ...

@final
class MhtStudy:
    @property
    def tracker(self) -> list[str]: ...
    @property
    def sensors(self) -> NDArray[np.int64]: ...
    @property
    def targets(self) -> NDArray[np.int64]: ...
    @property
    def false_alarms(self) -> NDArray[np.int64]: ...
    @property
    def metrics(self) -> NDArray[np.float64]: ...
    @property
    def metrics_lo(self) -> NDArray[np.float64]: ...
    @property
    def metrics_hi(self) -> NDArray[np.float64]: ...

@final
class MhtTracker:
    def __new__(
        cls,
        sensors: NDArray[np.float64],
        **options: Any,
    ) -> MhtTracker: ...
    def process_scan(self, time: float, sensor: int, detections: NDArray[np.float64]) -> int: ...
    @property
    def scans(self) -> int: ...
    @property
    def detections(self) -> int: ...
    def estimates(self, rank: int = 0) -> NDArray[np.float64]: ...
    def hypotheses(self, top: int = 5) -> list[tuple[float, NDArray[np.float64], list[int]]]: ...
    def track_of_detection(self) -> NDArray[np.float64]: ...

def pf_options() -> dict[str, list[tuple[str, str, Any, str, tuple[str, ...]]]]: ...
def pf_simulate_run(**options: Any) -> PfRun: ...
def pf_track(
    frames: NDArray[np.float64],
    init: NDArray[np.float64],
    *,
    sigma_z: float,
    **options: Any,
) -> PfTrack: ...
def pf_log_weights(
    frame: NDArray[np.float64],
    xy: NDArray[np.float64],
    *,
    amplitude: float,
    blur: float,
    sigma: float,
    half_box: int = 10,
) -> NDArray[np.float64]: ...
def pf_peaks(
    frame: NDArray[np.float64],
    *,
    count: int = 4,
    min_separation: float = 3.0,
    smoothing: float = 0.0,
) -> NDArray[np.float64]: ...
def pf_render(
    positions: NDArray[np.float64],
    *,
    width: int = 256,
    height: int = 256,
    amplitude: float = 1.0,
    blur: float = 2.0,
    sigma: float = 0.1,
    seed: int = 0,
) -> NDArray[np.float64]: ...
def pf_study(ic: NDArray[np.float64], **options: Any) -> PfStudy: ...

@final
class PfTrack:
    @property
    def estimates(self) -> NDArray[np.float64]: ...
    @property
    def covariances(self) -> NDArray[np.float64]: ...
    @property
    def peaks(self) -> NDArray[np.float64]: ...
    @property
    def peak(self) -> NDArray[np.int64]: ...
    @property
    def distances(self) -> NDArray[np.float64]: ...
    @property
    def residuals(self) -> NDArray[np.float64]: ...
    @property
    def ess(self) -> NDArray[np.float64]: ...

@final
class PfRun:
    @property
    def track(self) -> PfTrack: ...
    @property
    def truth(self) -> NDArray[np.float64]: ...
    @property
    def correct(self) -> NDArray[np.bool_]: ...
    @property
    def snapshots(self) -> NDArray[np.float64]: ...
    @property
    def frames(self) -> NDArray[np.float64]: ...
    @property
    def sigma_z(self) -> float: ...
    @property
    def dt(self) -> float: ...
    @property
    def filter_seed(self) -> int: ...

@final
class PfMetrics:
    @property
    def pca(self) -> NDArray[np.float64]: ...
    @property
    def hit(self) -> NDArray[np.float64]: ...
    @property
    def rmse_px(self) -> NDArray[np.float64]: ...
    @property
    def coverage(self) -> NDArray[np.float64]: ...
    @property
    def held(self) -> NDArray[np.float64]: ...

@final
class PfBankMetrics:
    @property
    def gospa(self) -> NDArray[np.float64]: ...
    @property
    def gospa_loc(self) -> NDArray[np.float64]: ...
    @property
    def gospa_missed(self) -> NDArray[np.float64]: ...
    @property
    def gospa_false(self) -> NDArray[np.float64]: ...
    @property
    def id_switches(self) -> NDArray[np.float64]: ...
    @property
    def fragmentations(self) -> NDArray[np.float64]: ...

@final
class PfStudy:
    @property
    def method(self) -> NDArray[np.int64]: ...
    @property
    def snr_db(self) -> NDArray[np.float64]: ...
    @property
    def xmax(self) -> NDArray[np.float64]: ...
    @property
    def vmax(self) -> NDArray[np.float64]: ...
    @property
    def all(self) -> PfMetrics: ...
    @property
    def lo(self) -> PfMetrics: ...
    @property
    def hi(self) -> PfMetrics: ...
    @property
    def bank(self) -> PfBankMetrics: ...
    @property
    def filter_pca(self) -> NDArray[np.float64]: ...
    @property
    def filter_rmse_px(self) -> NDArray[np.float64]: ...

def associate(
    reports: _ReportColumns,
    decisions: _DecisionColumns,
    *,
    options: Mapping[str, Any],
) -> AssociationOutput: ...

@final
class AssociationOutput:
    @property
    def a(self) -> NDArray[np.uint32]: ...
    @property
    def b(self) -> NDArray[np.uint32]: ...
    @property
    def score(self) -> NDArray[np.float64]: ...
    @property
    def instants(self) -> NDArray[np.uint32]: ...
    @property
    def llr(self) -> NDArray[np.float64]: ...
    @property
    def p_same(self) -> NDArray[np.float64]: ...
    @property
    def std_error(self) -> NDArray[np.float64]: ...
    @property
    def pair_class(self) -> NDArray[np.uint8]: ...
    @property
    def review_rank(self) -> NDArray[np.uint32]: ...
    @property
    def review_gain(self) -> NDArray[np.float64]: ...
    @property
    def settles_same(self) -> NDArray[np.uint32]: ...
    @property
    def settles_different(self) -> NDArray[np.uint32]: ...
    @property
    def component(self) -> NDArray[np.uint32]: ...
    @property
    def p_alone(self) -> NDArray[np.float64]: ...
    @property
    def object(self) -> NDArray[np.uint32]: ...
    @property
    def track_source(self) -> NDArray[np.uint32]: ...
    @property
    def track_spread(self) -> NDArray[np.float64]: ...
    @property
    def candidates(self) -> int: ...
    @property
    def inflation_a(self) -> NDArray[np.uint32]: ...
    @property
    def inflation_b(self) -> NDArray[np.uint32]: ...
    @property
    def inflation(self) -> NDArray[np.float64]: ...
    @property
    def coverage(self) -> NDArray[np.float64]: ...
    @property
    def track_breaks(self) -> NDArray[np.float64]: ...
    @property
    def false_overlap(self) -> NDArray[np.float64]: ...
    @property
    def component_tracks(self) -> NDArray[np.uint32]: ...
    @property
    def component_partitions(self) -> NDArray[np.uint64]: ...
    @property
    def component_method(self) -> NDArray[np.uint8]: ...
    @property
    def component_std_error(self) -> NDArray[np.float64]: ...
    @property
    def time_cover(self) -> TimeCover: ...
    @property
    def stats(self) -> PairStats: ...
    @property
    def counts(self) -> PictureCounts: ...
    @property
    def component_reused(self) -> NDArray[np.bool_]: ...
    @property
    def memo(self) -> PosteriorMemo: ...

@final
class PosteriorMemo:
    def __len__(self) -> int: ...

def association_options() -> list[dict[str, Any]]: ...
def association_candidates(
    reports: _ReportColumns,
    *,
    options: Mapping[str, Any],
    brute_force: bool = False,
) -> tuple[NDArray[np.uint32], NDArray[np.uint32]]: ...
def combine_instants(
    g: NDArray[np.float64],
    m: NDArray[np.float64],
    time: NDArray[np.float64],
    offsets: NDArray[np.uint64],
    rule: str,
    *,
    correlation_time: float = 0.0,
) -> NDArray[np.float64]: ...
def assign_one_to_one(
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    score: NDArray[np.float64],
    *,
    min_score: float = 0.0,
) -> NDArray[np.uint64]: ...
def association_default_upper() -> float: ...
def association_pair_instants(
    reports: _ReportColumns,
    a: int,
    b: int,
    *,
    alignment: Mapping[str, float],
) -> PairInstants: ...

@final
class PairInstants:
    @property
    def time(self) -> NDArray[np.float64]: ...
    @property
    def m(self) -> NDArray[np.float64]: ...
    @property
    def state_a(self) -> NDArray[np.float64]: ...
    @property
    def state_b(self) -> NDArray[np.float64]: ...

def association_states_at(
    reports: _ReportColumns,
    times: NDArray[np.float64],
    *,
    alignment: Mapping[str, float],
) -> StatesAt: ...

@final
class StatesAt:
    @property
    def track(self) -> NDArray[np.uint32]: ...
    @property
    def index(self) -> NDArray[np.uint64]: ...
    @property
    def state(self) -> NDArray[np.float64]: ...

WGS84_A: float
WGS84_F: float

def geodesic_inverse(
    lat1: NDArray[np.float64],
    lon1: NDArray[np.float64],
    lat2: NDArray[np.float64],
    lon2: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
def geodesic_direct(
    lat1: NDArray[np.float64],
    lon1: NDArray[np.float64],
    azi1: NDArray[np.float64],
    s12: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
def project_aeqd(aou: NDArray[np.float64], origin: tuple[float, float]) -> NDArray[np.float64]: ...
def decisions_contradiction(
    source: NDArray[np.uint32],
    start: NDArray[np.float64],
    end: NDArray[np.float64],
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    same: NDArray[np.bool_],
) -> tuple[list[int], str] | None: ...
def association_pair_stats(
    reports: _ReportColumns,
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    *,
    options: Mapping[str, Any],
    stream_ids: NDArray[np.uint32] | None = None,
) -> PairStats: ...

@final
class PairStats:
    @property
    def score(self) -> NDArray[np.float64]: ...
    @property
    def instants(self) -> NDArray[np.uint32]: ...
    @property
    def sum_m(self) -> NDArray[np.float64]: ...
    @property
    def k_eff(self) -> NDArray[np.float64]: ...
    @property
    def mean_mg(self) -> NDArray[np.float64]: ...
    @property
    def mean_ln_det(self) -> NDArray[np.float64]: ...
    @property
    def mean_trace_over_det(self) -> NDArray[np.float64]: ...
    @property
    def mean_inv_det(self) -> NDArray[np.float64]: ...
    @property
    def evidence_k_eff(self) -> NDArray[np.float64]: ...
    @property
    def pos_0(self) -> NDArray[np.float64]: ...
    @property
    def pos_1(self) -> NDArray[np.float64]: ...

def association_track_summary(
    reports: _ReportColumns,
    *,
    options: Mapping[str, Any],
) -> tuple[PictureCounts, TimeCover]: ...

@final
class PictureCounts:
    @property
    def micros(self) -> NDArray[np.uint64]: ...
    @property
    def reach(self) -> NDArray[np.uint64]: ...
    @property
    def reports(self) -> NDArray[np.uint64]: ...
    @property
    def cell_source(self) -> NDArray[np.uint32]: ...
    @property
    def cell_row(self) -> NDArray[np.int64]: ...
    @property
    def cell_col(self) -> NDArray[np.int64]: ...
    @property
    def cell_micros(self) -> NDArray[np.uint64]: ...
    @property
    def time(self) -> tuple[float, float]: ...

@final
class TimeCover:
    @property
    def cover_offsets(self) -> NDArray[np.uint32]: ...
    @property
    def cover_start(self) -> NDArray[np.float64]: ...
    @property
    def cover_end(self) -> NDArray[np.float64]: ...
    @property
    def cover_reports(self) -> NDArray[np.uint32]: ...

def association_track_partials(reports: _ReportColumns) -> NDArray[np.float64]: ...
def association_track_boxes(
    partials: NDArray[np.float64],
    track: NDArray[np.uint32],
    n_tracks: int,
    *,
    geographic: bool,
    alignment: Mapping[str, float],
    halo: float = 0.0,
) -> TrackBoxes: ...

@final
class TrackBoxes:
    @property
    def reports(self) -> NDArray[np.uint64]: ...
    @property
    def start(self) -> NDArray[np.float64]: ...
    @property
    def end(self) -> NDArray[np.float64]: ...
    @property
    def spread(self) -> NDArray[np.float64]: ...
    @property
    def halo(self) -> NDArray[np.float64]: ...
    @property
    def lo(self) -> NDArray[np.float64]: ...
    @property
    def hi(self) -> NDArray[np.float64]: ...
    @property
    def first_time(self) -> NDArray[np.float64]: ...
    @property
    def first_aou(self) -> NDArray[np.float64]: ...

def association_finish(
    tracks: Mapping[str, NDArray[Any]],
    pairs: dict[str, Any],
    counts: list[dict[str, Any]],
    decisions: _DecisionColumns,
    *,
    geographic: bool,
    options: Mapping[str, Any],
    memo: PosteriorMemo | None = None,
) -> AssociationOutput: ...
