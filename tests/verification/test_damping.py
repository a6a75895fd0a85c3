"""Artificial (source eqs. 7-8) and Cundall local damping, in small scenes.

Artificial: a free body (no gravity, no stress gradient) keeps a uniform velocity
under APIC, so with damping it decays as exp(-zeta_d t), zeta_d = (xi/h) sqrt(E/rho).
Local: an elastic column under gravity between slip walls, started stress-free,
settles to the static state sigma_v = -rho g (H - z) (tests/refdata/
analytic_selfweight_column_K0.csv) instead of oscillating about it.
"""

import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation


def _block(damping, gravity=(0.0, 0.0), velocity=(1.0, 0.5), end=0.5):
    return {
        "name": "block", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [4.0, 4.0], "cell_size": 0.1},
        "time": {"end": end}, "gravity": list(gravity),
        "materials": {"m": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e5,
                            "poisson_ratio": 0.2}},
        "bodies": [{"material": "m", "geometry": {"type": "box", "min": [1.0, 1.0], "max": [1.5, 1.5]},
                    "velocity": list(velocity)}],
        "damping": damping,
    }


def test_artificial_damping_decays_velocity_exponentially():
    xi = 0.002
    sim = Simulation(scene_from_dict(_block([{"model": "artificial", "xi": xi}])))
    zeta = xi / 0.1 * math.sqrt(1.0e5 / 1000.0)  # 0.2 1/s
    while sim.time < 2.0:
        sim.step(min(sim.stable_dt(), 2.0 - sim.time))
    v = sim.state.p_v.mean(axis=0)
    expected = np.array([1.0, 0.5]) * math.exp(-zeta * 2.0)
    np.testing.assert_allclose(v, expected, rtol=0.01)
    assert abs(v[0] / 1.0 - math.exp(-zeta * 2.0)) < 1e-6  # in fact exact up to round-off
    assert np.ptp(sim.state.p_v[:, 0]) < 1e-7  # still a rigid translation (round-off only)


def test_artificial_damping_reference_cell_size_fixes_the_rate():
    """With reference_cell_size h_ref, zeta_d = (xi/h_ref) sqrt(E/rho) at any h: the velocity decays as
    exp(-zeta_d t) with the same zeta_d (0.2 1/s) at h = 0.1 and 0.05 m, where eq. 8 alone would double it."""
    xi, t_end = 0.002, 1.0
    zeta = xi / 0.1 * math.sqrt(1.0e5 / 1000.0)
    for h in (0.1, 0.05):
        case = _block([{"model": "artificial", "xi": xi, "reference_cell_size": 0.1}])
        case["grid"]["cell_size"] = h
        sim = Simulation(scene_from_dict(case))
        while sim.time < t_end:
            sim.step(min(sim.stable_dt(), t_end - sim.time))
        assert sim.state.p_v[:, 0].mean() == pytest.approx(math.exp(-zeta * t_end), rel=1e-6)


def test_artificial_damping_selects_materials():
    case = _block([{"model": "artificial", "xi": 0.002, "materials": ["m"]}])
    case["materials"]["other"] = dict(case["materials"]["m"])
    case["bodies"].append({"material": "other", "geometry": {"type": "box", "min": [2.5, 2.5], "max": [3.0, 3.0]},
                           "velocity": [1.0, 0.5]})
    sim = Simulation(scene_from_dict(case))
    for _ in range(50):
        sim.step(sim.stable_dt())
    st = sim.state
    names = sim.scene.material_names
    (a, b), (c, d) = st.blocks[names.index("m")], st.blocks[names.index("other")]
    assert st.p_v[a:b, 0].mean() < 0.999 and st.p_v[c:d, 0].mean() == pytest.approx(1.0, abs=1e-12)


def test_local_damping_reaches_static_equilibrium():
    rho, E, nu, H, g = 2000.0, 1.0e6, 0.3, 1.0, 9.81
    case = {
        "name": "column", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [0.4, 1.2], "cell_size": 0.05},
        "time": {"end": 1.0}, "gravity": [0.0, -g],
        "materials": {"soil": {"model": "linear_elastic", "density": rho, "youngs_modulus": E, "poisson_ratio": nu}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [0.4, H]}}],
        "boundaries": [{"type": "wall", "side": s, "condition": "slip"} for s in ("x-", "x+", "y-")],
        "damping": [{"model": "local", "alpha": 0.8}],
    }
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    period = 4 * H / math.sqrt(M / rho)
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    ke_peak = 0.0
    while sim.time < 10 * period:
        sim.step(sim.stable_dt())
        ke_peak = max(ke_peak, 0.5 * float((st.p_mass * (st.p_v ** 2).sum(axis=1)).sum()))
    ke = 0.5 * float((st.p_mass * (st.p_v ** 2).sum(axis=1)).sum())
    assert ke < 1e-4 * ke_peak
    # vertical stress of the interior particles (away from the free top and the floor) within 5% of rho g depth
    depth = H - st.p_x0[:, 1]
    inner = (depth > 0.2) & (depth < 0.8)
    sv = -rho * g * depth[inner]
    err = np.abs(st.p_stress[inner, 1] - sv).max() / (rho * g * H)
    assert err < 0.05, f"max sigma_v error {err:.3f} of rho g H"
    np.testing.assert_allclose(st.p_stress[inner, 0].mean() / st.p_stress[inner, 1].mean(), nu / (1 - nu), rtol=0.05)
