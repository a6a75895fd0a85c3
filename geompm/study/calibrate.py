"""``geompm calibrate``: the fluid parameter whose X*(T*) and K*(T*) curves come closest to a soil run's.

    geompm calibrate cases/seed/dp_h0.02.json cases/seed/dp_h0.01.json --fluid cases/seed/cross.json

The source study (section 3.2) tunes the Cross mu_inf at each cell size h so
that the column's front X* and kinetic energy K* follow Drucker-Prager's.  For
each DP case, geompm runs it once, then runs the fluid case at the same
``grid.cell_size`` and minimises

    J(p) = e2(X*) + e2(K*)

(e2 the relative L2 distance over the DP run's times, metrics.py) over the
parameter p (default ``materials.soil.from_bingham.viscosity``) in
[lo, hi] by a bounded search in log p that evaluates ``--points`` values at
once on Dask, then narrows the bracket to the best value's neighbours, for
``--rounds`` rounds.  The bracket after the last round is the uncertainty.
With three or more cell sizes, the linear fit p = a + b h and its R^2 are
reported (the source: R^2 > 0.99).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from geompm.errors import CaseError
from geompm.files.atomic import atomic_write_json
from geompm.files.ownership import holds_only, prepare_folder
from geompm.schema.load import load_case
from geompm.study import metrics as M
from geompm.study.execute import Pool, add_threads_option, check_threads, finished, run_variant, threads_per_run, variant_case
from geompm.study.report import write_csv

COMPARED = ("X_star", "K_star")
CALIBRATION_FILES = {"calibration.csv", "evaluations.csv", "calibration.json", "calibration.png"}
# Source study, section 3.2: calibrated mu_inf [Pa s] against cell size h [m].
SOURCE_MU_INF = {0.02: 1.9, 0.01: 1.2, 0.005: 0.8, 0.0025: 0.6}


def add_parser(sub) -> None:
    p = sub.add_parser("calibrate", help="fit a fluid parameter so the fluid's X*(T*), K*(T*) match soil runs")
    p.add_argument("soil_cases", nargs="+", metavar="SOIL_CASE", help="soil (e.g. Drucker-Prager) cases, one per h")
    p.add_argument("--fluid", required=True, help="the fluid case; its grid.cell_size is set to each soil case's")
    p.add_argument("--param", default="materials.soil.from_bingham.viscosity", help="the fluid case key to fit")
    p.add_argument("--bounds", nargs="+", type=float, default=[0.05, 3.0], metavar="LO HI",
                   help="search interval of the parameter (default 0.05 3.0), or one LO HI pair per soil case")
    p.add_argument("--points", type=int, default=4, help="evaluations per round, run together (default 4)")
    p.add_argument("--rounds", type=int, default=3, help="rounds of narrowing (default 3)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override for every run")
    p.add_argument("--out", help="calibration folder (default calibrations/<fluid case name>)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="an existing Dask scheduler")
    p.add_argument("--workers", type=int, help="runs in flight on the LocalCluster (default: CPU cores)")
    add_threads_option(p)
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_calibrate)


def _has_normalised_series(raw: dict) -> bool:
    return any(o.get("writer") == "series" and o.get("normalise") for o in raw.get("outputs", []))


def _check(args) -> tuple[list, dict]:
    problems = []
    b = args.bounds
    if len(b) not in (2, 2 * len(args.soil_cases)):
        problems.append(("--bounds", f"give LO HI, or one LO HI pair per soil case ({2 * len(args.soil_cases)} "
                                     f"numbers); got {len(b)}"))
        b = [1.0, 2.0]
    pairs = [b[i:i + 2] for i in range(0, len(b), 2)]
    args.bound_pairs = pairs * len(args.soil_cases) if len(pairs) == 1 else pairs
    for lo, hi in pairs:
        if not 0 < lo < hi:
            problems.append(("--bounds", f"need 0 < LO < HI, got {lo:g} {hi:g}"))
    lo = pairs[0][0]
    if args.points < 2 or args.rounds < 1:
        problems.append(("--points/--rounds", "need at least 2 points per round and 1 round"))
    soils = []
    for path in args.soil_cases:
        try:
            loaded = load_case(path, args.set)
        except CaseError as exc:
            problems += [(f"{path}: {p}", m) for p, m in exc.problems]
            continue
        if not _has_normalised_series(loaded.raw):
            problems.append((f"{path}: outputs", "needs a series writer with 'normalise' (X_star, K_star columns)"))
        soils.append((path, loaded.raw, float(loaded.raw["grid"]["cell_size"])))
    try:
        fluid = load_case(args.fluid, args.set + [f"{args.param}={lo}"]).raw
        if not _has_normalised_series(fluid):
            problems.append((f"{args.fluid}: outputs", "needs a series writer with 'normalise' (X_star, K_star columns)"))
    except CaseError as exc:
        problems += [(f"--fluid {args.fluid}: {p}", m) for p, m in exc.problems]
        fluid = None
    if len({h for _, _, h in soils}) != len(soils):
        problems.append(("SOIL_CASE", "two soil cases have the same grid.cell_size"))
    if problems:
        raise CaseError(problems)
    return soils, fluid


def next_points(tried: dict[float, float], lo: float, hi: float, n: int) -> list[float]:
    """n new values, log-spaced inside the bracket around the best value tried so far."""
    if not tried:
        return [float(x) for x in np.geomspace(lo, hi, n)]
    xs = sorted(tried)
    finite = [x for x in xs if math.isfinite(tried[x])]
    if not finite:
        return []
    i = xs.index(min(finite, key=lambda x: tried[x]))
    a, b = xs[max(i - 1, 0)], xs[min(i + 1, len(xs) - 1)]
    new = [float(x) for x in np.geomspace(a, b, n + 2)[1:-1]]
    return [x for x in new if all(abs(x / t - 1) > 1e-6 for t in xs)]


def bracket(tried: dict[float, float]) -> tuple[float, float, float]:
    """(best value, lower and upper neighbours) among the evaluations."""
    xs = sorted(x for x in tried if math.isfinite(tried[x]))
    i = xs.index(min(xs, key=lambda x: tried[x]))
    return xs[i], xs[max(i - 1, 0)], xs[min(i + 1, len(xs) - 1)]


def linear_fit(h: list[float], p: list[float]) -> tuple[float, float, float]:
    """(intercept a, slope b, R^2) of p = a + b h by least squares."""
    b, a = np.polyfit(h, p, 1)
    pred = a + b * np.asarray(h)
    ss_res = float(((np.asarray(p) - pred) ** 2).sum())
    ss_tot = float(((np.asarray(p) - np.mean(p)) ** 2).sum())
    return float(a), float(b), (1.0 - ss_res / ss_tot) if ss_tot > 0 else 1.0


def objective(run: dict, ref: dict) -> tuple[float, float, float]:
    ex, ek = (M.series_error(run, ref, c) for c in COMPARED)
    return ex + ek, ex, ek


class _Runs:
    """Submits runs to the pool (or reuses finished ones) and reads their series."""

    def __init__(self, pool, quiet):
        self.pool, self.quiet, self.futures = pool, quiet, {}

    def want(self, case, run_dir: Path, sets: list[str], raw: dict, threads: int):
        if run_dir in self.futures or finished(run_dir, variant_case(raw, sets)):
            return
        self.futures[run_dir] = self.pool.submit(run_variant, str(Path(case).resolve()), str(run_dir), sets,
                                                 threads, name=run_dir.name)

    def wait(self):
        for run_dir, fut in list(self.futures.items()):
            try:
                out = fut.result()
            except Exception as exc:
                out = {"exit_code": -1, "error": f"worker lost: {exc}"}
            if out["exit_code"] and not self.quiet:
                print(f"  {run_dir} failed: {out['error'][-300:]}")
        self.futures.clear()

    @staticmethod
    def read(run_dir: Path):
        try:
            series, status = M.read_run(run_dir)
        except (OSError, ValueError):
            return None, {}
        return (series if status.get("finished") else None), status


def cmd_calibrate(args) -> int:
    check_threads(args.threads)
    soils, fluid_raw = _check(args)
    bounds = {h: pair for (_, _, h), pair in zip(soils, args.bound_pairs)}
    out = Path(args.out or Path("calibrations") / fluid_raw.get("name", "fluid"))
    prepare_folder(out, "calibration", resume=True, overwrite=False,
                   legacy=lambda f: holds_only(f, CALIBRATION_FILES, r"h[0-9.e+-]+"))
    folders = {h: out / f"h{h:g}" for _, _, h in soils}
    tried = {h: {} for _, _, h in soils}
    evaluations = []
    workers = None if args.scheduler else min(args.workers or os.cpu_count() or 1, args.points * len(soils))
    with Pool(args.scheduler, workers) as pool:
        runs = _Runs(pool, args.quiet)
        threads = threads_per_run(pool.workers, args.points * len(soils), args.threads)
        for path, raw, h in soils:
            runs.want(path, folders[h] / "soil", args.set, variant_case(_raw_of(path), args.set), threads)
        runs.wait()
        refs = {}
        for path, _, h in soils:
            refs[h], status = runs.read(folders[h] / "soil")
            if refs[h] is None:
                raise CaseError([(path, f"the soil run did not finish ({status.get('reason', 'no status.json')}); "
                                        f"see {folders[h] / 'soil' / 'run.log'}")])
        fluid_base = _raw_of(args.fluid)
        end = {h: float(raw["time"]["end"]) for _, raw, h in soils}
        for rnd in range(args.rounds):
            batch = {h: next_points(tried[h], *bounds[h], args.points) for h in tried}
            for h, values in batch.items():
                for v in values:
                    sets = _fluid_sets(args, h, v, end[h])
                    runs.want(args.fluid, _eval_dir(folders[h], v), sets, variant_case(fluid_base, sets), threads)
            runs.wait()
            for h, values in batch.items():
                for v in values:
                    series, status = runs.read(_eval_dir(folders[h], v))
                    j, ex, ek = objective(series, refs[h]) if series is not None else (math.nan,) * 3
                    tried[h][v] = j
                    evaluations.append({"cell_size": h, "value": v, "objective": j, "X_star_error": ex,
                                        "K_star_error": ek, "round": rnd, "steps": status.get("steps"),
                                        "wall_seconds": status.get("wall_seconds"),
                                        "status": "finished" if series is not None else "failed"})
            if not args.quiet:
                print(f"round {rnd + 1}/{args.rounds}: " + "; ".join(
                    f"h = {h:g}: best {args.param.split('.')[-1]} = {bracket(t)[0]:.4g} (J = {t[bracket(t)[0]]:.4g})"
                    for h, t in tried.items() if any(math.isfinite(x) for x in t.values())))
    return _report(args, out, soils, tried, evaluations, refs, folders, bounds)


def _raw_of(path) -> dict:
    from geompm.schema.load import read_json

    return read_json(Path(path))


def _fluid_sets(args, h: float, value: float, end: float) -> list[str]:
    """The fluid run at the soil run's cell size and end time, with the parameter set to ``value``."""
    return args.set + [f"grid.cell_size={h!r}", f"{args.param}={value!r}", f"time.end={end!r}"]


