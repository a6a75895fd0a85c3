"""Checks of a case with saturated materials (``materials.<name>.pore_water``) that need the whole case.

Refused, each with its JSON path: a fluid law with pore water (a fluid has no skeleton whose effective
stress the water could share); neither or both of hydraulic_conductivity and intrinsic_permeability; a
body's ``pore_pressure`` on a dry material; a water table without gravity or above the grid; and the
settings the two-phase step does not implement (MUSL, FLIP, periodic axes), each with
what to use instead (docs/pore-water.md, Limits).
"""

from __future__ import annotations

import numpy as np

from geompm.contract.stages import MERGE
from geompm.kernels.stencil import AFFINE


def saturated_materials(case) -> set[str]:
    """Names of the case's materials with pore water."""
    return {name for name, m in case.materials.items() if m.pore_water is not None}


def pore_water_problems(case, loaded) -> list[tuple[str, str]]:
    out = []
    wet = saturated_materials(case)
    for name in sorted(wet):
        pw = case.materials[name].pore_water
        path = f"materials.{name}.pore_water"
        if (pw.hydraulic_conductivity is None) == (pw.intrinsic_permeability is None):
            out.append((path, "give exactly one of 'hydraulic_conductivity' [m/s] and 'intrinsic_permeability' "
                              "[m2]"))
        if pw.max_porosity <= pw.porosity:
            out.append((f"{path}.max_porosity", f"{pw.max_porosity:g} is not above the initial porosity "
                                                f"{pw.porosity:g}: every particle would start separated"))
        r = loaded.materials.get(name)
        if r is not None and r.cls.fluid:
            out.append((path, f"'{r.cls.name}' is a fluid law: it has no grain skeleton to share the load with "
                              "pore water. Saturate a soil law (drucker_prager, mohr_coulomb, linear_elastic, "
                              "mu_i, ...) or model the mixture as one equivalent fluid without 'pore_water'"))
    up = _up(case.gravity)
    corners = np.array(np.meshgrid(*[(o, o + e) for o, e in zip(case.grid.origin, case.grid.extent)]))
    corners = corners.reshape(len(case.grid.origin), -1).T
    for i, body in enumerate(case.bodies):
        spec = body.pore_pressure
        if spec is None:
            continue
        path = f"bodies.{i}.pore_pressure"
        if body.material not in wet:
            out.append((path, f"material '{body.material}' has no 'pore_water': add it to the material or "
                              "remove pore_pressure"))
            continue
        if spec.water_table is not None:
            if up is None:
                out.append((f"{path}.water_table", "a water table needs gravity (it is a height against it); "
                                                   "remove it or set 'gravity'"))
            else:
                top = float((corners @ up).max())
                if spec.water_table > top:
                    out.append((f"{path}.water_table", f"{spec.water_table:g} m is above the grid (its highest "
                                f"point is at {top:.4g} m along the upward direction): water above the ground "
                                "is not modelled; lower it to the body's top or below"))
    if wet:
        out.extend(_unsupported(case, loaded))
    return out


#: the largest CFL number at which the saturated APIC/MLS step's flows are converged in time (docs/pore-water.md)
FLOW_CFL = 0.1


def pore_water_warnings(case) -> list[tuple[str, str]]:
    """(JSON path, sentence): a saturated case with APIC or MLS above FLOW_CFL (warned, not refused: a
    quasi-static case, consolidation, is verified at 0.4)."""
    if not saturated_materials(case) or case.solver.transfer not in AFFINE or case.time.dt is not None:
        return []
    if case.time.cfl <= FLOW_CFL:
        return []
    return [("time.cfl", f"{case.time.cfl:g} with saturated soil and '{case.solver.transfer}': a flowing "
                         f"saturated debris converges in time only at cfl <= {FLOW_CFL:g} (a 2D flume's front "
                         "at 1.2 s is 25 % short at cfl 0.4 and 6 % at 0.2, docs/pore-water.md); set "
                         f"time.cfl to {FLOW_CFL:g} for a flow (quasi-static consolidation is verified at 0.4)")]


def _up(gravity):
    g = np.asarray(gravity, float)
    norm = float(np.linalg.norm(g))
    return None if norm == 0.0 else -g / norm


def _unsupported(case, loaded) -> list[tuple[str, str]]:
    out = []
    why = "is not implemented for saturated materials (docs/pore-water.md, Limits)"
    if case.solver.update != "usl":
        out.append(("solver.update", f"'{case.solver.update}' {why}; use \"usl\""))
    if case.solver.transfer == "flip":
        out.append(("solver.transfer", f"'flip' {why}; use \"apic\", \"mls\" or \"pic\""))
    for r in loaded.boundaries + loaded.obstacles + loaded.damping:
        if r.cls.phase == MERGE:
            out.append((r.path, f"'{r.cls.name}' merges grid nodes (a periodic axis), which {why}; use walls"))
    return out
