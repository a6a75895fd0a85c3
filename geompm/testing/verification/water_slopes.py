"""Slopes with water as engineers draw them (docs/slope-stability.md, "Water in slopes"): the new user's
slope of issue 54, 10 m high at 1.5:1 (33.7 deg) on a rough rigid base at the toe's level, c' = 5 kPa,
phi' = 30 deg, psi = 0, gamma_sat = 20 kN/m3, E = 20 MPa, nu = 0.3, drucker_prager with its plane-strain
cone, linear shape functions, 2 x 2 particles per cell; the soil runs 12 m behind the crest to a smooth back
wall, the crest at (12, 10) m, the toe at (27, 0) m, the grid to x = 40 m.

- ``phreatic_line``: a curved phreatic surface from the back of the slope to its toe (a parabola-like
  line through the points the user drew, level beyond them);
- ``slope_case``: the slope drained under that line (``triggers.water_table.surface``) or a pond;
- ``two_phase_slope_case``: the same slope as two-phase soil, hydrostatic below the line at t = 0;
- ``bishop_with_line``: Bishop's simplified F with u = gamma_w (z_line(x) - z_arc) on the slip surface, the
  limit-equilibrium reference (bishop.py).
"""

from __future__ import annotations

import numpy as np

from geompm.testing.verification.bishop import critical_circle, surface_from_points

HEIGHT, CREST_X, TOE_X, EXTENT_X = 10.0, 12.0, 27.0, 40.0
GAMMA = 20000.0
RHO = GAMMA / 9.81
RHO_W = 1000.0


def phreatic_line(back: float = 8.0, toe: float = 0.0, cover: float = 0.0) -> list[list[float]]:
    """A phreatic line falling from ``back`` [m] at the back wall to ``toe`` [m] at the toe, curved as seepage
    towards a toe drain draws it (Casagrande's basic parabola in shape: z = toe + (back - toe) sqrt(1 - s)
    over the distance share s from the back to the toe), sampled every metre, and kept ``cover`` [m] below
    the ground (0: it meets the face near the toe, where the water seeps out)."""
    xs = np.linspace(0.0, TOE_X, 28)
    s = xs / TOE_X
    zs = toe + (back - toe) * np.sqrt(np.clip(1.0 - s, 0.0, 1.0))
    ground = np.interp(xs, [0.0, CREST_X, TOE_X], [HEIGHT, HEIGHT, 0.0])
    zs = np.minimum(zs, ground - cover)  # inside the ground: at or below the face
    return [[float(x), float(z)] for x, z in zip(xs, zs)]


def slope_case(cell_size: float, end: float = 3.0, line=None, pond=None, cohesion: float = 5.0e3,
               friction: float = 30.0, back_head: float | None = None) -> dict:
    """The slope, drained, under the phreatic ``line`` (points [[x, z], ...]; None: dry) and a ``pond``
    ({"times": [...], "levels": [...]}; None: none), or in the steady seepage state from a head ``back_head``
    [m] held on its back (the x- side: a reservoir behind it) with its face free to seep."""
    case = {
        "name": "water_slope",
        "description": "10 m slope at 1.5:1, c' 5 kPa, phi' 30 deg, on a rigid base; drained under a phreatic "
                       "line / pond (docs/slope-stability.md, Water in slopes)",
        "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [EXTENT_X, HEIGHT + 4 * cell_size], "cell_size": cell_size,
                 "shape_function": "linear"},
        "time": {"end": end, "cfl": 0.4},
        "gravity": [0.0, -9.81],
        "solver": {"transfer": "apic", "update": "usl"},
        "materials": {"soil": {"model": "drucker_prager", "density": RHO, "youngs_modulus": 2.0e7,
                               "poisson_ratio": 0.3, "friction_angle": friction, "cohesion": cohesion,
                               "dilation_angle": 0.0}},
        "bodies": [{"material": "soil", "geometry": {"type": "polygon", "vertices": [
            [0.0, 0.0], [TOE_X, 0.0], [CREST_X, HEIGHT], [0.0, HEIGHT]]},
                    "particles_per_cell": 2, "initial_stress": "geostatic"}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "fixed"},
                       {"type": "wall", "side": "x-", "condition": "slip"}],
        "outputs": [{"writer": "series", "interval": end / 40}],
    }
    water = {}
    if back_head is not None:
        water["seepage"] = {"heads": [{"side": "x-", "head": back_head}]}
    if line is not None:
        water["surface"] = {"points": line}
    if pond is not None:
        water["pond"] = pond
    if water:
        case["triggers"] = {"water_table": water}
    return case


