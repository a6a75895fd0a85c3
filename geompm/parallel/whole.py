"""The decomposition of a run in one process: the whole grid and every particle here.

The scheduler, the backend, the health check and the writers call the same methods whatever the number
of processes (parallel/slabs.py for several); here each one gives back what one process already has, so a
run in one process computes what it computed before runs could be shared.
"""

from __future__ import annotations

from geompm.parallel.comm import SERIAL


class Whole:
    comm = SERIAL
    size = 1
    rank = 0

    def distribute(self, state) -> None:
        """Keep this rank's particles of a state every rank holds whole (the start, a resume)."""

    def before_step(self, sim) -> None:
        """Move particles to the rank that owns them now (and rebalance when due)."""

    def stable_dt(self, backend) -> float:
        """The run's next step [s] (backend/timestep.py)."""
        return backend.stable_dt()

    def window(self, backend):
        """This rank's grid window (grid.GridView)."""
        return backend.window()

    def sum_halo(self, view, arrays) -> None:
        """Add the neighbours' partial sums of ``arrays`` (window arrays, nodes first) on shared nodes."""

    def node_parts(self, first, last):
        """The node box [first, last] as ((first, last, counted), ...): a reduction counts the parts
        marked counted and runs the rule on all (parallel/halo.py)."""
        return ((first, last, True),)

    def gathered(self, state):
        """Every particle of the run, in one state on rank 0 (None elsewhere)."""
        return state

    def report(self, state) -> dict:
        """What the decomposition measured, with the particles of ``state`` per rank (status.json's
        ``mpi``); empty in one process."""
        return {}


WHOLE = Whole()