def _eval_dir(folder: Path, value: float) -> Path:
    return folder / f"fluid_{value:.6g}"


def _report(args, out, soils, tried, evaluations, refs, folders, bounds) -> int:
    rows = []
    for _, _, h in sorted(soils, key=lambda s: -s[2]):
        if not any(math.isfinite(j) for j in tried[h].values()):
            rows.append({"cell_size": h, "value": None, "status": "no evaluation finished"})
            continue
        best, a, b = bracket(tried[h])
        ev = next(e for e in evaluations if e["cell_size"] == h and e["value"] == best)
        lo, hi = bounds[h]
        at_bound = abs(best / lo - 1) < 1e-9 or abs(best / hi - 1) < 1e-9
        rows.append({"cell_size": h, "value": best, "bracket_low": a, "bracket_high": b, "objective": ev["objective"],
                     "X_star_error": ev["X_star_error"], "K_star_error": ev["K_star_error"],
                     "evaluations": len(tried[h]), "source_value": SOURCE_MU_INF.get(h),
                     "status": "at a bound: widen --bounds" if at_bound else "finished"})
    write_csv(out / "calibration.csv", rows)
    write_csv(out / "evaluations.csv", evaluations)
    done = [r for r in rows if r.get("value") is not None]
    fit = linear_fit([r["cell_size"] for r in done], [r["value"] for r in done]) if len(done) >= 3 else None
    summary = {"param": args.param, "bounds": {str(h): bp for (_, _, h), bp in zip(soils, args.bound_pairs)}, "points": args.points, "rounds": args.rounds,
               "results": rows, "fit": dict(zip(("intercept", "slope", "r_squared"), fit)) if fit else None}
    atomic_write_json(out / "calibration.json", summary)
    name = args.param.split(".")[-1]
    for r in rows:
        if r.get("value") is not None:
            print(f"h = {r['cell_size']:g} m: {name} = {r['value']:.4g} (bracket {r['bracket_low']:.4g} to "
                  f"{r['bracket_high']:.4g}), J = {r['objective']:.4f} (X* {r['X_star_error']:.4f}, "
                  f"K* {r['K_star_error']:.4f}), {r['evaluations']} runs"
                  + ("" if r["status"] == "finished" else f"; WARNING: {r['status']}"))
        else:
            print(f"h = {r['cell_size']:g} m: {r['status']}")
    if fit:
        print(f"linear fit: {name} = {fit[0]:.4g} + {fit[1]:.4g} h, R^2 = {fit[2]:.4f}")
    try:
        from geompm.plots.calibration import plot_calibration

        fluids = {r["cell_size"]: M.read_run(_eval_dir(folders[r["cell_size"]], r["value"]))[0] for r in done}
        plot_calibration(out / "calibration.png", done, refs, fluids, fit, name, SOURCE_MU_INF)
        print(f"wrote {out / 'calibration.csv'}, {out / 'calibration.png'}")
    except ImportError:
        print(f"wrote {out / 'calibration.csv'} (calibration.png needs matplotlib)")
    return 0 if len(done) == len(rows) else 3
