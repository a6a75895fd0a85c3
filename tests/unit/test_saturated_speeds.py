"""The saturated scheme's stable step from its three waves (schemes/saturated/speeds.py), and a particle out
of range stopping the run rather than the interpreter."""

from __future__ import annotations

import json
import math

import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.errors import SimulationError
from tests.support.cases import CASES


def _terzaghi():
    return Simulation(scene_from_dict(json.loads((CASES / "terzaghi_consolidation.json").read_text()),
                                      base_dir=CASES))


def test_the_step_is_the_undrained_wave_of_the_case():
    """Terzaghi's case at rest: c_u = sqrt((M + K_w / n) / rho_sat) with M = rho_d c_s^2 of the elastic
    skeleton (E = 98 MPa, nu = 0.3 on the dry density), K_w and n from the case: the step is cfl h / c_u."""
    sim = _terzaghi()
    case = json.loads((CASES / "terzaghi_consolidation.json").read_text())
    soil = case["materials"]["soil"]
    pw = soil["pore_water"]
    e, nu, n = soil["youngs_modulus"], soil["poisson_ratio"], pw["porosity"]
    kw = pw["fluid"]["bulk_modulus"]
    rho_s, rho_w = soil["density"], pw["fluid"].get("density", 1000.0)
    m = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    c_u = math.sqrt((m + kw / n) / ((1 - n) * rho_s + n * rho_w))
    dt = case["time"]["cfl"] * case["grid"]["cell_size"] / c_u
    assert sim.stable_dt() == pytest.approx(dt, rel=1e-6)


@pytest.mark.parametrize("field, value", [("p_rho", -1000.0), ("p_n", -0.1)])
def test_a_crushed_particle_stops_the_run_naming_it(field, value):
    """A particle whose density or porosity left its range (a saturated density below zero, a negative
    porosity, as after a blow-up) makes the undrained wave speed imaginary: the step raises SimulationError
    (exit 3) naming the material and that particle's id, where math.sqrt raised a ValueError before."""
    sim = _terzaghi()
    st = sim.state
    getattr(st, field)[7] = value
    with pytest.raises(SimulationError) as err:
        sim.stable_dt()
    text = str(err.value)
    assert "material 'soil'" in text and f"particle {int(st.p_id[7])}" in text
