"""A phreatic surface from data: where the water stands in a slope, as an engineer draws it.

The pore pressure below it is hydrostatic along the vertical, p = rho_w |g| (z_s(x) - z) (the usual reading of
a drawn phreatic surface in limit-equilibrium practice: u = gamma_w h_w, Bishop 1955; Duncan, Wright &
Brandon 2014, Soil Strength and Slope Stability, sec. 6.3, "piezometric line"), and zero above it.

- 2D: a polyline through the points (x, z) of the section, x increasing, held level beyond its ends
  (kernels/phreatic.polyline_pressure);
- 3D: points (x, y, z), triangulated (a TIN: Delaunay in plan, linear on each triangle; beyond the
  points' hull the nearest point's height) and sampled on a lattice at a quarter of the cell size over the
  grid's plan, or a raster (GeoTIFF or ESRI ASCII grid, read as a DEM: files/dem.py), bilinear between its
  pixel centres (kernels/phreatic.lattice_pressure; the raster is read by setup/assemble.py).

Either rises or falls in time by the schedule's ``heights`` (the surface shifted along the vertical).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geompm.kernels.lattice import heights as lattice_heights
from geompm.kernels.phreatic import lattice_pressure, polyline_pressure

#: the lattice a 3D point set is sampled on, in cells
LATTICE_CELLS = 0.25


class PolylineSurface:
    """z_s(x) through ``xs`` (increasing) and ``zs`` [m], level beyond the ends."""

    #: a drawn surface: it may be drawn above the ground by mistake (table_warnings checks it)
    drawn = True

    def __init__(self, xs, zs):
        self.xs = np.ascontiguousarray(xs, float)
        self.zs = np.ascontiguousarray(zs, float)

    def elevation(self, plan: np.ndarray) -> np.ndarray:
        """z_s at the plan points ``plan`` (n, 1) [m]."""
        return np.interp(plan[:, 0], self.xs, self.zs)

    def pressure(self, p_x, p_material, acts, rise, gradient, out, time: float = 0.0) -> None:
        polyline_pressure(p_x, p_material, acts, self.xs.astype(p_x.dtype), self.zs.astype(p_x.dtype),
                          rise, gradient, out)

    def describe(self) -> str:
        return f"a phreatic line through {len(self.xs)} points, x {self.xs[0]:g}..{self.xs[-1]:g} m"


@dataclass
class Lattice:
    """Heights z[i, j] [m] at x0 + i dx, y0 + j dy (a raster's pixel centres: files/dem.Dem has these fields)."""

    z: np.ndarray
    x0: float
    y0: float
    dx: float
    dy: float


class LatticeSurface:
    """z_s(x, y) bilinear on a lattice (kernels/lattice.bilinear)."""

    drawn = True

    def __init__(self, dem, origin: str):
        self.dem = Lattice(np.ascontiguousarray(dem.z, float), float(dem.x0), float(dem.y0), float(dem.dx),
                           float(dem.dy))
        self.origin = origin

    def elevation(self, plan: np.ndarray) -> np.ndarray:
        d = self.dem
        return lattice_heights(d.z, d.x0, d.y0, d.dx, d.dy, np.ascontiguousarray(plan[:, 0], float),
                           np.ascontiguousarray(plan[:, 1], float))

    def pressure(self, p_x, p_material, acts, rise, gradient, out, time: float = 0.0) -> None:
        d = self.dem
        lattice_pressure(p_x, p_material, acts, d.z.astype(p_x.dtype), d.x0, d.y0, d.dx, d.dy, rise, gradient, out)

    def describe(self) -> str:
        return f"a phreatic surface from {self.origin}"


def tin_lattice(points, lo, hi, h) -> Lattice:
    """The TIN through ``points`` (n, 3) sampled on a lattice over the plan box [lo, hi] (2,) at
    LATTICE_CELLS * h, the nearest point's height beyond the hull."""
    from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

    pts = np.asarray(points, float)
    step = LATTICE_CELLS * h
    nx = int(np.ceil((hi[0] - lo[0]) / step)) + 1
    ny = int(np.ceil((hi[1] - lo[1]) / step)) + 1
    gx, gy = np.meshgrid(lo[0] + step * np.arange(nx), lo[1] + step * np.arange(ny), indexing="ij")
    z = LinearNDInterpolator(pts[:, :2], pts[:, 2])(gx, gy)
    hole = ~np.isfinite(z)
    if hole.any():
        z[hole] = NearestNDInterpolator(pts[:, :2], pts[:, 2])(gx[hole], gy[hole])
    return Lattice(np.ascontiguousarray(z), float(lo[0]), float(lo[1]), step, step)


def lattice_points(lo, hi, h) -> int:
    """How many lattice points tin_lattice makes over [lo, hi] (sized before it is allocated)."""
    step = LATTICE_CELLS * h
    return int((np.ceil((hi[0] - lo[0]) / step) + 1) * (np.ceil((hi[1] - lo[1]) / step) + 1))


def table_warnings(table, p_x, p_material, h) -> list[tuple[str, str]]:
    """The plausibility of a water table against the ground its soils make at t = 0: where the table stands
    above the ground (the top of the soil's particles in each column of cells, plus half a cell) outside a
    pond, the soil's face carries the table's pressure as if ponded water pressed on it (a warning: say so with
    'pond', or lower the table to the face, a seepage face). A pond below every soil particle has no face to
    act on (refused)."""
    from geompm.errors import CaseError

    acted = table.acts[p_material] > 0.0
    if not acted.any():
        return []
    solved = table.surface is not None and not table.surface.drawn  # a seepage state meets the faces itself
    x = p_x[acted]
    dim = x.shape[1]
    if table.pond is not None and float(np.max(table.pond[1])) <= float(x[:, -1].min()):
        raise CaseError([("triggers.water_table.pond.levels", f"the pond never reaches the soil (its highest level "
                          f"{float(np.max(table.pond[1])):g} m, the soil's lowest particle at {float(x[:, -1].min()):g} m): "
                          "there is no face below it to press on; raise the levels or remove 'pond'")])
    if solved:
        return []
    cols = np.floor(x[:, :-1] / h).astype(np.int64)
    keys, inv = np.unique(cols, axis=0, return_inverse=True)
    top = np.full(len(keys), -np.inf)
    np.maximum.at(top, inv.ravel(), x[:, -1])
    probe = np.zeros((len(keys), dim))
    probe[:, :-1] = (keys + 0.5) * h
    probe[:, -1] = top + 0.5 * h
    mat = np.full(len(keys), int(np.flatnonzero(table.acts > 0.0)[0]), np.int32)
    above = table.excess(np.ascontiguousarray(probe, x.dtype), mat, 0.0) > 0.0
    if not above.any():
        return []
    where = probe[above][0]
    return [("triggers.water_table", f"the water table stands above the ground at {int(above.sum())} of "
             f"{len(keys)} columns (first at {', '.join(f'{v:.3g}' for v in where[:-1])} m, ground at "
             f"{where[-1] - 0.5 * h:.3g} m) at t = 0: there the soil's face carries the table's pressure as ponded "
             "water would; if that water is a pond say so with 'pond' (its level), else lower the table to the face "
             "(a seepage face has p = 0)")]
