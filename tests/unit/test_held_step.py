"""The held step (engine/held_step.py, solver.held_step) on the CPU: no step exceeds the stable step of the state
it starts from, a check that fails ends the batch, held and ordinary steps give the same motion, the box is
exact for the laws' own wave speeds, and what a batch cannot carry is refused with its JSON path.

The bound checked is the one the time step states (backend/timestep.py: CFL with the law's wave speed, the
strain-increment limit): the stable step of each step's starting state is recomputed from the particles, apart
from the batch's own check."""

import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.backend.timestep import STRAIN_INCREMENT, step_limit
from geompm.engine import held_step as H
from geompm.engine.runner import Runner
from geompm.engine.scheduler import Simulation
from geompm.errors import CaseError
from geompm.kernels.step_end import BAD, END_ROW, RHO_MAX, SPEED
from geompm.schema.load import parse_case
from tests.support.cases import tiny_case


def impact_case(held=None, cfl=0.4) -> dict:
    """An elastic block (c = 26 m/s) thrown at 3 m/s onto a slip floor: its impact changes speeds, densities and
    rates from step to step."""
    case = tiny_case(outputs=[], time={"end": 1.0, "cfl": cfl})
    case["bodies"][0]["geometry"] = {"type": "box", "min": [0.2, 0.1], "max": [0.6, 0.4]}
    case["bodies"][0]["velocity"] = [0.5, -3.0]
    if held is not None:
        case["solver"]["held_step"] = held
    return case


def run_held(case, steps, tmp_path):
    sim = Simulation(scene_from_dict(case, tmp_path))
    runner = Runner(sim, tmp_path, [], progress=False)
    runner.start()
    record = []
    step = sim.step

    def checked(dt):
        record.append((dt, sim.backend.stable_dt()))  # from the particles, apart from the batch's check
        step(dt)

    sim.step = checked
    while sim.step_count < steps:
        runner.advance(math.inf)
    return sim, runner, np.array(record)


@pytest.mark.parametrize("fraction", [1.0, 0.97])
def test_no_held_step_exceeds_the_stable_step_and_a_failed_check_ends_the_batch(tmp_path, fraction):
    """60 steps in batches of up to 8: every step at most the stable step of the state it starts from, and (the
    impact moving the stable step) batches that end before their 8 steps; at fraction 1 every batch after the
    first step fails its first check as the block speeds up (c + |v| grows)."""
    sim, runner, rec = run_held(impact_case({"steps": 8, "fraction": fraction}), 60, tmp_path)
    dt, stable = rec[:, 0], rec[:, 1]
    assert (dt <= stable * (1 + 1e-12)).all(), float((dt / stable).max())
    assert runner.held_steps == sim.step_count and runner.held_batches * 8 > sim.step_count  # some ended early
    if fraction == 1.0:
        assert runner.held_batches >= 0.5 * sim.step_count
    else:  # the room of 3 % of the step holds most batches whole
        assert runner.held_batches <= 0.5 * sim.step_count
        assert (dt / stable).min() > 0.9


def test_held_steps_move_the_block_as_ordinary_steps_do(tmp_path):
    """To t = 0.04 s (the impact and its rebound waves), held steps at fraction 0.9 and ordinary steps at a CFL
    number 0.9 times as large take nearly the same steps; the positions agree within 1e-3 of a cell and the
    velocities within 1 % of the throw's speed."""
    out = []
    for held, cfl in (({"steps": 10, "fraction": 0.9}, 0.4), (None, 0.36)):
        sim = Simulation(scene_from_dict(impact_case(held, cfl), tmp_path))
        Runner(sim, tmp_path, [], progress=False).run(until=0.04)
        st = sim.state
        order = np.argsort(st.p_id)
        out.append((st.p_x[order].copy(), st.p_v[order].copy(), sim.step_count))
    (x1, v1, n1), (x2, v2, n2) = out
    assert abs(n1 - n2) <= 0.05 * n2
    assert np.abs(x1 - x2).max() < 1e-3 * 0.1
    assert np.abs(v1 - v2).max() < 0.01 * 3.0


