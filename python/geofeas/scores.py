"""Geofeasibility scores of pairs of 2-sigma AOU ellipses (seed 000).

Every ellipse is a row ``(x0, y0, rx, ry, phi)``: centre (x east, y north), 2-sigma semi-axes and
the bearing of the ``rx`` axis in radians clockwise from north. Every score accepts a single
ellipse ``(5,)`` or an array ``(n, 5)`` on either side: two arrays are scored elementwise (a single
ellipse broadcasts against an array), and two single ellipses give a ``float``. :func:`cdist`
scores all pairs between two sets. The work runs in Rust with the GIL released and can be
interrupted with Ctrl-C.

**Input domain** (every function here): every field finite, ``|x0|, |y0| <= 1e50``, semi-axes in
``[1e-50, 1e50]``, aspect ratio ``max(rx, ry) / min(rx, ry) <= 1e8``. Inside it every score is
computed to full accuracy (the exact overlap to ``1e-11``) without overflow or underflow;
outside it a :class:`GeofeasError` names the argument (``a``, ``b``, ``e``), row and field
(also as its ``argument``, ``row`` and ``field`` attributes). Options: ``vertices`` in
``[8, 2**20]``, ``samples`` in ``[1, 2**32]`` (the length of the Sobol sequence; one pair of
``2**32`` samples runs for minutes and stops at Ctrl-C); an option the chosen score does not take is
refused.
"""

from __future__ import annotations

import os
import secrets
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._arrays import _error, as_ellipses, as_float_array
from ._core import GeofeasError

