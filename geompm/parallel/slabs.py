"""One run on several MPI ranks: each owns a slab of cells and the particles in it (docs/parallel.md).

A step on rank r (engine/scheduler.py calls these around the backend's kernels):

1. ``before_step``: particles that left the slab go to the rank that owns their cell now, packed with
   every per-particle array and their law's state variables (parallel/migrate.py); every
   ``solver.rebalance_interval`` steps the cuts are first moved so that each slab holds about n / size particles
   (parallel/partition.py).
2. ``window``: the grid window of the slab's particles, across the other axes as wide as the whole run's
   (parallel/halo.py); a particle outside the grid on any rank stops every rank with its message.
3. P2G on the rank's own particles, then ``sum_halo``: the nodes two neighbours share get both partial
   sums (mass, momentum, force), so every node of the window holds the sum over all particles.
4. The grid update and the grid stages on the whole window; a stage's reduction counts the nodes
   ``node_parts`` marks, and the accumulator rows of every rank are stacked (``comm.rows``), so every
   rank hands its stages the same numbers and their states (an obstacle's force history) stay equal.
5. G2P, the particle stages and the stress update on the rank's own particles.

Where the answers differ from one process: a node's P2G sum is the sum of two ranks' partial sums (each
in particle order), and every reduction (kinetic energy, an obstacle's force, hazard-map column sums) is
summed per rank and then over ranks, so the result matches the one-process run to round-off, not bit
for bit.  The stable step, the health checks' and the series' maxima are exact.
"""

from __future__ import annotations

import numpy as np

from geompm.errors import CaseError, SimulationError
from geompm.mpm.grid import window_extent
from geompm.parallel import halo
from geompm.parallel.migrate import canonical, merge, nparticles, pack
from geompm.parallel.partition import (balanced_cuts, check_rank_count, owners, particle_cells, particle_owners,
                                       split_axis)
from geompm.parallel.whole import Whole


def refuse_unsplittable(scene, size: int) -> None:
    """CaseError before any work for what a run on several ranks cannot do yet (docs/parallel.md)."""
    problems = []
    scheme = scene.scheme
    if not type(scheme).splits_over_ranks:
        problems.append(("solver.update", f"scheme '{scheme.name}' runs in one process only; this run was "
                                          f"started on {size} MPI ranks"))
    for stage in scene.stages:
        if not type(stage).splits_over_ranks:
            problems.append((stage.json_path or stage.label,
                             f"stage '{stage.label}' ({type(stage).name}) sums particles outside its "
                             f"pass, so it cannot run on {size} MPI ranks; run the case in one process"))
    if scene.held_step is not None:
        problems.append(("solver.held_step", f"held steps run in one process only (particles move between ranks every "
                                             f"step); this run was started on {size} MPI ranks: remove "
                                             "solver.held_step or run the case in one process"))
    if problems:
        raise CaseError(problems)


