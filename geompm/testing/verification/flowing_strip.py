"""A saturated Drucker-Prager layer flowing down a periodic strip of a 31 degree slope: the infinite slope in
motion (docs/pore-water.md, Friction on effective stress; benchmarks/pore_water/flowing_strip.py,
tests/verification/test_effective_friction.py).

The layer (H = 0.25 m, phi = 40 degrees, psi = 0, n = 0.4, k = 1e-5 m/s: undrained over the run) starts
geostatic in the slope's frame and hydrostatic below a slope-parallel table at its top, on a base of
friction tan 40 = 0.839.  Its base then slides with a = g (sin b - mu (1 - lambda) cos b) for the basal
ratio lambda = p_b / sigma_n it carries, and sigma_n stays the layer's weight rho_sat g cos b H.
"""

from __future__ import annotations

import math

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

BETA, MU, H, G = 31.0, 0.839, 0.25, 9.81
N0, RHO_S, RHO_W = 0.4, 2700.0, 1000.0


def strip_case(h: float, shape: str = "linear", transfer: str = "pic", end: float = 0.5) -> dict:
    b = math.radians(BETA)
    return {"name": "flowing_strip", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [1.0, 0.4], "cell_size": h, "shape_function": shape},
            "time": {"end": end, "cfl": 0.2}, "gravity": [G * math.sin(b), -G * math.cos(b)],
            "solver": {"transfer": transfer},
            "materials": {"debris": {"model": "drucker_prager", "density": RHO_S, "youngs_modulus": 5e6,
                                     "poisson_ratio": 0.3, "friction_angle": 40.0, "cohesion": 0.0,
                                     "dilation_angle": 0.0, "cone": "outer",
                                     "pore_water": {"porosity": N0, "hydraulic_conductivity": 1e-5,
                                                    "fluid": {"density": RHO_W, "bulk_modulus": 2e7,
                                                              "viscosity": 0.001}}}},
            "bodies": [{"material": "debris", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [1.0, H]},
                        "particles_per_cell": 2, "initial_stress": "geostatic", "surface_normal": [0.0, 1.0],
                        "pore_pressure": {"table_normal": [0.0, 1.0]}}],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "friction", "friction": MU},
                           {"type": "periodic", "axis": "x"}]}


def basal(st):
    """(lambda, p_b [Pa], sigma_n [Pa]) over the lowest row of particles."""
    base = st.p_x[:, 1] < st.p_x[:, 1].min() + 1e-6
    sig = -st.p_stress[base, 1] + st.p_pore[base]
    return float(st.p_pore[base].mean() / sig.mean()), float(st.p_pore[base].mean()), float(sig.mean())


def flow(h: float, shape: str = "linear", transfer: str = "pic", t0: float = 0.1, t1: float = 0.5) -> dict:
    """The layer's mean acceleration between t0 and t1 against g (sin b - mu (1 - lambda) cos b) with its
    mean basal lambda over the same interval; sigma_n of the lowest row against the weight above it."""
    sim = Simulation(scene_from_dict(strip_case(h, shape, transfer, t1)))
    st = sim.state
    lam0 = basal(st)[0]
    samples, v0 = [], None
    while sim.time < t1 - 1e-12:
        sim.step(min(sim.stable_dt(), t1 - sim.time))
        if v0 is None and sim.time >= t0:
            v0, ta = float(st.p_v[:, 0].mean()), sim.time
        if v0 is not None:
            samples.append(basal(st))
    a = (float(st.p_v[:, 0].mean()) - v0) / (sim.time - ta)
    lam = float(np.mean([s[0] for s in samples]))
    b = math.radians(BETA)
    expected = G * (math.sin(b) - MU * (1.0 - lam) * math.cos(b))
    depth = H - float(st.p_x[:, 1].min())  # the lowest row's depth below the layer's top
    weight = ((1.0 - N0) * RHO_S + N0 * RHO_W) * G * math.cos(b) * depth
    return {"h": h, "lambda_start": lam0, "lambda": lam, "acceleration": a, "expected": expected,
            "a_error": a / expected - 1.0, "sigma_n": float(np.mean([s[2] for s in samples])), "weight": weight,
            "sigma_error": float(np.mean([s[2] for s in samples])) / weight - 1.0}
