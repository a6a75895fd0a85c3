"""What set-up checks of a release from GIS files before any step (3D): the volume the grid would cut off,
depths that look like a wrong unit, and whether the grid resolves the release's depth.

The release's columns (setup/release.Release: bottom(x, y) < z < top(x, y)) are sampled at the cell size h,
coarsened to at most MAX_COLUMNS per axis, in row blocks, so a large site needs no more memory than a few
rows of them.  Per unit plan area dA:

    V = sum (top - bottom) dA            the volume released [m3]
    V_cut = sum of the parts of each column above the grid's top or below its bottom

A cut of more than CUT_SHARE of V is refused with both volumes and the extent that holds it (a depth of
220.7 given in centimetres, clipped at the grid top, had silently released 43 406 m3 instead of about
134 000 m3).  A release reaching beside the grid in plan is seeded within it (the mass between two DEMs
that cover more than the grid, as intended) and the volume left out is warned about.  Warned: a column deeper than MAX_DEPTH [m] (a unit slip), and a mean depth V / A of fewer
than CELLS_DEEP cells (a flow about one cell deep lost 7 % of its runout between h = 1.5 and 1 m).
"""

from __future__ import annotations

import numpy as np

MAX_DEPTH = 50.0  # m: deeper releases are warned about (landslide sources of practice are shallower)
CELLS_DEEP = 4  # a release shallower than this many cells is warned about, with the cell size that resolves it
CUT_SHARE = 1e-3  # a cut-off volume above this share of the release is refused
MAX_COLUMNS = 2000  # columns per axis at most
ROWS = 64  # rows per block


def release_checks(release, lo, hi, origin, upper, h: float, json_path: str):
    """(problems, warnings) as (JSON path, sentence) lists."""
    spacing = max(h, float(np.max(hi[:2] - lo[:2])) / MAX_COLUMNS)
    xs = np.arange(lo[0] + 0.5 * spacing, hi[0], spacing)
    ys = np.arange(lo[1] + 0.5 * spacing, hi[1], spacing)
    dA = spacing * spacing
    vol = cut = beside = area = 0.0
    deepest, top_max = 0.0, -np.inf
    inside_x = (xs >= origin[0]) & (xs <= upper[0])
    for r in range(0, len(ys), ROWS):
        X, Y = np.meshgrid(xs, ys[r:r + ROWS], indexing="ij")
        bottom, top = release.columns(X.ravel(), Y.ravel())
        t = np.where(top > bottom, top - bottom, 0.0)
        released = t > 0.0
        if not released.any():
            continue
        vol += float(t.sum()) * dA
        area += float(released.sum()) * dA
        deepest = max(deepest, float(t.max()))
        top_max = max(top_max, float(top[released].max()))
        kept = np.minimum(np.clip(np.minimum(top, upper[2]) - np.maximum(bottom, origin[2]), 0.0, None), t)
        in_plan = (inside_x[:, None] & ((ys[r:r + ROWS] >= origin[1]) & (ys[r:r + ROWS] <= upper[1]))[None, :]).ravel()
        cut += float(np.where(in_plan, t - kept, 0.0).sum()) * dA
        beside += float(np.where(in_plan, 0.0, t).sum()) * dA
    problems, warnings = [], []
    if vol <= 0.0:
        return problems, warnings
    if cut > CUT_SHARE * vol:
        need = f"; the release's top reaches z = {top_max:.6g} m, the grid's top is {upper[2]:.6g} m" \
            if top_max > upper[2] else ""
        problems.append((json_path, f"the grid would cut off {cut:.6g} m3 of the {vol:.6g} m3 released "
                                    f"({100 * cut / vol:.3g} %) above its top or below its bottom{need}: enlarge "
                                    "grid.extent (or move grid.origin) to hold the whole release, or check the "
                                    "thickness's unit"))
    if beside > CUT_SHARE * vol:
        warnings.append((json_path, f"{beside:.6g} m3 of the {vol:.6g} m3 released ({100 * beside / vol:.3g} %) lies "
                                    "beside the grid in plan and is not seeded (the grid's plan clips the release)"))
    if deepest > MAX_DEPTH:
        warnings.append((json_path, f"the release is up to {deepest:.6g} m deep (mean {vol / area:.4g} m over "
                                    f"{area:.6g} m2, {vol:.6g} m3): thicknesses are in metres; a value in centimetres "
                                    "or millimetres would be 100 or 1000 times too deep"))
    mean = vol / area
    if mean < CELLS_DEEP * h:
        warnings.append((json_path, f"the release is {mean:.4g} m deep on average, {mean / h:.2g} cells at "
                                    f"h = {h:g} m: a flow's depth is resolved from about {CELLS_DEEP} cells, so its "
                                    f"runout moves with h; grid.cell_size = {mean / CELLS_DEEP:.3g} m would resolve it "
                                    "(docs/terrain.md)"))
    return problems, warnings
