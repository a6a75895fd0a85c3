"""A phreatic surface from data and a pond (schema triggers.water_table.surface / .pond; mpm/phreatic_surface.py,
mpm/water_table.py, kernels/phreatic.py).

Below a drawn phreatic surface the pore pressure is hydrostatic along the vertical, p = gamma_w (z_s(x) - z)
(the piezometric-line convention of limit equilibrium: Bishop 1955, Geotechnique 5(1):7; Duncan, Wright &
Brandon 2014, Soil Strength and Slope Stability, sec. 6.3), zero above it.  A pond of free water at z_p presses
on the soil's faces below it and stands in its pores: a level layer of saturated soil (rho_sat = 2000 kg/m3)
under 1 m of water carries the buoyant effective stress sigma'_v = (rho_sat - rho_w) g d (Terzaghi's
principle; the water above adds as much to the total stress as to the pore pressure), whatever the depth of
the water above it.  Bad input is refused with its JSON path; a table above the ground is warned."""

import copy

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.errors import CaseError
from geompm.schema.load import parse_case
from geompm.setup.assemble import assemble

from tests.unit.test_water_table import RHO, RHO_W, G, layer_case


def pond_case(level=3.0, geostatic=True) -> dict:
    """The 1 m x 2 m level layer of test_water_table under a pond at ``level`` [m] and no table of its own."""
    c = layer_case()
    c["triggers"]["water_table"] = {"pond": {"times": [0.0], "levels": [level]}}
    c["grid"]["extent"] = [1.0, 3.2]
    if not geostatic:
        c["bodies"][0]["initial_stress"] = "none"
        c["damping"] = [{"model": "local", "alpha": 0.7}]
    return c


def test_polyline_is_hydrostatic_along_the_vertical_below_it_and_level_beyond_its_ends():
    c = layer_case()
    c["triggers"]["water_table"] = {"surface": {"points": [[0.2, 1.0], [0.6, 1.8]]}, "times": [0.0, 2.0],
                                    "heights": [0.0, 0.1]}
    sim = Simulation(scene_from_dict(c))
    table = sim.water
    x = np.array([[0.0, 0.5], [0.4, 0.5], [0.4, 1.5], [0.9, 1.0], [0.9, 1.9]])
    p = table.pressure(x, np.zeros(5, np.int32), 1.0)  # raised by 0.05 m halfway through the schedule
    z_s = np.array([1.0, 1.4, 1.4, 1.8, 1.8]) + 0.05
    assert p == pytest.approx(RHO_W * G * np.maximum(z_s - x[:, 1], 0.0), rel=1e-12, abs=1e-9)
    assert p[-1] == 0.0 and p[2] == 0.0


def test_points_in_3d_make_a_tin_that_is_exact_on_a_plane_and_a_raster_reads_the_same(tmp_path):
    """A TIN through points of the plane z = 1 + 0.2 x - 0.1 y reproduces it to round-off inside the hull and
    holds the nearest point's height beyond it; a GeoTIFF of the same plane gives the same pressures."""
    rasterio = pytest.importorskip("rasterio")
    plane = lambda x, y: 1.0 + 0.2 * x - 0.1 * y  # noqa: E731
    pts = [[x, y, plane(x, y)] for x in (0.0, 0.5, 1.0) for y in (0.0, 0.5, 1.0)]
    c = {"name": "tin", "dimension": 3,
         "grid": {"origin": [0.0, 0.0, 0.0], "extent": [1.0, 1.0, 2.0], "cell_size": 0.25},
         "time": {"end": 0.1}, "gravity": [0.0, 0.0, -G],
         "materials": {"soil": {"model": "linear_elastic", "density": RHO, "youngs_modulus": 1e7,
                                "poisson_ratio": 0.3}},
         "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1.5]}}],
         "triggers": {"water_table": {"surface": {"points": pts}}}, "outputs": []}
    rng = np.random.default_rng(1)
    x = np.column_stack([rng.uniform(0, 1, 50), rng.uniform(0, 1, 50), rng.uniform(0, 1.5, 50)])
    mat = np.zeros(50, np.int32)
    expected = RHO_W * G * np.maximum(plane(x[:, 0], x[:, 1]) - x[:, 2], 0.0)
    p_tin = scene_from_dict(c).water_table.pressure(x, mat, 0.0).copy()
    assert p_tin == pytest.approx(expected, rel=1e-9, abs=1e-6)
    from rasterio.transform import from_origin
    step = 0.05
    xs = np.arange(-0.5 * step, 1.0 + step, step) + 0.5 * step  # pixel centres from 0 to 1.05
    ys = xs[::-1]
    z = plane(xs[None, :], ys[:, None])
    with rasterio.open(tmp_path / "table.tif", "w", driver="GTiff", height=z.shape[0], width=z.shape[1], count=1,
                       dtype="float64", transform=from_origin(xs[0] - 0.5 * step, ys[0] + 0.5 * step, step, step)) as dst:
        dst.write(z, 1)
    c["triggers"]["water_table"]["surface"] = {"raster": "table.tif"}
    p_raster = scene_from_dict(c, base_dir=tmp_path).water_table.pressure(x, mat, 0.0)
    assert p_raster == pytest.approx(expected, rel=1e-9, abs=1e-6)


