"""The impulse an obstacle records is the momentum the material lost to it, and a probe reads a known flow.

Momentum balance (no gravity, no damping, no other boundary): a block thrown at a rigid wall loses to it
exactly the momentum the wall's recorded vector impulse J holds, J + sum m_p v_p(t) = sum m_p v_p(0), for
APIC (its transfers conserve momentum), whatever the block's law does in the impact (a wrong sign, a
missing guard correction, a force counted twice or a step's dt mis-weighted breaks it).  The probe of a
block at rest or in uniform translation reads its height and speed exactly when the strip holds whole
particle columns (probes/section.py)."""

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation


def _case(law, end=0.45):
    mat = {"linear_elastic": {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 2e6,
                              "poisson_ratio": 0.3},
           "drucker_prager": {"model": "drucker_prager", "density": 2000.0, "youngs_modulus": 2e6,
                              "poisson_ratio": 0.3, "friction_angle": 35.0, "cohesion": 0.0,
                              "dilation_angle": 0.0}}[law]
    return {
        "name": "throw", "dimension": 2,
        "grid": {"origin": [0.0, -0.5], "extent": [2.0, 2.0], "cell_size": 0.05},
        "time": {"end": end, "cfl": 0.4}, "gravity": [0.0, 0.0],
        "solver": {"transfer": "apic", "update": "usl"},
        "materials": {"block": mat},
        "bodies": [{"material": "block", "geometry": {"type": "box", "min": [0.3, 0.35], "max": [0.8, 0.65]},
                    "velocity": [2.0, 0.0], "particles_per_cell": 2}],
        "obstacles": [{"type": "box", "name": "wall", "min": [1.2, -0.4], "max": [1.3, 1.4], "condition": "slip",
                       "probe": "gauge"}],
        "probes": [{"name": "gauge", "point": [0.5, 0.0], "half_width": 0.05, "direction": [0.0, 1.0]}],
    }


@pytest.mark.parametrize("law", ["linear_elastic", "drucker_prager"])
def test_the_recorded_impulse_is_the_momentum_lost(law):
    sim = Simulation(scene_from_dict(_case(law)))
    st = sim.state
    p0 = (st.p_mass[:, None] * st.p_v).sum(axis=0)
    while sim.time < 0.45:
        sim.step(sim.stable_dt())
    wall = sim.scene.obstacles[0]
    J = wall.impact.J
    p1 = (st.p_mass[:, None] * st.p_v).sum(axis=0)
    assert J[0] > 0.5 * p0[0]  # the block did hit the wall (0.2 s of flight, then contact)
    assert J + p1 == pytest.approx(p0, abs=1e-9 * abs(p0[0]))
    rep = wall.impact_report()
    assert rep["first_contact"] == pytest.approx(0.4 / 2.0 - 0.05 / 2.0 / 2.0, abs=0.03)  # the nodes a cell out
    assert rep["impulse"] >= np.linalg.norm(J) * (1 - 1e-12)  # int |F| dt >= |int F dt|


def test_a_probe_reads_the_block_it_stands_in():
    """A 0.5 x 0.3 m block moving at 2 m/s, four whole particle columns in the strip |x - 0.5| <= 0.05 m: after
    one step the probe reads depth 0.3 m, speed 2 m/s and density 2000 kg/m3 (to round-off)."""
    sim = Simulation(scene_from_dict(_case("linear_elastic")))
    sim.step(sim.stable_dt())
    depth, speed, rho = sim.scene.probes[0].reading
    assert depth == pytest.approx(0.3, rel=1e-12)
    assert speed == pytest.approx(2.0, rel=1e-9)
    assert rho == pytest.approx(2000.0, rel=1e-12)
    row = sim.series_row()
    assert row["gauge_depth"] == pytest.approx(0.3, rel=1e-12) and row["gauge_q"] == pytest.approx(0.6, rel=1e-9)
