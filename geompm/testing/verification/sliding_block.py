"""A saturated elastic block sliding on an impermeable plane: Coulomb friction on the effective normal force
(docs/pore-water.md, Friction on effective stress; tests/verification/test_effective_friction.py,
benchmarks/pore_water/sliding_block.py).

The plane is the grid's floor and gravity is tilted by the slope angle beta, so the block slides along x.  A
block of saturated density rho_sat whose base carries the pore pressure p_b = lambda sigma_n slides, once
its base slips, with

    a = g (sin beta - (1 - lambda) mu cos beta)

(the base's shear force mu (N - p_b A) = mu (1 - lambda) N, N = rho_sat g cos beta H L; Iverson 1997,
Rev. Geophys. 35:245, eq. 2).  With the water table at the block's top and parallel to the plane (seepage
parallel to the slope) lambda = rho_w / rho_sat; an initial uniform excess pore pressure Delta p adds
Delta p / (rho_sat g cos beta H).  The block is undrained over the run (k = 1e-8 m/s: its consolidation
time H^2 gamma_w / (k M) is hours), so lambda holds while it slides.
"""

from __future__ import annotations

import math

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

#: slope angle [deg], basal friction coefficient [-], block length and height [m], porosity [-], grain
#: density [kg/m3], water density [kg/m3], gravity [m/s2]
BETA, MU, LENGTH, HEIGHT, POROSITY, RHO_S, RHO_W, G = 25.0, 0.6, 1.0, 0.2, 0.4, 2650.0, 1000.0, 9.81
RHO_SAT = (1.0 - POROSITY) * RHO_S + POROSITY * RHO_W


def block_lambda(excess: float = 0.0) -> float:
    """The base's pore-pressure ratio p_b / sigma_n of the block with the table at its top and a uniform
    excess [Pa]."""
    normal = RHO_SAT * G * math.cos(math.radians(BETA)) * HEIGHT
    return (RHO_W * G * math.cos(math.radians(BETA)) * HEIGHT + excess) / normal


def excess_for(lam: float) -> float:
    """The uniform excess pore pressure [Pa] that makes the base's ratio ``lam`` (block_lambda inverted)."""
    return (lam - block_lambda(0.0)) * RHO_SAT * G * math.cos(math.radians(BETA)) * HEIGHT


def closed_form(lam: float) -> float:
    """a = g (sin beta - (1 - lambda) mu cos beta) [m/s2], 0 where the block stands."""
    b = math.radians(BETA)
    return max(0.0, G * (math.sin(b) - (1.0 - lam) * MU * math.cos(b)))


def block_case(h: float, saturated: bool = True, excess: float = 0.0, end: float = 0.4,
               shape: str = "quadratic", transfer: str | None = None, periodic: bool = True) -> dict:
    """The block at cell size h: H = 0.2 m, the whole 2 m period long with ``periodic`` (the infinite slope's
    layer), else L = 1 m with free ends, E = 10 MPa, nu = 0.3, n = 0.4, rho_s = 2650 kg/m3 (its
    dry twin has the same mass per volume as the saturated block's skeleton plus water: rho_sat), k = 1e-8
    m/s, K_w = 2.2e7 Pa (reduced: the block's volume hardly changes, and the step is the undrained wave's),
    geostatic on the plane, the table at its top and parallel to it."""
    b = math.radians(BETA)
    soil = {"model": "linear_elastic", "density": RHO_S if saturated else RHO_SAT, "youngs_modulus": 10e6,
            "poisson_ratio": 0.3}
    if saturated:
        soil["pore_water"] = {"porosity": POROSITY, "hydraulic_conductivity": 1e-8,
                              "fluid": {"bulk_modulus": 2.2e7, "density": RHO_W}}
    x0, x1 = (0.0, 2.0) if periodic else (0.1, 0.1 + LENGTH)
    body = {"material": "soil", "geometry": {"type": "box", "min": [x0, 0.0], "max": [x1, HEIGHT]},
            "particles_per_cell": 2, "initial_stress": "geostatic", "surface_normal": [0.0, 1.0]}
    if saturated:
        body["pore_pressure"] = {"table_normal": [0.0, 1.0], "excess": excess}
        if excess:
            body["stress_offset"] = [excess, excess, excess, 0.0, 0.0, 0.0]  # the total stress unchanged
    case = {"name": "sliding_block", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [2.0, 0.4], "cell_size": h, "shape_function": shape},
            "time": {"end": end}, "gravity": [G * math.sin(b), -G * math.cos(b)],
            "materials": {"soil": soil}, "bodies": [body],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "friction", "friction": MU}]}
    if periodic:
        case["boundaries"].append({"type": "periodic", "axis": "x"})
    if transfer is not None:
        case["solver"] = {"transfer": transfer}
    return case


def block_acceleration(case: dict, start: float = 0.1) -> dict:
    """Run the block; its acceleration [m/s2] as the least-squares slope of its mean velocity along the plane
    over [start, end], and the base's measured pore-pressure ratio (the bottom row's mean p over its mean
    total normal stress) at the end."""
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    end = case["time"]["end"]
    t, v = [], []
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))
        if sim.time >= start:
            t.append(sim.time)
            v.append(float(np.average(st.p_v[:, 0], weights=st.p_mass)))
    slope = float(np.polyfit(t, v, 1)[0])
    out = {"h": case["grid"]["cell_size"], "acceleration": slope, "steps": sim.step_count,
           "speed": v[-1]}
    pore = getattr(st, "p_pore", None)
    if pore is not None:
        y0 = np.round(st.p_x0[:, 1], 9)
        base = y0 == y0.min()
        sigma_n = -st.p_stress[base, 1] + pore[base]
        out["lambda_base"] = float(pore[base].mean() / sigma_n.mean())
    return out