def test_a_submerged_layer_starts_and_stays_at_its_buoyant_effective_stress():
    """Geostatic under a pond: sigma'_v = (rho_sat - rho_w) g d exactly, and at rest (the grid sees sigma' -
    (p - p_pond) I and the pond's buoyancy as a nodal force)."""
    sim = Simulation(scene_from_dict(pond_case()))
    st = sim.state
    d = 2.0 - st.p_x[:, 1]
    assert st.p_stress[:, 1] == pytest.approx(-(RHO - RHO_W) * G * d, rel=1e-9)
    for _ in range(200):
        sim.step(sim.stable_dt())
    assert float(np.abs(st.p_v).max()) < 1e-12  # measured 2.5e-17 m/s


def test_a_submerged_layer_settles_to_its_buoyant_effective_stress_from_none():
    """From no initial stress under Cundall's local damping the layer must reach the buoyant effective stress:
    the pond's buoyancy acts through the nodal force (a velocity kick instead would hide it from the damping,
    which then holds the layer at 1.42 times the buoyant stress: measured).  Row means over 0.3-1.7 m depth
    within 1 % (measured: mean +0.08 %)."""
    sim = Simulation(scene_from_dict(pond_case(geostatic=False)))
    for _ in range(3000):
        sim.step(sim.stable_dt())
    st = sim.state
    d = 2.0 - st.p_x0[:, 1]
    buoyant = -(RHO - RHO_W) * G * d
    mid = (d > 0.3) & (d < 1.7)
    assert float(np.mean(st.p_stress[mid, 1]) / np.mean(buoyant[mid])) == pytest.approx(1.0, abs=0.01)
    dry = -RHO * G * d  # the same layer with its water not buoyed by the pond is 2x off
    assert abs(float(np.mean(st.p_stress[mid, 1]) / np.mean(dry[mid])) - 1.0) > 0.4


def _problems(case):
    with pytest.raises(CaseError) as exc:
        assemble(parse_case(case, "."))
    return exc.value.problems


@pytest.mark.parametrize("edit, path, words", [
    (lambda c: c.update(gravity=[1.0, -G]), "triggers.water_table.surface", "gravity along -y"),
    (lambda c: c["triggers"]["water_table"]["surface"]["points"].append([1.5, 1.0]),
     "triggers.water_table.surface.points.2", "leaves the grid's plan"),
    (lambda c: c["triggers"]["water_table"]["surface"]["points"].insert(1, [0.0, 1.0]),
     "triggers.water_table.surface.points.1", "x must increase"),
    (lambda c: c["triggers"]["water_table"]["surface"]["points"].__setitem__(0, [0.0, 3.0]),
     "triggers.water_table.surface.points.0", "above the grid's top"),
    (lambda c: c["triggers"]["water_table"].update(pond={"times": [0.0, 1.0], "levels": [1.0, 9.0]}),
     "triggers.water_table.pond.levels.1", "above the grid's top"),
    (lambda c: c["triggers"]["water_table"].update(pond={"times": [0.0], "levels": [-1.0]}),
     "triggers.water_table.pond.levels", "never reaches the soil"),
])
def test_bad_surfaces_and_ponds_are_refused_with_their_json_path(edit, path, words):
    c = layer_case()
    c["triggers"]["water_table"] = {"surface": {"points": [[0.0, 1.0], [1.0, 1.5]]}}
    edit(c)
    problems = _problems(c)
    assert any(p == path and words in t for p, t in problems), problems


