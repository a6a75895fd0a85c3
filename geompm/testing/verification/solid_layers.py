"""Saturated layers at rest against impermeable rigid solids (docs/pore-water.md, Free surface;
tests/verification/test_solid_fill.py, benchmarks/pore_water/solid_layers.py).

Each layer starts geostatic and hydrostatic under a level water table at its top, with a conductivity high
enough (k = 1e-2 m/s) that any leak through a wrongly drained base shows within the run, and local damping
to bring the skeleton to rest.  At the end the particles of the bottom row (within one particle spacing of
the solid) must hold p = rho_w g (z_top - z), and none of them may be flagged drained.

- ``floor_2d``: a 2D column on an analytic box obstacle (or, for reference, on the grid's wall);
- ``terrain_3d``: a 3D layer between a level top and an inclined terrain DEM, walls around;
- ``floor_3d``: a 3D column on a floor given as an STL mesh;
- ``terrain_3d``'s ground inclined: measured in docs/pore-water.md (an oblique solid, plane or terrain,
  leaves a row-to-row pattern in the pressure at rest).
"""

from __future__ import annotations

import math

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing.verification.dem import write_dem
from geompm.testing.verification.saturated_columns import run_to

#: porosity, grain density [kg/m3], gravity [m/s2], water density [kg/m3]
N0, RHO_S, G, RHO_W = 0.4, 2650.0, 9.81, 1000.0


def _soil(shape: str = "linear") -> dict:
    return {"model": "linear_elastic", "density": RHO_S, "youngs_modulus": 10e6, "poisson_ratio": 0.3,
            "pore_water": {"porosity": N0, "hydraulic_conductivity": 1e-2, "fluid": {"bulk_modulus": 2.2e8}}}


def _case(name, dim, origin, extent, h, gravity, bodies, end, shape="linear") -> dict:
    return {"name": name, "dimension": dim,
            "grid": {"origin": origin, "extent": extent, "cell_size": h, "shape_function": shape},
            "time": {"end": end}, "gravity": gravity, "solver": {"transfer": "flip"},
            "materials": {"soil": _soil()}, "bodies": bodies,
            "damping": [{"model": "local", "alpha": 0.3}]}


def _on_floor_3d(case: dict, floor: dict) -> dict:
    """The 3D case between slip walls on its four sides, on the rigid ``floor`` with friction 0.5."""
    case["boundaries"] = [{"type": "wall", "side": s, "condition": "slip"} for s in ("x-", "x+", "y-", "y+")]
    case["obstacles"] = [{**floor, "condition": "friction", "friction": 0.5}]
    return case


def floor_2d(h: float, floor: str = "box", end: float = 0.2, shape: str = "linear") -> dict:
    """A 1 m saturated column, 0.2 m wide, between slip walls, on a 0.2 m thick analytic box obstacle
    (``floor`` 'box', friction 0.5) or on the grid's y- wall ('wall')."""
    base = 0.2 if floor == "box" else 0.0
    body = {"material": "soil", "geometry": {"type": "box", "min": [0.0, base], "max": [0.2, base + 1.0]},
            "particles_per_cell": 2, "initial_stress": "geostatic"}
    case = _case("column_on_" + floor, 2, [0.0, 0.0], [0.2, base + 1.2], h, [0.0, -G], [body], end, shape)
    sides = ["x-", "x+"] + (["y-"] if floor == "wall" else [])
    case["boundaries"] = [{"type": "wall", "side": s, "condition": "slip"} for s in sides]
    if floor == "box":
        case["obstacles"] = [{"type": "box", "name": "floor", "min": [-0.1, -0.1], "max": [0.3, base],
                              "condition": "friction", "friction": 0.5}]
    return case


def terrain_3d(tmp_path, h: float, slope_deg: float = 10.0, end: float = 0.2) -> dict:
    """A saturated layer in a 0.8 x 0.2 m box of slip walls between a level top at z = 0.5 m and a ground
    inclined at ``slope_deg`` along x, z = 0.2 + tan(slope) (0.8 - x) (a DEM of pixel h / 2, the terrain
    obstacle, friction 0.5): 0.3 m deep at its lower end."""
    tan = math.tan(math.radians(slope_deg))

    def ground(x, y):
        return 0.2 + tan * (0.8 - x)

    px = h / 2.0
    n = int(round(1.2 / px))
    write_dem(tmp_path / "ground.tif", ground, -0.2, -0.2, n, n, px)
    write_dem(tmp_path / "top.tif", lambda x, y: 0.5 + 0.0 * x, -0.2, -0.2, n, n, px)
    body = {"material": "soil", "geometry": {"type": "between_surfaces", "surface": "top.tif",
                                             "failure_surface": "ground.tif"},
            "particles_per_cell": 2, "initial_stress": "geostatic"}
    case = _case("layer_on_terrain", 3, [0.0, 0.0, 0.0], [0.8, 0.2, 0.6], h, [0.0, 0.0, -G], [body], end)
    return _on_floor_3d(case, {"type": "terrain", "name": "ground", "dem": "ground.tif"})


