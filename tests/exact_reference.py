"""An independent, high-precision reference for the area of the intersection of two ellipses.

Written from the geometry alone with mpmath at 60 significant digits, sharing nothing with the
Rust kernel: the boundary of ``A`` in the normalised frame of ``B`` gives
``g(t) = |z(t)|^2 - 1``, a trigonometric polynomial of degree 2; with ``w = exp(i t)``,
``w^2 g`` is a quartic in ``w`` whose roots on the unit circle are the crossings. The area then
follows from Green's theorem, ``area = 1/2 \\oint x dy - y dx``, over the arcs of ``A`` inside
``B`` and the arcs of ``B`` inside ``A``; an arc ``c + rx cos t e1 + ry sin t e2`` from ``t0`` to
``t1`` contributes ``1/2 c x (u(t1) - u(t0)) + 1/2 rx ry (e1 x e2) (t1 - t0)`` exactly.

Ellipses are rows ``(x0, y0, rx, ry, phi)``, ``phi`` the bearing of the ``rx`` axis clockwise
from north: the ``rx`` axis is ``(sin phi, cos phi)``, the ``ry`` axis ``(cos phi, -sin phi)``.
"""

from __future__ import annotations

import warnings

import mpmath as mp

DPS = 60


def _frame(e):
    x0, y0, rx, ry, phi = (mp.mpf(float(v)) for v in e)
    s, c = mp.sin(phi), mp.cos(phi)
    return (x0, y0), rx, ry, (s, c), (c, -s)


def _point(e, t):
    (x0, y0), rx, ry, e1, e2 = e
    ct, st = mp.cos(t), mp.sin(t)
    return (x0 + rx * ct * e1[0] + ry * st * e2[0], y0 + rx * ct * e1[1] + ry * st * e2[1])


def _q(e, p):
    """Squared normalised radius of point ``p`` in ellipse ``e``."""
    (x0, y0), rx, ry, e1, e2 = e
    dx, dy = p[0] - x0, p[1] - y0
    u = (dx * e1[0] + dy * e1[1]) / rx
    v = (dx * e2[0] + dy * e2[1]) / ry
    return u * u + v * v


def _param(e, p):
    """The parameter ``t`` of the point of ``e``'s boundary nearest to the ray through ``p``."""
    (x0, y0), rx, ry, e1, e2 = e
    dx, dy = p[0] - x0, p[1] - y0
    u = (dx * e1[0] + dy * e1[1]) / rx
    v = (dx * e2[0] + dy * e2[1]) / ry
    return mp.atan2(v, u)


