"""Run a scene to its end time: output schedule, checkpoints, health checks, progress bar.

Each writer writes at t = 0, at every multiple of its interval (the time step
is shortened to land on output times exactly) and at the end; one of interval 0
after every step, or with held steps (solver.held_step, engine/held_step.py)
after every batch.  After every
step the health check (health.py) stops a run that has become unphysical.
Checkpoints (checkpoint.py) are written every ``run.checkpoint_interval``
simulated seconds, every ``run.checkpoint_wall_minutes`` of wall time, when a
stop is requested (SIGINT/SIGTERM, through ``Runner.request_stop``) and at the
end; ``Runner.resume`` continues from one bit for bit.  Writers are closed
(files flushed) whatever happens.
"""

from __future__ import annotations

import logging
import math
import time as wallclock
from dataclasses import dataclass

from geompm.engine import checkpoint
from geompm.engine.gathered import gathered
from geompm.engine.health import HealthCheck, check_domain
from geompm.engine.held_step import widened
from geompm.engine.scheduler import Simulation

log = logging.getLogger("geompm")

#: when the gap to the next output time is below this many stable steps, it is crossed in two equal halves:
#: a full step would leave a sliver under half a step to land on the output with
SPLIT_BEFORE_OUTPUT = 1.5
#: a step that fell below this fraction of the first step (not because an output time is near) is warned
#: about once: the run will take longer than `geompm validate` estimated
SLOW_STEP_FRACTION = 0.1
#: the progress bar is redrawn every this many steps (a redraw costs about a step of a small case)
PROGRESS_EVERY = 20


class Interrupted(Exception):
    """The run stopped on request after writing a checkpoint."""


@dataclass
class RunSummary:
    steps: int
    sim_time: float
    wall_seconds: float
    particles: int
    steps_this_session: int | None = None  # steps since this session began (resumed runs)
    deleted: int = 0

    @property
    def particle_steps_per_second(self) -> float:
        steps = self.steps if self.steps_this_session is None else self.steps_this_session
        return self.particles * steps / max(self.wall_seconds, 1e-12)


class _Progress:
    """tqdm bar over simulated time; silent when not attached to a terminal or quiet."""

    def __init__(self, start, end, enabled):
        self.bar = None
        if enabled:
            from tqdm import tqdm

            self.bar = tqdm(total=end, initial=start, unit="s(sim)", disable=None, leave=True,
                            bar_format="{l_bar}{bar}| t={n:.4g}/{total:.4g} s [{elapsed}<{remaining}{postfix}]")
        self.last = start

    def update(self, sim, steps, t0):
        if self.bar is None:
            return
        self.bar.update(sim.time - self.last)
        self.last = sim.time
        self.bar.set_postfix_str(f"{steps / max(wallclock.perf_counter() - t0, 1e-9):.0f} steps/s", refresh=False)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _next_due(t, interval):
    return (math.floor(t / interval * (1 + 1e-12) + 1e-9) + 1) * interval