class Slabs(Whole):
    def __init__(self, comm, scene):
        refuse_unsplittable(scene, comm.size)
        g = scene.grid
        self.comm, self.size, self.rank = comm, comm.size, comm.rank
        self.spec = g
        st = scene.state
        spans = (np.floor((st.p_x.max(axis=0) - g.origin) / g.h) - np.floor((st.p_x.min(axis=0) - g.origin) / g.h)
                 + 1) if st.n else None
        self.axis = split_axis(g.ncells, [a for s in scene.stages for a in s.periodic_axes()], spans)
        self.ncells = int(g.ncells[self.axis])
        check_rank_count(self.size, self.ncells, self.axis)
        self.rebalance_every = int(scene.rebalance_interval)
        self.cuts = None
        self.windows = None  # per rank: (lo, hi) nodes along the axis of its window, None without particles
        self.c_range = None  # the nodes [c_lo, c_hi) along the axis whose reductions this rank counts
        self.sent_particles = 0  # particles this rank sent to others
        self.halo_nodes = 0  # nodes summed with neighbours, all steps
        self.halo_bytes_sent = 0  # bytes sent to neighbours
        self.halo_sums = 0  # halo sums made
        self.rebalanced = 0
        self._owner = np.empty(0, np.int64)  # each particle's rank, reused every step

    # -- particles -----------------------------------------------------------------------------
    def _cells(self, state):
        g, a = self.spec, self.axis
        return particle_cells(state.p_x, a, float(g.origin[a]), g.h, self.ncells)

    def distribute(self, state) -> None:
        if self.cuts is not None:  # distributed already: the state is this rank's slab, not the whole
            return
        cells = self._cells(state)
        self.cuts = balanced_cuts(np.bincount(cells, minlength=self.ncells), self.size)
        merge(state, owners(cells, self.cuts) == self.rank, [])

    def before_step(self, sim) -> None:
        st = sim.state
        moved = False
        if self.rebalance_every and sim.step_count and sim.step_count % self.rebalance_every == 0:
            counts = self.comm.sum(np.bincount(self._cells(st), minlength=self.ncells).astype(np.float64))
            cuts = balanced_cuts(np.rint(counts).astype(np.int64), self.size)
            if not (cuts == self.cuts).all():
                self.cuts = cuts
                self.rebalanced += 1
                moved = True
        g, a = self.spec, self.axis
        if self._owner.shape[0] < st.n:
            self._owner = np.empty(int(st.n * 1.25) + 16, np.int64)
        own = self._owner[:st.n]
        away, far = particle_owners(st.p_x, a, float(g.origin[a]), 1.0 / g.h, self.cuts, self.rank, own)
        if self.comm.max([float(far or moved)])[0] > 0.0:  # after a rebalance: anyone to anyone
            out = [None] * self.size
            if away:
                for r in np.unique(own[own != self.rank]):
                    out[r] = pack(st, own == r)
            got = self.comm.exchange(out)
            arrived = [p for r, p in enumerate(got) if r != self.rank]
        else:  # a step moves a particle less than a cell, and a slab is 4 cells: to a neighbour only
            down, up = (pack(st, own == r) if away and (own == r).any() else None
                        for r in (self.rank - 1, self.rank + 1))
            out = [down, up]
            arrived = list(self.comm.shift(up, down))
        self.sent_particles += sum(nparticles(p) for p in out)
        if away or any(nparticles(p) for p in arrived):
            merge(st, own == self.rank, arrived)

    def gathered(self, state):
        import copy

        parts = self.comm.gather_root(pack(state, np.ones(state.n, bool)))
        if parts is None:
            return None
        whole = copy.copy(state)
        whole.sort_work = None
        merge(whole, np.zeros(state.n, bool), parts)
        canonical(whole)
        return whole

    def stable_dt(self, backend) -> float:
        """The limits of backend/timestep.py from the largest wave speed, speed and stretching rate of all
        ranks: the step one process takes, to the last bit (maxima do not depend on order)."""
        if backend.scene.dt_fixed is not None:
            return backend.scene.dt_fixed
        c, v, rate = self.comm.max(np.array(backend.dt_parts(), np.float64))
        return backend.step_from(float(c) + float(v), float(rate))

    # -- grid ----------------------------------------------------------------------------------
    def window(self, backend):
        spec, a = self.spec, self.axis
        mine = backend.particle_cells()
        d = spec.dim
        rows = self.comm.stack(np.full(2 * d, np.nan) if mine is None else mine.reshape(-1))
        every = [None if np.isnan(row[0]) else row.reshape(2, d).astype(np.int64) for row in rows]
        bad = [r for r, b in enumerate(every) if b is not None and ((b[0] < -1).any() or (b[1] > spec.ncells).any())]
        if bad:
            message = None
            if self.rank == bad[0]:
                try:
                    window_extent(spec, mine, lambda: backend.host_state().p_x)
                except SimulationError as exc:
                    message = str(exc)
            raise SimulationError(self.comm.gather(message)[bad[0]] or "a particle left the grid")
        live = [b for b in every if b is not None]
        if not live:
            raise SimulationError("no particle is left on any rank")
        b = np.array([np.min([x[0] for x in live], axis=0), np.max([x[1] for x in live], axis=0)])
        self.windows = [None if x is None else (int(x[0, a]) - 1, int(x[1, a]) + 3) for x in every]
        lo, nloc = window_extent(spec, b, None)
        if mine is None:
            nloc[a] = 0
            self.c_range = (int(lo[a]), int(lo[a]))
        else:
            lo[a], nloc[a] = self.windows[self.rank][0], self.windows[self.rank][1] - self.windows[self.rank][0]
            self.c_range = halo.counted(self.windows, self.cuts, self.rank)
        return backend.window_at(lo, nloc)

    def sum_halo(self, view, arrays) -> None:
        """Neighbours add each other's partial sums on the nodes they share.  A device backend's arrays
        (CUDA) travel through the host: copied down, summed, copied back."""
        held = [x for x in arrays if x is not None]
        arrays = [x if isinstance(x, np.ndarray) else x.copy_to_host() for x in held]
        self._sum_on_host(view, arrays)
        for dev, host in zip(held, arrays):
            if dev is not host:
                dev.copy_to_device(host)

    def _sum_on_host(self, view, arrays) -> None:
        r, a = self.rank, self.axis
        lo_a = int(view.lo[a])
        below, above = halo.overlap(self.windows, r - 1, r), halo.overlap(self.windows, r, r + 1)

        def packed(ov):
            return None if ov is None else np.concatenate(
                [np.ascontiguousarray(halo.slab_of(x, view.nloc, a, lo_a, *ov)).reshape(-1) for x in arrays])

        send_up, send_down = packed(above), packed(below)
        self.halo_bytes_sent += sum(b.nbytes for b in (send_up, send_down) if b is not None)
        from_below = None if below is None else np.empty_like(send_down)
        from_above = None if above is None else np.empty_like(send_up)
        self.comm.swap(send_up, r + 1, from_below, r - 1)
        self.comm.swap(send_down, r - 1, from_above, r + 1)
        for ov, got in ((below, from_below), (above, from_above)):
            if ov is None:
                continue
            k = 0
            for x in arrays:
                part = halo.slab_of(x, view.nloc, a, lo_a, *ov)
                part += got[k:k + part.size].reshape(part.shape)
                k += part.size
            self.halo_nodes += (ov[1] - ov[0]) * int(np.prod(view.nloc)) // max(int(view.nloc[a]), 1)
        self.halo_sums += 1

    def node_parts(self, first, last):
        return halo.node_parts(first, last, self.axis, *self.c_range)

    def report(self, state) -> dict:
        """status.json's ``mpi`` entry (a collective call): the slabs, how often they moved, the particles
        each rank holds in ``state`` and the traffic of every rank."""
        sent = self.comm.gather(dict(self.measured(), particles=state.n))
        return {"ranks": self.size, "split_axis": "xyz"[self.axis], "cuts": [int(c) for c in self.cuts],
                "particles_per_rank": [int(m["particles"]) for m in sent],
                "rebalanced": self.rebalanced, "particles_migrated": sum(m["sent_particles"] for m in sent),
                "halo_bytes_sent_per_rank": [int(m["bytes_sent"]) for m in sent],
                "halo_sums": self.halo_sums}

    def measured(self) -> dict:
        """This rank's traffic so far: particles sent, halo sums, halo nodes and bytes sent."""
        return {"sent_particles": self.sent_particles, "halo_sums": self.halo_sums,
                "halo_nodes": self.halo_nodes,
                "bytes_sent": self.halo_bytes_sent, "all_bytes_sent": getattr(self.comm, "bytes_sent", 0)}

