"""The whole run seen from rank 0: the simulation with every rank's particles gathered into one state.

Writers that read particles without joining the ranks' parts themselves (``Writer.ranks = "gathered"``:
VTU, HDF5) and checkpoints are handed this on rank 0; every other attribute is the simulation's own
(time, step, scene, stages), which is the same on every rank.
"""

from __future__ import annotations


class Gathered:
    def __init__(self, sim, state):
        self._sim = sim
        self.state = state

    def __getattr__(self, name):
        return getattr(self._sim, name)


def gathered(sim):
    """The simulation itself in one process; on several ranks (a collective call) a Gathered view on rank 0
    and None elsewhere."""
    whole = sim.domain.gathered(sim.state)
    if whole is sim.state:
        return sim
    return None if whole is None else Gathered(sim, whole)