class Runner:
    def __init__(self, sim: Simulation, run_dir, writers, progress: bool = True):
        self.sim = sim
        self.run_dir = run_dir
        self.writers = writers
        self.progress = progress
        opts = sim.scene.run_options  # schema.case.RunSpec
        self.ckpt_interval = opts.checkpoint_interval
        wall_min = opts.checkpoint_wall_minutes
        self.ckpt_wall = None if wall_min is None else 60.0 * wall_min
        self.keep = opts.keep_checkpoints
        self.delete_outside = opts.on_leave_domain == "delete"
        self.due = [0.0] * len(writers)
        self.last_written = [None] * len(writers)
        self.ckpt_due = self.ckpt_interval
        self.wall_before = 0.0  # wall seconds of earlier sessions (resumed runs)
        self.deleted = 0
        self.stop_reason = None
        self.resumed = False
        self._warned = set()

    # -- control ------------------------------------------------------------------------
    def request_stop(self, reason: str) -> None:
        """Ask the loop to write a checkpoint and stop after the current step (signal-safe)."""
        self.stop_reason = reason

    def warn_once(self, key: str, message: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            log.warning(f"warning: {message}")

    # -- checkpoints ----------------------------------------------------------------------
    def _meta(self) -> dict:
        return {"due": self.due, "last_written": self.last_written, "ckpt_due": self.ckpt_due,
                "wall": self.wall_before + wallclock.perf_counter() - self.t0, "deleted": self.deleted}

    def checkpoint(self):
        """Write a checkpoint (rank 0, from every rank's particles: a collective call); its path on rank 0."""
        whole = gathered(self.sim)
        path = None if whole is None else checkpoint.save(self.run_dir, whole, self._meta(), self.writers, self.keep)
        self.last_ckpt_wall = wallclock.perf_counter()
        return path

    def resume(self) -> None:
        """Continue the run in ``run_dir`` from its newest checkpoint (call before ``run``)."""
        arrays, meta = checkpoint.load(self.run_dir)
        checkpoint.restore(self.sim, arrays, meta)
        r = meta["runner"]
        self.due, self.last_written, self.ckpt_due = r["due"], r["last_written"], r["ckpt_due"]
        self.wall_before, self.deleted = r["wall"], r["deleted"]
        self.writer_states = meta["writers"]
        self.resumed = True

    # -- the loop -------------------------------------------------------------------------
    def _each_writer(self, writers, call):
        """``call(writer, sim)`` for each writer this rank runs, with what it reads (Writer.ranks): its
        own particles, or (rank 0) every particle gathered; one process: every writer with the
        simulation."""
        sim = self.sim
        whole = gathered(sim) if any(w.ranks == "gathered" for w in writers) else sim
        for w in writers:
            if w.ranks == "own":
                call(w, sim)
            elif sim.domain.comm.is_root:
                call(w, whole if w.ranks == "gathered" else sim)

    def _emit(self, force=False):
        sim = self.sim
        due = [k for k, w in enumerate(self.writers) if self.last_written[k] != sim.step_count and
               (force or w.interval == 0.0 or sim.time >= self.due[k] * (1 - 1e-12) - 1e-15)]
        if not due:
            return
        self._each_writer([self.writers[k] for k in due], lambda w, view: w.write(view))
        for k in due:
            self.last_written[k] = sim.step_count
            if self.writers[k].interval > 0.0:
                self.due[k] = _next_due(sim.time, self.writers[k].interval)

    def _checkpoint_due(self) -> bool:
        sim = self.sim
        if self.ckpt_due is not None and sim.time >= self.ckpt_due * (1 - 1e-12):
            self.ckpt_due = _next_due(sim.time, self.ckpt_interval)
            return True
        return self.ckpt_wall is not None and self._anywhere(
            wallclock.perf_counter() - self.last_ckpt_wall >= self.ckpt_wall)

    def _anywhere(self, flag: bool) -> bool:
        """Whether ``flag`` holds on any rank (a stop request, a wall-clock checkpoint: every rank must
        take the same branch)."""
        return bool(self.sim.domain.comm.max([1.0 if flag else 0.0])[0] > 0.0)

    def _target(self, end) -> float:
        """The next time a step must land on: the end or the next output time."""
        return min([end] + [self.due[k] for k, w in enumerate(self.writers) if w.interval > 0.0])

    def _landing(self, dt, time, target):
        """The step [s] from ``dt`` at ``time``: shortened to land on ``target`` (module docstring); and whether
        it lands there."""
        gap = target - time
        if dt >= gap:
            return gap, True
        if SPLIT_BEFORE_OUTPUT * dt > gap:
            dt = 0.5 * gap
        if dt < SLOW_STEP_FRACTION * self.first_dt:
            self.warn_once("dt", f"the time step fell to {dt:.3g} s (from {self.first_dt:.3g} s) at "
                                 f"t = {time:.6g} s: the run will take longer than first estimated")
        return dt, False

    def advance(self, end):
        """One step of the loop, or one held batch of steps (engine/held_step.py): time-step control, the
        step(s), health and domain checks (no output)."""
        sim = self.sim
        dt = sim.stable_dt()
        self.health.before_step(sim, dt)
        if self.held is not None:
            self._advance_held(end, dt)
        else:
            sim.step(self._landing(dt, sim.time, self._target(end))[0])
        self.health.after_step(sim)
        removed = check_domain(sim, self.delete_outside)
        if removed:
            self.deleted += removed
            self.warn_once("deleted", f"{removed} particles left the grid at t = {sim.time:.6g} s and were deleted "
                                      "(run.on_leave_domain = delete); later deletions are counted in the summary")

    def _advance_held(self, end, stable) -> None:
        """Up to ``held_step.steps`` steps at ``fraction`` of the ``stable`` step [s], each after the first
        checked before it is taken (engine/held_step.py); the batch ends before an output time is passed, after a
        checkpoint time and before a spatial sort, so that what reads the host between steps sees every step."""
        from geompm.engine.held_step import limits

        sim, be = self.sim, self.sim.backend
        steps, fraction, margin = self.held
        hold = stable if sim.scene.dt_fixed is not None else fraction * stable
        cells = be.particle_cells()
        if cells is None:  # no particle here: one ordinary step
            sim.step(self._landing(stable, sim.time, self._target(end))[0])
            return
        cells = widened(cells, margin, sim.scene.grid)
        be.hold(limits(sim.scene, be.end_rows(), hold, cells), cells)
        every, target = sim.scene.sort_interval, self._target(end)
        after = []  # (time, step count, dt) after each step asked for
        try:
            for i in range(steps):
                if i and ((every and sim.step_count % every == 0) or not be.gate(i)):
                    break
                dt, lands = self._landing(hold, sim.time, target)
                sim.step(dt)
                after.append((sim.time, sim.step_count, sim.dt))
                if lands or (self.ckpt_due is not None and sim.time >= self.ckpt_due * (1 - 1e-12)):
                    break
        finally:
            taken = be.release(len(after))
        if taken < len(after):  # the device found a step that would have exceeded its state's stable step
            sim.time, sim.step_count, sim.dt = after[taken - 1]
        self.held_steps += taken
        self.held_batches += 1

    def start(self) -> None:
        """Set up the health check and the clocks; ``run`` calls it, ``geompm bench`` calls it before
        stepping with ``advance``."""
        self.t0 = self.last_ckpt_wall = wallclock.perf_counter()
        self.sim.distribute()
        self.health = HealthCheck(self.sim.scene, self.sim.domain.comm)
        self.first_dt = self.sim.stable_dt()
        self.held = self.sim.scene.held_step
        self.held_steps = self.held_batches = 0

    def run(self, until: float | None = None) -> RunSummary:
        sim = self.sim
        end = sim.scene.end_time if until is None else until
        self.start()
        if self.resumed:
            states = {id(w): s for w, s in zip(self.writers, self.writer_states)}
            self._each_writer(self.writers, lambda w, view: w.resume(self.run_dir, view, states[id(w)]))
        else:
            self._each_writer(self.writers, lambda w, view: w.open(self.run_dir, view))
        bar = _Progress(sim.time, end, self.progress)
        step0 = drawn = sim.step_count
        try:
            self._emit(force=not self.resumed)
            while sim.time < end * (1 - 1e-12):
                if sim.count() == 0 and not sim.pending():
                    self.warn_once("empty", f"every particle has left the grid by t = {sim.time:.6g} s: "
                                            "the run ends here")
                    break
                self.advance(end)
                self._emit()
                if sim.step_count - drawn >= PROGRESS_EVERY:  # a held batch takes several steps at once
                    bar.update(sim, sim.step_count - step0, self.t0)
                    drawn = sim.step_count
                if self._anywhere(self.stop_reason is not None):
                    self.checkpoint()
                    raise Interrupted(self.stop_reason or "a stop request on another rank")
                if self._checkpoint_due():
                    self.checkpoint()
            self._emit(force=True)
            bar.update(sim, sim.step_count - step0, self.t0)
            self.checkpoint()
        finally:
            bar.close()
            for w in self.writers:
                if w.ranks == "own" or sim.domain.comm.is_root:
                    w.close(sim)
        wall = wallclock.perf_counter() - self.t0
        return RunSummary(sim.step_count, sim.time, wall, sim.count(), sim.step_count - step0, self.deleted)


def run(sim: Simulation, run_dir, writers, progress: bool = True, until: float | None = None) -> RunSummary:
    """Run ``sim`` from its current state to ``until`` (default: the case's end time)."""
    return Runner(sim, run_dir, writers, progress).run(until)
