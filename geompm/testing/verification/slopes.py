"""Slope cases the stability tests and benchmarks share, with their closed-form factors of safety."""

from __future__ import annotations

import math

import numpy as np


def infinite_slope_case(cell_size: float, slope: float = 20.0, friction: float = 30.0, dilation: float = 30.0,
                        cohesion: float = 0.0, depth: float = 1.0, model: str = "drucker_prager",
                        youngs_modulus: float = 2.0e6, end: float = 2.0) -> dict:
    """A strip ``depth`` deep, eight cells wide (the x period), on a fixed base; gravity 9.81 m/s2 tilted by
    ``slope`` degrees, so the grid's x axis runs down the slope.  rho = 2000 kg/m3, nu = 0.3, linear shape
    functions, APIC, 2x2 particles per cell; the dilatancy cut-off is set far away (1.0) so that an
    associated soil stays associated through a trial."""
    b = math.radians(slope)
    width = 8 * cell_size  # the x period: the slope is uniform along x, eight cells suffice
    return {
        "name": "infinite_slope",
        "description": f"Infinite slope: {depth:g} m of soil (phi {friction:g} deg, psi {dilation:g} deg, c {cohesion:g} Pa) "
                       f"on a fixed base, gravity tilted by {slope:g} deg, periodic along the slope",
        "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [width, depth + 4 * cell_size], "cell_size": cell_size,
                 "shape_function": "linear"},
        "time": {"end": end, "cfl": 0.4},
        "gravity": [9.81 * math.sin(b), -9.81 * math.cos(b)],
        "solver": {"transfer": "apic", "update": "usl"},
        "materials": {"soil": {"model": model, "density": 2000.0, "youngs_modulus": youngs_modulus,
                               "poisson_ratio": 0.3, "friction_angle": friction, "dilation_angle": dilation,
                               "cohesion": cohesion, "dilation_cutoff": 1.0}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [width, depth]},
                    "particles_per_cell": 2}],
        "boundaries": [{"type": "periodic", "axis": "x"}, {"type": "wall", "side": "y-", "condition": "fixed"}],
        "damping": [{"model": "local", "alpha": 0.8}],
        "outputs": [{"writer": "series", "interval": end / 40}],
    }


def saturated_infinite_slope_case(cell_size: float, slope: float = 20.0, friction: float = 40.0, **over) -> dict:
    """infinite_slope_case with a water table at its surface and seepage parallel to the slope
    (triggers.water_table with the surface's normal, rho_w = 1000 kg/m3 against the soil's saturated 2000),
    from the geostatic effective stress of that state."""
    case = infinite_slope_case(cell_size, slope=slope, friction=friction, dilation=friction, **over)
    depth = case["bodies"][0]["geometry"]["max"][1]
    case["description"] += "; water table at the surface, seepage parallel to the slope"
    case["triggers"] = {"water_table": {"times": [0.0], "heights": [depth], "normal": [0.0, 1.0]}}
    case["bodies"][0].update({"initial_stress": "geostatic", "surface_normal": [0.0, 1.0]})
    return case


def two_phase_infinite_slope_case(cell_size: float, slope: float = 20.0, friction: float = 40.0,
                                  conductivity: float = 1.0e-5, **over) -> dict:
    """saturated_infinite_slope_case as two-phase soil: the same saturated density 2000 kg/m3 (n = 0.4,
    rho_s = 2666.7 kg/m3, rho_w = 1000 kg/m3, K_w = 2e7 Pa), its pore pressure that of the table at its
    surface with seepage parallel to the slope (``pore_pressure.table_normal``), hydraulic conductivity
    ``conductivity`` [m/s]; PIC (the saturated step refuses APIC with linear hats) and the saturated step."""
    case = infinite_slope_case(cell_size, slope=slope, friction=friction, dilation=friction, **over)
    depth = case["bodies"][0]["geometry"]["max"][1]
    n = 0.4
    soil = case["materials"]["soil"]
    soil["density"] = (2000.0 - n * 1000.0) / (1.0 - n)
    soil["pore_water"] = {"porosity": n, "hydraulic_conductivity": conductivity,
                          "fluid": {"density": 1000.0, "bulk_modulus": 2.0e7, "viscosity": 1.0e-3}}
    case["solver"] = {"transfer": "pic", "update": "saturated"}
    case["description"] += "; two-phase, table at the surface, seepage parallel to the slope"
    case["bodies"][0].update({"initial_stress": "geostatic", "surface_normal": [0.0, 1.0],
                              "pore_pressure": {"water_table": depth, "table_normal": [0.0, 1.0]}})
    return case


def saturated_limit_equilibrium(slope: float, friction: float, density: float = 2000.0, fluid: float = 1000.0) -> float:
    """F of a cohesionless infinite slope with the water table at its surface and slope-parallel seepage,
    (gamma' / gamma_sat) tan(phi) / tan(beta) (Skempton & DeLory 1957; Duncan, Wright & Brandon 2014, sec. 6.2)."""
    return (density - fluid) / density * math.tan(math.radians(friction)) / math.tan(math.radians(slope))


