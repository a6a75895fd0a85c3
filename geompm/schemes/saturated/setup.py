"""Saturated bodies at set-up (the saturated scheme's set-up hooks, schemes/saturated/scheme.py): the
pore-water table of the materials, each particle's water and the initial pore pressure (docs/pore-water.md).

A material with ``pore_water`` has ``density`` = the grains' density rho_s; the law runs with the dry density
(1 - n0) rho_s (``skeleton_params``), its particles carry the solids' mass (1 - n0) rho_s V0 and, below their
body's water table (by default its own surface, column by column), water of mass n0 rho_w V0 under the
hydrostatic pressure p = rho_w |g| (z_wt - z) plus the body's uniform excess.  Particles above the table start dry.  Geostatic stress is then effective stress: the
overburden is weighed with each particle's solids and water less the water it displaces below the table (its
buoyant weight), so sigma'_v = (1 - n)(rho_s - rho_w) g depth in a fully saturated layer.
"""

from __future__ import annotations

import numpy as np

from geompm.mpm.phreatic_surface import LatticeSurface, PolylineSurface, tin_lattice
from geompm.mpm.seepage import head_at, solve_seepage
from geompm.schemes.saturated.fields import PoreWater
from geompm.schemes.saturated.kernels import WALL, WATER
from geompm.schemes.saturated.surface import column_surface

#: standard gravity [m/s2], converting a hydraulic conductivity k to an intrinsic permeability
#: kappa = k mu_w / (rho_w g0) (the conductivity is a property measured under standard gravity)
STANDARD_GRAVITY = 9.80665
#: an incompressible water's bulk modulus in the table (its storage n / K_w is 0)
INFINITE = float("inf")
#: a drained material's permeability factor (setup.drain): the water's relative velocity 1e-12 of Darcy's
DRAINED_KAPPA = 1.0e-12


def material_table(case, names) -> PoreWater | None:
    """The pore-water table of the case's materials in ``names`` order, or None if none is saturated."""
    specs = [case.materials[k].pore_water for k in names]
    if all(s is None for s in specs):
        return None
    table = np.zeros((len(names), len(WATER)))
    for k, pw in enumerate(specs):
        if pw is None:
            table[k, WATER.n_max] = 1.0
            continue
        f = pw.fluid
        kappa = pw.intrinsic_permeability
        if kappa is None:
            kappa = pw.hydraulic_conductivity * f.viscosity / (f.density * STANDARD_GRAVITY)
        k_w = INFINITE if f.bulk_modulus == "incompressible" else f.bulk_modulus
        table[k, list(WATER)] = (
            f.density, k_w, f.viscosity, pw.porosity, kappa,
            1.0 if pw.permeability_update == "kozeny_carman" else 0.0, pw.max_porosity, pw.cavitation_pressure)
    drain(table, [s is not None and s.drainage == "drained" for s in specs])
    g = np.asarray(case.gravity, float)
    norm = float(np.linalg.norm(g))
    return PoreWater(table=table, wet=[s is not None for s in specs], up=None if norm == 0.0 else -g / norm,
                     g=norm, smoothing=case.solver.pore_pressure_smoothing,
                     grid=(np.asarray(case.grid.origin, float), np.asarray(case.grid.extent, float),
                           float(case.grid.cell_size)))


def drain(table: np.ndarray, rows) -> None:
    """Make the ``rows`` (a mask or indices) of the pore-water table drained: the pore pressure held at its
    state (K_w = 0 in dp = -dt (K_w / n) [...]) and the water bound to the grains (kappa times DRAINED_KAPPA:
    the implicit drag's relative velocity w -> 0), so that the mixture moves under sigma' - p I with the held
    p, whose gradient carries the seepage force, as a drained soil under a water table does
    (mpm/water_table.py)."""
    table[rows, WATER.k_w] = 0.0
    table[rows, WATER.kappa0] *= DRAINED_KAPPA


def skeleton_params(case, name: str, params):
    """The law's parameters as the engine runs them: for a saturated material ``density`` becomes the
    skeleton's dry density (1 - n0) rho_s, the solids' mass per volume that its particles carry (the law's
    reference density: a law that relates the current density to it, as the Kirchhoff stress does, then sees
    the skeleton's volume change); other materials' unchanged."""
    pw = case.materials[name].pore_water
    if pw is None:
        return params
    return params.with_porosity(pw.porosity)