__all__ = [
    "DEFAULT_VERTICES",
    "SAMPLERS",
    "SCORE_DEFAULTS",
    "SCORE_NAMES",
    "SCORE_OPTIONS",
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

#: The options of the scores, defined once in the core (``score::schema``): dicts of ``name``,
#: ``default``, ``kind`` (``"bool"``, ``"int"`` or ``"text"``), ``choices``, ``range`` (``(min,
#: max)`` of an integer, or ``None``), ``help`` and ``scores`` (the scores that take it). The
#: keyword defaults of the functions below, the options the association passes to its score and
#: the flags of ``geofeas score`` are these (``tests/test_score_schema.py``).
SCORE_OPTIONS: tuple[dict[str, Any], ...] = tuple(_core.score_options())
_SPEC = {o["name"]: o for o in SCORE_OPTIONS}
#: The defaults of the score options, from :data:`SCORE_OPTIONS`.
SCORE_DEFAULTS: dict[str, Any] = {o["name"]: o["default"] for o in SCORE_OPTIONS}

#: Default polygon resolution of ``overlap(..., method="polygon")`` (``|g - g_true| <= 1e-4`` on
#: typical pairs).
DEFAULT_VERTICES: int = int(SCORE_DEFAULTS["vertices"])

#: Samplers of :func:`monte_carlo`.
SAMPLERS: tuple[str, ...] = tuple(_SPEC["sampler"]["choices"])

#: The names of the scores (the core's ``score::schema::score_names``).
SCORE_NAMES: tuple[str, ...] = tuple(_core.score_names())
ScoreName = Literal[
    "glr", "overlap", "monte_carlo", "bhattacharyya", "hellinger", "gaussian_product"
]
#: The options each score takes (the others are refused), from :data:`SCORE_OPTIONS`.
_OPTIONS: dict[str, frozenset[str]] = {
    score: frozenset(o["name"] for o in SCORE_OPTIONS if score in o["scores"])
    for score in SCORE_NAMES
}
_METHODS: tuple[str, ...] = tuple(_SPEC["method"]["choices"])


def _seed(seed: int | None) -> int:
    if seed is None:
        return secrets.randbits(64)
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise GeofeasError(f"seed must be an integer or None, got {seed!r}")
    if not 0 <= int(seed) < 2**64:
        raise GeofeasError(f"seed must be in [0, 2**64), got {seed}")
    return int(seed)


def _count(value: Any, name: str, minimum: int, below: int | None = 2**64) -> int:
    """``value`` as an int in ``[minimum, below)``; the core then checks the option's own
    range (``below`` only keeps the value convertible to a machine word)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise _error(name, f"must be an integer, got {value!r}")
    if int(value) < minimum:
        raise _error(name, f"must be >= {minimum}, got {value}")
    if below is not None and int(value) >= below:
        raise _error(name, f"must be < {below}, got {value}")
    return int(value)


def _options(score: str, options: dict[str, Any]) -> dict[str, Any]:
    if score not in _OPTIONS:
        raise GeofeasError(f"unknown score {score!r}; expected one of {sorted(_OPTIONS)}")
    unknown = set(options) - _OPTIONS[score]
    if unknown:
        raise GeofeasError(
            f"option(s) {sorted(unknown)} do not apply to score {score!r}; "
            f"it takes {sorted(_OPTIONS[score])}"
        )
    out: dict[str, Any] = {}
    if score == "overlap":
        options = {k: v for k, v in options.items() if v is not None}
        # a resolution alone asks for the polygon method (the exact method has none)
        options.setdefault("method", "polygon" if "vertices" in options else "exact")
        if "vertices" in options and options["method"] != "polygon":
            raise GeofeasError(
                "vertices applies only to method='polygon' (the exact method has no resolution)"
            )
    if "threshold" in options:
        out["threshold"] = bool(options["threshold"])
    if "vertices" in options:
        out["vertices"] = _count(options["vertices"], "vertices", _SPEC["vertices"]["range"][0])
    if "method" in options:
        if options["method"] not in _METHODS:
            raise GeofeasError(
                f"unknown overlap method {options['method']!r}; expected one of {list(_METHODS)}"
            )
        out["method"] = str(options["method"])
    if "sampler" in options:
        if options["sampler"] not in SAMPLERS:
            raise GeofeasError(
                f"unknown sampler {options['sampler']!r}; expected one of {list(SAMPLERS)}"
            )
        out["sampler"] = str(options["sampler"])
    if "samples" in options:
        out["samples"] = _count(options["samples"], "samples", _SPEC["samples"]["range"][0])
    if score == "monte_carlo":
        out["seed"] = _seed(options.get("seed"))
    return out


def _pairs(a: ArrayLike, b: ArrayLike, score: str, options: dict[str, Any]) -> Any:
    ea, single_a = as_ellipses(a, "a")
    eb, single_b = as_ellipses(b, "b")
    out = _core.score_pairs(ea, eb, score, _core.ScoreOptions(**_options(score, options)))
    if single_a and single_b:
        return float(out[0])
    return out


def glr(a: ArrayLike, b: ArrayLike, /, *, threshold: bool = False) -> Any:
    """Generalized likelihood ratio ``exp(-0.5 d^T (R1 + R2)^-1 d)`` (seed 000, eq. 71).

    Parameters
    ----------
    a, b : array_like, shape (5,) or (n, 5)
        Ellipses ``(x0, y0, rx, ry, phi)``.
    threshold : bool
        Return exactly 0 when the ellipses do not touch and exactly 1 when one lies inside the
        other (constraints 46-48 of the paper); the GLR in between.

    Returns
    -------
    float or ndarray of shape (n,)
    """
    return _pairs(a, b, "glr", {"threshold": threshold})


def overlap(
    a: ArrayLike,
    b: ArrayLike,
    /,
    *,
    method: str | None = None,
    vertices: int | None = None,
) -> Any:
    """Normalised overlap area ``area(A ∩ B) / area(smaller)`` (seed 000, eqs. 49-50).

    ``method="exact"`` (the default) computes the intersection analytically: the polygon of the
    boundary crossings plus one elliptic segment per boundary arc, the crossings isolated by
    certified subdivision of the boundary function; accurate to about ``1e-13`` and independent
    of the argument order. ``method="polygon"`` clips equal-area polygons of ``vertices``
    vertices with parry (error at most ``26 (1 + A_max / A_min) / vertices**3``). Disjoint pairs
    give exactly 0, nested and identical pairs exactly 1.

    Parameters
    ----------
    a, b : array_like, shape (5,) or (n, 5)
    method : {"exact", "polygon"}, optional
        Default ``"exact"``, or ``"polygon"`` when ``vertices`` is given.
    vertices : int, optional
        Polygon resolution (>= 8) of ``method="polygon"`` (default :data:`DEFAULT_VERTICES`);
        giving it alone selects the polygon method; an error with ``method="exact"``.

    Returns
    -------
    float or ndarray of shape (n,)
    """
    return _pairs(a, b, "overlap", {"vertices": vertices, "method": method})


def intersection_area(a: ArrayLike, b: ArrayLike, /) -> Any:
    """Exact area of the intersection of two ellipses (the numerator of eq. 49).

    Parameters
    ----------
    a, b : array_like, shape (5,) or (n, 5)

    Returns
    -------
    float or ndarray of shape (n,)
        In the squared unit of the coordinates.
    """
    ea, single_a = as_ellipses(a, "a")
    eb, single_b = as_ellipses(b, "b")
    out = _core.intersection_area(ea, eb)
    if single_a and single_b:
        return float(out[0])
    return out


def monte_carlo(
    a: ArrayLike,
    b: ArrayLike,
    /,
    *,
    samples: int = 500,
    seed: int | None = None,
    sampler: str = "importance",
) -> Any:
    """Monte-Carlo estimate of the normalised overlap area (seed 000, eq. 55).

    ``sampler="importance"`` is eq. 55: samples from the Gaussian of the smaller ellipse with
    weights ``1/p``. ``"uniform"`` draws the samples uniformly inside the smaller ellipse (the
    fraction inside the other is ``g``). ``"sobol"`` uses the first ``samples`` points of an
    Owen-scrambled Sobol sequence mapped uniformly into the smaller ellipse (randomised
    quasi-Monte-Carlo, error falling like ``samples**-0.75``: 64 points are as accurate as eq. 55
    with 500). Pair ``k`` of a call draws from its own stream derived from ``(seed, k)``, so a
    seed gives bit-identical results whatever the number of threads. ``seed=None`` draws a fresh
    random seed.

    Returns
    -------
    float or ndarray of shape (n,)
    """
    return _pairs(a, b, "monte_carlo", {"samples": samples, "seed": seed, "sampler": sampler})


def bhattacharyya(a: ArrayLike, b: ArrayLike, /) -> Any:
    """Bhattacharyya coefficient ``∫ sqrt(p1 p2)`` of the ellipses' Gaussians (eqs. 56-59).

    ``sqrt(4 sqrt(det R1 det R2) / det(R1 + R2)) exp(-d^T (R1 + R2)^-1 d / 4)``, evaluated
    without cancellation; 1 for identical ellipses.

    Returns
    -------
    float or ndarray of shape (n,)
    """
    return _pairs(a, b, "bhattacharyya", {})


def hellinger(a: ArrayLike, b: ArrayLike, /) -> Any:
    """Hellinger distance ``sqrt(1 - BC)`` of the ellipses' Gaussians (0 for identical ones).

    Returns
    -------
    float or ndarray of shape (n,)
    """
    return _pairs(a, b, "hellinger", {})


def gaussian_product(a: ArrayLike, b: ArrayLike, /) -> Any:
    """Normalised product of the two Gaussians, ``∫ p1 p2 / sqrt(∫ p1² ∫ p2²)``.

    The red line of the paper's Fig. 6, in closed form:
    ``sqrt(4 sqrt(det R1 det R2) / det(R1 + R2)) exp(-d^T (R1 + R2)^-1 d / 2)``, i.e. the GLR
    (eq. 71) times a shape factor that is 1 for equal covariances.

    Returns
    -------
    float or ndarray of shape (n,)
    """
    return _pairs(a, b, "gaussian_product", {})


def _memory_limit() -> int:
    """The largest ``cdist`` output accepted: half of the memory this process may use, the
    smallest of the physical memory, the cgroup limit (v2 ``memory.max``, v1
    ``memory.limit_in_bytes``) and the address-space limit ``RLIMIT_AS``."""
    limits = []
    try:
        limits.append(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        limits.append(16 << 30)
    for path in (
        "/sys/fs/cgroup/memory.max",
        "/sys/fs/cgroup/memory/memory.limit_in_bytes",
    ):
        try:
            with open(path, encoding="ascii") as fh:
                text = fh.read().strip()
        except OSError:
            continue
        if text.isdigit():
            limits.append(int(text))
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft != resource.RLIM_INFINITY and soft > 0:
            limits.append(soft)
    except (ImportError, OSError, ValueError):  # pragma: no cover - not POSIX
        pass
    return min(limits) // 2


def cdist(
    a: ArrayLike,
    b: ArrayLike,
    /,
    *,
    score: ScoreName = "glr",
    max_bytes: int | None = None,
    **options: Any,
) -> NDArray[np.float64]:
    """Scores of all pairs between two sets, like ``scipy.spatial.distance.cdist``.

    Parameters
    ----------
    a : array_like, shape (n, 5) or (5,)
    b : array_like, shape (m, 5) or (5,)
    score : {"glr", "overlap", "monte_carlo", "bhattacharyya", "hellinger", "gaussian_product"}
    max_bytes : int, optional
        Refuse outputs larger than this, before allocating (default, and upper bound: half
        of the memory the process may use: physical memory, cgroup limit, ``RLIMIT_AS``).
    **options
        The options of the chosen score (``threshold``; ``method``, ``vertices``; ``samples``,
        ``seed``, ``sampler``).
        Pair ``(i, j)`` of ``monte_carlo`` uses stream ``i * m + j``.

    Returns
    -------
    ndarray of shape (n, m)
    """
    ea, _ = as_ellipses(a, "a")
    eb, _ = as_ellipses(b, "b")
    # a caller's limit can lower the guard, never raise it past the memory this process has
    limit = _memory_limit()
    if max_bytes is not None:
        limit = min(limit, _count(max_bytes, "max_bytes", 0, below=None))
    result: NDArray[np.float64] = _core.score_cdist(
        ea, eb, score, _core.ScoreOptions(**_options(score, options)), max_bytes=limit
    )
    return result


def to_gaussian(e: ArrayLike, /) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Means ``(n, 2)`` and covariances ``(n, 2, 2)`` of ellipses (eqs. 56-59).

    A single ellipse ``(5,)`` gives a mean ``(2,)`` and a covariance ``(2, 2)``.
    """
    arr, single = as_ellipses(e, "e")
    mean, cov = _core.to_gaussian(arr)
    if single:
        return mean[0], cov[0]
    return mean, cov


def from_gaussian(mean: ArrayLike, cov: ArrayLike, /) -> NDArray[np.float64]:
    """The 2-sigma ellipses ``(n, 5)`` of Gaussians; the inverse of :func:`to_gaussian`.

    Uses a closed-form symmetric 2x2 eigen-decomposition; ``phi`` is returned in ``[0, pi)``
    and ``rx >= ry``. Covariances must be symmetric positive definite. A single mean ``(2,)`` and
    covariance ``(2, 2)`` give one ellipse ``(5,)``.
    """
    m = as_float_array(mean, "mean")
    c = as_float_array(cov, "cov")
    single = m.ndim == 1 and c.ndim == 2
    if single:
        m, c = m.reshape(1, -1), c.reshape(1, *c.shape)
    if m.ndim != 2 or m.shape[1] != 2 or c.ndim != 3 or c.shape[1:] != (2, 2):
        raise GeofeasError(
            f"mean, cov: expected shapes (n, 2) and (n, 2, 2), got {np.shape(mean)} and "
            f"{np.shape(cov)}"
        )
    if m.shape[0] != c.shape[0]:
        raise GeofeasError(f"mean has {m.shape[0]} rows but cov has {c.shape[0]}")
    out: NDArray[np.float64] = _core.from_gaussian(m, c)
    return out[0] if single else out
