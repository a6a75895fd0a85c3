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
A ``surface`` from data and a ``pond`` are hydrostatic along the vertical: they need gravity along the last
axis (-y in 2D, -z in 3D), their points inside the grid's plan, and their levels inside the grid.
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
        out.append((path, "a water table or pond and a saturated material ('pore_water', two-phase) in one case are "
                          "not supported; give the saturated body its own 'pore_pressure' ('water_table', or a drawn "
                          "'surface'); ponded water on two-phase soil is not modelled yet (docs/pore-water.md, Limits)"))
    if case.solver.backend != "cpu":
        out.append((path, "the water table runs on the CPU backend only; use solver.backend \"cpu\""))
    if spec.normal is not None:
        if len(spec.normal) != case.dimension:
            out.append((f"{path}.normal", f"give {case.dimension} components, one per axis"))
        elif any(g) and sum(a * b for a, b in zip(spec.normal, g)) >= 0.0:
            out.append((f"{path}.normal", "the normal must point out of the ground, against gravity (its dot "
                                          "product with 'gravity' negative)"))
    out += _surface_problems(case, spec, path)
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


def _surface_problems(case, spec, path: str) -> list[tuple[str, str]]:
    """A phreatic surface from data and a pond: vertical gravity, points in the grid's plan, levels in the
    grid."""
    if spec.surface is None and spec.pond is None and spec.seepage is None:
        return []
    d = case.dimension
    hi = [a + b for a, b in zip(case.grid.origin, case.grid.extent)]
    what = "surface" if spec.surface is not None else "seepage" if spec.seepage is not None else "pond"
    out = vertical_gravity_problems(case, f"{path}.{what}")
    if out:
        return out
    if spec.seepage is not None:
        out += seepage_problems(case, spec.seepage, f"{path}.seepage")
    if spec.pond is not None:
        for i, z in enumerate(spec.pond.levels):
            if z > hi[-1]:
                out.append((f"{path}.pond.levels.{i}", f"{z:g} m is above the grid's top ({hi[-1]:g} m): raise "
                                                        "grid.extent or lower the pond"))
    srf = spec.surface
    if srf is None or srf.points is None:
        if srf is not None and d == 2:
            out.append((f"{path}.surface.raster", "a raster is a 3D surface; in 2D give the phreatic line's "
                                                  "'points' [[x, z], ...]"))
        return out
    rises = spec.heights if spec.heights is not None else [0.0]
    return out + surface_points_problems(case, srf.points, f"{path}.surface.points", max(rises))


def seepage_problems(case, seepage, path: str) -> list[tuple[str, str]]:
    """A seepage state's heads: each on a side the grid has, none above the grid's top."""
    d = case.dimension
    top = case.grid.origin[-1] + case.grid.extent[-1]
    out = []
    for i, held in enumerate(seepage.heads):
        where = f"{path}.heads.{i}"
        if "xyz".index(held.side[0]) >= d:
            out.append((f"{where}.side", f"a {d}D grid has no side {held.side}"))
        elif held.highest() > top:
            out.append((f"{where}.head", f"{held.highest():g} m is above the grid's top ({top:g} m): raise "
                                         "grid.extent or lower the head"))
    return out


def vertical_gravity_problems(case, where: str) -> list[tuple[str, str]]:
    """A surface hydrostatic along the vertical needs gravity along the last axis, downwards."""
    d, g = case.dimension, list(case.gravity)
    if len(g) == d and (any(g[:-1]) or not g[-1] < 0.0):
        return [(where, f"a phreatic surface from data and a pond are hydrostatic along the vertical: they need "
                        f"gravity along -{'yz'[d - 2]} only (the case has {g}); for a tilted frame use a planar "
                        "table with 'normal'")]
    return []


def surface_points_problems(case, pts, where: str, rise: float = 0.0) -> list[tuple[str, str]]:
    """A drawn surface's points: their dimension, x increasing along a 2D line, inside the grid's plan and,
    raised by ``rise`` [m], below the grid's top."""
    d = case.dimension
    lo = list(case.grid.origin)
    hi = [a + b for a, b in zip(case.grid.origin, case.grid.extent)]
    if len(pts[0]) != d:
        return [(where, f"a {d}D case takes points of {d} coordinates ([x, z] in 2D, [x, y, z] in 3D)")]
    out = []
    if d == 2 and any(b[0] <= a[0] for a, b in zip(pts, pts[1:])):
        i = next(i for i, (a, b) in enumerate(zip(pts, pts[1:])) if b[0] <= a[0]) + 1
        out.append((f"{where}.{i}", f"x must increase along the line (point {i} at x = {pts[i][0]:g} m follows "
                                    f"x = {pts[i - 1][0]:g} m)"))
    if d == 3 and len(pts) < 3:
        out.append((where, "a surface needs three points or more (a TIN)"))
    for i, p in enumerate(pts):
        if any(not lo[a] - 1e-9 <= p[a] <= hi[a] + 1e-9 for a in range(d - 1)):
            plan = ", ".join(f"{a:g}..{b:g}" for a, b in zip(lo[:-1], hi[:-1]))
            out.append((f"{where}.{i}", f"{p} leaves the grid's plan ({plan} m): give the line over the section "
                                        "the grid covers (it is held level beyond its ends)"))
            break
        if p[-1] + rise > hi[-1]:
            out.append((f"{where}.{i}", f"the surface at {p} (raised by up to {rise:g} m) is above the grid's top "
                                        f"({hi[-1]:g} m): raise grid.extent or lower the surface"))
            break
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
