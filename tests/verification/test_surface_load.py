"""Surface load (boundaries/surface_load.py): a pressure or traction on the particles of a box, as nodal force.

- Closed form (1D consolidation of an elastic layer, drained and weightless, e.g. Verruijt, *Soil
  Mechanics*, ch. 15 on the oedometer): a laterally confined column under a surface pressure q settles by
  u_y(y) = -q y / M, M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), and carries sigma_yy = -q at every depth.
  At h = 0.1 and 0.05 m (the docs table h = 0.025 m too, benchmarks/surface_load/column.py) the top row's
  settlement and the displacement profile are within 5 % of the closed form (measured 4.1 % and 2.2 %:
  first order, from the particles next to the slip floor, which settle 0.4 h q / M too far), the
  mid-height stress within 0.5 % (measured 0.40 % and 0.02 %), and the settlement and profile errors
  fall with h. Local damping brings the column to rest, so this also checks
  that the load is in the nodal force that damping reads (a velocity kick instead held it at
  q / (1 + alpha)).
- The applied force is the box's face area times the traction, r(t) A t, ramped linearly: the series
  column equals -q W r(t) at every output (2D), and the full traction times the face area in 3D (the
  nodal shares sum to it: partition of unity), both to 1e-9. geompm.run's health check accepts the
  kinetic energy the load supplies.
- Only the face row inside the box is loaded: a box reaching half-way down the column selects the same
  particles (the top row, ids equal) as a box half a cell deep, and with a normal along -x the particles
  of the left face.
- Bad input is refused with the JSON path: an empty box, both or neither of pressure and traction.
"""

import numpy as np
import pytest

import geompm
from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.errors import CaseError

from geompm.testing.verification.loaded_column import H, Q, W, column_case, run_column


def test_confined_column_settles_by_q_h_over_m():
    coarse, fine = run_column(0.1), run_column(0.05)
    for r in (coarse, fine):
        assert abs(r["settlement_error"]) < 0.05, r
        assert r["profile_error"] < 0.05, r
        assert abs(r["stress_error"]) < 0.005, r
    assert abs(fine["settlement_error"]) < abs(coarse["settlement_error"]), (coarse, fine)
    assert fine["profile_error"] < coarse["profile_error"], (coarse, fine)


def test_applied_force_is_the_ramped_traction_times_the_area(tmp_path):
    case = column_case(0.1, ramp=0.05)
    case["time"]["end"] = 0.08
    case["outputs"] = [{"writer": "series", "interval": 0.01}]
    run = geompm.run(case, out=tmp_path / "run", progress=False)
    assert run.status["finished"] is True
    t, fy = run.series["time"], run.series["footing_load_y"]
    assert len(t) >= 8
    # the load of the step that ended at t, r(t) = min(1, t / ramp)
    np.testing.assert_allclose(fy, -Q * W * np.minimum(1.0, t / 0.05), rtol=1e-9, atol=1e-9 * Q * W)
    assert np.all(run.series["footing_load_x"] == 0.0)
    assert run.series["footing_load_work"][-1] > 0.0


def test_3d_traction_sums_to_traction_times_face_area():
    h = 0.1
    case = {"name": "block3d", "dimension": 3,
            "grid": {"origin": [0.0, 0.0, 0.0], "extent": [0.6, 0.6, 0.6], "cell_size": h},
            "time": {"end": 0.01}, "gravity": [0.0, 0.0, 0.0],
            "materials": {"soil": {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 1e7,
                                   "poisson_ratio": 0.3}},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.1, 0.1, 0.0],
                                                          "max": [0.5, 0.4, 0.3]}}],
            "boundaries": [{"type": "wall", "side": "z-", "condition": "fixed"},
                           {"type": "surface_load", "region": {"min": [0.1, 0.1, 0.25], "max": [0.5, 0.4, 0.3]},
                            "normal": [0, 0, 1], "traction": [2000.0, -500.0, -8000.0]}]}
    scene = scene_from_dict(case)
    sim = Simulation(scene)
    load = next(s for s in scene.stages if type(s).__name__ == "SurfaceLoad")
    for _ in range(3):
        sim.step(sim.stable_dt())
        area = 0.4 * 0.3
        np.testing.assert_allclose(load.applied, area * np.array([2000.0, -500.0, -8000.0]), rtol=1e-9)
    assert load.area == pytest.approx(0.12, rel=1e-12)


@pytest.mark.parametrize("change, where", [
    (lambda b: b.update(region={"min": [0.0, 2.0], "max": [0.2, 2.05]}), "boundaries.3.region"),
    (lambda b: b.update(traction=[0.0, -1.0]), "boundaries.3"),
    (lambda b: b.pop("pressure"), "boundaries.3"),
    (lambda b: b.update(region={"min": [0.2, 0.9], "max": [0.0, 1.0]}), "boundaries.3.region"),
])
def test_bad_loads_are_refused_with_the_json_path(change, where):
    case = column_case(0.1)
    change(case["boundaries"][3])
    with pytest.raises(CaseError) as err:
        scene_from_dict(case)
    assert any(path.startswith(where) for path, _ in err.value.problems), err.value.problems


def test_only_the_face_row_inside_the_box_is_loaded():
    h = 0.1

    def loaded(region, normal):
        case = column_case(h)
        case["boundaries"][3].update(region=region, normal=normal)
        scene = scene_from_dict(case)
        load = next(s for s in scene.stages if type(s).__name__ == "SurfaceLoad")
        return load.loaded_ids, scene.state

    thin, st = loaded({"min": [0.0, H - h / 2], "max": [W, H]}, [0.0, 1.0])
    deep, _ = loaded({"min": [0.0, H / 2], "max": [W, H]}, [0.0, 1.0])
    assert len(thin) == round(W / (h / 2)) == 4
    np.testing.assert_array_equal(thin, deep)
    assert np.allclose(st.p_x0[np.isin(st.p_id, thin), 1], H - h / 4)
    left, st = loaded({"min": [0.0, 0.0], "max": [W / 2, H]}, [-1.0, 0.0])
    assert len(left) == round(H / (h / 2))
    assert np.allclose(st.p_x0[np.isin(st.p_id, left), 0], h / 4)
