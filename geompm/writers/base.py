"""Writer plugin shape: ``open(run_dir, sim)``, ``write(sim)``, ``close(sim)``.

The runner calls ``write`` at t = 0, every ``interval`` simulated seconds
(every step when the interval is 0) and at the end of the run.
"""

from __future__ import annotations

from pathlib import Path

from ..plugin import Plugin


class Writer(Plugin):
    def __init__(self, params, interval: float):
        self.params = params
        self.interval = float(interval)

    def open(self, run_dir: Path, sim) -> None:
        pass

    def write(self, sim) -> None:
        raise NotImplementedError

    def close(self, sim) -> None:
        pass