def body_water(body, pw: PoreWater, mid: int, pts: np.ndarray, h: float, ppc: int):
    """(saturated flag, water-table height [m], pore pressure [Pa], buoyant flag: 1 where the water carries
    its own weight at t = 0, so that the geostatic overburden weighs the particle buoyant) of a body's
    particles; None for a body of a dry material.  Without ``water_table`` and ``table_normal`` the table is
    the body's own surface, column by column (surface.column_surface: columns one cell wide, the top particle
    standing for half a spacing above it), p = rho_w |g| (z_s - z): a body on a slope or on terrain is
    hydrostatic below its own surface everywhere, as the geostatic overburden weighs it.  Below a level
    ``water_table`` p = rho_w |g| depth; below a table parallel to a slope (``table_normal`` n)
    p = rho_w (-g . n) depth along n, seepage parallel to the slope; with ``hydrostatic`` false (or no
    gravity) saturated throughout at the uniform excess; below a drawn ``surface`` (points) hydrostatic along
    the vertical, dry above."""
    if not pw.wet[mid]:
        return None
    spec = body.pore_pressure
    n = len(pts)
    if pw.up is None or (spec is not None and not spec.hydrostatic):  # saturated throughout, the excess only
        excess = 0.0 if spec is None else spec.excess
        top = float((pts @ pw.up).max()) + 0.5 * h / ppc if pw.up is not None and n else 0.0
        return np.ones(n), np.full(n, top), np.full(n, excess), np.zeros(n)
    rho_w = pw.table[mid, WATER.rho_w]
    excess = 0.0 if spec is None else spec.excess
    if spec is not None and spec.seepage is not None:  # the steady seepage state through the body
        head = seepage_head(spec.seepage, pw, pts)
        height = pts @ pw.up
        sat = (head >= height - 1e-9 * h).astype(float)
        return sat, head, sat * (excess + rho_w * pw.g * np.maximum(head - height, 0.0)), np.ones(n)
    if spec is not None and spec.surface is not None:  # a drawn phreatic surface, hydrostatic along the vertical
        z_s = drawn_surface(spec.surface, pw, pts)
        height = pts @ pw.up
        sat = (height <= z_s + 1e-9 * h).astype(float)
        return sat, z_s, sat * (excess + rho_w * pw.g * np.maximum(z_s - height, 0.0)), np.ones(n)
    if spec is None or (spec.water_table is None and spec.table_normal is None):  # the table at its own surface
        origin, extent, cell = pw.grid
        table = column_surface(pts, h / ppc, pw.up, origin, extent, cell) if n else np.zeros(0)
        return np.ones(n), table, excess + rho_w * pw.g * (table - pts @ pw.up), np.ones(n)
    up, g_normal = pw.up, pw.g  # the table's normal and gravity's component against it
    if spec.table_normal is not None:
        up = np.asarray(spec.table_normal[:len(pw.up)], float)
        up = up / np.linalg.norm(up)
        g_normal = pw.g * float(up @ pw.up)
    height = pts @ up
    top = float(height.max()) + 0.5 * h / ppc if n else 0.0
    table = top if spec.water_table is None else spec.water_table
    sat = (height <= table + 1e-9 * h).astype(float)
    hydrostatic = rho_w * g_normal * np.maximum(table - height, 0.0)
    return sat, np.full(n, table), sat * (excess + hydrostatic), np.ones(n)


def drawn_surface(spec, pw: PoreWater, pts: np.ndarray) -> np.ndarray:
    """The height [m] of a body's drawn phreatic surface (schema PhreaticSurfaceSpec, points) above each of
    ``pts`` (mpm/phreatic_surface.py: a line in 2D, a TIN in 3D)."""
    points = np.asarray(spec.points, float)
    if points.shape[1] == 2:
        return PolylineSurface(points[:, 0], points[:, 1]).elevation(pts[:, :1])
    origin, extent, cell = pw.grid
    lattice = tin_lattice(points, origin[:2], origin[:2] + extent[:2], cell)
    return LatticeSurface(lattice, "points").elevation(pts[:, :2])


def seepage_head(spec, pw: PoreWater, pts: np.ndarray) -> np.ndarray:
    """The head [m] of the steady seepage (schema SeepageSpec) through a body's particles ``pts``, at each of
    them (mpm/seepage.py; the grid's own cells)."""
    origin, extent, cell = pw.grid
    ncells = np.maximum(np.round(extent / cell).astype(np.int64), 1)
    heads = [("xyz".index(s.side[0]), s.side[1] == "+", s.at(spec.times, 0.0)) for s in spec.heads]
    nodal, _ = solve_seepage(pts, origin, cell, ncells, heads, None, spec.unsaturated)
    return head_at(nodal, origin, cell, pts)


def buoyant_mass(p_mass, p_vol, p_material, p_sat, p_buoyant, pw: PoreWater) -> np.ndarray:
    """Each particle's weight in the overburden of geostatic effective stress [kg]: its solids, plus its
    water where saturated, less the water it displaces (-rho_w V0) where that water carries its own weight
    (p_buoyant 1: hydrostatic at t = 0; 0 for a body saturated at a uniform pressure, whose skeleton then
    carries the water too)."""
    rho_w, n0 = pw.table[p_material, WATER.rho_w], pw.table[p_material, WATER.n0]
    return p_mass + p_sat * (n0 * rho_w * p_vol - p_buoyant * rho_w * p_vol)


def wall_row(wall, held: bool = False) -> np.ndarray:
    """A water boundary (Stage.water_boundary: point, normal, layer, drained) as a row of kernels.WALL; ``held``:
    it holds a head (Stage.water_head), drained 2 (head.py)."""
    point, normal, layer, drained = wall
    row = np.zeros(len(WALL))
    row[WALL.px:WALL.px + len(point)] = point
    row[WALL.nx:WALL.nx + len(normal)] = normal
    row[WALL.layer] = layer
    row[WALL.drained] = 2.0 if held else (1.0 if drained else 0.0)
    return row
