"""A saturated run resumes from its checkpoint exactly (engine/checkpoint.py; docs/pore-water.md): the water's
velocity and affine matrix, the acting and the carried pore pressure and the drained flags are particle
state and must all be saved; one left out changes the resumed run at the first step."""

import json

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine import checkpoint
from geompm.engine.scheduler import Simulation

CASE = {"name": "saturated_restart", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 0.8], "cell_size": 0.1},
        "time": {"end": 1.0}, "gravity": [0.0, -9.81], "solver": {"sort_interval": 1},
        "materials": {"soil": {"model": "drucker_prager", "density": 2650.0, "youngs_modulus": 2e6,
                               "poisson_ratio": 0.3, "friction_angle": 30.0,
                               "pore_water": {"porosity": 0.4, "hydraulic_conductivity": 1e-3,
                                              "fluid": {"bulk_modulus": 2e7}}}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [0.3, 0.3]},
                    "particles_per_cell": 2, "velocity": [1.0, 0.0]}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "friction", "friction": 0.4},
                       {"type": "wall", "side": "x+", "condition": "slip", "drainage": "drained"}]}


def stepped(sim, n):
    for _ in range(n):
        sim.step(sim.stable_dt())
    return sim


def test_a_saturated_run_resumes_exactly(tmp_path):
    """20 steps in one go against 10 steps, a checkpoint, and 10 more in a new simulation (a spatial sort
    every step): every saturated array equal to the last bit (measured 0), with pore pressures of tens of
    kPa, so the comparison is not between zeros."""
    full = stepped(Simulation(scene_from_dict(json.loads(json.dumps(CASE)))), 20)
    first = stepped(Simulation(scene_from_dict(json.loads(json.dumps(CASE)))), 10)
    checkpoint.save(tmp_path, first, {}, [])
    resumed = Simulation(scene_from_dict(json.loads(json.dumps(CASE))))
    checkpoint.restore(resumed, *checkpoint.load(tmp_path))
    stepped(resumed, 10)
    a, b = full.state, resumed.state
    assert float(np.abs(a.p_pore).max()) > 1e3
    for name in ("p_x", "p_v", "p_stress", "p_vw", "p_Cw", "p_pore", "p_pore_carried", "p_drained", "p_n"):
        x, y = getattr(a, name)[np.argsort(a.p_id)], getattr(b, name)[np.argsort(b.p_id)]
        assert np.array_equal(x, y), (name, float(np.abs(x - y).max()))
