"""Independent NumPy reference of the planar time alignment and the per-instant GLR distance,
written from the model in docs/association.md (nothing here calls geofeas).

A track is ``(t, rows)`` with rows ``x, y, rx, ry, phi`` sorted by time. At time ``t`` between
reports ``k`` and ``k + 1`` (gap ``T <= max_gap``, or ``T <= max_still_gap`` with the two centres
at most ``sqrt(chi2_2(0.99) q T)`` apart, ``chi2_2(0.99) = -2 ln 0.01``; ``tau = t - t_k``,
``w = tau / T``):
centre ``(1 - w) c_k + w c_{k+1}``, covariance ``(1 - w) R_k + w R_{k+1} + q tau (T - tau) / T I``.
Within ``horizon`` of an end, the centre moves at the velocity of the two end reports (if they
are at most ``max_gap`` apart) and the covariance grows by ``q |dt| I``. The instants of a pair
are the reports of either track at which the other has a state, a shared time counted once.
"""

from __future__ import annotations

import numpy as np

from reference import covariance


def state(t_rep, rows, t, *, max_gap, horizon, q, max_still_gap=900.0):
    """``(centre, covariance)`` of a track at ``t`` or ``None``."""
    t_rep = np.asarray(t_rep, float)
    covs = covariance(np.asarray(rows, float))
    centres = np.asarray(rows, float)[:, :2]
    n = len(t_rep)
    hit = np.flatnonzero(t_rep == t)
    if hit.size:
        return centres[hit[0]], covs[hit[0]]
    if t < t_rep[0] or t > t_rep[-1]:
        end, nb = (0, 1) if t < t_rep[0] else (n - 1, n - 2)
        dt = t - t_rep[end]
        if abs(dt) > horizon:
            return None
        v = np.zeros(2)
        if n >= 2 and abs(t_rep[end] - t_rep[nb]) <= max_gap:
            v = (centres[end] - centres[nb]) / (t_rep[end] - t_rep[nb])
        return centres[end] + v * dt, covs[end] + q * abs(dt) * np.eye(2)
    k = int(np.searchsorted(t_rep, t)) - 1
    gap = t_rep[k + 1] - t_rep[k]
    step = np.hypot(*(centres[k + 1] - centres[k]))
    still = gap <= max_still_gap and step**2 <= -2.0 * np.log(0.01) * q * gap
    if gap > max_gap and not still:
        return None
    tau = t - t_rep[k]
    w = tau / gap
    c = (1 - w) * centres[k] + w * centres[k + 1]
    r = (1 - w) * covs[k] + w * covs[k + 1] + q * tau * (gap - tau) / gap * np.eye(2)
    return c, r


def pair_distances(ta, ra, tb, rb, *, max_gap=300.0, horizon=0.0, q=0.0, max_still_gap=900.0):
    """Times and squared Mahalanobis distances ``d^T (R_a + R_b)^-1 d`` of the common
    instants of two planar tracks, sorted by time."""
    ta, tb = np.asarray(ta, float), np.asarray(tb, float)
    ra, rb = np.asarray(ra, float), np.asarray(rb, float)
    out = []
    kw = dict(max_gap=max_gap, horizon=horizon, q=q, max_still_gap=max_still_gap)
    for k, t in enumerate(ta):
        if tb[0] - horizon <= t <= tb[-1] + horizon:
            s = state(tb, rb, t, **kw)
            if s is not None:
                out.append((t, ra[k, :2], covariance(ra[k])[0], s[0], s[1]))
    for k, t in enumerate(tb):
        if t in set(ta.tolist()):
            continue
        if ta[0] - horizon <= t <= ta[-1] + horizon:
            s = state(ta, ra, t, **kw)
            if s is not None:
                out.append((t, s[0], s[1], rb[k, :2], covariance(rb[k])[0]))
    out.sort(key=lambda x: x[0])
    times = np.array([o[0] for o in out])
    m = np.array([(o[1] - o[3]) @ np.linalg.solve(o[2] + o[4], o[1] - o[3]) for o in out])
    return times, m


def effective_instants(times, tau):
    """``k^2 / sum_ij exp(-2 |t_i - t_j| / tau)``."""
    times = np.asarray(times, float)
    k = len(times)
    if tau <= 0 or k < 2:
        return float(k)
    rho = np.exp(-2 * np.abs(times[:, None] - times[None, :]) / tau)
    return float(np.clip(k * k / rho.sum(), 1, k))