def rising_table_case(cell_size: float, rise=(1.0, 0.4, 7.0, 1.0), end: float = 8.0) -> dict:
    """The infinite slope of infinite_slope_case (beta = 20 deg, phi = psi = 30 deg, c = 0, 1 m deep) under a
    water table parallel to it that rises from rise[1] m above the base at t = rise[0] to rise[3] m at
    t = rise[2] (slope-parallel seepage), from the geostatic effective stress of its first height; the
    trial's viscous damping (zeta = 20 1/s, trial.py) and the series with displacements every 0.05 s."""
    case = infinite_slope_case(cell_size, end=end)
    t0, z0, t1, z1 = rise
    case["description"] += "; a water table parallel to the slope rising through it"
    case["triggers"] = {"water_table": {"times": [t0, t1], "heights": [z0, z1], "normal": [0.0, 1.0]}}
    case["bodies"][0].update({"initial_stress": "geostatic", "surface_normal": [0.0, 1.0]})
    case["damping"] = [{"model": "artificial", "xi": 1e-3, "reference_cell_size": 1e-3 * math.sqrt(2.0e6 / 2000.0) / 20.0}]
    case["outputs"] = [{"writer": "series", "interval": 0.05, "displacement": True}]
    return case


def onset_from_velocity(series: dict, after: float, low: float = 5e-3, high: float = 3e-2) -> float:
    """The time [s] a slide under a rising trigger started: the surface speed (the rate of the series column
    ``max_displacement``) fitted by a line over the rows where it lies in [low, high] m/s, extrapolated to zero.
    Past its limit an overdamped slope (viscous damping zeta) slides at v = a / zeta with an acceleration a
    that grows linearly with the table's height, so v is linear in time from the onset; below ``low`` the
    slope's creep before the onset (about 1e-3 m/s) biases the line."""
    t = np.asarray(series["time"], float)
    d = np.asarray(series["max_displacement"], float)
    v = np.diff(d) / np.diff(t)
    mid = 0.5 * (t[1:] + t[:-1])
    pick = (v >= low) & (v <= high) & (mid >= after)
    slope, intercept = np.polyfit(mid[pick], v[pick], 1)
    return float(-intercept / slope)


def critical_table(slope: float, friction: float, depth: float = 1.0, density: float = 2000.0,
                   fluid: float = 1000.0) -> float:
    """The height above the base [m] of a slope-parallel water table at which a cohesionless infinite slope
    ``depth`` deep reaches F = 1 on its base: F(h_w) = (1 - rho_w h_w / (rho H)) tan(phi) / tan(beta)."""
    ratio = math.tan(math.radians(slope)) / math.tan(math.radians(friction))
    return (1.0 - ratio) * density * depth / fluid


def limit_equilibrium(slope: float, friction: float, cohesion: float, depth: float = 1.0, density: float = 2000.0) -> float:
    """F of the slope-parallel plane at ``depth``: c / (gamma z cos^2(beta) tan(beta)) + tan(phi) / tan(beta)
    (Taylor 1948, Fundamentals of Soil Mechanics, ch. 16; Duncan, Wright & Brandon 2014, Soil Strength and
    Slope Stability, 2nd ed., sec. 6.2)."""
    b, phi = math.radians(slope), math.radians(friction)
    return cohesion / (density * 9.81 * depth * math.cos(b) ** 2 * math.tan(b)) + math.tan(phi) / math.tan(b)


def biaxial_case(cell_size: float, reference_cell_size: float | None, end: float = 1.5, speed: float = 0.02,
                 viscoplastic_time: float | None = None) -> dict:
    """Plane-strain compression of a softening sample 1 m wide and 2 m high between a smooth base and a smooth
    rigid platen moving down at ``speed`` [m/s], sides free, no gravity; ``viscoplastic_time`` [s]: the laws'
    Duvaut-Lions time (solver.viscoplastic_time), default none.  drucker_prager_softening with
    phi = psi = 0 (so the strength is c alone): c falls linearly from 100 kPa to 50 kPa between eps_p = 0 and
    0.05 (thresholds of a band ``reference_cell_size`` wide; None: strains at every cell size).  A weaker
    corner (0.2 m x 0.2 m at the bottom left, c peak 90 kPa) seeds the band.  E = 50 MPa, nu = 0.3,
    rho = 2000 kg/m3; viscous damping at 20 1/s; quadratic shape functions; the platen's force is the series
    column platen_fy [N/m]."""
    def soil(c):
        return {"model": "drucker_prager_softening", "density": 2000.0, "youngs_modulus": 5.0e7, "poisson_ratio": 0.3,
                "friction_angle": 0.0, "cohesion": c, "dilation_angle": 0.0, "residual_cohesion": 5.0e4,
                "residual_friction_angle": 0.0,
                "softening": {"start": 0.0, "end": 0.05, "shape": "linear", "reference_cell_size": reference_cell_size}}

    box = lambda lo, hi: {"type": "box", "min": lo, "max": hi}  # noqa: E731
    return {
        "name": "biaxial",
        "description": "plane-strain compression of a softening sample (docs/slope-stability.md)",
        "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [2.0, 2.8], "cell_size": cell_size, "shape_function": "quadratic"},
        "time": {"end": end, "cfl": 0.3},
        "gravity": [0.0, 0.0],
        "solver": {"transfer": "apic", "update": "usl",
                   **({"viscoplastic_time": viscoplastic_time} if viscoplastic_time else {})},
        "materials": {"soil": soil(1.0e5), "weak": soil(9.0e4)},
        "bodies": [{"material": "weak", "geometry": box([0.5, 0.0], [0.7, 0.2]), "particles_per_cell": 2},
                   {"material": "soil", "geometry": box([0.7, 0.0], [1.5, 0.2]), "particles_per_cell": 2},
                   {"material": "soil", "geometry": box([0.5, 0.2], [1.5, 2.0]), "particles_per_cell": 2}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "slip"}],
        "obstacles": [{"type": "box", "name": "platen", "min": [0.2, 2.0], "max": [1.8, 2.5], "condition": "slip",
                       "velocity": [0.0, -speed]}],
        "damping": [{"model": "artificial", "xi": 1e-3, "reference_cell_size": 1e-3 * math.sqrt(5.0e7 / 2000.0) / 20.0}],
        "outputs": [{"writer": "series", "interval": end / 150}],
    }


