"""Python entry points: run a case as ``geompm run`` does, or build a scene and step it yourself.

Run a case to its end in a run folder (series.csv, the case's writers, checkpoints, status.json):

    import geompm
    run = geompm.run("cases/column_collapse.json", out="runs/cc", overrides=["grid.cell_size=0.02"])
    run.exit_code          # 0 finished, 3 unphysical, 128 + N stopped by signal N (resume=run.folder continues)
    run.series["front_x"]  # series.csv as arrays [m]
    run.outputs["vtu"]     # the files each writer wrote
    run.peak_forces        # {label: (peak |F| [N], time [s])} of every stage that records a force

Step a scene yourself (no folder, no writers, no health checks):

    from geompm.api import scene_from_file
    from geompm.engine.scheduler import Simulation
    sim = Simulation(scene_from_file("cases/elastic_bar.json"))
    while sim.time < 1.0:
        sim.step(sim.stable_dt())
"""

from __future__ import annotations

from pathlib import Path

from geompm.engine.run_case import Run, run_case
from geompm.schema.load import apply_overrides, load_case, parse_case
from geompm.setup.assemble import Scene, assemble

__all__ = ["Run", "run", "scene_from_dict", "scene_from_file"]


def run(case: str | Path | dict, out: str | Path | None = None, overrides=(), progress: bool = True,
        resume: str | Path | None = None, overwrite: bool = False, quiet: bool = False, comm=None) -> Run:
    """Run ``case`` (a case file or a case dict) to its end time in ``out`` (default runs/<case name>);
    ``overrides`` are KEY=VALUE strings as `geompm run --set`.  A bad case raises geompm.errors.CaseError
    naming its JSON paths, before any folder is made.  ``overwrite`` replaces only a folder geompm made;
    ``resume`` continues a stopped run from its checkpoint.  Under mpiexec every rank calls it and the
    ranks share the run; ``comm`` (geompm.parallel.comm.MpiComm) shares it among a communicator's ranks
    instead (docs/parallel.md)."""
    # what an overwrite must never delete besides the current and home folders: the case file's folder
    protect = ((Path(case).resolve().parent, f"the case file {case}"),) if not isinstance(case, dict) else ()
    return run_case(case, out=out, overrides=overrides, progress=progress, resume=resume, overwrite=overwrite,
                    protect=protect, quiet=quiet, comm=comm)


def scene_from_file(path: str | Path, sets=()) -> Scene:
    return assemble(load_case(path, sets))


def scene_from_dict(raw: dict, base_dir: str | Path = ".", sets=()) -> Scene:
    return assemble(parse_case(apply_overrides(raw, list(sets)), base_dir))
