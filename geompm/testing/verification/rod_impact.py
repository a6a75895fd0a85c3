"""An elastic block thrown at a rigid wall in uniaxial strain: the closed form of a first-contact load.

A block of length L, height H, density rho and constrained modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu))
between two slip walls (uniaxial strain, plane strain) strikes a rigid slip wall at speed v.  One-dimensional
wave theory (de Saint-Venant's rod impact; e.g. Graff 1975, Wave Motion in Elastic Solids, section 1.4;
Johnson 1972, Impact Strength of Materials, ch. 1): the contact stress is the acoustic impedance times the
speed, sigma = rho c v with c = sqrt(M / rho), for the time a wave takes to cross the block and back, 2 L /
c; then the block leaves at -v, so the wall takes the impulse 2 rho L H v.  Per metre of depth:

    F = rho c v H   for 0 < t - t_c < 2 L / c,     J = 2 rho L H v.

This is the first-contact spike of every flow against a rigid surface: its height follows the material's
elastic stiffness (a numerical one for granular debris), its length the time a wave crosses the flow
(docs/impact-forces.md).
"""

from __future__ import annotations

import math

RHO, NU, SPEED, LENGTH, HEIGHT = 2000.0, 0.3, 2.0, 0.5, 0.2  # kg/m3, -, m/s, m, m
WALL = 0.65  # the wall's face [m]; the block starts at 0.1 .. 0.6 m


def wave_speed(E: float) -> float:
    return math.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)) / RHO)


def rod_case(h: float, E: float = 2e6, window_share: float = 0.1) -> dict:
    """The case at cell size h [m]; the wall's force window is ``window_share`` of 2 L / c."""
    c = wave_speed(E)
    return {"name": "rod_impact", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [1.0, HEIGHT], "cell_size": h},
            "time": {"end": 0.1, "cfl": 0.4}, "gravity": [0.0, 0.0],
            "solver": {"transfer": "apic", "update": "usl"},
            "materials": {"bar": {"model": "linear_elastic", "density": RHO, "youngs_modulus": E,
                                  "poisson_ratio": NU}},
            "bodies": [{"material": "bar", "geometry": {"type": "box", "min": [0.1, 0.0],
                                                        "max": [0.1 + LENGTH, HEIGHT]},
                        "velocity": [SPEED, 0.0], "particles_per_cell": 2}],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "slip"},
                           {"type": "wall", "side": "y+", "condition": "slip"}],
            "obstacles": [{"type": "box", "name": "wall", "min": [WALL, -0.1], "max": [WALL + 0.1, HEIGHT + 0.1],
                           "condition": "slip", "force_window": window_share * 2 * LENGTH / c}]}


def rod_impact(h: float, E: float = 2e6, window_share: float = 0.1) -> dict:
    """Run the case to 0.1 s: the wall's raw and filtered peak [N/m], the x impulse [N s/m], the time the
    force stayed above 5 % of rho c v H [s], beside the closed forms."""
    from geompm.api import scene_from_dict
    from geompm.engine.scheduler import Simulation

    sim = Simulation(scene_from_dict(rod_case(h, E, window_share)))
    wall = sim.scene.obstacles[0]
    c = wave_speed(E)
    load = RHO * c * SPEED * HEIGHT
    loaded = []
    while sim.time < 0.1:
        sim.step(sim.stable_dt())
        if wall.force[0] > 0.05 * load:
            loaded.append(sim.time)
    rep = wall.impact_report()
    return {"h": h, "E": E, "c": c, "load": load, "impulse_exact": 2 * RHO * LENGTH * HEIGHT * SPEED,
            "duration_exact": 2 * LENGTH / c, "raw_peak": wall.peak[0], "filtered_peak": rep["filtered_peak_force"],
            "window": rep["force_window"], "impulse_x": rep["impulse_vector"][0],
            "duration": (loaded[-1] - loaded[0]) if loaded else 0.0, "steps": sim.step_count}
