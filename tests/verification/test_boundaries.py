"""Rigid boundaries with Coulomb friction, against rigid-body closed forms.

Block on an incline (tests/refdata/analytic_block_on_incline.csv): a block
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


@pytest.mark.parametrize("mu, layer", [(0.7, 0.0), (0.62, 0.05)])
def test_block_stays_when_friction_exceeds_tan_theta(mu, layer):
    """mu > tan 30 deg = 0.577: the block sticks (rigid-body statics, tests/refdata
    analytic_block_on_incline.csv), displacement < 1% of a cell after 0.5 s.

    The block starts in equilibrium, as a block at rest does: the infinite-slope
    geostatic stress (``surface_normal`` = the bed normal, bed-parallel shear
    included), and runs MUSL.  Measured margins (docs/method.md, "Frictional
    contact"): with contact_layer 0 it sticks from mu = 0.68 (0.65 creeps 7 mm);
    with a layer of one cell from mu = 0.62 at least.  Under USL the mu = 0.7 block
    creeps 18 mm: the light nodes behind the plane keep a normal vibration that
    switches friction off.  From zero stress under MUSL it creeps 1.8 mm.
    """
    case, t = _incline_case(mu)
    body = case["bodies"][0]
    body["initial_stress"] = "geostatic"
    body["surface_normal"] = case["boundaries"][0]["normal"]
    case["boundaries"][0]["contact_layer"] = layer
    case["solver"] = {"update": "musl"}
    sim = _run(case, 0.5)
    st = sim.state
    s = float(np.abs((st.p_x - st.p_x0) @ t).mean())
    assert s < 0.01 * 0.05, f"displacement along the slope {s:.2e} m"
    assert float(np.abs(st.p_v).max()) < 1e-3  # at rest at the end, not sliding slowly


def test_geostatic_stress_on_a_slope_is_the_infinite_slope_solution():
    """With ``surface_normal`` n at 30 deg, the stress at depth z below the block's top
    satisfies sigma n = rho g z (the infinite-slope stress, e.g. Duncan, Wright & Brandon
    2014, Soil Strength and Slope Stability, ch. 6: sigma_nn = -rho g z cos theta,
    bed-parallel shear rho g z sin theta), sampled at the block's mid-length, within half
    a particle spacing of overburden."""
    case, t = _incline_case(0.7)
    n = np.array(case["boundaries"][0]["normal"])
    case["bodies"][0].update(initial_stress="geostatic", surface_normal=list(n))
    st = scene_from_dict(case).state
    sig = np.zeros((st.n, 2, 2))
    sig[:, 0, 0], sig[:, 1, 1], sig[:, 0, 1], sig[:, 1, 0] = (st.p_stress[:, 0], st.p_stress[:, 1],
                                                              st.p_stress[:, 3], st.p_stress[:, 3])
    along = (st.p_x - np.array([0.2, 1.6])) @ t
    mid = np.abs(along - 0.4) < 0.05
    depth = 0.2 - (st.p_x[mid] - np.array([0.2, 1.6])) @ n
    traction = np.einsum("pij,j->pi", sig[mid], n)
    expected = 1000.0 * depth[:, None] * np.array([0.0, -G])
    # the lattice is at 30 deg to the surface: each column's top particle lies 0..s below it (s = 25 mm)
    tol = 1000.0 * G * 0.025 / 2
    assert np.abs(traction[:, 0]).max() < 1e-9 * tol  # sigma n carries the weight only: vertical
    assert np.abs(traction - expected).max() < tol
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert np.abs(traction @ n + 1000.0 * G * depth * c).max() < tol  # sigma_nn = -rho g z cos theta
    # sigma_tn = +rho g z sin theta: the material below pushes the part above up-slope, sigma (-n)
    assert np.abs(traction @ t - 1000.0 * G * depth * s).max() < tol
    assert np.abs(traction @ t).max() > 0.4 * 1000.0 * G * 0.2 * s  # the shear is there (not level-ground K0)


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
