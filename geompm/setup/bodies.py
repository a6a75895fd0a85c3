"""Seeding particles inside body geometries (set-up only, vectorised numpy).

Particles are placed on a regular lattice of ``ppc`` points per cell and axis,
at the centres of the sub-cells of every grid cell; a point belongs to the body
when it lies inside the geometry.  Each particle carries the volume of its
sub-cell, (h / ppc)^d, so a body that fills whole cells has its exact volume.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geompm.errors import CaseError
from geompm.files.atomic import case_relative
from geompm.mpm.memory import require_memory
from geompm.files.mesh import load_surface_mesh, mesh_signed_distance, mesh_size_problem
from geompm.setup.polygon import points_in_polygon

#: body geometries built from GIS files (setup/release.py)
RELEASE_TYPES = ("release_polygon", "release_raster", "between_surfaces")


def lattice(lo, hi, origin, h, ppc) -> np.ndarray:
    """Sub-cell centres of the cells overlapping the box [lo, hi] (m, d)."""
    axes = []
    for a in range(len(lo)):
        i0 = int(np.floor((lo[a] - origin[a]) / h))
        i1 = int(np.ceil((hi[a] - origin[a]) / h))
        k = np.arange(i0 * ppc, i1 * ppc)
        x = origin[a] + (k + 0.5) * h / ppc
        axes.append(x[(x >= lo[a]) & (x <= hi[a])])
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=1)


def body_region(geom, dim, base_dir: Path, json_path: str, grid=None, crs: str | None = None):
    """(lo, hi, contains) of a body geometry: its bounding box and a point-membership test; with ``grid``
    (origin, upper corner, cell size) a mesh's size is checked against it (mesh_size_problem)."""
    if geom.type == "box":
        lo, hi = np.asarray(geom.min, float), np.asarray(geom.max, float)
        eps = 1e-9 * max(float(np.abs(hi - lo).max()), 1.0)
        return lo, hi, lambda pts: np.all((pts > lo + eps) & (pts < hi - eps), axis=1)
    if geom.type == "polygon":
        verts = np.asarray(geom.vertices, dtype=float)
        lo, hi = verts.min(axis=0), verts.max(axis=0)
        if dim == 2:
            return lo, hi, lambda pts: points_in_polygon(pts[:, :2], verts)
        z0, z1 = geom.extrude
        return (np.r_[lo, z0], np.r_[hi, z1],
                lambda pts: points_in_polygon(pts[:, :2], verts) & (pts[:, 2] > z0) & (pts[:, 2] < z1))
    if geom.type in RELEASE_TYPES:
        from geompm.setup.release import release_region

        return release_region(geom, base_dir, json_path, crs)
    mesh = load_surface_mesh(case_relative(base_dir, geom.file), geom.scale, geom.translate, json_path + ".file")
    if grid is not None:
        problem = mesh_size_problem(mesh, grid[0], grid[1], grid[2], json_path, geom.scale)
        if problem:
            raise CaseError([(json_path + ".scale", problem)])
    lo, hi = mesh.bounds
    return lo, hi, lambda pts: mesh_signed_distance(mesh, pts) < 0.0


def seed_body(geom, dim, origin, h, ppc, base_dir: Path, json_path: str, upper=None, crs: str | None = None):
    """Particle positions (m, dim) of one body's geometry and its membership test; with ``upper`` (the
    grid's upper corner) the seeding box is clipped to the grid."""
    lo, hi, contains = body_region(geom, dim, base_dir, json_path, None if upper is None else (origin, upper, h), crs)
    if upper is not None:
        lo, hi = np.maximum(lo, origin), np.minimum(hi, upper)
    if geom.type in RELEASE_TYPES:  # column by column: memory follows the particles, not the box
        from geompm.setup.release_seed import seed_release

        pts = seed_release(contains, lo, hi, origin, h, ppc, json_path)
        if len(pts) == 0:
            raise CaseError([(json_path, "the geometry contains no particle; enlarge it or refine the grid")])
        return pts, contains
    points = float(np.prod(np.maximum(np.ceil((np.asarray(hi) - np.asarray(lo)) / h * ppc) + 1, 0.0)))
    require_memory(points * 8 * (dim + 2), json_path,
                   f"seeding {points:.3g} candidate particles ({ppc} per cell and axis in a box of "
                   f"{' x '.join(f'{x:.3g}' for x in np.asarray(hi) - np.asarray(lo))} m)",
                   "raise grid.cell_size, lower particles_per_cell, or check the geometry's unit")
    pts = lattice(lo, hi, origin, h, ppc)
    if geom.type != "box":
        pts = pts[contains(pts)]
    if len(pts) == 0:
        raise CaseError([(json_path, "the geometry contains no particle; enlarge it or refine the grid")])
    return pts, contains


def overlap_problems(points: list[np.ndarray], tests: list) -> list[tuple[str, str]]:
    """One problem per pair of bodies where particles of one lie strictly inside the other."""
    problems = []
    for j in range(len(points)):
        for i in range(j):
            k = int(np.count_nonzero(tests[i](points[j]))) + int(np.count_nonzero(tests[j](points[i])))
            if k:
                problems.append((f"bodies.{j}.geometry",
                                 f"overlaps bodies.{i} ({k} particles of one lie inside the other); "
                                 "bodies may touch but not overlap: trim one of the geometries"))
    return problems
