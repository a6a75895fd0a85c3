"""Plane-strain biaxial (unconfined) compression of a dilatant soil sample, and its dilation rate.

A 0.1 m x 0.2 m sample (c = 10 kPa, phi = 30 deg, E = 10 MPa, nu = 0.3, rho 2000 kg/m3,
no gravity) stands on a slip floor and is compressed by a rigid slip plate moving down at
0.05 m/s (axial strain rate 0.25 /s; the loading time to yield is 50 times the P-wave transit
time, so the test is quasi-static). It yields at the plane-strain unconfined strength
2 c cos(phi) / (1 - sin(phi)) = 34.6 kPa and then flows at constant load.

Closed form (Vermeer & de Borst 1984, Heron 29(3), sec. 2; the definition of psi in plane
strain): in steady plastic flow the elastic strain rates vanish, so each yielding point deforms
with
    tr(D) / gamma_max = sin(psi),   gamma_max = sqrt((D_xx - D_yy)^2 + (2 D_xy)^2),
for Mohr-Coulomb and for Drucker-Prager matched to it in plane strain
(alpha = tan(phi) / sqrt(9 + 12 tan^2 phi), beta the same with psi; docs/numerical-envelope.md derives it).
Perfect plasticity localises (Vermeer 1990, Geotechnique 40(2):223): the upper part of the sample
shears while the lower part stays elastic, so the dilation rate is measured where the soil yields,
not from the sample's outline: the volume-weighted sums of tr(D) dt and gamma_max dt over the
particles whose plastic strain grew in the step and whose stress is off the apex, from an axial
strain of 1.5 % (past the peak) to 3.75 %.

    python tests/envelope/biaxial.py [drucker_prager|mohr_coulomb] PSI H [H ...]
"""

from __future__ import annotations

import math
import sys

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

WIDTH, HEIGHT, PLATE_SPEED, COHESION = 0.1, 0.2, 0.05, 1.0e4
AXIAL_END = 0.0375


def biaxial_case(model: str, psi: float, h: float) -> dict:
    mat = {"model": model, "density": 2000.0, "youngs_modulus": 1.0e7, "poisson_ratio": 0.3,
           "friction_angle": 30.0, "cohesion": COHESION, "dilation_angle": psi}
    if model == "drucker_prager":
        mat["cone"] = "plane_strain"
    return {
        "name": "biaxial", "dimension": 2,
        "grid": {"origin": [-0.1, 0.0], "extent": [0.3, 0.3], "cell_size": h},
        "time": {"end": AXIAL_END * HEIGHT / PLATE_SPEED, "cfl": 0.4}, "gravity": [0.0, 0.0],
        # the probe compares per-particle arrays across each step: no spatial sort in between
        "solver": {"sort_interval": 0},
        "materials": {"soil": mat},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [WIDTH, HEIGHT]},
                    "particles_per_cell": 2}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "slip"}],
        "obstacles": [{"type": "box", "name": "plate", "min": [-0.1, HEIGHT], "max": [0.2, HEIGHT + 0.05],
                       "velocity": [0.0, -PLATE_SPEED], "condition": "slip"}],
        "outputs": [],
    }


def dilation_rate(model: str, psi: float, h: float, from_strain: float = 0.015) -> tuple[float, float]:
    """(measured tr(D) / gamma_max in the yielding soil, the plate's force per metre over the
    sample's current width at the end [Pa])."""
    scene = scene_from_dict(biaxial_case(model, psi, h))
    sim = Simulation(scene)
    st = sim.state
    eps_p = st.p_state[0][:, 0]
    vol_sum = shear_sum = 0.0
    t_from = from_strain * HEIGHT / PLATE_SPEED
    while sim.time < scene.end_time * (1 - 1e-12):
        before = eps_p.copy()
        dt = min(sim.stable_dt(), scene.end_time - sim.time)
        sim.step(dt)
        if sim.time < t_from:
            continue
        s = st.p_stress
        mean = s[:, :3].mean(axis=1)
        sqrt_j2 = np.sqrt(0.5 * ((s[:, :3] - mean[:, None]) ** 2).sum(axis=1) + (s[:, 3:] ** 2).sum(axis=1))
        flowing = (eps_p > before) & (sqrt_j2 > 1e-3 * COHESION)  # yielding, not at the apex (separation)
        L, vol = st.p_L[flowing], st.p_vol[flowing]
        vol_sum += float((vol * (L[:, 0, 0] + L[:, 1, 1])).sum()) * dt
        shear_sum += float((vol * np.hypot(L[:, 0, 0] - L[:, 1, 1], L[:, 0, 1] + L[:, 1, 0])).sum()) * dt
    width = float(st.p_x[:, 0].max() - st.p_x[:, 0].min()) + h / 2  # particle centres are h/4 inside each face
    return vol_sum / shear_sum, abs(sim.series_row()["plate_fy"]) / width


if __name__ == "__main__":
    law, psi_deg = sys.argv[1], float(sys.argv[2])
    print(f"{law}, psi = {psi_deg} deg: sin(psi) = {math.sin(math.radians(psi_deg)):.5f}")
    for cell in map(float, sys.argv[3:]):
        rate, stress = dilation_rate(law, psi_deg, cell)
        print(f"h = {cell}: tr(D)/gamma_max = {rate:.5f}, error {rate - math.sin(math.radians(psi_deg)):+.5f}, "
              f"plate stress {stress:.0f} Pa against {2 * COHESION * math.cos(math.radians(30)) / (1 - 0.5):.0f}")
