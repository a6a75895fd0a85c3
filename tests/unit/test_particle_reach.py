"""Particle stages skipped where they cannot reach the particles (ParticleStage.particle_reach,
backend/cpu.py particle_stages; issue 38's per-pass table: a box's walls cost 8-11 % of a step).

G2P finds the moved particles' box as a by-product; a half-space whose deepest box corner is not behind
it is not run.  Checked here: the box is exactly the particles' bounds (2D and 3D, USL and MUSL); a run
with the skip gives bit-for-bit the positions, velocities and stresses of a run with every pass, in a
scene where particles do end behind a plane (so some passes run and some are skipped); and the
half-space's reach is exact: never None while a point of the box is behind the plane, and its grown box
holds every point the rule moves.
"""

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.boundaries.halfspace import N0, P0, HalfSpace, halfspace_particle_rule
from geompm.contract.stages import ParticleStage
from geompm.engine.scheduler import Simulation


def _case(dim, musl=False):
    """An elastic block thrown down onto a friction plane that cuts the cells between nodes (y = 0.08 m, h =
    0.05 m), in a box of walls; damping on, so a stage that does not move particles sits among them."""
    lo, hi = [0.3, 0.1, 0.3][:dim], [0.6, 0.4, 0.6][:dim]
    vel = [1.0, -20.0, 0.5][:dim]  # fast enough to end steps behind the plane
    walls = [{"type": "wall", "side": s} for s in ("x-", "x+", "y+", "z-", "z+")[:2 * dim - 1]]
    return {
        "name": "reach", "dimension": dim,
        "grid": {"origin": [0.0] * dim, "extent": [1.0] * dim, "cell_size": 0.05 if dim == 2 else 0.1},
        "time": {"end": 0.1, "cfl": 0.4}, "gravity": [0.0, -9.81, 0.0][:dim],
        "solver": {"update": "musl" if musl else "usl"},
        "materials": {"block": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e6,
                                "poisson_ratio": 0.2}},
        "bodies": [{"material": "block", "geometry": {"type": "box", "min": lo, "max": hi}, "velocity": vel}],
        "boundaries": [*walls, {"type": "plane", "point": [0.0, 0.08, 0.0][:dim],
                                "normal": [0.0, 1.0, 0.0][:dim], "condition": "friction", "friction": 0.3}],
        "damping": [{"model": "artificial", "xi": 0.002}],
    }


def _run(case, steps, skip):
    """(positions, velocities, stresses, half-space passes run, half-space passes asked) after ``steps``
    steps."""
    reach = HalfSpace.particle_reach
    if not skip:
        HalfSpace.particle_reach = ParticleStage.particle_reach
    try:
        sim = Simulation(scene_from_dict(case))
        be, ran, asked = sim.backend, [0], [0]
        inner_pass, inner_stages = be._particle_pass, be.particle_stages

        def counted(stage, *a):
            ran[0] += isinstance(stage, HalfSpace)
            return inner_pass(stage, *a)

        def every(stages, *a):
            asked[0] += sum(isinstance(s, HalfSpace) for s in stages)
            return inner_stages(stages, *a)

        be._particle_pass, be.particle_stages = counted, every
        for _ in range(steps):
            sim.step(sim.stable_dt())
    finally:
        HalfSpace.particle_reach = reach
    st = sim.state
    return st.p_x.copy(), st.p_v.copy(), st.p_stress.copy(), ran[0], asked[0]


@pytest.mark.parametrize("dim,musl", [(2, False), (2, True), (3, False)])
def test_skipping_changes_no_bit(dim, musl):
    """Against a run of every pass: identical state; the plane's pass runs on the steps some particle
    ends behind it (a run that skipped it too differs: checked by hand), and most half-space passes are
    skipped."""
    case = _case(dim, musl)
    steps = 60 if dim == 2 else 25
    *skipped, ran, asked = _run(case, steps, skip=True)
    *every, ran_all, asked_all = _run(case, steps, skip=False)
    for a, b in zip(skipped, every):
        assert np.array_equal(a, b)
    assert ran_all == asked_all == asked  # without the skip every asked pass runs
    assert 0 < ran < asked / 2  # some pass ran: particles did end behind the plane; most were skipped