def test_a_schedule_out_of_order_is_refused():
    c = layer_case()
    c["triggers"]["water_table"] = {"pond": {"times": [1.0, 0.0], "levels": [1.0, 2.0]}}
    with pytest.raises(CaseError) as exc:
        parse_case(c, ".")
    assert any("triggers.water_table.pond" in p and "must not decrease" in t for p, t in exc.value.problems)


def test_a_table_above_the_ground_is_warned_as_a_pond_and_not_under_a_pond():
    c = layer_case()
    c["triggers"]["water_table"] = {"surface": {"points": [[0.0, 1.5], [1.0, 2.3]]}}
    loaded = parse_case(copy.deepcopy(c), ".")
    assemble(loaded)
    assert any(p == "triggers.water_table" and "above the ground" in t and "pond" in t for p, t in loaded.warnings)
    c["triggers"]["water_table"]["pond"] = {"times": [0.0], "levels": [2.35]}
    loaded = parse_case(c, ".")
    assemble(loaded)
    assert not any("above the ground" in t for _, t in loaded.warnings)


def test_a_two_phase_body_starts_hydrostatic_below_its_drawn_line():
    """bodies.N.pore_pressure.surface: the two-phase slope's initial pore pressure is rho_w g (z_line(x) - z)
    below the line (its particles saturated) and zero above (dry)."""
    from geompm.testing.verification.water_slopes import phreatic_line, two_phase_slope_case

    case = two_phase_slope_case(1.0, loading=False, table=None)
    line = phreatic_line(back=6.0)
    case["bodies"][0]["pore_pressure"] = {"surface": {"points": line}}
    st = scene_from_dict(case).state
    pts = np.asarray(line)
    z_s = np.interp(st.p_x[:, 0], pts[:, 0], pts[:, 1])
    below = st.p_x[:, 1] <= z_s
    assert st.p_pore == pytest.approx(RHO_W * G * np.maximum(z_s - st.p_x[:, 1], 0.0), rel=1e-9, abs=1e-6)
    assert (st.p_sat[below] == 1.0).all() and (st.p_sat[~below] == 0.0).all() and 0 < below.sum() < len(below)
    case["bodies"][0]["pore_pressure"]["surface"]["points"] = [[0.0, 1.0], [50.0, 1.0]]
    with pytest.raises(CaseError) as exc:
        assemble(parse_case(case, "."))
    assert any(p == "bodies.0.pore_pressure.surface.points.1" and "leaves the grid's plan" in t
               for p, t in exc.value.problems)


def test_a_submerged_layer_in_3d_starts_and_stays_at_its_buoyant_effective_stress():
    """The pond in 3D (the vertical is z): a 1 x 1 x 1 m layer under a pond at 1.5 m, geostatic, sigma'_zz =
    (rho_sat - rho_w) g d and at rest after 100 steps (the buoyancy scattered to the 3D stencil)."""
    c = {"name": "pond3d", "dimension": 3,
         "grid": {"origin": [0.0, 0.0, 0.0], "extent": [1.0, 1.0, 1.8], "cell_size": 0.2, "shape_function": "linear"},
         "time": {"end": 0.1, "cfl": 0.4}, "gravity": [0.0, 0.0, -G],
         "materials": {"soil": {"model": "drucker_prager", "density": RHO, "youngs_modulus": 2e7,
                                "poisson_ratio": 0.3, "friction_angle": 30.0, "cohesion": 0.0,
                                "dilation_angle": 0.0}},
         "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]},
                     "particles_per_cell": 2, "initial_stress": "geostatic"}],
         "boundaries": [{"type": "wall", "side": "z-", "condition": "fixed"}]
         + [{"type": "wall", "side": s, "condition": "slip"} for s in ("x-", "x+", "y-", "y+")],
         "triggers": {"water_table": {"pond": {"times": [0.0], "levels": [1.5]}}}, "outputs": []}
    sim = Simulation(scene_from_dict(c))
    st = sim.state
    assert st.p_stress[:, 2] == pytest.approx(-(RHO - RHO_W) * G * (1.0 - st.p_x[:, 2]), rel=1e-9)
    for _ in range(100):
        sim.step(sim.stable_dt())
    assert float(np.abs(st.p_v).max()) < 1e-12
