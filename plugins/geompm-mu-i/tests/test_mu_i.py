"""Tests of the mu(I) plugin: found by geompm, conformant, and the rheology's defining relation.

Reference: Jop, Forterre & Pouliquen (2006) Nature 441:727, eq. for mu(I):
in steady simple shear at pressure p, the shear stress is |tau| = mu(I) p with
I = gamma_dot d / sqrt(p / rho_s).
"""

import math

import numpy as np
import pytest

from geompm.contract import registry
from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing import check_material, update_stress
from geompm_mu_i import MuI


def test_found_through_its_entry_point():
    info = registry.available("materials")["mu_i"]
    assert info.plugin is MuI and info.package == "geompm-mu-i"


def test_conformance():
    check_material(MuI)


@pytest.mark.parametrize("gdot", [1e-3, 1e-1, 1.0, 10.0, 100.0, 1000.0])
def test_steady_simple_shear_follows_mu_of_i(gdot):
    mat = MuI(MuI.example_params())
    p = 2.0e3
    n = 1
    stress = np.zeros((n, 6))
    stress[:, :3] = -p
    state = mat.initial_state(n)
    L = np.zeros((n, 3, 3))
    L[:, 0, 1] = gdot
    dt = 0.05 / gdot / 400  # 5% shear strain in 400 steps: far past the elastic range
    for _ in range(400):
        update_stress(mat, dt, L, np.full(n, 1500.0), stress, state)
    prm = mat.params
    inertial = gdot * prm.grain_diameter / math.sqrt(p / prm.grain_density)
    mu = prm.friction_static + (prm.friction_limit - prm.friction_static) / (prm.inertial_number_ref / inertial + 1)
    s = stress[0]
    tau = math.sqrt(0.5 * ((s[:3] - s[:3].mean()) ** 2).sum() + (s[3:] ** 2).sum())
    assert -s[:3].mean() == pytest.approx(p, rel=1e-9)  # simple shear is isochoric
    assert tau / p == pytest.approx(mu, rel=1e-6)
    assert state[0, 0] == pytest.approx(inertial, rel=1e-12)


def test_no_tension():
    mat = MuI(MuI.example_params())
    stress, state = np.zeros((1, 6)), mat.initial_state(1)
    update_stress(mat, 1e-3, np.eye(3)[None].copy(), np.full(1, 1500.0), stress, state)
    assert np.all(stress == 0.0)


def test_granular_block_on_the_floor_comes_to_rest():
    """A mu_i block released on a slip floor spreads and stops: kinetic energy < 1e-3 of its peak."""
    case = {
        "name": "mu_i_block", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [0.6, 0.2], "cell_size": 0.01},
        "time": {"end": 1.0}, "gravity": [0.0, -9.81],
        "materials": {"beads": {"model": "mu_i", **MuI.example_params().model_dump()}},
        "bodies": [{"material": "beads", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [0.1, 0.1]}}],
        "boundaries": [{"type": "wall", "side": "x-", "condition": "slip"},
                       {"type": "wall", "side": "y-", "condition": "friction", "friction": 0.4}],
    }
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    peak = ke = 0.0
    while sim.time < 1.0:
        sim.step(min(sim.stable_dt(), 1.0 - sim.time))
        ke = 0.5 * float((st.p_mass * (st.p_v ** 2).sum(axis=1)).sum())
        peak = max(peak, ke)
    assert ke < 1e-3 * peak
    runout = st.p_x[:, 0].max()
    assert 0.11 < runout < 0.4  # it spread beyond the 0.1 m column, and stopped well inside the box