@pytest.mark.parametrize("material", [
    {"model": "newtonian", "density": 1000.0, "viscosity": 1e-3, "sound_speed": 20.0},
    {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 1.0e6, "poisson_ratio": 0.3},
])
def test_the_box_holds_the_stable_step_and_its_edges_are_checked(tmp_path, material):
    """Inside the box (held_step.limits) the time step's own formula gives at least the held step, evaluated at
    the box's corners with the law's wave speed (for the weakly compressible fluid it grows with the density);
    the starting state fits, and each quantity just past its edge, a non-finite particle or a particle past the
    margin does not."""
    case = tiny_case(outputs=[])
    case["materials"] = {"soil": material}
    sim = Simulation(scene_from_dict(case, tmp_path))
    scene, be = sim.scene, sim.backend
    be.update_stress(1e-6)  # a rate for the check
    stable = be.stable_dt()
    hold = 0.9 * stable
    rows = be.end_rows()
    cells = be.particle_cells()
    box = H.limits(scene, rows, hold, H.widened(cells, 2, scene.grid))
    mat = scene.materials[0]
    wave = type(mat).particle_wave_speed
    c_box = max(wave(mat.prm, box[H.RHO]), wave(mat.prm, box[H.RHO + 1]))
    assert step_limit(scene, c_box + box[H.V_ALLOW], box[H.RATE_ALLOW]) >= hold
    assert box[H.RATE_ALLOW] == pytest.approx(STRAIN_INCREMENT / hold, rel=1e-9)
    assert box[H.RHO] < rows[10 + 0] * -1 and box[H.RHO + 1] > rows[RHO_MAX]  # a density room either way
    rate = be.max_rate
    assert H.fits(rows, rate, box)

    def fails(slot, value, r=rate):
        bad = rows.copy()
        bad[slot] = value
        return not H.fits(bad, r, box)

    assert fails(SPEED, box[H.V_ALLOW] * 1.001)
    assert fails(RHO_MAX, box[H.RHO + 1] * 1.001)
    assert fails(BAD, 1.0)
    assert fails(6, np.nan)  # a NaN coordinate shows in its axis' sum
    assert fails(3, box[H.X_HI] + 1e-6)  # past the margin (highest x)
    assert fails(0, -(box[H.X_LO] - 1e-6))  # past the margin (lowest x, negated in its row)
    assert not H.fits(rows, box[H.RATE_ALLOW] * 1.001, box)
    assert rows.shape == (END_ROW,)


def test_a_fixed_step_is_held_with_the_place_and_finiteness_checks_only(tmp_path):
    case = impact_case({"steps": 5})
    case["time"] = {"end": 1.0, "dt": 1e-4}
    sim, runner, rec = run_held(case, 20, tmp_path)
    assert (rec[:, 0] == 1e-4).all() and runner.held_batches == 4


@pytest.mark.parametrize("over, path", [
    ({"triggers": {"strength_reduction": {"times": [0.0, 1.0], "factors": [1.0, 1.5]}}}, "triggers.strength_reduction"),
    ({"outputs": [{"writer": "series", "interval": 0.0}]}, "outputs.0.interval"),
    ({"boundaries": [{"type": "wall", "side": "y-", "condition": "slip"},
                     {"type": "surface_load", "name": "footing", "region": {"min": [0.2, 0.3], "max": [0.6, 0.4]},
                      "normal": [0.0, 1.0], "pressure": 1.0e3}]}, "boundaries.1"),
])
def test_what_a_batch_cannot_carry_is_refused_with_its_path(over, path):
    case = tiny_case(**{"outputs": [{"writer": "series", "interval": 0.01}], **over})
    case["materials"]["soil"] = {"model": "drucker_prager", "density": 2000.0, "youngs_modulus": 1e6,
                                 "poisson_ratio": 0.3, "friction_angle": 30.0, "cohesion": 100.0}
    case["solver"]["held_step"] = {"steps": 10}
    with pytest.raises(CaseError) as err:
        parse_case(case)
    assert path in [p for p, _ in err.value.problems]
    case["solver"].pop("held_step")
    parse_case(case)  # the same case without held steps is valid


def test_a_run_over_several_ranks_is_refused(tmp_path):
    """Before any work on several ranks (parallel/slabs.refuse_unsplittable): particles move between ranks every
    step, which a batch cannot carry."""
    from geompm.parallel.slabs import refuse_unsplittable

    scene = scene_from_dict(impact_case({"steps": 4}), tmp_path)
    with pytest.raises(CaseError) as err:
        refuse_unsplittable(scene, 2)
    assert [p for p, _ in err.value.problems] == ["solver.held_step"]
    refuse_unsplittable(scene_from_dict(impact_case(), tmp_path), 2)  # without held steps it runs on ranks


def test_particles_that_leave_the_grid_end_a_batch_and_are_deleted_as_in_an_ordinary_run(tmp_path):
    """A block thrown out of the grid at 5 m/s (run.on_leave_domain = delete): the check ends the batch at the
    step after which particles lie beyond the batch's cells, and the domain check deletes the same 40 particles
    an ordinary run deletes, within a step of the same time."""
    out = []
    for held in (None, {"steps": 10}):
        case = tiny_case(outputs=[], boundaries=[], gravity=[0.0, 0.0], run={"on_leave_domain": "delete"})
        case["bodies"][0]["velocity"] = [5.0, 0.0]
        if held:
            case["solver"]["held_step"] = held
        sim = Simulation(scene_from_dict(case, tmp_path))
        runner = Runner(sim, tmp_path, [], progress=False)
        summary = runner.run(until=0.15)
        out.append((runner.deleted, sim.state.n, summary.steps, runner.held_batches))
    (d0, n0, s0, _), (d1, n1, s1, b1) = out
    assert d0 == d1 == 40 and n0 == n1 == 24
    assert b1 < s1 / 3  # batches of several steps, ended where the block left its cells