def floor_3d(tmp_path, h: float, end: float = 0.2) -> dict:
    """A 1 m saturated column, 0.2 x 0.2 m, between slip walls, on a floor given as an STL mesh (a box
    0.2 m thick reaching beyond the grid's sides, friction 0.5)."""
    import trimesh

    floor = trimesh.creation.box(bounds=[[-0.2, -0.2, -0.2], [0.4, 0.4, 0.2]])
    floor.export(tmp_path / "floor.stl")
    body = {"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0, 0.2], "max": [0.2, 0.2, 1.2]},
            "particles_per_cell": 2, "initial_stress": "geostatic"}
    case = _case("column_on_stl", 3, [0.0, 0.0, 0.0], [0.2, 0.2, 1.4], h, [0.0, 0.0, -G], [body], end)
    return _on_floor_3d(case, {"type": "rigid_mesh", "name": "floor", "file": "floor.stl"})


def inclined_plane_3d(tmp_path, h: float, slope_deg: float = 10.0, end: float = 0.2) -> dict:
    """terrain_3d with the analytic plane of the same ground in place of the DEM (a halfspace boundary,
    mirrored in the fill): the reference for the oblique boundary's own error."""
    case = terrain_3d(tmp_path, h, slope_deg, end)
    tan = math.tan(math.radians(slope_deg))
    normal = np.array([tan, 0.0, 1.0]) / math.hypot(tan, 1.0)
    case.pop("obstacles")
    case["boundaries"].append({"type": "plane", "point": [0.8, 0.1, 0.2], "normal": normal.tolist(),
                               "condition": "friction", "friction": 0.5})
    return case


def inclined_plane_2d(h: float, slope_deg: float = 10.0, end: float = 0.2, update: str = "saturated") -> dict:
    """A 1.6 m wide saturated layer, its top level at 0.8 m, on an analytic plane through (0.8, 0.2) at
    ``slope_deg`` (friction 0.5), between slip walls, in 2D, run by the scheme ``update``: the oblique
    boundary's error without a DEM or a third dimension."""
    tan = math.tan(math.radians(slope_deg))

    def ground(x):
        return 0.2 - tan * (x - 0.8)

    body = {"material": "soil", "geometry": {"type": "polygon",
                                             "vertices": [[0.0, ground(0.0)], [1.6, ground(1.6)], [1.6, 0.8],
                                                          [0.0, 0.8]]},
            "particles_per_cell": 2, "initial_stress": "geostatic"}
    case = _case("layer_on_plane_2d", 2, [0.0, 0.0], [1.6, 1.2], h, [0.0, -G], [body], end)
    case["solver"]["update"] = update
    normal = [math.sin(math.radians(slope_deg)), math.cos(math.radians(slope_deg))]
    case["boundaries"] = [{"type": "wall", "side": s, "condition": "slip"} for s in ("x-", "x+")]
    case["boundaries"].append({"type": "plane", "point": [0.8, 0.2], "normal": normal, "condition": "friction",
                               "friction": 0.5})
    return case


def floor_path(case: dict) -> str:
    """The JSON path of the layer's floor: its obstacle, else its last boundary (the plane or the y- wall)."""
    if case.get("obstacles"):
        return "obstacles.0"
    return f"boundaries.{len(case['boundaries']) - 1}"


def bottom_row(case: dict, end: float, base_dir=".") -> dict:
    """Run ``case`` to ``end``; of the particles within one particle spacing of its floor (floor_path: the
    stage's solid_depth) and more than two spacings below the top: the mean and the largest relative error
    of p against rho_w g (top - height) and the fraction flagged drained; and the largest error over every
    particle that deep."""
    scene = scene_from_dict(case, base_dir=base_dir)
    sim = Simulation(scene)
    st = sim.state
    up = -np.asarray(case["gravity"], float) / G
    spacing = st.p_vol0 ** (1.0 / scene.dim)
    top = float((st.p_x @ up).max()) + 0.5 * spacing.max()  # the body's top surface
    run_to(sim, end)
    floor = next(s for s in scene.stages if s.json_path == floor_path(case))
    hyd = RHO_W * G * (top - st.p_x @ up)
    deep = hyd > RHO_W * G * 2.0 * spacing.max()
    row = (floor.solid_depth(st.p_x) > -spacing) & deep
    err = st.p_pore / hyd - 1.0
    return {"particles": int(row.sum()), "mean_error": float(err[row].mean()),
            "max_error": float(np.abs(err[row]).max()), "drained": float(st.p_drained[row].mean()),
            "all_max_error": float(np.abs(err[deep]).max()), "steps": sim.step_count}
