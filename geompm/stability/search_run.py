"""The factor of safety of a case as a library call: what `geompm stability` does, returning its JSON object.

    import geompm
    result = geompm.stability("cases/slope_failure.json", sets=["grid.cell_size=0.5"])
    result["factor_of_safety"], result["bracket"], result["trials"], result["message"]

The object is the one `geompm stability --json` prints and ``stability.json`` holds: ``factor_of_safety``
(the bracket's middle, None without a bracket), ``bracket``, ``bound`` ("F < 0.1" where the slope failed at
every trial), ``criterion``, ``trials`` (each with its factor, run folder, outcome and criterion values),
``message`` (why a search ended without a factor, '' otherwise), ``drained_water`` (the saturated materials
whose pore pressure the trials held at its initial state: trial.py).  A case refused before any trial raises
CaseError; a search that cannot finish (a trial refused, every trial failed down to the lowest factor) still
writes its trials and says why in ``message``.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from geompm.errors import CaseError
from geompm.files.atomic import atomic_write_json
from geompm.files.ownership import holds_only, prepare_folder
from geompm.schema.load import load_case, read_json
from geompm.stability import criterion, report
from geompm.stability.search import Search
from geompm.stability.trial import check_case, drained_materials, trial_damping, trial_sets, viscoplastic_time
from geompm.study.execute import Pool, check_threads, run_variant, threads_per_run
from geompm.study.metrics import read_series

STABILITY_FILES = {"trials", "stability.json", "mechanism.vtu", "mechanism.png", "slip_surface.csv"}
MAX_TRIALS = 60


class TrialRefused(Exception):
    """A trial the case's checks refused (its factor and why)."""


def check_options(loaded, tolerance, start, duration, damping_rate, local_damping, ratio, workers):
    """(duration [s], viscous damping rate [1/s], floor [m]) after refusing impossible settings (the CLI's
    option names in the paths)."""
    problems = []
    if not 0.0 < tolerance < 1.0:
        problems.append(("--tolerance", f"{tolerance:g} is not a tolerance on F; give e.g. 0.01"))
    if not 0.05 <= start <= 20.0:
        problems.append(("--start", f"{start:g}: give a first factor between 0.05 and 20"))
    if not 0.0 <= local_damping < 1.0:
        problems.append(("--local-damping", f"{local_damping:g}: Cundall's alpha lies in [0, 1)"))
    if not 0.0 < ratio <= 2.0:
        problems.append(("--ratio", f"{ratio:g}: give a ratio of displacement increments in (0, 2], e.g. 0.7"))
    duration = float(duration if duration is not None else loaded.case.time.end)
    if not duration > 0.0:
        problems.append(("--duration", f"{duration:g} s: give the simulated time of a trial in seconds"))
    rate = (40.0 / duration if duration > 0.0 else 1.0) if damping_rate is None else float(damping_rate)
    if duration > 0.0 and not rate > 0.0:
        problems.append(("--damping-rate", f"{rate:g}: give a viscous damping rate in 1/s, e.g. {40.0 / duration:.3g}"))
    if workers is not None and workers < 1:
        problems.append(("--workers", f"{workers}: give 1 or more"))
    if problems:
        raise CaseError(problems)
    return duration, rate, criterion.FLOOR_CELLS * float(loaded.case.grid.cell_size)


def _round(pool, case, out: Path, factors, sets_of, threads, first: int) -> list[dict]:
    """Run the trials at ``factors`` at once; their outcomes (exit code, wall time, criterion)."""
    from distributed import as_completed

    jobs = {}
    for i, f in enumerate(factors):
        run_dir = out / "trials" / f"t{first + i:02d}"
        fut = pool.submit(run_variant, case, str(run_dir), sets_of(f), threads, name=run_dir.name)
        jobs[fut] = (f, run_dir, time.perf_counter())
    done, refused = [], None
    for fut in as_completed(jobs):
        f, run_dir, t0 = jobs[fut]
        outcome = fut.result()
        if outcome["exit_code"] == 2 or not (run_dir / "series.csv").is_file():
            refused = refused or f"the trial at F = {f:.4f} ({run_dir}) was refused: {outcome['error']}"
            continue
        done.append({"factor": f, "run_dir": str(run_dir), "wall_seconds": time.perf_counter() - t0,
                     "error": outcome["error"] if outcome["exit_code"] else ""})
    return done, refused


