"""Robust measures of a granular deposit in 2D: its front and its height, from particle volumes.

The furthest particle is not a runout: one particle that rolls ahead of the
deposit moves it by a cell, and more particles per cell make such outliers
likelier, so that "runout" grows with refinement for reasons that have
nothing to do with the bulk (issue 15).  Here the deposit is a thickness
profile instead.  Each particle stands for a square of area A_p (a volume
per metre in plane strain; pass m_p / rho_0, the solid area, so that a
particle whose volume grew as it separated from the flow does not thicken
the deposit) and width w_p = sqrt(A_p): spread as a
top-hat of height A_p / w_p over [x_p - w_p/2, x_p + w_p/2], the particles
add up to the local thickness t(x) [m], exactly for a regular particle
lattice whatever the cell size.  The **front** is the largest x with
t(x) >= ``threshold`` (e.g. 0.05 H0), the **height** the largest t.  Both are
tied to the initial column's size, not to the grid, so they compare across
cell sizes, as long as one particle layer (the particle spacing) is thinner
than the threshold; with 2 particles per cell and h <= H0/20 it is at most
H0/40 against a threshold of 0.05 H0.  t is sampled every ``dx``.
"""

from __future__ import annotations

import numpy as np


def thickness_profile(p_x: np.ndarray, p_vol: np.ndarray, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """(x samples [m], thickness t [m]) of a 2D deposit, every dx, from top-hat particles."""
    x = p_x[:, 0]
    w = np.sqrt(p_vol)
    lo = float((x - 0.5 * w).min())
    n = int(np.ceil(((x + 0.5 * w).max() - lo) / dx)) + 2
    diff = np.zeros(n + 1)
    a = np.clip(np.rint((x - 0.5 * w - lo) / dx).astype(np.int64), 0, n)
    b = np.clip(np.rint((x + 0.5 * w - lo) / dx).astype(np.int64), 0, n)
    np.add.at(diff, a, p_vol / w)
    np.add.at(diff, b, -p_vol / w)
    return lo + dx * (np.arange(n) + 0.5), np.cumsum(diff)[:n]


def deposit_front(p_x: np.ndarray, p_vol: np.ndarray, threshold: float, dx: float) -> float:
    """Largest x [m] where the deposit is at least ``threshold`` [m] thick."""
    xs, t = thickness_profile(p_x, p_vol, dx)
    thick = np.nonzero(t >= threshold)[0]
    return float(xs[thick[-1]] + 0.5 * dx) if thick.size else float("nan")


def deposit_height(p_x: np.ndarray, p_vol: np.ndarray, dx: float) -> float:
    """Largest thickness [m] of the deposit."""
    return float(thickness_profile(p_x, p_vol, dx)[1].max())
