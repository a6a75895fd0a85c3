"""Bishop's simplified method of slices over circular slip surfaces: the limit-equilibrium reference of the
stability tests (docs/slope-stability.md), written for geompm and checked in tests/unit/test_bishop.py.

For a circle of centre (xc, yc) and radius R cutting a ground surface y_s(x) of one soil (c, phi, gamma),
the slip mass is cut into n vertical slices of width b; slice i has weight W_i = gamma b (y_s - y_arc) at
its middle, base inclination alpha_i (sin(alpha_i) = (x_i - xc) / R, signed so that the mass moves down the
slope) and pore pressure u_i on its base.  Moment equilibrium about the centre with the interslice shear
forces neglected (Bishop 1955, Geotechnique 5(1):7) gives

    F = sum [c b + (W - u b) tan(phi)] / m_alpha  /  sum W sin(alpha),
    m_alpha = cos(alpha) + sin(alpha) tan(phi) / F,

solved by fixed-point iteration.  The factor of safety of the slope is the least F over the circles that
stay above a rigid base (``base``): a grid over centres and radii, refined around the best circle.
For phi = 0 the method is exact moment equilibrium of a circular block (Taylor 1948, ch. 16).
"""

from __future__ import annotations

import math

import numpy as np


def surface_from_points(xs, ys):
    """The ground surface y_s(x) through the points (xs increasing), held flat beyond them."""
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    return lambda x: np.interp(x, xs, ys)


def _slip_interval(surface, xc, yc, R, lo, hi, samples=400):
    """The x interval where the circle's lower arc lies below the ground and bounds the most soil (a circle
    may dip below the ground again beyond the toe: that sliver is not the slip mass), or None."""
    x = np.linspace(max(lo, xc - R), min(hi, xc + R), samples)  # x[0], x[-1]: the arc's ends (or lo, hi)
    if x.size < 2 or x[-1] <= x[0]:
        return None
    arc = yc - np.sqrt(np.maximum(R * R - (x - xc) ** 2, 0.0))
    inside = surface(x) - arc > 0.0
    if not inside.any():
        return None
    idx = np.flatnonzero(inside)
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    depth = surface(x) - arc
    run = max(runs, key=lambda r: float(depth[r].sum()))
    g = lambda xx: surface(xx) - (yc - math.sqrt(max(R * R - (xx - xc) ** 2, 0.0)))  # noqa: E731

    def edge(a, b):  # g(a) <= 0 < g(b) or the reverse: bisect
        for _ in range(60):
            m = 0.5 * (a + b)
            if (g(m) > 0.0) == (g(b) > 0.0):
                b = m
            else:
                a = m
        return 0.5 * (a + b)

    i0, i1 = run[0], run[-1]
    if i0 == 0 or i1 == x.size - 1:  # the arc ends inside the soil: it does not bound a mass with the ground
        return None
    x1 = edge(x[i0 - 1], x[i0]) if i0 > 0 else x[0]
    x2 = edge(x[i1 + 1], x[i1]) if i1 < x.size - 1 else x[-1]
    return x1, x2


def bishop_factor(surface, xc, yc, R, c, phi_deg, gamma, base=-np.inf, slices=80, pore=None, lo=-1e9, hi=1e9,
                  tol=1e-9, column=None):
    """Bishop's simplified F of one circle (module docstring); None if the circle cuts no soil, passes below
    ``base`` or drives nothing.  ``pore(x, y)``: pore pressure [Pa] on the slip surface (default none);
    ``column(x, y_arc)``: a slice's weight per unit width [Pa] in place of gamma (y_s - y_arc) (a soil of two
    unit weights: buoyant below a pond)."""
    span = _slip_interval(surface, xc, yc, R, lo, hi)
    if span is None:
        return None
    x1, x2 = span
    b = (x2 - x1) / slices
    x = x1 + b * (np.arange(slices) + 0.5)
    root = np.sqrt(np.maximum(R * R - (x - xc) ** 2, 1e-300))
    arc = yc - root
    if arc.min() < base - 1e-9 or (yc - R < base - 1e-9 and x1 <= xc <= x2):
        return None
    W = b * (gamma * np.maximum(surface(x) - arc, 0.0) if column is None else column(x, arc))
    sin_a = (x - xc) / R
    drive = float(np.sum(W * sin_a))
    if abs(drive) < 1e-12 * max(float(W.sum()), 1e-300):
        return None
    if drive < 0.0:  # the mass moves towards -x: measure alpha the other way
        sin_a, drive = -sin_a, -drive
    cos_a = root / R
    t = math.tan(math.radians(phi_deg))
    u = np.zeros_like(x) if pore is None else np.asarray([pore(xi, yi) for xi, yi in zip(x, arc)], float)
    num0 = c * b + np.maximum(W - u * b, 0.0) * t
    F = 1.0
    for _ in range(200):
        m = cos_a + sin_a * t / F
        if t > 0.0 and np.any(m <= 0.2):  # m_alpha too small: an unrealistic circle (Whitman & Bailey 1967)
            return None
        F_new = float(np.sum(num0 / m)) / drive
        if abs(F_new - F) <= tol * F_new:
            return F_new
        F = F_new
    return F


def critical_circle(surface, c, phi_deg, gamma, centres, radii, base=-np.inf, refine=4, **kw):
    """(least F, (xc, yc, R)) over the grid ``centres`` (xs, ys) x ``radii`` (and, for each centre, the circle
    tangent to a finite ``base``, where the critical circle of a slope on a firm layer often lies), then
    ``refine`` times over a grid three times finer around the best circle found."""
    xs, ys, rs = (np.asarray(a, float) for a in (*centres, radii))
    best = (math.inf, None)
    for level in range(refine + 1):
        for xc in xs:
            for yc in ys:
                tangent = [yc - base] if np.isfinite(base) and yc > base else []  # the circle touching the base
                for R in [*rs, *tangent]:
                    F = bishop_factor(surface, xc, yc, R, c, phi_deg, gamma, base=base, **kw)
                    if F is not None and F < best[0]:
                        best = (F, (float(xc), float(yc), float(R)))
        if best[1] is None:
            break
        dx, dy, dr = ((a[-1] - a[0]) / max(len(a) - 1, 1) for a in (xs, ys, rs))
        xc, yc, R = best[1]
        xs = np.linspace(xc - dx, xc + dx, 7)
        ys = np.linspace(yc - dy, yc + dy, 7)
        rs = np.linspace(max(R - dr, 1e-6), R + dr, 7)
    return best
