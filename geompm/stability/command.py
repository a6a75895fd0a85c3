"""``geompm stability``: the factor of safety of a case by strength reduction.

    geompm stability cases/slope_failure.json --json

Each trial divides the soils' shear strength by F (trial.py) and runs the case quasi-statically under
viscous damping; criterion.py says whether it failed; search.py brackets F and splits the bracket, with as
many trials in flight as ``--workers`` (Dask, as `geompm study`).  Writes to ``--out`` (default
``stability/<case name>``): ``trials/tNN`` (ordinary run folders), ``stability.json`` and the failure
mechanism of the smallest failed F, ``mechanism.vtu`` and ``mechanism.png``.  The search itself is
search_run.stability (``geompm.stability``), which returns the JSON object this command prints.
"""

from __future__ import annotations

import json
import sys

from geompm.stability import criterion, report
from geompm.stability.search_run import stability
from geompm.study.execute import add_threads_option


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
    p.add_argument("--viscoplastic-time", type=float, metavar="TAU",
                   help="the laws' Duvaut-Lions relaxation time in the trials [s] (default the case's "
                        "solver.viscoplastic_time, else duration / 800; 0: none): keeps a non-associated soil from "
                        "failing through bands one cell wide (docs/slope-stability.md)")
    p.add_argument("--bishop-circle", type=float, nargs=3, metavar=("XC", "YC", "R"),
                   help="a limit-equilibrium slip circle [m] drawn over the mechanism beside its slip surface (2D)")
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


def cmd_stability(args) -> int:
    """Exit 0 with a factor of safety (or a bound past the search's range), 1 when the search ended without
    one for another reason (its message says why; the trials are in the JSON)."""
    def progress(row):
        if not args.quiet and not args.json:
            print(f"trial F = {row['factor']:.4f}: {'failed' if row['failed'] else 'stable'} "
                  f"(increment ratio {row['ratio']:.3g}, last quarter {row['last_increment']:.3g} m, "
                  f"{row['wall_seconds']:.1f} s)", flush=True)

    summary = stability(args.case, out=args.out, sets=args.set, tolerance=args.tolerance, start=args.start,
                        duration=args.duration, damping_rate=args.damping_rate, local_damping=args.local_damping,
                        ratio=args.ratio, relaxation=args.viscoplastic_time, circle=args.bishop_circle,
                        overwrite=args.overwrite, workers=args.workers, scheduler=args.scheduler,
                        threads=args.threads, progress=progress)
    folder = summary.pop("folder")
    if args.json:
        print(json.dumps(summary))
    else:
        report.print_result(summary)
        if summary["message"]:
            print(f"error: {summary['message']}")
        print(f"wrote {folder}/stability.json")
    sys.stdout.flush()
    return 1 if summary["message"] and summary["bound"] is None else 0
