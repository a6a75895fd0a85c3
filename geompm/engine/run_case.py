"""Run a case to its end in a run folder: what ``geompm run`` does, as a library call (``geompm.run``).

    run = run_case("cases/column_collapse.json", out="runs/cc", overrides=["grid.cell_size=0.02"])
    run.exit_code, run.steps, run.series["front_x"], run.outputs["vtu"], run.peak_forces

The steps, in order: the case is loaded and assembled (a bad case raises CaseError before any folder is
made), the first step is checked (engine/first_step.py), the run folder is made (or, with ``resume``,
checked against the case it was started with), run.log is opened beside the terminal messages, the runner
steps the Simulation with its writers, checkpoints and health checks, and status.json says how it ended.
A series writer is added when the case has none, so every run folder has series.csv.

The outcome is a ``Run``: exit code 0 (finished), 3 (the run became unphysical; the output so far is kept)
or 128 + the signal number (stopped by SIGINT/SIGTERM after a checkpoint; ``resume`` continues it).
"""

from __future__ import annotations

import json
import logging
import signal
import sys
from dataclasses import dataclass, field
from pathlib import Path

from geompm.errors import CaseError, SimulationError
from geompm.files.atomic import atomic_write_json
from geompm.files.ownership import create_folder, mark_folder, marked_kind, owned_kind, remove_tree
from geompm.parallel.whole import WHOLE
from geompm.version import __version__

log = logging.getLogger("geompm")

#: what may change on resume: the end time (to extend a run), and where and in what width the step runs
RESUME_MAY_CHANGE = (("time", "end"), ("solver", "backend"), ("solver", "precision"))
#: exit codes of a run (and of `geompm run`)
FINISHED, UNPHYSICAL = 0, 3


@dataclass
class Run:
    """The outcome of a run: its folder, exit code and status.json, with what it wrote."""

    folder: Path
    exit_code: int
    status: dict
    #: writer name -> the files it wrote (each writer's declared ``files`` patterns, sorted)
    outputs: dict[str, list[Path]] = field(default_factory=dict)

    @property
    def finished(self) -> bool:
        return bool(self.status.get("finished"))

    @property
    def steps(self) -> int:
        return int(self.status.get("steps", 0))

    @property
    def time(self) -> float:
        """Simulated time reached [s]."""
        return float(self.status.get("time", 0.0))

    @property
    def series(self) -> dict:
        """series.csv as arrays, one per column (``time`` [s], ``kinetic_energy`` [J; J/m in 2D], ...)."""
        from geompm.writers.series import read_series

        return read_series(self.folder / "series.csv")

    @property
    def peak_forces(self) -> dict[str, tuple[float, float]]:
        """label -> (peak |F| [N; N/m in 2D], its time [s]) of every stage that records a contact force."""
        return {k: (v["peak_force"], v["peak_time"]) for k, v in self.status.get("obstacles", {}).items()}


def setup_logging(run_dir: Path | None = None, quiet: bool = False, silent: bool = False) -> None:
    """Messages to the terminal (warnings and errors only when quiet; only a rank's own crash when silent:
    the MPI ranks other than 0) and to the run folder's run.log."""
    log.setLevel(logging.INFO)
    for h in list(log.handlers):
        h.close()
    log.handlers.clear()
    term = logging.StreamHandler(sys.stdout)
    term.setFormatter(logging.Formatter("%(message)s"))
    term.setLevel(logging.CRITICAL if silent else logging.WARNING if quiet else logging.INFO)
    log.addHandler(term)
    if run_dir is not None:
        fh = logging.FileHandler(run_dir / "run.log", mode="a")
        fh.setFormatter(logging.Formatter("%(asctime)s %(message)s"))
        log.addHandler(fh)


def same_case(old: dict, new: dict) -> bool:
    """A run may resume with the case it started with; only time.end, solver.backend and solver.precision
    may differ (a run started on a GPU finishes on a CPU, a checkpoint is read in either width)."""
    a, b = json.loads(json.dumps(old)), json.loads(json.dumps(new))
    for c in (a, b):
        for section, key in RESUME_MAY_CHANGE:
            sub = c.get(section)
            if isinstance(sub, dict):
                sub.pop(key, None)
            if sub == {}:
                c.pop(section)
    return a == b


def saved_end_time(run_dir) -> float | None:
    """time.end of the case a run folder was started (or last resumed) with, before a resume changes it."""
    try:
        return float(json.loads((Path(run_dir) / "case.json").read_text())["time"]["end"])
    except (OSError, ValueError, KeyError, TypeError):
        return None  # run_folder refuses a folder without a readable case.json