@pytest.mark.parametrize("dim,musl", [(2, False), (2, True), (3, False)])
def test_g2p_box_is_the_particles_bounds(dim, musl):
    """The box G2P hands the particle stages is exactly (min, max) of the moved positions."""
    sim = Simulation(scene_from_dict(_case(dim, musl)))
    be, seen = sim.backend, []
    inner = be.particle_stages

    def record(*a):
        seen.append((be.p_box, sim.state.p_x.min(axis=0), sim.state.p_x.max(axis=0)))
        return inner(*a)

    be.particle_stages = record
    for _ in range(5):
        sim.step(sim.stable_dt())
    assert len(seen) == 5
    for (lo, hi), xmin, xmax in seen:
        assert np.array_equal(lo, xmin) and np.array_equal(hi, xmax)
    assert be.p_box is None  # used once, then forgotten


def _halfspace(point, normal):
    hs = HalfSpace.__new__(HalfSpace)
    prm = np.zeros(9)
    prm[P0:P0 + len(point)] = point
    prm[N0:N0 + len(normal)] = np.asarray(normal) / np.linalg.norm(normal)
    hs.prm = prm
    return hs


def test_halfspace_reach_is_exact():
    """Random slanted planes and boxes (3D): where reach is None no point of the box is behind the plane
    (corners included, and a box touching the plane exactly); otherwise every point the rule moves lands
    in the grown box."""
    rng = np.random.default_rng(38)
    rule = halfspace_particle_rule.py_func
    skipped = reached = 0
    for _ in range(300):
        hs = _halfspace(rng.normal(size=3) * 0.3, rng.normal(size=3))
        lo = rng.uniform(-1.0, 0.5, 3)
        hi = lo + rng.uniform(0.0, 0.8, 3)
        corners = np.array([[(lo, hi)[(c >> a) & 1][a] for a in range(3)] for c in range(8)])
        pts = np.vstack([corners, rng.uniform(lo, hi, (64, 3))])
        reach = hs.particle_reach(hs.prm, lo, hi)
        moved = []
        for x in pts:
            x = x.copy()
            before = x.copy()
            rule(hs.prm, None, 0.0, 0, x, x, np.zeros(3), np.zeros((3, 3)), 1.0, np.zeros(6), None, None)
            if not np.array_equal(x, before):
                moved.append(x)
        if reach is None:
            skipped += 1
            assert not moved
        else:
            reached += 1
            for x in moved:
                assert np.all(x >= reach[0]) and np.all(x <= reach[1])
    assert skipped > 30 and reached > 30
    touching = _halfspace([0.0, 0.25, 0.0], [0.0, 1.0, 0.0])  # the box's floor on the plane: phi = 0, kept
    assert touching.particle_reach(touching.prm, np.array([0.1, 0.25, 0.1]), np.array([0.2, 0.5, 0.2])) is None
    assert touching.particle_reach(touching.prm, np.array([0.1, np.nextafter(0.25, 0.0), 0.1]),
                                   np.array([0.2, 0.5, 0.2])) is not None


def test_obstacle_guard_skipped_until_the_debris_nears_it():
    """A block thrown at a box obstacle (2D): the guard is skipped while the particles' box lies beside its
    lattice and runs once the block nears it; the positions and the obstacle's force history are
    bit-for-bit those of a run of every guard pass, and the guard did put particles back (a run that
    skipped it throughout would differ)."""
    from geompm.obstacles.base import RigidObstacle

    case = _case(2)
    case["bodies"][0]["velocity"] = [10.0, -20.0]
    case["obstacles"] = [{"type": "box", "min": [0.72, 0.1], "max": [0.8, 0.5]}]

    def run(skip):
        reach = RigidObstacle.particle_reach
        if not skip:
            RigidObstacle.particle_reach = ParticleStage.particle_reach
        try:
            sim = Simulation(scene_from_dict(case))
            be, ran = sim.backend, [0]
            inner = be._particle_pass

            def counted(stage, *a):
                ran[0] += isinstance(stage, RigidObstacle)
                return inner(stage, *a)

            be._particle_pass = counted
            guard = next(s for s in sim.particle_stages if isinstance(s, RigidObstacle))
            forces = []
            for _ in range(60):
                sim.step(sim.stable_dt())
                forces.append(guard.force.copy())
        finally:
            RigidObstacle.particle_reach = reach
        return sim.state.p_x.copy(), np.array(forces), ran[0], guard.particles_put_back

    x, f, ran, back = run(True)
    x_all, f_all, ran_all, back_all = run(False)
    assert np.array_equal(x, x_all) and np.array_equal(f, f_all)
    assert ran_all == 60 and 0 < ran < 60
    assert back == back_all > 0
