"""The pieces of a run over MPI ranks, without MPI: slab cuts, halo ownership, particle packets and the
refusals (parallel/, docs/parallel.md).  The runs themselves are tests/mpi."""

from __future__ import annotations

import numpy as np
import pytest

from geompm.schemes.usl import Usl

from geompm.errors import CaseError
from geompm.mpm.state import ParticleState
from geompm.parallel import halo
from geompm.parallel.migrate import canonical, merge, pack
from geompm.parallel.partition import (MIN_SLAB_CELLS, balanced_cuts, check_rank_count, owners, particle_owners,
                                       split_axis)


def test_cuts_balance_particle_counts_and_keep_four_cells():
    """Cuts from a particle histogram: each slab holds n / size particles to within one cell's count, and
    slabs never thinner than MIN_SLAB_CELLS, even when every particle sits in one cell."""
    rng = np.random.default_rng(3)
    counts = rng.integers(0, 50, 200)
    for size in (2, 3, 7):
        cuts = balanced_cuts(counts, size)
        assert cuts[0] == 0 and cuts[-1] == 200 and (np.diff(cuts) >= MIN_SLAB_CELLS).all()
        per = [counts[a:b].sum() for a, b in zip(cuts, cuts[1:])]
        assert max(per) - min(per) <= 2 * counts.max(), per
    packed = np.zeros(40, np.int64)
    packed[20] = 1000  # every particle in cell 20: the first cut falls before it (333 of 1000 is nearer 0
    assert list(balanced_cuts(packed, 3)) == [0, 20, 24, 40]  # than 1000), the second 4 cells on


def test_owners_follow_the_cuts_and_clip_outside_cells():
    """A cell's owner from the cuts; a particle's from its cell, one outside the grid belonging to the
    first or the last rank; the count of those another rank owns."""
    cuts = np.array([0, 5, 12, 30])
    assert list(owners(np.array([0, 4, 5, 11, 12, 29]), cuts)) == [0, 0, 1, 1, 2, 2]
    h = 0.5
    x = np.array([[-3.0, 0.0], [0.1, 1.0], [2.6, 0.0], [5.99, 0.0], [6.0, 0.0], [99.0, 0.0]])
    own = np.empty(6, np.int64)
    assert particle_owners(x, 0, 0.0, 1.0 / h, cuts, 1, own) == (4, 0)
    assert list(own) == [0, 0, 1, 1, 2, 2]
    assert particle_owners(x, 0, 0.0, 1.0 / h, cuts, 0, own) == (4, 2)  # two are beyond the neighbour


def test_split_axis_skips_periodic_axes_and_refuses_all_periodic():
    assert split_axis([100, 40, 60]) == 0
    assert split_axis([100, 40, 60], periodic_axes=[0]) == 2
    assert split_axis([50, 50]) == 0
    assert split_axis([64, 64, 64], spans=[26, 38, 26]) == 1  # dp3d: a cube, its block longest along y
    assert split_axis([64, 64, 64], periodic_axes=[1], spans=[26, 38, 26]) == 0
    assert split_axis([120, 50], spans=[20, 40]) == 0  # the dam break: along the runout
    with pytest.raises(CaseError, match="periodic along every axis"):
        split_axis([10, 10], periodic_axes=[0, 1])


def test_too_many_ranks_for_the_split_axis_are_refused():
    """8 cells hold 2 slabs of 4; 3 ranks are refused naming the cells needed and the largest rank count."""
    check_rank_count(2, 8, 0)
    with pytest.raises(CaseError) as exc:
        check_rank_count(3, 8, 1)
    text = exc.value.problems[0][1]
    assert "3 MPI ranks need at least 12 cells along the split axis y" in text and "at most 2 ranks" in text