def run_folder(loaded, scene, out=None, resume=None, overwrite: bool = False, protect=()) -> Path:
    """The run folder: a fresh one (refusing to overwrite one geompm did not make) or, with ``resume``, the
    existing one.  ``protect``: (folder, why) pairs a delete must never touch (the case file's folder)."""
    if resume:
        run_dir = Path(resume)
        saved = run_dir / "case.json"
        if not saved.is_file():
            raise CaseError([("--resume", f"'{run_dir}' is not a geompm run folder (no case.json)")])
        if not same_case(json.loads(saved.read_text()), loaded.raw):
            raise CaseError([("--resume", f"the case differs from the one '{run_dir}' was started with "
                                          "(only time.end, solver.backend and solver.precision may change on "
                                          "--resume); use that case.json")])
        if owned_kind(run_dir) != "run" and (run_dir / "checkpoints").is_dir() and marked_kind(run_dir) in (None, "run"):
            # a run folder of a geompm without markers, or one the user moved: continuing it there makes it
            # this run's folder again (it rotates its checkpoints)
            mark_folder(run_dir, "run", adopted=True)
        if json.loads(saved.read_text()) != loaded.raw:  # a new end time (or backend): the folder's case says so
            atomic_write_json(saved, loaded.raw)
        return run_dir
    run_dir = Path(out) if out else Path("runs") / scene.name
    if run_dir.exists() and (not run_dir.is_dir() or any(run_dir.iterdir())):
        if not overwrite:
            raise CaseError([("--out", f"run folder '{run_dir}' already exists; use --overwrite (only for a "
                                       "folder geompm made), --out DIR, or --resume to continue it")])
        remove_tree(run_dir, "run", protect=tuple(protect))
    create_folder(run_dir, "run")
    atomic_write_json(run_dir / "case.json", loaded.raw)
    return run_dir


def hot_spot(stage) -> dict:
    """status.json's peak face pressure of a stage whose force is spread on its faces."""
    spot = stage.hot_spot()
    if spot is None:
        return {}
    return {"peak_pressure": spot[0], "peak_pressure_at": [float(c) for c in spot[1][:stage.dim]],
            "peak_pressure_time": spot[2]}


def write_status(run_dir: Path, scene, runner, summary, finished: bool, reason: str = "") -> dict:
    """status.json, written by rank 0 from every rank's particles (a collective call); the status on
    every rank."""
    import numba

    from geompm.mpm.memory import peak_rss

    sim = runner.sim
    comm = sim.domain.comm
    n = sim.count()
    front = float(comm.max([sim.state.p_x[:, 0].max() if sim.state.n else -float("inf")])[0])
    rss = [int(x) for x in comm.gather(peak_rss())]
    status = {
        "case": scene.name, "finished": finished, "reason": reason, "time": sim.time, "end_time": scene.end_time,
        "steps": sim.step_count, "particles": n, "deleted_particles": runner.deleted,
        "cells": int(scene.grid.ncells.prod()), "cell_size": scene.grid.h, "threads": numba.get_num_threads(),
        "wall_seconds": runner.wall_before + (summary.wall_seconds if summary else 0.0),
        "particle_steps_per_second": summary.particle_steps_per_second if summary else None,
        "peak_rss_bytes": rss[0] if len(rss) == 1 else sum(rss),
        "front_x": front if n else None,
        "obstacles": {o.label: {"peak_force": pk[0], "peak_time": pk[1], **hot_spot(o), **o.impact_report()}
                      for o in scene.stages if o.records_force and (pk := o.peak_force()) is not None},
        "grounds": [o.label for o in scene.stages if o.provides_ground],
        **({"mpi": {**sim.domain.report(sim.state), "peak_rss_bytes_per_rank": rss}} if comm.size > 1 else {}),
        **({"gravity_loading": scene.loading} if scene.loading else {}),
        **({"held_step": {"batches": runner.held_batches, "steps": runner.held_steps}}  # this session's
           if scene.held_step is not None and hasattr(runner, "held_batches") else {}),
        "geompm": __version__,
    }
    if comm.is_root:
        atomic_write_json(run_dir / "status.json", status)
    return status


class StopOnSignal:
    """SIGINT/SIGTERM ask the runner to checkpoint and stop; restored on exit.  Outside the main thread (a
    Dask worker's thread) signals cannot be caught there, and nothing is installed."""

    def __init__(self, runner):
        self.runner = runner
        self.signum = None
        self.old = {}

    def _handler(self, signum, frame):
        if self.signum is not None:  # a second signal: stop now
            raise KeyboardInterrupt
        self.signum = signum
        self.runner.request_stop(signal.Signals(signum).name)

    def __enter__(self):
        import threading

        if threading.current_thread() is threading.main_thread():
            self.old = {s: signal.signal(s, self._handler) for s in (signal.SIGINT, signal.SIGTERM)}
        return self

    def __exit__(self, *exc):
        for s, h in self.old.items():
            signal.signal(s, h)


