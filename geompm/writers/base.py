"""Writer plugin shape: ``open(run_dir, sim)``, ``write(sim)``, ``close(sim)``.

The runner calls ``write`` at t = 0, every ``interval`` simulated seconds
(every step when the interval is 0) and at the end of the run.  For
checkpoints, ``state()`` returns what the writer needs to carry on (plain JSON
values) and ``resume(run_dir, sim, state)`` replaces ``open`` on a resumed run:
it must drop whatever was written after that state, so the resumed output has
no duplicate and no missing entry.  Every file must be written so that a
killed process leaves it readable (files/atomic.atomic_path, or one write() per row).
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

from geompm.contract.plugin import Plugin


class Writer(Plugin):
    #: whether the obstacles must spread their contact force onto their faces (recorded.ContactForceStage)
    wants_face_forces: ClassVar[bool] = False
    #: the files it writes, as glob patterns relative to the run folder (geompm.run's Run.outputs and
    #: geompm plot find them through this)
    files: ClassVar[tuple[str, ...]] = ()
    #: what it reads of the particles when a run is shared between MPI ranks (docs/parallel.md):
    #: "gathered": rank 0 alone opens, writes and closes it, with every particle of the run gathered there
    #: (in material blocks, each ordered by particle id); "none": rank 0 alone, and it reads no particle;
    #: "own": every rank calls it with its own particles, it joins the ranks' parts through
    #: ``sim.domain.comm`` itself and writes files on rank 0 only (``comm.is_root``)
    ranks: ClassVar[str] = "gathered"

    def __init__(self, params, interval: float):
        self.params = params
        self.interval = float(interval)

    def open(self, run_dir: Path, sim) -> None:
        pass

    def write(self, sim) -> None:
        raise NotImplementedError

    def close(self, sim) -> None:
        pass

    def state(self) -> dict:
        return {}

    def resume(self, run_dir: Path, sim, state: dict) -> None:
        self.open(run_dir, sim)
