"""Which 2D points lie inside a polygon (even-odd rule): shared by body shapes and release areas."""

from __future__ import annotations

import numpy as np


def points_in_polygon(pts: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """Even-odd rule for 2D points (m, 2) against a closed polygon (k, 2)."""
    x, y = pts[:, 0], pts[:, 1]
    inside = np.zeros(len(pts), dtype=bool)
    xj, yj = verts[-1]
    for xi, yi in verts:
        crosses = (yi > y) != (yj > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xcross = (xj - xi) * (y - yi) / (yj - yi) + xi
        inside ^= crosses & (x < xcross)
        xj, yj = xi, yi
    return inside
