"""Slope cases the stability tests and benchmarks share, with their closed-form factors of safety."""

from __future__ import annotations

import math


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


def limit_equilibrium(slope: float, friction: float, cohesion: float, depth: float = 1.0, density: float = 2000.0) -> float:
    """F of the slope-parallel plane at ``depth``: c / (gamma z cos^2(beta) tan(beta)) + tan(phi) / tan(beta)
    (Taylor 1948, Fundamentals of Soil Mechanics, ch. 16; Duncan, Wright & Brandon 2014, Soil Strength and
    Slope Stability, 2nd ed., sec. 6.2)."""
    b, phi = math.radians(slope), math.radians(friction)
    return cohesion / (density * 9.81 * depth * math.cos(b) ** 2 * math.tan(b)) + math.tan(phi) / math.tan(b)
