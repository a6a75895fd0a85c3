"""A saturated soil column fed from below by a wall that holds a head (schemes/saturated/head.py).

A column of soil L = 1 m tall and 0.2 m wide (linear elastic skeleton, E = 20 MPa, n = 0.4, water of
K_w = 20 MPa) stands on a fixed base that holds the water's level H; its sides are impermeable slip walls and its
top a free surface (p = 0).  Once steady, the head falls linearly through the column from H at the base to the
top's elevation L (Darcy's law, homogeneous k), so that

    p(z) = rho_w g (H - (H - L) z / L - z),        discharge q = k (H - L) / L   (upward),

with no flow and a hydrostatic p = rho_w g (L - z) when H = L.  The consolidation coefficient
c_v = k / (gamma_w (1 / M + n / K_w)) (docs/pore-water.md) sets the time to steady state, L^2 / c_v: 0.55 s
for k = 1e-3 m/s.
"""

from __future__ import annotations

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

L, W, RHO_W, G = 1.0, 0.2, 1000.0, 9.81
#: heights [m] at which the profile is compared: the particles within a quarter cell of each
HEIGHTS = (0.1, 0.25, 0.5, 0.75)


def column_case(h: float, k: float, head, times=(0.0,), end: float = 0.6) -> dict:
    """The column at cell size ``h`` [m], hydraulic conductivity ``k`` [m/s], the base's head ``head`` [m]
    (one value or one per ``times``)."""
    wall = {"type": "wall", "side": "y-", "condition": "fixed", "drainage": "head",
            "head": list(head) if np.ndim(head) else float(head)}
    if np.ndim(head):
        wall["head_times"] = list(times)
    return {
        "name": "head_column", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [W, L + 4 * h], "cell_size": h},
        "time": {"end": end}, "gravity": [0.0, -G],
        "materials": {"soil": {"model": "linear_elastic", "density": 2650.0, "youngs_modulus": 2.0e7,
                               "poisson_ratio": 0.3,
                               "pore_water": {"porosity": 0.4, "hydraulic_conductivity": k,
                                              "fluid": {"bulk_modulus": 2.0e7}}}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [W, L]},
                    "initial_stress": "geostatic"}],
        "boundaries": [{"type": "wall", "side": "x-", "condition": "slip"},
                       {"type": "wall", "side": "x+", "condition": "slip"}, wall],
        "damping": [{"model": "local", "alpha": 0.3}], "outputs": [],
    }


def steady_pressure(z, head: float) -> np.ndarray:
    """Closed-form steady pore pressure [Pa] at heights z for the base's head ``head``."""
    return RHO_W * G * (head - (head - L) * np.asarray(z) / L - np.asarray(z))


def run_column(h: float, k: float, head, times=(0.0,), end: float = 0.6) -> dict:
    """Run the column; the mean pore pressure of the particles within a quarter cell of each of HEIGHTS, its
    closed form at the final head and the relative errors, and the discharge: the water's mean flux
    n (v_w - v_s) over the particles between 0.3 and 0.7 m against k (H - L) / L."""
    sim = Simulation(scene_from_dict(column_case(h, k, head, times, end)))
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))
    st = sim.state
    y = st.p_x[:, 1]
    final = float(head[-1]) if np.ndim(head) else float(head)
    measured = np.array([st.p_pore[np.abs(y - z) < 0.26 * h].mean() for z in HEIGHTS])
    closed = steady_pressure(np.array([y[np.abs(y - z) < 0.26 * h].mean() for z in HEIGHTS]), final)
    middle = (y > 0.3) & (y < 0.7)
    flux = float((st.p_n[middle] * (st.p_vw[middle, 1] - st.p_v[middle, 1])).mean())
    return {"h": h, "k": k, "head": final, "measured": measured, "closed": closed,
            "error": measured / closed - 1.0, "flux": flux, "flux_closed": k * (final - L) / L}
