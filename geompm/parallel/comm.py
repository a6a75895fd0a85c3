"""The processes of one run, and every operation that joins them.

``SERIAL`` is one process: each operation returns its input, so a run in one process calls the same code
and computes the same bits as it did before runs were shared.  ``MpiComm`` wraps an mpi4py communicator
(``MPI.COMM_WORLD`` under ``mpiexec``).

Every reduction is made in rank order on every rank from the gathered parts (``sum``, ``max``,
``rows``): MPI's own Allreduce may combine the parts in a different order on different ranks, and a sum
that differs in its last bit between ranks would let their copies of a stage's state (an obstacle's force
history) drift apart.  The parts are a few numbers per step, so gathering them costs what one Allreduce
costs.
"""

from __future__ import annotations

import numpy as np


class Serial:
    """One process."""

    size = 1
    rank = 0
    is_root = True

    def sum(self, values):
        """Element-wise sum over the ranks of a vector (float64), in rank order."""
        return np.asarray(values, np.float64)

    def max(self, values):
        """Element-wise largest over the ranks (NaN where a part is NaN)."""
        return np.asarray(values, np.float64)

    def min(self, values):
        return np.asarray(values, np.float64)

    def rows(self, rows: np.ndarray) -> np.ndarray:
        """A reduction's accumulator rows (threads, k) of every rank, stacked in rank order: a stage sums
        or takes the largest over the rows as it does over one process's threads."""
        return rows

    def gather(self, obj) -> list:
        """Every rank's ``obj`` in rank order, on every rank."""
        return [obj]

    def stack(self, values) -> np.ndarray:
        """Every rank's vector of numbers (float64, one length on every rank) as rows in rank order, on
        every rank: a gather without pickling."""
        return np.asarray(values, np.float64).reshape(1, -1)

    def gather_root(self, obj) -> list | None:
        """Every rank's ``obj`` in rank order on rank 0, None elsewhere."""
        return [obj]

    def bcast(self, obj):
        """Rank 0's ``obj`` on every rank."""
        return obj

    def exchange(self, outgoing: list) -> list:
        """``outgoing[r]`` goes to rank r; returns what each rank sent here, in rank order."""
        return list(outgoing)

    def shift(self, up, down):
        """Send ``up`` to rank + 1 and ``down`` to rank - 1 (Python objects; None: nothing); returns
        (what rank - 1 sent up, what rank + 1 sent down), None at the ends."""
        return None, None

    def swap(self, send, dest: int, recv, source: int) -> None:
        """Send the array ``send`` to rank ``dest`` while receiving rank ``source``'s into ``recv`` (either
        None: nothing that way); both sides know the sizes."""
        if send is not None or recv is not None:
            raise ValueError("one process has no other rank to swap with")

    def barrier(self) -> None:
        pass

    def abort(self, code: int) -> None:
        raise SystemExit(code)


SERIAL = Serial()


class MpiComm(Serial):
    """The ranks of an mpi4py communicator."""

    is_root = False

    def __init__(self, comm):
        self.comm = comm
        self.size = comm.Get_size()
        self.rank = comm.Get_rank()
        self.is_root = self.rank == 0
        #: bytes this rank sent in point-to-point exchanges (halo sums, migration), for the scaling report
        self.bytes_sent = 0

    def _parts(self, values) -> np.ndarray:
        mine = np.ascontiguousarray(values, np.float64).reshape(-1)
        parts = np.empty((self.size, mine.size), np.float64)
        self.comm.Allgather(mine, parts)
        return parts

    def sum(self, values):
        parts = self._parts(values)
        total = parts[0].copy()
        for r in range(1, self.size):
            total += parts[r]
        return total.reshape(np.shape(values))

    def max(self, values):
        return np.max(self._parts(values), axis=0).reshape(np.shape(values))

    def min(self, values):
        return np.min(self._parts(values), axis=0).reshape(np.shape(values))

    def stack(self, values):
        return self._parts(values)

    def rows(self, rows):
        rows = np.asarray(rows)
        flat = self._parts(rows.astype(np.float64, copy=False))
        return flat.reshape((self.size * rows.shape[0],) + rows.shape[1:])

    def gather(self, obj) -> list:
        return self.comm.allgather(obj)

    def gather_root(self, obj):
        return self.comm.gather(obj, root=0)

    def bcast(self, obj):
        return self.comm.bcast(obj, root=0)

    def exchange(self, outgoing):
        self.bytes_sent += sum(_nbytes(o) for r, o in enumerate(outgoing) if r != self.rank)
        return self.comm.alltoall(outgoing)

    def shift(self, up, down):
        from mpi4py import MPI

        below = self.rank - 1 if self.rank > 0 else MPI.PROC_NULL
        above = self.rank + 1 if self.rank < self.size - 1 else MPI.PROC_NULL
        self.bytes_sent += _nbytes(up) + _nbytes(down)
        from_below = self.comm.sendrecv(up, dest=above, source=below)
        from_above = self.comm.sendrecv(down, dest=below, source=above)
        return from_below, from_above

    def swap(self, send, dest, recv, source):
        from mpi4py import MPI

        if send is not None:
            self.bytes_sent += send.nbytes
        self.comm.Sendrecv(send, dest=dest if send is not None else MPI.PROC_NULL,
                           recvbuf=recv, source=source if recv is not None else MPI.PROC_NULL)

    def barrier(self):
        self.comm.Barrier()

    def abort(self, code):
        self.comm.Abort(code)


def _nbytes(obj) -> int:
    if obj is None:
        return 0
    if isinstance(obj, np.ndarray):
        return obj.nbytes
    if isinstance(obj, dict):
        return sum(_nbytes(v) for v in obj.values())
    if isinstance(obj, (list, tuple)):
        return sum(_nbytes(v) for v in obj)
    return 0