def griffiths_lane_case(cell_size: float, end: float = 3.0, model: str = "drucker_prager", friction: float = 20.0,
                        cohesion: float = 1.0e4) -> dict:
    """Griffiths & Lane's (1999, Geotechnique 49(3):387) first example: a 2:1 slope 10 m high on a rigid rough
    base at the toe's level (no foundation layer), phi' = 20 deg, psi = 0, c' / (gamma H) = 0.05 (gamma = 20
    kN/m3, c' = 10 kPa), E = 100 MPa, nu = 0.3 (their values).  The soil runs 12 m behind the crest (x = 0 to
    12 m) to a smooth back wall; the slope from the crest (12, 10) to the toe (32, 0); the grid reaches
    x = 42 m.  Geostatic initial stress, linear shape functions, 2x2 particles per cell.  ``friction`` and
    ``cohesion`` give the other slopes of docs/slope-stability.md on the same geometry (phi = 0: undrained)."""
    rho = 20000.0 / 9.81
    return {
        "name": "griffiths_lane_1",
        "description": "Griffiths & Lane (1999) example 1: 2:1 slope, H = 10 m, phi' 20 deg, c'/(gamma H) = 0.05, "
                       "rigid base at the toe (docs/slope-stability.md)",
        "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [42.0, 10.0 + 4 * cell_size], "cell_size": cell_size,
                 "shape_function": "linear"},
        "time": {"end": end, "cfl": 0.4},
        "gravity": [0.0, -9.81],
        "solver": {"transfer": "apic", "update": "usl"},
        "materials": {"soil": {"model": model, "density": rho, "youngs_modulus": 1.0e8, "poisson_ratio": 0.3,
                               "friction_angle": friction, "cohesion": cohesion, "dilation_angle": 0.0}},
        "bodies": [{"material": "soil", "geometry": {"type": "polygon",
                                                     "vertices": [[0.0, 0.0], [32.0, 0.0], [12.0, 10.0], [0.0, 10.0]]},
                    "particles_per_cell": 2, "initial_stress": "geostatic"}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "fixed"},
                       {"type": "wall", "side": "x-", "condition": "slip"}],
        "outputs": [{"writer": "series", "interval": end / 40}],
    }


def griffiths_lane_case_3d(cell_size: float, width: float, ends: str = "slip", end: float = 3.0,
                           model: str = "drucker_prager", friction: float = 20.0, cohesion: float = 1.0e4) -> dict:
    """griffiths_lane_case's slope extruded ``width`` [m] along z between two end walls: ``ends`` "slip" (smooth:
    symmetry planes, so the factor is the plane-strain one at any width) or "fixed" (rough, bonded: the ends
    hold the slide and the factor exceeds the plane-strain one, less so as the slope widens; Griffiths &
    Marquez 2007, Geotechnique 57(6):537).  Gravity along -y, 2x2x2 particles per cell."""
    case = griffiths_lane_case(cell_size, end=end, model=model, friction=friction, cohesion=cohesion)
    case["name"] = f"griffiths_lane_3d_{ends}_{width:g}"
    case["description"] = (f"Griffiths & Lane (1999) example 1 extruded {width:g} m between {ends} end walls "
                           "(docs/slope-stability.md, Slopes in 3D)")
    case["dimension"] = 3
    grid = case["grid"]
    grid["origin"] = [0.0, 0.0, 0.0]
    grid["extent"] = [grid["extent"][0], grid["extent"][1], width]
    case["gravity"] = [0.0, -9.81, 0.0]
    body = case["bodies"][0]
    body["geometry"]["extrude"] = [0.0, width]
    case["boundaries"] = case["boundaries"] + [{"type": "wall", "side": "z-", "condition": ends},
                                               {"type": "wall", "side": "z+", "condition": ends}]
    return case