def test_every_node_is_counted_by_exactly_one_rank():
    """Random slabs and particle spans: each node of the union of the windows is counted by one rank
    (parallel/halo.counted), and node_parts cuts a box into parts that tile it."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        size = int(rng.integers(2, 6))
        cuts = np.cumsum(np.r_[0, rng.integers(4, 12, size)])
        windows = []
        for r in range(size):
            if rng.random() < 0.2:
                windows.append(None)
                continue
            lo_cell = int(rng.integers(cuts[r], cuts[r + 1]))
            hi_cell = int(rng.integers(lo_cell, cuts[r + 1]))
            windows.append((lo_cell - 1, hi_cell + 3))
        seen = {}
        for r in range(size):
            if windows[r] is None:
                continue
            c_lo, c_hi = halo.counted(windows, cuts, r)
            assert windows[r][0] <= c_lo <= c_hi <= windows[r][1]
            for node in range(c_lo, c_hi):
                assert node not in seen, (node, seen.get(node), r, windows, cuts)
                seen[node] = r
        union = {n for w in windows if w is not None for n in range(*w)}
        assert set(seen) == union
        for r in range(size - 2):  # only neighbours share nodes
            assert halo.overlap(windows, r, r + 2) is None
    first, last = np.array([-5, 0]), np.array([40, 9])
    parts = halo.node_parts(first, last, 0, 10, 20)
    assert [(p[0][0], p[1][0], p[2]) for p in parts] == [(-5, 9, False), (10, 19, True), (20, 40, False)]
    assert all((p[0][1], p[1][1]) == (0, 9) for p in parts)


def test_halo_slab_is_a_view_along_any_axis():
    arr = np.arange(4 * 5 * 3 * 2, dtype=float).reshape(-1, 2)
    part = halo.slab_of(arr, (4, 5, 3), 1, 10, 12, 14)
    assert part.shape == (4, 2, 3, 2)
    part += 1000.0
    grid = arr.reshape(4, 5, 3, 2)
    assert (grid[:, 2:4] >= 1000).all() and (grid[:, :2] < 1000).all() and (grid[:, 4:] < 1000).all()


def _state(n0=5, n1=4):
    rng = np.random.default_rng(1)
    n = n0 + n1
    st = ParticleState(p_x=rng.random((n, 2)), p_v=rng.random((n, 2)), p_mass=rng.random(n) + 1.0,
                       p_vol0=rng.random(n) + 1.0, p_material=np.r_[np.zeros(n0), np.ones(n1)].astype(np.int32),
                       p_body=np.zeros(n, np.int32), p_stress=rng.random((n, 6)))
    st.blocks = [(0, n0), (n0, n)]
    st.p_state = [rng.random((n0, 2)), rng.random((n1, 1))]
    return st


def test_packets_carry_every_array_and_law_state_and_keep_blocks_contiguous():
    """Particles sent from two ranks and merged: every per-particle array and each material's state
    variables arrive with their particle, material blocks stay contiguous, and the canonical order (by id
    within each block) gives back the original state exactly."""
    whole = _state()
    ref = {k: v.copy() for k, v in whole.arrays().items()}
    ref_states = [sv.copy() for sv in whole.p_state]
    a, b = _state(), _state()
    to_b = np.array([1, 0, 1, 0, 0, 1, 1, 0, 0], bool)
    packet = pack(a, to_b)
    merge(a, ~to_b, [])  # rank A keeps the rest
    merge(b, np.zeros(b.n, bool), [pack(b, ~to_b), packet])  # rank B: nothing of its own, A's and the packet
    assert b.n == 9 and b.blocks == [(0, 5), (5, 9)] and a.n == 5
    assert (b.p_material[:5] == 0).all() and (b.p_material[5:] == 1).all()
    canonical(b)
    for name, arr in ref.items():
        assert np.array_equal(getattr(b, name), arr), name
    for sv, want in zip(b.p_state, ref_states):
        assert np.array_equal(sv, want)


class _TwoRanks:
    """What Slabs reads of a communicator before any exchange."""
    size, rank, is_root = 2, 0, True


class _OneProcessScheme(Usl):
    """A scheme whose passes do not go through the decomposition (a plugin's, say)."""
    name = "one_process_usl"
    splits_over_ranks = False


def test_what_cannot_be_shared_between_ranks_is_refused_before_any_work():
    """A scheme that declares ``splits_over_ranks = False`` and a stage that declares the same are refused on
    2 ranks with a CaseError naming each one's place in the case; the saturated scheme and a surface load
    (its loaded mass and force lattice summed through the stage's comm) are not refused."""
    from geompm.parallel.slabs import Slabs
    from geompm.schema.load import load_case
    from geompm.setup.assemble import assemble
    from tests.support.cases import CASES

    scene = assemble(load_case(CASES / "debris_obstacle.json"))
    scene.scheme = _OneProcessScheme()
    stage = scene.stages[0]
    stage.__class__ = type("OneProcessStage", (type(stage),), {"splits_over_ranks": False})
    with pytest.raises(CaseError) as exc:
        Slabs(_TwoRanks(), scene)
    found = exc.value.problems
    assert any(p == "solver.update" and "scheme 'one_process_usl' runs in one process only" in m for p, m in found)
    assert any(p == stage.json_path and "cannot run on 2 MPI ranks" in m for p, m in found), found
    for name, sets in (("saturated_debris_obstacle", []), ("loaded_column", ["grid.cell_size=0.1"])):
        assert Slabs(_TwoRanks(), assemble(load_case(CASES / f"{name}.json", sets))).size == 2
