"""The thalweg from a cell of a height raster: the line of steepest descent, cell to cell.

The relief shorter than a few cells (a DEM's roughness, 0.3 m hollows on a 1 m raster) would make the line
wander and end in every hollow, so the ground is first averaged over ``SMOOTH`` x ``SMOOTH`` cells (a box
filter), as a practitioner draws a channel's axis, and the distance along the path is measured on its points
averaged over up to ``SMOOTH`` neighbours each way, symmetrically, so the ends stay (removing D8's staircase, up to 8 % longer than the line it
follows).  From the start cell the path steps to the neighbour, of eight, with the largest drop per distance (dz / dist:
a diagonal step is sqrt(cx^2 + cy^2) long; D8 routing, O'Callaghan & Mark 1984).  In a pit (a hollow of the
DEM's relief, no neighbour lower) it steps to the unvisited neighbour that rises least, over the hollow's
lowest rim as water filling it would, and goes on down; it ends at the raster's edge or when every
neighbour has been visited.  The hazard maps measure the runout along it: the distance along the path to
the last of its cells the flow reached (writers/hazard_maps.py).
"""

from __future__ import annotations

import math

import numpy as np

STEPS = [(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)]
#: cells of the box filter on the ground, and points each way of the path's moving average
SMOOTH = 5


def thalweg(ground: np.ndarray, cx: float, cy: float, start: tuple[int, int]) -> tuple[list, np.ndarray]:
    """(cells (i, j) of the path from ``start``, the distance [m] along it to each) on ``ground`` (nx, ny), cells
    cx by cy [m] (axis 0 along x)."""
    from scipy.ndimage import uniform_filter

    ground = uniform_filter(np.asarray(ground, float), size=SMOOTH, mode="nearest")
    nx, ny = ground.shape
    path = [tuple(int(k) for k in start)]
    seen = {path[0]}
    i, j = path[0]
    for _ in range(nx * ny):
        if i in (0, nx - 1) or j in (0, ny - 1):
            break  # the raster's edge
        best, step = -math.inf, None
        for di, dj in STEPS:
            a, b = i + di, j + dj
            if (a, b) not in seen:
                length = math.hypot(di * cx, dj * cy)
                slope = (ground[i, j] - ground[a, b]) / length
                if slope > best:
                    best, step = slope, (a, b)
        if step is None:
            break
        i, j = step[0], step[1]
        seen.add((i, j))
        path.append((i, j))
    pts = np.asarray(path, float) * np.array([cx, cy])
    k = SMOOTH
    last = len(pts) - 1
    mean = np.array([pts[n - w:n + w + 1].mean(axis=0) for n in range(len(pts)) for w in [min(k, n, last - n)]])
    return path, np.r_[0.0, np.cumsum(np.hypot(*np.diff(mean, axis=0).T))]


def runout_along(path: list, dist: np.ndarray, reached: np.ndarray) -> float | None:
    """The distance along ``path`` to the last of its cells where ``reached`` (nx, ny) holds, None if none."""
    hit = [k for k, (i, j) in enumerate(path) if reached[i, j]]
    return float(dist[hit[-1]]) if hit else None
