"""Robust measures of a granular deposit in 2D: its front and its height, from particle volumes.

The furthest particle is not a runout: one particle that rolls ahead of the
deposit moves it by a cell, and more particles per cell make such outliers
likelier, so that "runout" grows with refinement for reasons that have
nothing to do with the bulk (docs/validation/column-collapse.md).  Here the deposit is a thickness
profile instead.  Each particle stands for a square of area A_p (a volume
per metre in plane strain; pass m_p / rho_0, the solid area, so that a
particle whose volume grew as it separated from the flow does not thicken
the deposit) and width w_p = sqrt(A_p): spread as a
top-hat of height A_p / w_p over [x_p - w_p/2, x_p + w_p/2], the particles
add up to the local thickness t(x) [m], exactly for a regular particle
lattice whatever the cell size; the profile is the exact mean of t over
bins of width dx, so particles narrower than a bin are not aliased.  The **front** is the largest x where t(x)
>= ``threshold`` (e.g. 0.05 H0) both at x and on average over a window of
5 x threshold (0.25 H0) centred on x, the **height** the largest t averaged over a window as wide
as the threshold.  The averaging matters for tall columns: their deposit
ends in a tail about as thick as 0.05 H0 (a = 2: 7-10 mm over 0.1 m), where
the raw profile crosses the threshold at clumps, and the front moved by
up to 10 % between grids for that reason alone (docs/validation/column-collapse.md).  Both are
tied to the initial column's size, not to the grid (particle lattices bunch
into a bin by 10 % and more: hence the averaging), so they compare across
cell sizes, as long as one particle layer (the particle spacing) is thinner
than the threshold; with 2 particles per cell and h <= H0/20 it is at most
H0/40 against a threshold of 0.05 H0.  t is sampled every ``dx``.
"""

from __future__ import annotations

import numpy as np


def thickness_profile(p_x: np.ndarray, p_vol: np.ndarray, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """(bin centres [m], thickness t [m]) of a 2D deposit: the exact mean over each bin of width dx of the
    particles' top-hats, so that a particle narrower than a bin is neither dropped nor doubled.

    The integral F(x) of the top-hat sum is piecewise linear, with slope steps +c_p at a_p = x_p - w_p/2
    and -c_p at b_p = x_p + w_p/2 (c_p = A_p / w_p); at the bin edges e_j, F(e_j) = e_j S1_j - S2_j with
    S1_j, S2_j the sums of the slope steps c and of c a (resp. c b) left of e_j, and t_j = (F_j+1 - F_j)/dx.
    """
    x = p_x[:, 0]
    w = np.sqrt(p_vol)
    c = p_vol / w
    left, right = x - 0.5 * w, x + 0.5 * w
    lo = float(left.min())
    n = int(np.ceil((right.max() - lo) / dx)) + 2
    edges = lo + dx * np.arange(n + 1)
    # a step at s counts for the edges e_j > s, i.e. j >= floor((s - lo)/dx) + 1
    ia = np.clip(np.floor((left - lo) / dx).astype(np.int64) + 1, 0, n + 1)
    ib = np.clip(np.floor((right - lo) / dx).astype(np.int64) + 1, 0, n + 1)
    s1 = np.cumsum(np.bincount(ia, c, n + 2) - np.bincount(ib, c, n + 2))[:n + 1]
    s2 = np.cumsum(np.bincount(ia, c * left, n + 2) - np.bincount(ib, c * right, n + 2))[:n + 1]
    F = edges * s1 - s2
    return lo + dx * (np.arange(n) + 0.5), np.diff(F) / dx


def _window(t: np.ndarray, dx: float, window: float, kind: str) -> np.ndarray:
    """Means of t over ``window`` [m]: 'same' centred (odd sample count; zero beyond the profile's ends, where
    there is no material) or 'valid' (windows inside the profile); never longer than the profile."""
    k = min(len(t), max(1, int(round(window / dx))))
    if kind == "same":
        k -= 1 - k % 2
    return np.convolve(t, np.ones(k) / k, mode=kind)


def front_of(xs: np.ndarray, t: np.ndarray, threshold: float, dx: float, window: float | None = None) -> float:
    """deposit_front of a profile from thickness_profile."""
    around = _window(t, dx, 5.0 * threshold if window is None else window, "same")
    thick = np.nonzero((t >= threshold) & (around >= threshold))[0]
    return float(xs[thick[-1]] + 0.5 * dx) if thick.size else float("nan")


def height_of(t: np.ndarray, dx: float, window: float) -> float:
    """deposit_height of a profile from thickness_profile."""
    return float(_window(t, dx, window, "valid").max())


def deposit_front(p_x: np.ndarray, p_vol: np.ndarray, threshold: float, dx: float,
                  window: float | None = None) -> float:
    """Largest x [m] where the deposit is at least ``threshold`` [m] thick, both there and on average over
    the ``window`` [m] (default 5 x threshold) centred on it: the front of the main deposit, which neither
    one particle nor a clump in a thin tail can move, and which an abrupt or tapering edge keeps where
    it is (the average alone would carry an abrupt edge half a window forward)."""
    return front_of(*thickness_profile(p_x, p_vol, dx), threshold, dx, window)


def deposit_height(p_x: np.ndarray, p_vol: np.ndarray, dx: float, window: float) -> float:
    """Largest thickness [m] of the deposit averaged over ``window`` [m] (e.g. the front's threshold,
    0.05 H0): one column of particles bunched into a bin does not raise it."""
    return height_of(thickness_profile(p_x, p_vol, dx)[1], dx, window)