def declared_outputs(run_dir: Path, writers) -> dict[str, list[Path]]:
    """writer name -> the files in ``run_dir`` that match the writer's declared ``files`` patterns, pattern by
    pattern (e.g. particles.pvd, then the vtu files in order)."""
    return {w.name: [p for pattern in w.files for p in sorted(run_dir.glob(pattern))] for w in writers}


def on_root(comm, make):
    """``make()`` on rank 0, its result (or its CaseError) on every rank."""
    result = error = None
    if comm.is_root:
        try:
            result = make()
        except CaseError as exc:
            error = exc
    result, problems = comm.bcast((result, None if error is None else error.problems))
    if error is not None:
        raise error
    if problems is not None:
        raise CaseError(problems)
    return result


def run_on_every_rank(runner, domain, run_dir):
    """``runner.run()``; on several ranks, an error that is not the run's own (a bug, a full disk) on one
    rank stops them all (MPI_Abort), since the others would wait for it in their next exchange."""
    from geompm.engine.runner import Interrupted

    try:
        return runner.run()
    except (SimulationError, Interrupted):
        raise
    except Exception:
        if domain.size > 1:
            log.critical(f"error on MPI rank {domain.rank}; stopping every rank (the checkpoints written so "
                          f"far are kept in {run_dir})", exc_info=True)
            domain.comm.abort(1)
        raise


def settle(scene, spec) -> dict:
    """The gravity-loading stage on the whole scene (engine/gravity_loading.py; every MPI rank alike, before
    the run is shared), its report kept on the scene for status.json; SimulationError if it does not settle."""
    from geompm.engine.gravity_loading import gravity_loading
    from geompm.engine.scheduler import Simulation

    scene.loading = gravity_loading(scene, spec, Simulation)
    return scene.loading


