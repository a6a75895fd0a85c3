"""Checks of ``triggers`` (the specs are in case.py) that need the resolved materials.

``triggers``: what changes over a run to take a slope from stable to failure (docs/slope-stability.md).

``strength_reduction``: the factor F(t) by which the shear strength of the named soils (default every
soil whose law has a strength to reduce, ``Material.strength_reduction``) is divided, piecewise linear
through (``times``, ``factors``) and held at its end values outside them; each law's
``strength_reduced(params, F)`` says what dividing its strength means (c / F and tan(phi) / F for the
Mohr-Coulomb-type laws).  `geompm stability` writes its trials with the same trigger.

``water_table``: a phreatic surface at height z_wt(t) along its normal n (default against gravity) whose
pore pressure p = rho_w (-g . n) (z_wt - x . n) acts on the named dry soils (default every material that
is neither a fluid nor saturated by ``pore_water``, which carries its own water); the CPU backend runs it.
"""

from __future__ import annotations


def trigger_problems(case, loaded) -> list[tuple[str, str]]:
    """The materials a trigger names: each must exist and have a strength to reduce, or carry drained pore
    pressure."""
    return _strength_problems(case, loaded) + _water_table_problems(case, loaded)


def water_table_materials(case, loaded) -> list[str]:
    """The materials under a water table's pore pressure: those it names, or every dry soil."""
    spec = case.triggers.water_table
    if spec.materials is not None:
        return list(spec.materials)
    return [n for n, r in loaded.materials.items() if not r.cls.fluid and case.materials[n].pore_water is None]


def _water_table_problems(case, loaded) -> list[tuple[str, str]]:
    spec = case.triggers.water_table if case.triggers is not None else None
    if spec is None:
        return []
    path = "triggers.water_table"
    out = []
    g = list(case.gravity)
    if not any(g):
        out.append((path, "a water table needs gravity (its pore pressure is rho_w g times the depth below it)"))
    if any(m.pore_water is not None for m in case.materials.values()):
        out.append((path, "a water table and a saturated material ('pore_water', two-phase) in one case are not "
                          "supported; give the saturated body its own 'pore_pressure.water_table'"))
    if case.solver.backend != "cpu":
        out.append((path, "the water table runs on the CPU backend only; use solver.backend \"cpu\""))
    if spec.normal is not None:
        if len(spec.normal) != case.dimension:
            out.append((f"{path}.normal", f"give {case.dimension} components, one per axis"))
        elif any(g) and sum(a * b for a, b in zip(spec.normal, g)) >= 0.0:
            out.append((f"{path}.normal", "the normal must point out of the ground, against gravity (its dot "
                                          "product with 'gravity' negative)"))
    if spec.materials is None:
        if not water_table_materials(case, loaded):
            out.append((path, "no dry soil for the water table to act on (fluids have no skeleton; a material "
                              "with 'pore_water' carries its own water)"))
        return out
    for i, name in enumerate(spec.materials):
        r = loaded.materials.get(name)
        if name not in case.materials:
            out.append((f"{path}.materials.{i}", f"no material named '{name}' in 'materials' (there are: "
                                                 f"{', '.join(sorted(case.materials))})"))
        elif r is not None and r.cls.fluid:
            out.append((f"{path}.materials.{i}", f"material '{name}' ({r.cls.name}) is a fluid: it has no "
                                                 "skeleton for an effective stress"))
        elif case.materials[name].pore_water is not None:
            out.append((f"{path}.materials.{i}", f"material '{name}' has 'pore_water': its pore pressure is its "
                                                 "own (two-phase); leave it out of the water table"))
    return out


def _strength_problems(case, loaded) -> list[tuple[str, str]]:
    spec = case.triggers.strength_reduction if case.triggers is not None else None
    if spec is None:
        return []
    out = []
    path = "triggers.strength_reduction.materials"
    names = spec.materials
    if names is None:
        if not any(r.cls.strength_reduction for r in loaded.materials.values()):
            out.append(("triggers.strength_reduction", "no material of the case has a strength to reduce; give a "
                                                        "body a soil law such as mohr_coulomb or drucker_prager"))
        return out
    for i, name in enumerate(names):
        r = loaded.materials.get(name)
        if name not in case.materials:
            out.append((f"{path}.{i}", f"no material named '{name}' in 'materials' (there are: "
                                       f"{', '.join(sorted(case.materials))})"))
        elif r is not None and not r.cls.strength_reduction:
            out.append((f"{path}.{i}", f"material '{name}' ({r.cls.name}) has no shear strength to reduce"))
    return out
