"""The thalweg from a cell of a height raster: the line of steepest descent, cell to cell.

From the start cell the path steps to the lowest of its eight neighbours while that is lower than the cell
(the drop per distance, dz / dist, decides: a diagonal step is sqrt(cx^2 + cy^2) long), until a pit or the
raster's edge (D8 routing, O'Callaghan & Mark 1984).  The hazard maps measure the runout along it: the
distance along the path to the last of its cells the flow reached (writers/hazard_maps.py).
"""

from __future__ import annotations

import math

import numpy as np

STEPS = [(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)]


def thalweg(ground: np.ndarray, cx: float, cy: float, start: tuple[int, int]) -> tuple[list, np.ndarray]:
    """(cells (i, j) of the path from ``start``, the distance [m] along it to each) on ``ground`` (nx, ny), cells
    cx by cy [m] (axis 0 along x)."""
    nx, ny = ground.shape
    path, dist = [tuple(int(k) for k in start)], [0.0]
    i, j = path[0]
    for _ in range(nx * ny):
        best, step = 0.0, None
        for di, dj in STEPS:
            a, b = i + di, j + dj
            if 0 <= a < nx and 0 <= b < ny:
                length = math.hypot(di * cx, dj * cy)
                slope = (ground[i, j] - ground[a, b]) / length
                if slope > best:
                    best, step = slope, (a, b, length)
        if step is None:
            break
        i, j = step[0], step[1]
        path.append((i, j))
        dist.append(dist[-1] + step[2])
    return path, np.asarray(dist)


def runout_along(path: list, dist: np.ndarray, reached: np.ndarray) -> float | None:
    """The distance along ``path`` to the last of its cells where ``reached`` (nx, ny) holds, None if none."""
    hit = [k for k, (i, j) in enumerate(path) if reached[i, j]]
    return float(dist[hit[-1]]) if hit else None
