"""The water table (schema triggers.water_table, mpm/water_table.py, kernels/phreatic.py).

Its pore pressure must be hydrostatic under a level table, p = rho_w |g| (z_wt - z), and under a table
parallel to a slope of angle beta the pressure of slope-parallel seepage, gamma_w z cos^2(beta) at vertical
depth z (Skempton & DeLory 1957; Duncan, Wright & Brandon 2014, Soil Strength and Slope Stability, sec. 6.2);
zero above the table and on soils it does not name.  The geostatic stress under it must be effective,
sigma'_v = (rho - rho_w) g depth, sigma'_h = K0 sigma'_v (Terzaghi's principle with the layer's total weight),
and a layer so initialised must stay at rest: the grid sees sigma' - p I.  Bad input is refused with its
JSON path before any work."""

import math

import numpy as np
import pytest

from geompm.mpm.water_table import NO_WATER_TABLE
from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.errors import CaseError
from geompm.kernels.phreatic import pore_work
from geompm.mpm.water_table import WaterTable
from geompm.schema.load import parse_case
from geompm.writers.vtu import particle_fields

RHO, RHO_W, G = 2000.0, 1000.0, 9.81


def layer_case(table=2.0, times=(0.0,), **water) -> dict:
    """A level layer 1 m wide and 2 m deep of Drucker-Prager soil (rho = 2000 kg/m3, nu = 0.3) on a fixed
    base between slip walls, h = 0.1 m, geostatic, under a water table at ``table`` [m]."""
    heights = list(table) if isinstance(table, (list, tuple)) else [table] * len(times)
    return {
        "name": "layer", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 2.4], "cell_size": 0.1, "shape_function": "linear"},
        "time": {"end": 1.0, "cfl": 0.4}, "gravity": [0.0, -G],
        "materials": {"soil": {"model": "drucker_prager", "density": RHO, "youngs_modulus": 2e7,
                               "poisson_ratio": 0.3, "friction_angle": 30.0, "cohesion": 0.0,
                               "dilation_angle": 0.0}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [1.0, 2.0]},
                    "particles_per_cell": 2, "initial_stress": "geostatic"}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "fixed"},
                       {"type": "wall", "side": "x-", "condition": "slip"},
                       {"type": "wall", "side": "x+", "condition": "slip"}],
        "triggers": {"water_table": {"times": list(times), "heights": heights, **water}},
        "outputs": [],
    }


def test_level_table_gives_hydrostatic_pressure_and_none_above():
    x = np.array([[0.3, 0.0], [0.3, 0.5], [0.3, 1.5], [0.3, 2.5]])
    mat = np.zeros(4, np.int32)
    table = WaterTable((0.0, 10.0), (1.0, 3.0), (0.0, 1.0), RHO_W * G, (1.0,))
    p = table.pressure(x, mat, 5.0)  # the table at 2.0 m halfway through its rise
    assert p == pytest.approx([RHO_W * G * 2.0, RHO_W * G * 1.5, RHO_W * G * 0.5, 0.0], rel=1e-12)
    assert table.height(20.0) == 3.0 and table.height(0.0) == 1.0
    off = WaterTable((0.0,), (3.0,), (0.0, 1.0), RHO_W * G, (0.0,))  # a soil the table does not name
    assert not off.pressure(x, mat, 0.0).any()


def test_table_parallel_to_a_slope_gives_the_pressure_of_slope_parallel_seepage():
    """gamma_w z cos^2(beta) at vertical depth z under a table through the origin, gravity vertical."""
    beta = math.radians(25.0)
    normal = np.array([-math.sin(beta), math.cos(beta)])
    gradient = -RHO_W * float(np.array([0.0, -G]) @ normal)
    table = WaterTable((0.0,), (0.0,), normal, gradient, (1.0,))
    xs = np.array([3.0, 7.0])
    z = np.array([0.4, 2.2])  # vertical depth below the table's trace y = x tan(beta)
    pts = np.column_stack([xs, xs * math.tan(beta) - z])
    p = table.pressure(pts, np.zeros(2, np.int32), 0.0)
    assert p == pytest.approx(RHO_W * G * z * math.cos(beta) ** 2, rel=1e-12)


