"""The spatial sort (kernels/sort.py, mpm/state.py; issue 17, point 4).

Particles are re-ordered by grid cell inside each material block; every particle keeps its data
(checked through its stable ``p_id``), the arrays keep their identity, and a run that sorts every
step follows the same physics as one that never sorts, to round-off (only the order of the P2G sums
changes).  Outputs carry ``particle_id``.
"""

import json

import meshio
import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.bench.worker import permute_blocks
from geompm.cli import main
from geompm.errors import CaseError
from geompm.engine.scheduler import Simulation
from geompm.kernels.sort import cell_order

from tests.support.cases import tiny_case


def far_neighbours(p_x, origin, h):
    """Fraction of memory neighbours (p, p+1) more than one cell apart along some axis."""
    c = np.floor((p_x - origin) / h)
    return float((np.abs(np.diff(c, axis=0)).max(axis=1) > 1).mean())


def _two_materials():
    case = tiny_case()
    case["materials"]["sand"] = {"model": "drucker_prager", "density": 1800.0, "youngs_modulus": 1e6,
                                 "poisson_ratio": 0.3, "friction_angle": 30.0}
    case["bodies"].append({"material": "sand", "geometry": {"type": "box", "min": [0.6, 0.0], "max": [0.9, 0.3]},
                           "particles_per_cell": 2})
    return case


def test_cell_order_is_a_stable_counting_sort():
    """Keys are the cell's linear index (last axis fastest, the grid's node order); particles of one cell
    keep their order, so a sorted block sorts to itself."""
    rng = np.random.default_rng(3)
    x = rng.random((500, 3)) * [1.0, 0.5, 0.25]
    perm = cell_order(x, np.zeros(3), 0.1, 100, 400)
    assert sorted(perm) == list(range(100, 400))
    cells = np.floor(x[perm] / 0.1).astype(int)
    keys = (cells[:, 0] * 10 + cells[:, 1]) * 10 + cells[:, 2]
    assert (np.diff(keys) >= 0).all()
    for k in np.unique(keys):  # stable inside a cell
        assert (np.diff(perm[keys == k]) > 0).all()
    x[100:400] = x[perm]
    assert (cell_order(x, np.zeros(3), 0.1, 100, 400) == np.arange(100, 400)).all()


def test_sort_keeps_every_particle_its_data_and_the_arrays_their_identity():
    scene = scene_from_dict(_two_materials())
    st = scene.state
    sim = Simulation(scene)
    for _ in range(3):
        sim.step(sim.stable_dt())
    permute_blocks(st, seed=1)
    h, origin = scene.grid.h, scene.grid.origin
    assert far_neighbours(st.p_x, origin, h) > 0.5
    before = {name: arr.copy() for name, arr in st.arrays().items()}
    state_before = [sv.copy() for sv in st.p_state]
    ids = [id(a) for a in st.arrays().values()]
    st.sort_by_cell(origin, h)
    assert far_neighbours(st.p_x, origin, h) < 0.1
    assert [id(a) for a in st.arrays().values()] == ids
    old_row = np.argsort(before["p_id"])[st.p_id]  # where each particle sat before
    for name, arr in st.arrays().items():
        np.testing.assert_array_equal(arr, before[name][old_row])
    for (a, b), sv, sv0 in zip(st.blocks, st.p_state, state_before):
        np.testing.assert_array_equal(sv, sv0[old_row[a:b] - a])
        assert set(st.p_material[a:b]) <= {st.p_material[a]}  # blocks stay per material


def test_sorting_every_step_changes_the_physics_at_round_off_only():
    """40 steps of the tiny case (elastic block on a slip floor) and a DP block, sorted every step
    against never: positions of each particle (by p_id) agree to 1e-12 m, stresses to 1e-9 relative."""
    runs = []
    for every in (0, 1):
        case = _two_materials()
        case["solver"]["sort_interval"] = every
        sim = Simulation(scene_from_dict(case))
        permute_blocks(sim.state, seed=2)  # something to sort
        for _ in range(40):
            sim.step(sim.stable_dt())
        st = sim.state
        order = np.argsort(st.p_id)
        runs.append((st.p_x[order], st.p_stress[order], st.p_v[order]))
    assert np.abs(runs[0][2]).max() > 1e-3  # it moved
    np.testing.assert_allclose(runs[1][0], runs[0][0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(runs[1][1], runs[0][1], rtol=0, atol=1e-9 * np.abs(runs[0][1]).max())


def test_vtu_carries_particle_id_in_the_solver_order(tmp_path):
    case = tiny_case()
    case["solver"]["sort_interval"] = 1
    f = tmp_path / "case.json"
    f.write_text(json.dumps(case))
    assert main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    files = sorted((tmp_path / "run" / "particles").glob("*.vtu"))
    first, last = (meshio.read(p) for p in (files[0], files[-1]))
    pid = last.point_data["particle_id"]
    assert sorted(pid) == list(range(len(pid)))
    # displacement = x - x0 for the same particle, whatever its row
    x0 = first.points[np.argsort(first.point_data["particle_id"])]
    np.testing.assert_allclose(last.points - x0[pid], last.point_data["displacement"], atol=1e-12)


@pytest.mark.parametrize("interval", [0, 7])
def test_sort_interval_reaches_the_scene_and_a_negative_one_is_refused(interval):
    case = tiny_case()
    case["solver"]["sort_interval"] = interval
    assert scene_from_dict(case).sort_interval == interval
    case["solver"]["sort_interval"] = -interval - 1
    with pytest.raises(CaseError) as err:
        scene_from_dict(case)
    assert any(path == "solver.sort_interval" for path, _ in err.value.problems)
