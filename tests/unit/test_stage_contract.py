"""The stage kernel contract (contract/stages.py, backend/cpu_stage_loops.py; issue 17, point 2).

Every shipped boundary, damping and obstacle plugin gives per-node or per-particle @njit functions
and the backend owns the loops.  Checked here: each registered stage declares exactly the functions
its base classes ask for; a pass allocates nothing per node or per particle (numba's allocation
counters over half and all of the items); a stage whose rule is defined inside a function (the
uncached closure loop) moves particles exactly as the shipped module-level stage does; the node box
is only an optimisation (the rule alone, over every node, gives the same velocities).
"""

import numpy as np
import pytest
from numba import njit
from numba.core.dispatcher import Dispatcher
from numba.core.runtime import _nrt_python, rtsys

from geompm.api import scene_from_dict
from geompm.backend import cpu_stage_loops
from geompm.backend.cpu import CpuBackend
from geompm.boundaries.halfspace import halfspace_node_rule, halfspace_particle_rule
from geompm.boundaries.plane import Plane
from geompm.engine.scheduler import Simulation
from geompm.contract.registry import available
from geompm.contract.stages import DRY_NODE, GridStage, ParticleStage


def _case(extra_boundaries=(), damping=(), obstacles=()):
    """A 2D elastic block dropped onto a floor plane in a walled box, with any extra stages."""
    return {
        "name": "stages", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 1.0], "cell_size": 0.05},
        "time": {"end": 0.1, "cfl": 0.4}, "gravity": [0.0, -9.81],
        "materials": {"block": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e6,
                                "poisson_ratio": 0.2}},
        "bodies": [{"material": "block", "geometry": {"type": "box", "min": [0.3, 0.1], "max": [0.6, 0.4]},
                    "velocity": [1.0, -1.0]}],
        "boundaries": [{"type": "wall", "side": "x-"}, {"type": "wall", "side": "x+", "condition": "fixed"},
                       {"type": "plane", "point": [0.0, 0.08], "normal": [0.0, 1.0], "condition": "friction",
                        "friction": 0.3}, *extra_boundaries],
        "damping": list(damping),
        "obstacles": list(obstacles),
    }


def test_every_registered_stage_declares_its_functions():
    found = 0
    for group in ("boundaries", "damping", "obstacles"):
        for name, info in available(group).items():
            cls = info.plugin
            if issubclass(cls, GridStage):
                fns = [f for f in (cls.node_rule, cls.node_image) if f is not None]
                assert len(fns) == 1, f"{name}: exactly one of node_rule / node_image"
                assert isinstance(fns[0], Dispatcher), f"{name}: the node function is not @njit"
                found += 1
            if issubclass(cls, ParticleStage):
                assert isinstance(cls.particle_rule, Dispatcher), f"{name}: particle_rule is not @njit"
                found += 1
    assert found >= 11  # 3 boundaries and 4 obstacles on both, 2 damping on one


def _allocations(fn):
    before = rtsys.get_allocation_stats().alloc
    fn()
    return rtsys.get_allocation_stats().alloc - before


