"""``geompm stability``: the factor of safety of a case by strength reduction.

    geompm stability cases/slope_failure.json --json

Each trial divides the soils' shear strength by F (trial.py) and runs the case quasi-statically under
viscous damping; criterion.py says whether it failed; search.py brackets F and splits the bracket, with as
many trials in flight as ``--workers`` (Dask, as `geompm study`).  Writes to ``--out`` (default
``stability/<case name>``): ``trials/tNN`` (ordinary run folders), ``stability.json`` and the failure
mechanism of the smallest failed F, ``mechanism.vtu`` and ``mechanism.png``.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

from geompm.errors import CaseError
from geompm.files.atomic import atomic_write_json
from geompm.files.ownership import holds_only, prepare_folder
from geompm.schema.load import load_case, read_json
from geompm.stability import criterion, report
from geompm.stability.search import Search
from geompm.stability.trial import check_case, trial_damping, trial_sets
from geompm.study.execute import Pool, add_threads_option, check_threads, run_variant, threads_per_run
from geompm.study.metrics import read_series

STABILITY_FILES = {"trials", "stability.json", "mechanism.vtu", "mechanism.png"}
MAX_TRIALS = 60


def add_parser(sub) -> None:
    p = sub.add_parser("stability", help="factor of safety by strength reduction (trials run on Dask)")
    p.add_argument("case")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override a case value")
    p.add_argument("--json", action="store_true", help="print one JSON object (factor_of_safety, bracket, trials)")
    p.add_argument("--tolerance", type=float, default=0.01, help="width of the final bracket on F (default 0.01)")
    p.add_argument("--start", type=float, default=1.0, help="the first F tried (default 1)")
    p.add_argument("--duration", type=float,
                   help="simulated time of each trial [s] (default the case's time.end)")
    p.add_argument("--damping-rate", type=float, metavar="ZETA",
                   help="viscous damping rate of the trials [1/s] (default 40 / duration)")
    p.add_argument("--local-damping", type=float, default=0.0, metavar="ALPHA",
                   help="add Cundall local damping (default 0: it adds strength, docs/slope-stability.md)")
    p.add_argument("--ratio", type=float, default=criterion.DEFAULT_RATIO,
                   help="failure criterion: a trial failed if its largest displacement grew over its last quarter "
                        f"by at least this share of its growth over the quarter before (default {criterion.DEFAULT_RATIO})")
    p.add_argument("--out", help="stability folder (default stability/<case name>)")
    p.add_argument("--overwrite", action="store_true", help="delete an existing stability folder first")
    p.add_argument("--workers", type=int, help="trials in flight per round (default: CPU cores)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="an existing Dask scheduler (default: LocalCluster)")
    add_threads_option(p)
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_stability)


def _check_args(args, loaded) -> tuple[float, float, float]:
    """(duration [s], viscous damping rate [1/s], floor [m]) after refusing impossible settings."""
    problems = []
    if not 0.0 < args.tolerance < 1.0:
        problems.append(("--tolerance", f"{args.tolerance:g} is not a tolerance on F; give e.g. 0.01"))
    if not 0.05 <= args.start <= 20.0:
        problems.append(("--start", f"{args.start:g}: give a first factor between 0.05 and 20"))
    if not 0.0 <= args.local_damping < 1.0:
        problems.append(("--local-damping", f"{args.local_damping:g}: Cundall's alpha lies in [0, 1)"))
    if not 0.0 < args.ratio <= 2.0:
        problems.append(("--ratio", f"{args.ratio:g}: give a ratio of displacement increments in (0, 2], e.g. 0.7"))
    duration = float(args.duration if args.duration is not None else loaded.case.time.end)
    if not duration > 0.0:
        problems.append(("--duration", f"{duration:g} s: give the simulated time of a trial in seconds"))
    rate = (40.0 / duration if duration > 0.0 else 1.0) if args.damping_rate is None else float(args.damping_rate)
    if duration > 0.0 and not rate > 0.0:
        problems.append(("--damping-rate", f"{rate:g}: give a viscous damping rate in 1/s, e.g. {40.0 / duration:.3g}"))
    if args.workers is not None and args.workers < 1:
        problems.append(("--workers", f"{args.workers}: give 1 or more"))
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
    done = []
    for fut in as_completed(jobs):
        f, run_dir, t0 = jobs[fut]
        outcome = fut.result()
        if outcome["exit_code"] == 2 or not (run_dir / "series.csv").is_file():
            raise CaseError([(f"trial at F = {f:.4f} ({run_dir})", f"the run was refused: {outcome['error']}")])
        done.append({"factor": f, "run_dir": str(run_dir), "wall_seconds": time.perf_counter() - t0,
                     "error": outcome["error"] if outcome["exit_code"] else ""})
    return done


def cmd_stability(args) -> int:
    check_threads(args.threads)
    raw = read_json(Path(args.case))
    loaded = load_case(args.case, args.set)
    check_case(loaded)
    duration, rate, floor = _check_args(args, loaded)
    damping = trial_damping(loaded, rate, args.local_damping)

    def sets_of(f):
        return list(args.set) + trial_sets(loaded, f, duration, damping)

    load_case(args.case, sets_of(args.start))  # the trial case itself is valid before anything runs
    out = Path(args.out or Path("stability") / raw.get("name", Path(args.case).stem))
    prepare_folder(out, "stability", resume=False, overwrite=args.overwrite,
                   protect=((Path(args.case).resolve().parent, f"the case file {args.case}"),),
                   legacy=lambda f: holds_only(f, STABILITY_FILES))
    (out / "trials").mkdir(exist_ok=True)

    search = Search(tolerance=args.tolerance, start=args.start)
    rows: list[dict] = []
    workers = None if args.scheduler else (args.workers or os.cpu_count() or 1)
    with Pool(args.scheduler, workers) as pool:
        threads = threads_per_run(pool.workers, pool.workers, args.threads)
        while not search.done() and len(rows) < MAX_TRIALS:
            factors = search.next_factors(pool.workers)
            for row in _round(pool, str(Path(args.case).resolve()), out, factors, sets_of, threads, len(rows)):
                row.update(criterion.judge(read_series(Path(row["run_dir"]) / "series.csv"), args.ratio, floor))
                row["failed"] = row["failed"] or bool(row["error"])  # a run stopped by its health checks failed
                search.record(row["factor"], row["failed"])
                rows.append(row)
                if not args.quiet and not args.json:
                    print(f"trial F = {row['factor']:.4f}: {'failed' if row['failed'] else 'stable'} "
                          f"(increment ratio {row['ratio']:.3g}, last quarter {row['last_increment']:.3g} m, "
                          f"{row['wall_seconds']:.1f} s)", flush=True)

    rows.sort(key=lambda r: r["factor"])
    summary = {"case": str(args.case), **search.result(), "tolerance": args.tolerance,
               "criterion": {"ratio": args.ratio, "floor_m": floor, "duration_s": duration,
                             "damping_rate": rate, "local_damping": args.local_damping},
               "inconsistent": search.inconsistent(), "trials": rows}
    failed = [r for r in rows if r["failed"]]
    if failed:
        first = min(failed, key=lambda r: r["factor"])
        summary["mechanism"] = report.write_mechanism(out, Path(first["run_dir"]),
                                                      f"{raw.get('name', '')}: trial at F = {first['factor']:.4f}")
        summary["mechanism_factor"] = first["factor"]
    atomic_write_json(out / "stability.json", summary)
    if args.json:
        print(json.dumps(summary))
    else:
        report.print_result(summary)
        print(f"wrote {out / 'stability.json'}")
    sys.stdout.flush()
    return 0
