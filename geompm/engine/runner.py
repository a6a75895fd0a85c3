"""Run a scene to its end time: output schedule, progress bar, summary.

Each writer writes at t = 0, at every multiple of its interval (the time step
is shortened to land on output times exactly) and at the end.  Writers are
closed (files flushed) even when the run stops with an error or Ctrl-C.
"""

from __future__ import annotations

import math
import time as wallclock
from dataclasses import dataclass

from .scheduler import Simulation


@dataclass
class RunSummary:
    steps: int
    sim_time: float
    wall_seconds: float
    particles: int

    @property
    def particle_steps_per_second(self) -> float:
        return self.particles * self.steps / max(self.wall_seconds, 1e-12)


class _Progress:
    """tqdm bar over simulated time; silent when not attached to a terminal or quiet."""

    def __init__(self, end, enabled):
        self.bar = None
        if enabled:
            from tqdm import tqdm

            self.bar = tqdm(total=end, unit="s(sim)", disable=None, leave=True,
                            bar_format="{l_bar}{bar}| t={n:.4g}/{total:.4g} s [{elapsed}<{remaining}{postfix}]")
        self.last = 0.0

    def update(self, sim, t0):
        if self.bar is None:
            return
        self.bar.update(sim.time - self.last)
        self.last = sim.time
        self.bar.set_postfix_str(f"{sim.step_count / max(wallclock.perf_counter() - t0, 1e-9):.0f} steps/s",
                                 refresh=False)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _next_due(t, interval):
    return (math.floor(t / interval * (1 + 1e-12) + 1e-9) + 1) * interval


def run(sim: Simulation, run_dir, writers, progress: bool = True, until: float | None = None) -> RunSummary:
    end = sim.scene.end_time if until is None else until
    for w in writers:
        w.open(run_dir, sim)
    due = [0.0] * len(writers)
    last_written = [None] * len(writers)
    bar = _Progress(end, progress)
    t0 = wallclock.perf_counter()

    def emit(force=False):
        for k, w in enumerate(writers):
            if last_written[k] == sim.step_count:
                continue
            if force or w.interval == 0.0 or sim.time >= due[k] * (1 - 1e-12) - 1e-15:
                w.write(sim)
                last_written[k] = sim.step_count
                if w.interval > 0.0:
                    due[k] = _next_due(sim.time, w.interval)

    try:
        emit(force=True)
        while sim.time < end * (1 - 1e-12):
            dt = sim.stable_dt()
            target = min([end] + [due[k] for k, w in enumerate(writers) if w.interval > 0.0])
            gap = target - sim.time
            if dt >= gap:
                dt = gap
            elif 1.5 * dt > gap:
                dt = 0.5 * gap
            sim.step(dt)
            emit()
            if sim.step_count % 20 == 0:
                bar.update(sim, t0)
        emit(force=True)
        bar.update(sim, t0)
    finally:
        bar.close()
        for w in writers:
            w.close(sim)
    return RunSummary(sim.step_count, sim.time, wallclock.perf_counter() - t0, sim.state.n)