def _crossings(a, b):
    """Parameters on ``a`` where ``a``'s boundary crosses ``b``'s (roots of the quartic on the
    unit circle), sorted in ``[0, 2 pi)``."""
    (xa, ya), rxa, rya, e1a, e2a = a
    (xb, yb), rxb, ryb, e1b, e2b = b

    def to_b(dx, dy):
        return (
            (dx * e1b[0] + dy * e1b[1]) / rxb,
            (dx * e2b[0] + dy * e2b[1]) / ryb,
        )

    w = to_b(xa - xb, ya - yb)
    p = to_b(rxa * e1a[0], rxa * e1a[1])
    q = to_b(rya * e2a[0], rya * e2a[1])
    pp = p[0] ** 2 + p[1] ** 2
    qq = q[0] ** 2 + q[1] ** 2
    pq = p[0] * q[0] + p[1] * q[1]
    ww = w[0] ** 2 + w[1] ** 2
    k0 = ww - 1 + (pp + qq) / 2
    k1, k2 = (pp - qq) / 2, pq
    k3, k4 = 2 * (w[0] * p[0] + w[1] * p[1]), 2 * (w[0] * q[0] + w[1] * q[1])
    # g = k0 + k1 cos 2t + k2 sin 2t + k3 cos t + k4 sin t; cos nt = (w^n + w^-n)/2,
    # sin nt = (w^n - w^-n)/(2i): w^2 g = c4 w^4 + c3 w^3 + c2 w^2 + c1 w + c0
    c4 = (k1 - 1j * k2) / 2
    c3 = (k3 - 1j * k4) / 2
    c2 = k0
    c1 = (k3 + 1j * k4) / 2
    c0 = (k1 + 1j * k2) / 2
    coeffs = [mp.mpc(c) for c in (c4, c3, c2, c1, c0)]
    size = max(abs(c) for c in coeffs) + 1
    if all(abs(c) <= size * mp.mpf(10) ** (-DPS + 5) for c in coeffs):
        return None  # g vanishes identically: the boundaries coincide
    while coeffs and abs(coeffs[0]) == 0:
        coeffs.pop(0)
    if len(coeffs) < 2:
        return []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        roots = mp.polyroots(coeffs, maxsteps=400, extraprec=4 * DPS)
    ts = []
    for r in roots:
        if abs(abs(r) - 1) < mp.mpf(10) ** (-DPS // 2):
            t = mp.arg(r) % (2 * mp.pi)
            ts.append(t)
    ts.sort()
    return ts


def _arc(e, t0, t1):
    """``1/2 \\int x dy - y dx`` along ``e``'s boundary from ``t0`` to ``t1`` (``t1 > t0``)."""
    (x0, y0), rx, ry, e1, e2 = e
    p0, p1 = _point(e, t0), _point(e, t1)
    du = (p1[0] - p0[0], p1[1] - p0[1])
    cross_axes = e1[0] * e2[1] - e1[1] * e2[0]
    return (x0 * du[1] - y0 * du[0]) / 2 + rx * ry * cross_axes * (t1 - t0) / 2


def _inside_arcs(a, b, ts):
    """Green's integral over the arcs of ``a`` (between consecutive crossings ``ts``) that lie
    inside ``b``, oriented like ``a``."""
    total = mp.mpf(0)
    n = len(ts)
    for i in range(n):
        t0 = ts[i]
        t1 = ts[(i + 1) % n] + (2 * mp.pi if i + 1 == n else 0)
        if t1 - t0 <= 0:
            continue
        mid = _point(a, (t0 + t1) / 2)
        if _q(b, mid) < 1:
            total += _arc(a, t0, t1)
    return total


def area(ea, eb) -> mp.mpf:
    """The area of the intersection of the ellipses ``ea`` and ``eb`` (rows), to about 30
    significant digits."""
    with mp.workdps(DPS):
        a, b = _frame(ea), _frame(eb)
        area_a = mp.pi * a[1] * a[2]
        area_b = mp.pi * b[1] * b[2]
        ta = _crossings(a, b)
        if ta is None:
            return area_a
        if len(ta) < 2:
            # no crossing (a tangency at most): nested or disjoint
            if _q(b, _point(a, mp.mpf("0.3"))) < 1 and _q(b, _point(a, mp.mpf("3.4"))) < 1:
                return area_a
            if _q(a, _point(b, mp.mpf("0.3"))) < 1 and _q(a, _point(b, mp.mpf("3.4"))) < 1:
                return area_b
            return mp.mpf(0)
        tb = sorted(_param(b, _point(a, t)) % (2 * mp.pi) for t in ta)
        # both boundaries run the same way round (the frames have one handedness), so the
        # signed integrals add; their sign is that orientation
        total = _inside_arcs(a, b, ta) + _inside_arcs(b, a, tb)
        return abs(total)


def overlap(ea, eb) -> mp.mpf:
    """``area(A ∩ B) / area(smaller)``."""
    with mp.workdps(DPS):
        small = mp.pi * min(
            mp.mpf(float(ea[2])) * mp.mpf(float(ea[3])),
            mp.mpf(float(eb[2])) * mp.mpf(float(eb[3])),
        )
        return min(area(ea, eb) / small, mp.mpf(1))
