"""Checks of a case with saturated materials (``materials.<name>.pore_water``) that need the whole case.

Refused, each with its JSON path: a fluid law with pore water (a fluid has no skeleton whose effective
stress the water could share); neither or both of hydraulic_conductivity and intrinsic_permeability; a
body's ``pore_pressure`` on a dry material; a fluid body beside saturated soil (the two waters do not
mix); a water table without gravity or above the grid; a law's parameters that disagree with its pore water
or, dry, lack what the pore water would give (MaterialParams.saturation_checks; its warnings join the case's).  What the saturated step itself cannot run is the
scheme's check (schemes/saturated/checks.py: every transfer and periodic axes run).
"""

from __future__ import annotations

import numpy as np

from geompm.schema.triggers import seepage_problems, surface_points_problems, vertical_gravity_problems



def saturated_materials(case) -> set[str]:
    """Names of the case's materials with pore water."""
    return {name for name, m in case.materials.items() if m.pore_water is not None}


def pore_water_problems(case, loaded) -> list[tuple[str, str]]:
    out = []
    wet = saturated_materials(case)
    for name, r in sorted(loaded.materials.items()):
        pw = case.materials[name].pore_water
        bad, warn = r.params.saturation_checks(None if pw is None else pw.porosity)
        out += [(f"materials.{name}.{field}", text) for field, text in bad]
        loaded.warnings.extend((f"materials.{name}.{field}", text) for field, text in warn)
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
    if wet:
        fluid_bodies = [i for i, b in enumerate(case.bodies)
                        if loaded.materials.get(b.material) is not None and loaded.materials[b.material].cls.fluid]
        for i in fluid_bodies:
            out.append((f"bodies.{i}.material",
                        f"'{case.bodies[i].material}' is a fluid and the case has saturated soil: a fluid body would "
                        "meet the saturated one as a dry material, its water never entering the pores nor the pores' "
                        "water leaving into it (not modelled). Put the water in the soil's pore_water (a saturated "
                        "debris) or run the fluid with dry soil"))
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
        if spec.seepage is not None:
            where = f"{path}.seepage"
            out += vertical_gravity_problems(case, where) or seepage_problems(case, spec.seepage, where)
        if spec.surface is not None:
            where = f"{path}.surface"
            out += vertical_gravity_problems(case, where) or surface_points_problems(case, spec.surface.points,
                                                                                     f"{where}.points")
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
    return out


def _up(gravity):
    g = np.asarray(gravity, float)
    norm = float(np.linalg.norm(g))
    return None if norm == 0.0 else -g / norm
