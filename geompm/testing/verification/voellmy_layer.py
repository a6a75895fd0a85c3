"""A layer sliding on a Voellmy bed: the closed form of its speed (contact/voellmy.py).

An infinite layer of depth H (periodic along the slope) on a rigid bed inclined at beta (gravity tilted,
the bed the grid's y- wall with condition 'voellmy') starts from rest.  As a plug, per unit bed area,
rho H du/dt = rho g H (sin beta - mu cos beta) - rho g u^2 / xi, so

    u(t) = u_T tanh(t / tau),   u_T = sqrt(xi H (sin beta - mu cos beta)),   tau = u_T / (g (sin beta - mu cos beta))

(Voellmy 1955; the terminal speed RAMMS's users check a calibration with).
"""

from __future__ import annotations

import math

import numpy as np

G, BETA, MU, XI, DEPTH, RHO = 9.81, 30.0, 0.2, 50.0, 0.2, 2000.0  # m/s2, deg, -, m/s2, m, kg/m3


def terminal_speed(xi: float = XI, depth: float = DEPTH) -> float:
    b = math.radians(BETA)
    return math.sqrt(xi * depth * (math.sin(b) - MU * math.cos(b)))


def speed(t: float, xi: float = XI, depth: float = DEPTH) -> float:
    b = math.radians(BETA)
    a0 = G * (math.sin(b) - MU * math.cos(b))
    ut = terminal_speed(xi, depth)
    return ut * math.tanh(t * a0 / ut)


def layer_case(h: float, xi: float = XI, end: float = 2.5) -> dict:
    b = math.radians(BETA)
    return {"name": "voellmy_layer", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [0.2, 0.4], "cell_size": h},
            "time": {"end": end, "cfl": 0.4}, "gravity": [G * math.sin(b), -G * math.cos(b)],
            "solver": {"transfer": "apic", "update": "usl"},
            "materials": {"debris": {"model": "linear_elastic", "density": RHO, "youngs_modulus": 2e6,
                                     "poisson_ratio": 0.3}},
            "bodies": [{"material": "debris", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [0.2, DEPTH]},
                        "particles_per_cell": 2, "initial_stress": "geostatic"}],
            "boundaries": [{"type": "periodic", "axis": "x"},
                           {"type": "wall", "side": "y-", "condition": "voellmy", "friction": MU, "xi": xi}]}


def layer_speeds(h: float, times=(0.25, 0.5, 1.0, 2.5), xi: float = XI) -> list[tuple[float, float]]:
    """(time, the layer's mean speed along the slope) at ``times`` [s]."""
    from geompm.api import scene_from_dict
    from geompm.engine.scheduler import Simulation

    sim = Simulation(scene_from_dict(layer_case(h, xi, max(times))))
    st = sim.state
    out = []
    for t in times:
        while sim.time < t - 1e-12:
            sim.step(min(sim.stable_dt(), t - sim.time))
        out.append((sim.time, float((st.p_mass * st.p_v[:, 0]).sum() / st.p_mass.sum())))
    return out
