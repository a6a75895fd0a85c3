"""Checks of ``inflows`` (the spec is in case.py) that need the whole case: the gate's vectors, the material,
the hydrograph (read here once, from its CSV file or the inline table: sources/hydrograph.py), the names, the
backend and the scheme (an inflow adds particles of the core's arrays only)."""

from __future__ import annotations

import numpy as np

from geompm.files.atomic import case_relative, unreadable_file
from geompm.sources.hydrograph import Hydrograph, read_hydrograph, table_problems


def inflow_problems(case, loaded) -> list[tuple[str, str]]:
    """(JSON path, sentence) of every problem of the case's inflows; their hydrographs go to
    ``loaded.hydrographs`` (None for one that cannot be read)."""
    out = []
    dim = case.dimension
    taken = {r.label: r.path for r in loaded.boundaries + loaded.obstacles + loaded.damping}
    taken.update({pr.name: f"probes.{i}" for i, pr in enumerate(case.probes)})
    loaded.hydrographs = []
    g = np.asarray(case.gravity, float)
    for i, spec in enumerate(case.inflows):
        path = f"inflows.{i}"
        if spec.name in taken:
            out.append((f"{path}.name", f"'{spec.name}' is already used by {taken[spec.name]}: series columns would "
                                        "overwrite each other; give the inflow a distinct name"))
        taken.setdefault(spec.name, path)
        if spec.material not in case.materials:
            out.append((f"{path}.material", f"no material '{spec.material}' (materials: "
                                            f"{', '.join(repr(m) for m in case.materials)})"))
        out += _gate_problems(spec, dim, g, path)
        hg, bad = _hydrograph(spec, loaded.base_dir, path)
        out += bad
        loaded.hydrographs.append(hg)
    if case.inflows and case.solver.backend != "cpu":
        out.append(("inflows", f"inflows run on the CPU backend only (solver.backend is '{case.solver.backend}'): "
                               "particles are added on the host between steps; use \"cpu\""))
    return out


def _gate_problems(spec, dim: int, g, path: str) -> list[tuple[str, str]]:
    out = []
    if len(spec.direction) != dim:
        return [(f"{path}.direction", f"must have {dim} entries (one per dimension)")]
    direction = np.asarray(spec.direction, float)
    if not np.linalg.norm(direction) > 0:
        return [(f"{path}.direction", "must not be the zero vector")]
    direction /= np.linalg.norm(direction)
    if np.linalg.norm(g - (g @ direction) * direction) <= 1e-9 * max(np.linalg.norm(g), 1e-300):
        out.append((f"{path}.direction", "gravity is zero or along the flow: the inflow's depth is measured "
                                         "against gravity, normal to the flow; give a direction along the bed"))
    if dim == 2:
        if len(spec.section) != 1 or len(spec.section[0]) != 2:
            out.append((f"{path}.section", "in 2D the gate is one point on the bed: [[x, y]]"))
    else:
        if len(spec.section) < 2:
            out.append((f"{path}.section", "in 3D the gate is a polyline across the channel: two points or more"))
        for k, q in enumerate(spec.section):
            if len(q) not in (2, 3):
                out.append((f"{path}.section.{k}", "a point is [x, y, z], or [x, y] on the ground below it"))
    return out


def _hydrograph(spec, base_dir, path: str):
    """(Hydrograph or None, problems) of an inflow."""
    if spec.table is not None:
        rows = np.asarray(spec.table, float)
        bad = table_problems(rows[:, 0], rows[:, 1], rows[:, 2], spec.columns)
        if bad:
            return None, [(f"{path}.table", b) for b in bad]
        return Hydrograph(rows[:, 0], rows[:, 1], rows[:, 2], spec.columns), []
    file = case_relative(base_dir, spec.hydrograph)
    why = unreadable_file(file, spec.hydrograph)
    if why:
        return None, [(f"{path}.hydrograph", why)]
    hg, bad = read_hydrograph(file)
    return hg, [(f"{path}.hydrograph", b) for b in bad]


def inflow_particles(case, loaded) -> float:
    """How many particles the inflows add over the run (the memory check): each hydrograph's volume over a
    particle's."""
    h = case.grid.cell_size
    return sum(hg.total / (h / spec.particles_per_cell) ** case.dimension
               for spec, hg in zip(case.inflows, getattr(loaded, "hydrographs", [])) if hg is not None)
