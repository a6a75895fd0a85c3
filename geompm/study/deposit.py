"""Robust measures of a granular deposit in 2D: its front and its height, from particle volumes.

The furthest particle is not a runout: one particle that rolls ahead of the
deposit moves it by a cell, and more particles per cell make such outliers
likelier, so that "runout" grows with refinement for reasons that have
nothing to do with the bulk (issue 15).  Here the deposit is a thickness
profile instead: the particles' volumes (areas per metre in plane strain)
summed over columns of width ``dx`` along x and divided by dx give the local
thickness t(x) [m]; the **front** is the right edge of the furthest column
with t >= ``threshold`` (e.g. 0.05 H0), the **height** the largest t.  Both
are tied to the initial column's size, not to the grid, so they compare
across cell sizes.
"""

from __future__ import annotations

import numpy as np


def thickness_profile(p_x: np.ndarray, p_vol: np.ndarray, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """(left edges of the columns [m], thickness t [m]) of a 2D deposit, columns of width dx from x = min."""
    x = p_x[:, 0]
    lo = float(np.floor(x.min() / dx) * dx)
    idx = np.floor((x - lo) / dx).astype(np.int64)
    t = np.bincount(idx, weights=p_vol, minlength=int(idx.max()) + 1) / dx
    return lo + dx * np.arange(t.size), t


def deposit_front(p_x: np.ndarray, p_vol: np.ndarray, threshold: float, dx: float) -> float:
    """Right edge [m] of the furthest column whose thickness is at least ``threshold`` [m]."""
    edges, t = thickness_profile(p_x, p_vol, dx)
    thick = np.nonzero(t >= threshold)[0]
    return float(edges[thick[-1]] + dx) if thick.size else float("nan")


def deposit_height(p_x: np.ndarray, p_vol: np.ndarray, dx: float) -> float:
    """Largest column thickness [m] of the deposit."""
    return float(thickness_profile(p_x, p_vol, dx)[1].max())