def stability(case, out=None, sets=(), tolerance: float = 0.01, start: float = 1.0, duration: float | None = None,
              damping_rate: float | None = None, local_damping: float = 0.0, ratio: float = criterion.DEFAULT_RATIO,
              relaxation: float | None = None, circle=None, overwrite: bool = False, workers: int | None = None, scheduler: str | None = None,
              threads: int | None = None, progress=None) -> dict:
    """The factor of safety of ``case`` (a case file) by strength reduction; see the module docstring.
    ``progress(row)``: called with each trial's row as it is judged (the CLI prints it)."""
    check_threads(threads)
    if circle is not None and (len(circle) != 3 or not circle[2] > 0.0):
        raise CaseError([("--bishop-circle", f"{circle}: give the centre and the radius, XC YC R [m], R > 0")])
    case = str(case)
    raw = read_json(Path(case))
    loaded = load_case(case, list(sets))
    check_case(loaded)
    duration, rate, floor = check_options(loaded, tolerance, start, duration, damping_rate, local_damping, ratio,
                                          workers)
    damping = trial_damping(loaded, rate, local_damping)
    if relaxation is not None and relaxation < 0.0:
        raise CaseError([("--viscoplastic-time", f"{relaxation:g} s: give a relaxation time in seconds, or 0 for none")])
    tau = viscoplastic_time(loaded, duration, relaxation)

    def sets_of(f):
        return list(sets) + trial_sets(loaded, f, duration, damping, tau)

    load_case(case, sets_of(start))  # the trial case itself is valid before anything runs
    out = Path(out or Path("stability") / raw.get("name", Path(case).stem))
    prepare_folder(out, "stability", resume=False, overwrite=overwrite,
                   protect=((Path(case).resolve().parent, f"the case file {case}"),),
                   legacy=lambda f: holds_only(f, STABILITY_FILES))
    (out / "trials").mkdir(exist_ok=True)

    search = Search(tolerance=tolerance, start=start)
    rows: list[dict] = []
    message = ""
    pool_workers = None if scheduler else (workers or os.cpu_count() or 1)
    with Pool(scheduler, pool_workers) as pool:
        per_run = threads_per_run(pool.workers, pool.workers, threads)
        while not search.done() and len(rows) < MAX_TRIALS:
            factors = search.next_factors(pool.workers)
            done, refused = _round(pool, str(Path(case).resolve()), out, factors, sets_of, per_run, len(rows))
            for row in done:
                row.update(criterion.judge(read_series(Path(row["run_dir"]) / "series.csv"), ratio, floor))
                row["failed"] = row["failed"] or bool(row["error"])  # a run stopped by its health checks failed
                search.record(row["factor"], row["failed"])
                rows.append(row)
                if progress is not None:
                    progress(row)
            if refused:
                message = refused
                break
    result = search.result()
    if not message and result["factor_of_safety"] is None:
        message = _no_bracket(search, len(rows))
    rows.sort(key=lambda r: r["factor"])
    summary = {"case": case, **result, "tolerance": tolerance, "message": message,
               "criterion": {"ratio": ratio, "floor_m": floor, "duration_s": duration,
                             "damping_rate": rate, "local_damping": local_damping,
                             "viscoplastic_time_s": tau},
               "bishop_circle": list(circle) if circle is not None else None,
               "drained_water": drained_materials(loaded),
               "inconsistent": search.inconsistent(), "trials": rows}
    failed = [r for r in rows if r["failed"]]
    if failed:
        first = min(failed, key=lambda r: r["factor"])
        summary["mechanism"] = report.write_mechanism(out, Path(first["run_dir"]),
                                                      f"{raw.get('name', '')}: trial at F = {first['factor']:.4f}",
                                                      dim=loaded.case.dimension, cell_size=float(loaded.case.grid.cell_size),
                                                      duration=duration, circle=circle,
                                                      vertical=int(np.argmax(np.abs(loaded.case.gravity))))
        summary["mechanism_factor"] = first["factor"]
    atomic_write_json(out / "stability.json", summary)
    summary["folder"] = str(out)
    return summary


def _no_bracket(search: Search, count: int) -> str:
    """Why a search ended without a factor of safety."""
    lo, hi = search.bracket()
    if count >= MAX_TRIALS:
        return f"no bracket after {count} trials (the most a search runs); the trials are in the JSON"
    if lo is None and hi is not None:
        return (f"every trial failed, down to F = {hi:g} (the lowest tried): the slope does not stand as given "
                "(check its initial state: a slope that moves at F = 1 under its own weight, creep of a coupled "
                "pore pressure, a trigger) or the criterion reads its settling as failure (longer --duration)")
    if hi is None and lo is not None:
        return f"every trial stood, up to F = {lo:g} (the highest tried): F > {lo:g}"
    return "no trial ran"