def two_phase_slope_case(cell_size: float, end: float = 0.5, table: float | None = 2.0, conductivity: float = 1e-6,
                         loading: bool = True, tolerance: float = 1e-5) -> dict:
    """The slope as two-phase soil (n = 0.4, rho_sat = gamma / g, K_w = 2e7 Pa), PIC, hydrostatic below a
    level table at ``table`` [m] (None: below its own surface, column by column), with a gravity-loading stage
    if ``loading``; at rest over ``end``."""
    case = slope_case(cell_size, end=end)
    n = 0.4
    soil = case["materials"]["soil"]
    soil["density"] = (RHO - n * RHO_W) / (1.0 - n)
    soil["pore_water"] = {"porosity": n, "hydraulic_conductivity": conductivity,
                          "fluid": {"density": RHO_W, "bulk_modulus": 2.0e7, "viscosity": 1.0e-3}}
    case["solver"] = {"transfer": "pic", "update": "saturated"}
    if table is not None:
        case["bodies"][0]["pore_pressure"] = {"water_table": table}
    if loading:
        case["gravity_loading"] = {"tolerance": tolerance, "max_time": 10.0}
    case["outputs"] = [{"writer": "series", "interval": end / 10}]
    return case


def bishop_with_line(line=None, cohesion: float = 5.0e3, friction: float = 30.0, pond: float | None = None,
                     centres=None, radii=None, head=None):
    """(F, circle) of Bishop's simplified method over circles that stay above the base, under the phreatic
    ``line`` (points [[x, z], ...]) and a ``pond`` at level z_p [m]: the pore pressure on the slip surface
    u = gamma_w (max(z_line(x), z_p) - z_arc), and the pond's water on the submerged face.  The pond is taken
    as buoyant unit weight below its level and the excess u - gamma_w (z_p - z_arc) on the base, which is the
    same equilibrium as the slices' total weight with the pond's water column on them and the full u (the
    hydrostatic pond pressure over the sliding mass's closed boundary is its buoyancy; per slice, the
    vertical balance W + W_water - u b = W' - u_excess b), and what the run itself does
    (mpm/water_table.py).  ``head(x, y)``: a solved head field [m] in place of the line."""
    ground = surface_from_points([-100.0, CREST_X, TOE_X, 200.0], [HEIGHT, HEIGHT, 0.0, 0.0])
    pts = None if line is None else np.asarray(line, float)
    g_w = RHO_W * 9.81
    z_p = -np.inf if pond is None else float(pond)

    def table(x):
        return -np.inf if pts is None else float(np.interp(x, pts[:, 0], pts[:, 1]))

    def pore(x, y):
        level = max(table(x), z_p) if head is None else max(head(x, y), z_p)  # a solved head field H(x, y)
        return g_w * (max(level - y, 0.0) - max(z_p - y, 0.0))

    def column(x, arc):
        top = ground(x)
        submerged = np.clip(z_p - arc, 0.0, np.maximum(top - arc, 0.0))
        return GAMMA * np.maximum(top - arc, 0.0) - g_w * submerged

    centres = centres or (np.linspace(5, 35, 11), np.linspace(8, 30, 11))
    radii = np.linspace(5, 40, 15) if radii is None else radii
    return critical_circle(ground, cohesion, friction, GAMMA, centres, radii, base=0.0, lo=0.0, hi=EXTENT_X,
                           pore=pore, column=None if pond is None else column)