def test_a_stage_pass_allocates_nothing_per_item():
    """One pass over half the particles (nodes) and over all of them makes the same number of numba
    allocations: the rules allocate nothing per item (the loops' own bookkeeping is per call)."""
    case = _case(damping=[{"model": "artificial", "xi": 0.002}, {"model": "local", "alpha": 0.5}],
                 obstacles=[{"type": "box", "min": [0.7, 0.0], "max": [0.8, 0.3]}])
    sim = Simulation(scene_from_dict(case))
    for _ in range(3):
        sim.step(sim.stable_dt())
    st, view = sim.state, sim.view
    n = st.n
    _nrt_python.memsys_enable_stats()
    try:
        for stage in sim.particle_stages:
            loop = CpuBackend._stage_loops(type(stage))["particle"]
            prm, aux = stage.particle_args(1e-5, sim.time)
            out = np.zeros((2, max(type(stage).particle_reduction, 1)))
            work = np.zeros((2, max(type(stage).particle_scratch, 1)))

            def one(end, loop=loop, prm=prm, aux=aux, out=out, work=work):
                loop(prm, aux, 1e-5, 0, 0, end, st.p_x, st.p_x0, st.p_v, st.p_C, st.p_mass, st.p_stress, work, out)
            one(n)
            assert _allocations(lambda: one(n // 2)) == _allocations(lambda: one(n)), stage.label
        g = sim.scene.grid
        for stage in sim.grid_stages:
            loop = CpuBackend._stage_loops(type(stage))["grid"]
            prm, aux = stage.grid_args(1e-5, sim.time, False)
            out = np.zeros((2, max(type(stage).node_reduction, 1)))
            work = np.zeros((2, g.dim + type(stage).node_scratch))
            v_old = view.g_vel_old if view.g_vel_old is not None else view.g_vel
            f = view.g_force if view.g_force is not None else view.g_vel

            def one(rows, loop=loop, prm=prm, aux=aux, out=out, work=work, v_old=v_old, f=f):
                first, last = view.lo.copy(), view.lo + view.nloc - 1
                last[0] = view.lo[0] + rows - 1
                loop(prm, aux, 1e-5, g.origin, g.h, view.lo, view.nloc, first, last, view.g_mass,
                     view.g_vel, v_old, f, DRY_NODE, False, work, out)
            one(int(view.nloc[0]))
            full = int(view.nloc[0])
            assert _allocations(lambda: one(full // 2)) == _allocations(lambda: one(full)), stage.label
    finally:
        _nrt_python.memsys_disable_stats()


def test_a_stage_defined_in_a_function_runs_through_the_uncached_loop():
    """A plane whose rules are @njit functions made inside this test (not importable by name, so the
    backend compiles its loops in-process) gives the shipped plane's particle positions to the bit."""
    @njit(inline="always")
    def my_node_rule(prm, aux, dt, x, m, v, v_old, f, pw, work, out):
        halfspace_node_rule(prm, aux, dt, x, m, v, v_old, f, pw, work, out)

    @njit(inline="always")
    def my_particle_rule(prm, aux, dt, k, x, x0, v, C, m, s, work, out):
        halfspace_particle_rule(prm, aux, dt, k, x, x0, v, C, m, s, work, out)

    class MyPlane(Plane):
        name = "my_plane"
        node_rule = my_node_rule
        particle_rule = my_particle_rule

    runs = []
    for cls in (Plane, MyPlane):
        scene = scene_from_dict(_case())
        floor = scene.boundaries[2]
        mine = cls(floor.params, floor.label, floor.json_path)
        mine.setup(scene)
        scene.boundaries[2] = mine
        sim = Simulation(scene)
        for _ in range(60):
            sim.step(sim.stable_dt())
        runs.append(sim.state.p_x.copy())
    assert runs[0][:, 1].min() >= 0.08 - 1e-12  # the floor held
    np.testing.assert_array_equal(runs[1], runs[0])


def test_the_node_box_only_skips_nodes_the_rule_leaves_alone():
    """A wall's node box (the slab on and beyond its face) against the same wall's rule over the whole
    window: identical grid velocities."""
    case = _case()
    case["bodies"][0]["geometry"].update(min=[0.01, 0.1], max=[0.99, 0.3])  # the window reaches both walls
    sim = Simulation(scene_from_dict(case))
    for _ in range(5):
        sim.step(sim.stable_dt())
    view, g = sim.view, sim.scene.grid
    wall = sim.scene.boundaries[1]  # x+, fixed: zeroes the nodes it acts on
    rng = np.random.default_rng(1)
    start = rng.normal(size=view.g_vel.shape)
    results = []
    for first, last in (wall.node_box(0.0), (view.lo, view.lo + view.nloc - 1)):
        view.g_vel[:] = start
        loop = cpu_stage_loops.node_loop(type(wall).node_rule)
        loop(wall.prm, np.zeros(1), 1e-5, g.origin, g.h, view.lo, view.nloc, first, last, view.g_mass, view.g_vel,
             view.g_vel, view.g_vel, DRY_NODE, False, np.zeros((2, 2 + type(wall).node_scratch)), np.zeros((2, 1)))
        results.append(view.g_vel.copy())
    changed = (results[1] != start).any(axis=1)
    assert changed.sum() >= 5  # the wall acted on the nodes of its face (and beyond)
    assert changed.sum() < 0.2 * len(changed)
    np.testing.assert_array_equal(results[0], results[1])


@pytest.mark.parametrize("threads", [1, 2])
def test_obstacle_force_is_the_sum_of_the_threads_rows(threads):
    """The backend sums the threads' accumulator rows: the obstacle's recorded force equals the sum of
    the per-node contact forces whatever the chunk count (to round-off)."""
    case = _case(obstacles=[{"type": "box", "min": [0.35, 0.0], "max": [0.55, 0.09]}])  # under the block
    scene = scene_from_dict(case)
    sim = Simulation(scene, nchunks=threads)
    for _ in range(40):
        sim.step(sim.stable_dt())
    box = scene.obstacles[0]
    assert abs(box.force[1]) > 0.0
    # the same grid pass with one chunk: the same force to round-off
    view, g = sim.view, scene.grid
    prm, aux = box.grid_args(sim.dt, sim.time, False)
    loop = CpuBackend._stage_loops(type(box))["grid"]
    first, last = box.node_box(sim.time)
    rows = []
    for nc in (1, 3):
        v = view.g_vel.copy()
        out = np.zeros((nc, type(box).node_reduction))
        loop(prm, aux, sim.dt, g.origin, g.h, view.lo, view.nloc, first, last, view.g_mass, v, v, v,
             DRY_NODE, False, np.zeros((nc, 2 + type(box).node_scratch)), out)
        rows.append(out.sum(axis=0))
    np.testing.assert_allclose(rows[1], rows[0], rtol=1e-12, atol=1e-12 * np.abs(rows[0]).max())


def test_the_how_to_screen_plugin_runs_and_decays_the_velocity_exactly():
    """The complete example of docs/how-to/write-a-stage-plugin.md, taken from the page's code and
    added to a scene without gravity: an elastic block moving at 1 m/s inside the screen keeps
    v(t) = exp(-t / tau) (linear drag, exact per step: the nodes' velocities are all scaled by the same
    factor and G2P carries that to the particles), and the screen's force is the momentum it removes,
    F = M v / tau to first order in dt / tau."""
    import re
    import sys
    import types
    from pathlib import Path

    page = (Path(__file__).parents[2] / "docs" / "how-to" / "write-a-stage-plugin.md").read_text()
    source = re.search(r"```python\n# mypkg/screen.py\n(.*?)```", page, re.S).group(1)
    path = Path(__file__).parent / "_howto_screen.py"  # a real file, so its loop is cached like a plugin's
    module = types.ModuleType("_howto_screen")
    module.__file__ = str(path)
    path.write_text(source)
    try:
        sys.modules["_howto_screen"] = module
        exec(compile(source, str(path), "exec"), module.__dict__)
        case = _case()
        case["gravity"] = [0.0, 0.0]
        case["boundaries"] = []
        case["bodies"][0]["velocity"] = [1.0, 0.0]
        scene = scene_from_dict(case)
        tau = 0.05
        screen = module.Screen(module.ScreenParams(min=[0.0, 0.0], max=[1.0, 1.0], relaxation_time=tau),
                               "screen", "obstacles.0")
        screen.setup(scene)
        scene.obstacles.append(screen)
        sim = Simulation(scene)
        while sim.time < 0.1 - 1e-12:
            sim.step(min(sim.stable_dt(), 0.1 - sim.time))
        st = sim.state
        v = float((st.p_mass * st.p_v[:, 0]).sum() / st.p_mass.sum())
        assert v == pytest.approx(np.exp(-0.1 / tau), rel=1e-3), v
        total = float(st.p_mass.sum())
        force = screen.series()["screen_fx"]
        assert force == pytest.approx(total * v / tau, rel=0.02), (force, total * v / tau)
    finally:
        path.unlink()
        sys.modules.pop("_howto_screen", None)