def test_geostatic_stress_under_the_table_is_effective():
    sc = scene_from_dict(layer_case())
    st = sc.state
    depth = 2.0 - st.p_x[:, 1]
    k0 = sc.materials[0].k0()  # the law's own (Jaky: 1 - sin(phi) = 0.5)
    assert k0 == pytest.approx(0.5)
    assert st.p_stress[:, 1] == pytest.approx(-(RHO - RHO_W) * G * depth, rel=1e-9)
    assert st.p_stress[:, 0] == pytest.approx(-k0 * (RHO - RHO_W) * G * depth, rel=1e-9)
    assert not st.p_stress[:, 3].any()
    # the table 0.5 m below the surface: effective stress is total above it, less p below it
    st2 = scene_from_dict(layer_case(table=1.5)).state
    d2 = 2.0 - st2.p_x[:, 1]
    assert st2.p_stress[:, 1] == pytest.approx(-RHO * G * d2 + RHO_W * G * np.maximum(d2 - 0.5, 0.0), rel=1e-9)


def test_a_layer_under_the_table_stays_at_rest_and_would_sink_without_its_pore_pressure():
    """The grid sees sigma' - p I: from the effective geostatic state the layer is in equilibrium (speeds of
    round-off and of the discrete stencil only); the same state with the table switched off carries only
    its buoyant weight and sinks."""
    speeds = []
    for water_on in (True, False):
        sim = Simulation(scene_from_dict(layer_case()))
        if not water_on:
            sim.water = NO_WATER_TABLE
        for _ in range(200):
            sim.step(sim.stable_dt())
        speeds.append(float(np.abs(sim.state.p_v).max()))
    at_rest, sinking = speeds
    assert at_rest < 1e-9 * sinking, speeds  # measured 1.9e-17 m/s against 2.2e-3 m/s
    assert sinking > 1e-3, speeds


def test_vtu_fields_and_series_column_under_the_table():
    sim = Simulation(scene_from_dict(layer_case(table=(1.0, 2.0), times=(0.0, 1.0))))
    sim.step(sim.stable_dt())
    fields = particle_fields(sim)
    st = sim.state
    expected = RHO_W * G * np.maximum(sim.water.height(sim.time) - st.p_x[:, 1], 0.0)
    assert fields["pore_pressure"] == pytest.approx(expected, rel=1e-12, abs=1e-9)
    assert fields["stress"][:, 1] == pytest.approx(st.p_stress[:, 1] - expected, rel=1e-12, abs=1e-9)
    assert fields["effective_stress"][:, 1] == pytest.approx(st.p_stress[:, 1])
    row = sim.series_row()
    assert row["water_table"] == pytest.approx(1.0 + sim.time)


def test_pore_work_counts_dilation_and_uplift():
    x0 = np.array([[0.0, 0.0], [0.0, 0.0]])
    x = np.array([[0.0, 0.1], [0.0, -0.1]])
    w = pore_work(np.array([1e4, 1e4]), np.array([1.2, 1.0]), np.array([1.0, 1.0]), x, x0, np.array([0.0, 1.0]),
                  RHO_W * G)
    assert w == pytest.approx(1e4 * 0.2 + RHO_W * G * 1.2 * 0.1)


@pytest.mark.parametrize("change, path, words", [
    (lambda c: c["solver"].update(backend="cuda"), "triggers.water_table", "CPU backend"),
    (lambda c: c.update(gravity=[0.0, 0.0]), "triggers.water_table", "needs gravity"),
    (lambda c: c["triggers"]["water_table"].update(normal=[0.0, -1.0]), "triggers.water_table.normal", "against gravity"),
    (lambda c: c["triggers"]["water_table"].update(normal=[0.0, 0.0, 1.0]), "triggers.water_table.normal", "2 components"),
    (lambda c: c["triggers"]["water_table"].update(materials=["rock"]), "triggers.water_table.materials.0", "no material"),
    (lambda c: c["triggers"]["water_table"].update(heights=[1.0, 2.0]), "triggers.water_table", "one height per time"),
    (lambda c: c["materials"]["soil"].update(pore_water={"porosity": 0.4, "hydraulic_conductivity": 1e-4}),
     "triggers.water_table", "two-phase"),
])
def test_bad_water_tables_are_refused_with_their_path(change, path, words):
    case = layer_case()
    case.setdefault("solver", {})
    change(case)
    with pytest.raises(CaseError) as err:
        parse_case(case)
    hits = [(p, m) for p, m in err.value.problems if p == path]
    assert hits and any(words in m for _, m in hits), err.value.problems


def test_a_fluid_under_the_table_is_refused():
    case = layer_case()
    case["materials"]["water"] = {"model": "newtonian", "density": 1000.0, "viscosity": 1e-3, "sound_speed": 20.0}
    case["triggers"]["water_table"]["materials"] = ["soil", "water"]
    with pytest.raises(CaseError) as err:
        parse_case(case)
    assert any(p == "triggers.water_table.materials.1" and "fluid" in m for p, m in err.value.problems)
