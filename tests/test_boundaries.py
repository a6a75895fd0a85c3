"""Rigid boundaries with Coulomb friction, against rigid-body closed forms.

Block on an incline (shared/refdata/analytic_block_on_incline.csv): a block
released on a plane at theta with friction mu slides iff tan(theta) > mu, with
a = g (sin theta - mu cos theta) and s(t) = a t^2 / 2.  Block sliding on a
horizontal friction floor at v0: it stops after v0^2 / (2 mu g).
"""

import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

G = 9.81


def _incline_case(mu, theta=30.0):
    th = math.radians(theta)
    t = np.array([math.cos(th), -math.sin(th)])  # down the slope
    n = np.array([math.sin(th), math.cos(th)])  # out of the bed
    p0 = np.array([0.2, 1.6])
    a, b = p0 + 0.2 * t, p0 + 0.6 * t
    verts = [a, b, b + 0.2 * n, a + 0.2 * n]
    return {
        "name": "incline", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [3.0, 2.0], "cell_size": 0.05},
        "time": {"end": 0.5, "cfl": 0.4}, "gravity": [0.0, -G],
        "materials": {"block": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e7,
                                "poisson_ratio": 0.2}},
        "bodies": [{"material": "block", "geometry": {"type": "polygon", "vertices": [list(v) for v in verts]},
                    "particles_per_cell": 2}],
        "boundaries": [{"type": "plane", "point": list(p0), "normal": list(n), "condition": "friction",
                        "friction": mu}],
    }, t


def _run(case, end):
    sim = Simulation(scene_from_dict(case))
    while sim.time < end:
        sim.step(min(sim.stable_dt(), end - sim.time))
    return sim


@pytest.mark.parametrize("mu", [0.0, 0.2, 0.3])
def test_block_slides_down_the_incline(mu):
    case, t = _incline_case(mu)
    sim = _run(case, 0.5)
    st = sim.state
    s = float(((st.p_x - st.p_x0) @ t).mean())
    a = G * (math.sin(math.radians(30)) - mu * math.cos(math.radians(30)))
    assert s == pytest.approx(a * 0.5 ** 2 / 2, rel=0.03), f"mu={mu}: s={s:.4f} m, exact {a * 0.125:.4f} m"


@pytest.mark.xfail(strict=True, reason=(
    "known deficiency (issue 4 open): with mu = 0.7 > tan 30 deg the block creeps 19 mm in 0.5 s under USL "
    "(1.8 mm under MUSL) instead of < 0.5 mm; nodes behind the plane lose friction whenever their normal "
    "velocity turns outward, so contact is intermittent. Linear basis: the run blows up."))
def test_block_stays_when_friction_exceeds_tan_theta():
    case, t = _incline_case(0.7)  # tan 30 deg = 0.577
    sim = _run(case, 0.5)
    st = sim.state
    s = float(np.abs((st.p_x - st.p_x0) @ t).mean())
    assert s < 0.01 * 0.05, f"displacement along the slope {s:.2e} m"


def test_block_on_friction_floor_stops_at_v0_squared_over_2_mu_g():
    mu, v0 = 0.3, 2.0
    case = {
        "name": "slide", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [2.0, 0.5], "cell_size": 0.025},
        "time": {"end": 1.0, "cfl": 0.4}, "gravity": [0.0, -G],
        "materials": {"block": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e7,
                                "poisson_ratio": 0.2}},
        "bodies": [{"material": "block", "geometry": {"type": "box", "min": [0.1, 0.0], "max": [0.3, 0.1]},
                    "particles_per_cell": 2, "velocity": [v0, 0.0], "initial_stress": "geostatic"}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "friction", "friction": mu}],
    }
    sim = _run(case, 1.0)
    st = sim.state
    travel = float((st.p_x[:, 0] - st.p_x0[:, 0]).mean())
    assert travel == pytest.approx(v0 ** 2 / (2 * mu * G), rel=0.05)
    assert np.abs(st.p_v[:, 0]).max() < 0.01 * v0  # stopped, not sliding back