def run_case(case, out=None, overrides=(), progress: bool = True, resume=None, overwrite: bool = False,
             protect=(), quiet: bool = False, comm=None) -> Run:
    """Run ``case`` (a path to a case JSON, or a case dict) to its end time; see the module docstring.
    ``overrides``: KEY=VALUE strings as `geompm run --set`.  Raises CaseError for a bad case (nothing is
    made); an unphysical or stopped run returns a Run with a non-zero exit code.  Started by an MPI
    launcher on several processes (or given an mpi4py-backed ``comm``, parallel/comm.MpiComm), the
    processes share the run (docs/parallel.md)."""
    from geompm.engine.first_step import (check_output_intervals, first_step_estimate, fixed_step_problem,
                                          stage_warnings, viscous_warning)
    from geompm.engine.launch import world
    from geompm.engine.runner import Interrupted, Runner
    from geompm.engine.scheduler import Simulation
    from geompm.schema.load import apply_overrides, load_case, parse_case
    from geompm.setup.assemble import assemble
    from geompm.writers.series import SeriesWriter

    comm = comm if comm is not None else world()
    sets = list(overrides)
    saved_end = saved_end_time(resume) if resume else None
    loaded = load_case(case, sets) if not isinstance(case, dict) else parse_case(apply_overrides(case, sets), ".")
    try:
        scene = assemble(loaded)
        check_output_intervals(scene, loaded.case.outputs)
    except CaseError as exc:
        exc.warnings = exc.warnings or loaded.warnings
        raise
    domain = WHOLE
    if comm is not None and comm.size > 1:
        from geompm.parallel.slabs import Slabs

        domain = Slabs(comm, scene)
    mem, _, dt = first_step_estimate(scene)
    run_dir = on_root(domain.comm, lambda: run_folder(loaded, scene, out, resume, overwrite, protect))
    setup_logging(run_dir if domain.comm.is_root else None, quiet=quiet, silent=not domain.comm.is_root)
    if loaded.case.gravity_loading is not None and not resume:
        try:
            report = settle(scene, loaded.case.gravity_loading)
        except SimulationError as exc:
            log.error(f"error: {exc}")
            status = {"case": scene.name, "finished": False, "reason": f"unphysical: {exc}", "time": 0.0,
                      "steps": 0, "geompm": __version__}
            if domain.comm.is_root:
                atomic_write_json(run_dir / "status.json", status)
            return Run(run_dir, UNPHYSICAL, status, {})
        log.info(f"gravity loading: {report['steps']} steps over {report['time']:.4g} s (held at t = 0, drained, "
                 f"local damping {loaded.case.gravity_loading.alpha:g}), unbalanced-force ratio {report['ratio']:.3g}, "
                 f"largest displacement {report['max_displacement']:.3g} m (reset), {report['wall_seconds']:.1f} s wall")
    writers = list(scene.writers)
    if not any(isinstance(w, SeriesWriter) for w in writers):
        writers.insert(0, SeriesWriter(SeriesWriter.Params(), 0.0))
    nchunks = None
    if resume:
        from geompm.engine import checkpoint

        nchunks = checkpoint.read_meta(run_dir)["nchunks"]
    sim = Simulation(scene, nchunks=nchunks, domain=domain)
    runner = Runner(sim, run_dir, writers, progress=progress and not quiet and domain.comm.is_root)
    if resume:
        runner.resume()
        if sim.time >= scene.end_time * (1 - 1e-12):
            log.warning(f"'{run_dir}' already reached t = {sim.time:.6g} s, its case's end time "
                        f"(time.end = {scene.end_time:g} s): nothing to do; to run on, resume with "
                        f"--set time.end=<a later time>")
            status = json.loads((run_dir / "status.json").read_text()) if (run_dir / "status.json").is_file() else {}
            return Run(run_dir, FINISHED, status, declared_outputs(run_dir, writers))  # every rank alike
        explicit = any(x.split("=", 1)[0] == "time.end" for x in sets)
        if saved_end is not None and saved_end != scene.end_time and not explicit:
            log.warning(f"warning: the case file's time.end is {scene.end_time:g} s but '{run_dir}' was run to "
                        f"{saved_end:g} s (an earlier --set, or an edited file): it continues to "
                        f"{scene.end_time:g} s; --set time.end={saved_end:g} keeps the old end")
        log.info(f"geompm {__version__}: resuming '{scene.name}' in {run_dir} at step {sim.step_count}, "
                 f"t = {sim.time:.6g} s, to end time {scene.end_time:g} s")
    else:
        ranks = f" on {domain.size} MPI ranks (slabs along {'xyz'[domain.axis]})" if domain.size > 1 else ""
        log.info(f"geompm {__version__}: case '{scene.name}', {scene.dim}D, {scene.state.n} particles, "
                 f"h = {scene.grid.h:g} m, end time {scene.end_time:g} s, first dt {dt:.3g} s, "
                 f"~{mem / 2**20:.0f} MiB -> {run_dir}{ranks}")
        viscous_warning(loaded, scene, log.warning)
        stage_warnings(scene, log.warning, loaded)
        problem = fixed_step_problem(scene)
        if problem:  # validate refuses it; a run goes on, so that a stability experiment can see the blow-up
            log.warning(f"warning: {problem[0]}: {problem[1]} (geompm validate refuses this case)")
    summary = None
    try:
        with StopOnSignal(runner) as stopper:
            summary = run_on_every_rank(runner, domain, run_dir)
    except SimulationError as exc:
        log.error(f"error: the run stopped at step {sim.step_count}, t = {sim.time:.6g} s: {exc}")
        log.error(f"output written so far is kept in {run_dir}; the last checkpoint is before this step")
        status = write_status(run_dir, scene, runner, summary, False, f"unphysical: {exc}")
        return Run(run_dir, UNPHYSICAL, status, declared_outputs(run_dir, writers))
    except Interrupted as exc:
        shown = "".join(f" --set {x}" for x in sets)
        log.error(f"stopped by {exc} at step {sim.step_count}, t = {sim.time:.6g} s; checkpoint written. "
                  f"Continue with: geompm run {case if not isinstance(case, dict) else 'CASE'}{shown} "
                  f"--resume {run_dir}")
        status = write_status(run_dir, scene, runner, summary, False, f"stopped by {exc}")
        return Run(run_dir, 128 + (stopper.signum or signal.SIGINT), status, declared_outputs(run_dir, writers))
    for stage in scene.stages:
        if stage.summary():
            log.info(stage.summary())
    if summary.deleted:
        log.info(f"{summary.deleted} particles left the grid and were deleted")
    status = write_status(run_dir, scene, runner, summary, True)
    log.info(f"done: {summary.steps} steps to t = {summary.sim_time:.6g} s in {summary.wall_seconds:.2f} s wall, "
             f"{summary.particle_steps_per_second:.3g} particle-steps/s")
    return Run(run_dir, FINISHED, status, declared_outputs(run_dir, writers))
