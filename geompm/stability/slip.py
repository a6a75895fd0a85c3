"""The failure mechanism's slip surface: the band of largest plastic shear strain rate in the failed trial.

A trial writes the particles at 3T/4 and at T (stability/trial.py); each particle's plastic shear strain rate
over the last quarter is (eps_p(T) - eps_p(3T/4)) / (T/4), the particles matched by ``particle_id``.  The
surface is found column by column across the vertical (the axis gravity acts along, ``vertical``): the particles
are binned by their other coordinates (x in 2D, the plan's two in 3D) into columns one ``width`` wide, and in each
column where the band is present (its largest rate at least ``share`` of the largest anywhere) the slip
surface's height is the rate-weighted mean height of the column's particles whose rate is at least half the
column's largest.  In 2D it is a polyline (x, y) along the slope, the curve a limit-equilibrium slip circle is
laid over; in 3D a set of points (x, y, z) on a plan lattice.  The rows keep the case's axes: the vertical
coordinate sits in its own column.  A band that doubles back over itself in one
column (a vertical scarp beside a basal band) is read as its mean height there.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def plastic_rate(early: Path, late: Path, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """(positions at ``late``, plastic shear strain rate [1/s]) of the particles in both VTU files."""
    import meshio

    a, b = meshio.read(early), meshio.read(late)
    ida = np.asarray(a.point_data["particle_id"]).astype(np.int64)
    idb = np.asarray(b.point_data["particle_id"]).astype(np.int64)
    ea = dict(zip(ida.tolist(), np.asarray(a.point_data["plastic_strain"], float).tolist()))
    eb = np.asarray(b.point_data["plastic_strain"], float)
    before = np.array([ea.get(i, np.nan) for i in idb.tolist()])
    keep = np.isfinite(before)
    return np.asarray(b.points, float)[keep], (eb[keep] - before[keep]) / dt


def slip_surface(x: np.ndarray, rate: np.ndarray, dim: int, width: float, share: float = 0.2,
                 vertical: int | None = None) -> np.ndarray:
    """Points of the slip surface (module docstring), one row per column in the case's axes ((x, y) in 2D,
    (x, y, z) in 3D), the ``vertical`` coordinate (default the last axis) the band's height; empty (0, dim)
    where no particle deforms plastically."""
    x = np.asarray(x, float)[:, :dim]
    rate = np.asarray(rate, float)
    if rate.size == 0 or not np.isfinite(rate).any() or np.nanmax(rate) <= 0.0:
        return np.zeros((0, dim))
    v = dim - 1 if vertical is None else int(vertical)
    across = [a for a in range(dim) if a != v]
    top = float(np.nanmax(rate))
    plan = np.floor(x[:, across] / width).astype(np.int64)
    keys, inverse = np.unique(plan, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    rows = []
    for k in range(len(keys)):
        sel = inverse == k
        r = rate[sel]
        peak = float(r.max())
        if peak < share * top:
            continue
        band = r >= 0.5 * peak
        w = r[band]
        pts = x[sel][band]
        row = np.empty(dim)
        row[across] = (keys[k] + 0.5) * width
        row[v] = float((pts[:, v] * w).sum() / w.sum())
        rows.append(row)
    return np.array(rows, float).reshape(-1, dim)


def write_csv(path: Path, points: np.ndarray, dim: int) -> None:
    """The surface as CSV with a header naming its columns and units."""
    from geompm.files.atomic import atomic_path

    names = ("x_m", "y_m") if dim == 2 else ("x_m", "y_m", "z_m")
    with atomic_path(path) as tmp:
        np.savetxt(tmp, points, delimiter=",", header=",".join(names), comments="", fmt="%.6g")
