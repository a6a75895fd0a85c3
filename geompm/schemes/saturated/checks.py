"""What the saturated scheme cannot run, and what it advises against (docs/pore-water.md, Limits).

Every transfer runs (the water's follows the solid's: its affine matrix with APIC and MLS, its FLIP blend with
FLIP); a periodic axis runs (the scheme folds its scatters onto the images: passes.fold).  Refused: APIC with
linear hats (unstable in motion, stencil.LINEAR_APIC; a dry case is warned).  MUSL order is the scheme
``saturated_musl`` (musl.py).  Warned: APIC or MLS above FLOW_CFL; under the semi-implicit step any transfer
above it.
"""

from __future__ import annotations

from geompm.kernels.stencil import AFFINE, LINEAR_APIC, linear_apic


#: the largest CFL number at which the saturated APIC/MLS step's flows are converged in time (docs/pore-water.md)
FLOW_CFL = 0.1


def flow_warnings(case) -> list[tuple[str, str]]:
    """(JSON path, sentence): a saturated case with APIC or MLS above FLOW_CFL (warned, not refused: a
    quasi-static case, consolidation, is verified at 0.4)."""
    if case.solver.transfer not in AFFINE or case.time.dt is not None:
        return []
    if case.time.cfl <= FLOW_CFL:
        return []
    return [("time.cfl", f"{case.time.cfl:g} with saturated soil and '{case.solver.transfer}': a flowing "
                         f"saturated debris converges in time only at cfl <= {FLOW_CFL:g} (a 2D flume's front "
                         "at 0.8 s is 15 % short at cfl 0.4 and 4 % at 0.2, docs/pore-water.md); set "
                         f"time.cfl to {FLOW_CFL:g} for a flow (quasi-static consolidation is verified at 0.4)")]


def semi_implicit_warnings(case) -> list[tuple[str, str]]:
    """flow_warnings, and under the semi-implicit step the same advice whatever the transfer: its spreading
    flows lose pore pressure above FLOW_CFL with PIC as well (docs/pore-water.md, The semi-implicit step)."""
    out = flow_warnings(case)
    if out or case.time.dt is not None or case.time.cfl <= FLOW_CFL:
        return out
    return [("time.cfl", f"{case.time.cfl:g} with the semi-implicit two-phase step: a spreading saturated flow "
                         f"loses pore pressure above cfl {FLOW_CFL:g} whatever the transfer (a 2D block on a slip "
                         "bed at cfl 0.4: mean p -291 Pa against the explicit step's +55 Pa, docs/pore-water.md); "
                         f"set time.cfl to {FLOW_CFL:g} for a flow (consolidation is verified at 0.4)")]


def unsupported(case, loaded, incompressible: bool = False) -> list[tuple[str, str]]:
    """(JSON path, sentence) of what the scheme cannot run: APIC with linear hats; incompressible water
    unless the scheme solves the pressure implicitly (``incompressible``), drained water if it does; a wall
    that holds a head with the implicit pressure or on a GPU."""
    out = [("solver.transfer", LINEAR_APIC)] if linear_apic(case) else []
    for r in loaded.boundaries:
        if r.cls(r.params, r.label, r.path).water_head() is None:
            continue
        if incompressible:
            out.append((f"{r.path}.drainage", "a held head is built for the explicit two-phase step: set "
                                              "solver.update to \"saturated\" (or \"saturated_musl\")"))
        elif case.solver.backend != "cpu":
            out.append((f"{r.path}.drainage", "a held head runs on the CPU backend only (its band's force is a "
                                              "serial scatter, schemes/saturated/head.py): set solver.backend to "
                                              "\"cpu\""))
    if incompressible:
        for name, mat in case.materials.items():
            if mat.pore_water is not None and mat.pore_water.drainage == "drained":
                out.append((f"materials.{name}.pore_water.drainage",
                            "'drained' holds the pore pressure where the semi-implicit step solves for it: set "
                            "solver.update to \"saturated\" for a drained analysis"))
    else:
        for name, mat in case.materials.items():
            if mat.pore_water is not None and mat.pore_water.fluid.bulk_modulus == "incompressible":
                out.append((f"materials.{name}.pore_water.fluid.bulk_modulus",
                            "incompressible water needs the pore pressure implicit: set solver.update to "
                            "\"saturated_semi_implicit\", or give water's bulk modulus in Pa (2.2e9)"))
    return out
