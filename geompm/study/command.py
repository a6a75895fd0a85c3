"""``geompm study``: run every variant of a case on Dask and measure speed against accuracy.

    geompm study cases/column_collapse.json --vary grid.cell_size=0.02,0.01,0.005
    geompm study cases/landslide.json --sample materials.soil.friction_angle=normal(31,2) --samples 64 --seed 1

Writes to ``--out`` (default ``studies/<case name>``): ``runs/vNNN`` (one
ordinary run folder per variant), ``study.csv``, ``study_summary.json`` and
``study.png``.  Every variant is validated before anything runs.
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

from geompm.errors import CaseError
from geompm.files.atomic import atomic_write_json
from geompm.files.ownership import holds_only, prepare_folder
from geompm.schema.load import apply_overrides, load_case, read_json
from geompm.study import metrics as M
from geompm.study import report
from geompm.study.execute import Pool, add_threads_option, check_threads, finished, run_variant, threads_per_run, variant_case
from geompm.study.maps import ensemble_maps
from geompm.study.plan import build_plan, parse_sample, parse_vary

SCALARS = ("runout", "height", "peak_force", "impulse")
#: what a study reports per obstacle (``--metric impact`` asks for all of them)
OBSTACLE_SCALARS = ("peak_force", "filtered_peak_force", "impulse", "final_force", "alpha", "hydrostatic_ratio")


def add_parser(sub) -> None:
    p = sub.add_parser("study", help="run variants of a case on Dask: convergence, speed vs accuracy, Monte Carlo")
    p.add_argument("case")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="values of one case key, e.g. grid.cell_size=0.02,0.01,0.005 (all combinations run)")
    p.add_argument("--sample", action="append", default=[], metavar="KEY=DIST(ARGS)",
                   help="draw a case key, e.g. materials.soil.friction_angle=normal(31,2)")
    p.add_argument("--samples", type=int, default=16, help="number of draws with --sample (default 16)")
    p.add_argument("--seed", type=int, default=0, help="random seed for --sample (default 0)")
    p.add_argument("--metric", action="append", default=[], metavar="NAME",
                   help="runout, runout:body<b> or runout:<material> (cases with several bodies or materials), "
                        "peak_force, filtered_peak_force, impulse, final_force, alpha, hydrostatic_ratio (each "
                        "per obstacle, or NAME:LABEL), impact (all of these), or a series.csv column (front_x, kinetic_energy, X_star, ...)")
    p.add_argument("--reference", help="'finest' (default with --vary), a run folder, or a CSV with a time column")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override for every variant")
    p.add_argument("--out", help="study folder (default studies/<case name>)")
    p.add_argument("--resume", action="store_true", help="keep finished variants, run (or resume) the others")
    p.add_argument("--overwrite", action="store_true", help="delete an existing study folder first")
    p.add_argument("--keep-outputs", action="store_true",
                   help="keep the case's VTU/HDF5 writers in every variant (default: series.csv only)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="an existing Dask scheduler (default: LocalCluster)")
    p.add_argument("--workers", type=int, help="variants in flight on the LocalCluster (default: CPU cores)")
    add_threads_option(p)
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_study)


def series_only(raw: dict) -> list[str]:
    """A --set that keeps only the case's series writer (one is added at the finest output interval if absent)
    and its hazard maps (small rasters: the study's ensemble maps are made of them)."""
    outs = raw.get("outputs", [])
    if not isinstance(outs, list) or not all(isinstance(o, dict) for o in outs):
        return []  # not a list of writers: left as it is, for the case check to refuse with its JSON path
    keep = [o for o in outs if o.get("writer") == "series"]
    if not keep:
        keep = [{"writer": "series", "interval": min((o.get("interval", 0.0) for o in outs), default=0.0)}]
    keep += [o for o in outs if o.get("writer") == "hazard_maps"]
    return [f"outputs={json.dumps(keep)}"]


def _variant_label(v) -> str:
    return f"variant {v.name} ({', '.join(v.sets)})" if v.values else f"variant {v.name}"


def validate_all(case: str, variants, common: list[str]) -> list[str]:
    """Every variant through all the case checks (schema, plugins, assembly); one CaseError listing all
    problems, before any run.  Returns the warnings of stages whose physics changes with the cell size
    (Stage.refines_with_the_grid) when the variants differ in it."""
    from geompm.engine.first_step import check_output_intervals
    from geompm.setup.assemble import assemble

    problems, warnings, sizes = [], {}, set()
    for v in variants:
        try:
            loaded = load_case(case, common + v.sets)
            scene = assemble(loaded)
            check_output_intervals(scene, loaded.case.outputs)
            sizes.add(scene.grid.h)
            warnings.update(dict.fromkeys(w for s in scene.stages if (w := s.refines_with_the_grid())))
        except CaseError as exc:
            problems += [(f"{_variant_label(v)}: {path}", msg) for path, msg in exc.problems]
    if problems:
        raise CaseError(problems)
    return list(warnings) if len(sizes) > 1 else []


def load_reference(spec: str | None, has_vary: bool):
    """('finest' | None | (scalars, series)) from the --reference argument."""
    if spec is None:
        return "finest" if has_vary else None
    if spec == "finest":
        return "finest"
    path = Path(spec)
    try:
        if path.is_dir():
            series, status = M.read_run(path)
        elif path.is_file():
            series, status = M.read_series(path), {}
        else:
            raise CaseError([("--reference", f"'{spec}' is neither 'finest', a run folder nor a CSV file")])
    except (OSError, ValueError) as exc:
        raise CaseError([("--reference", f"cannot read '{spec}': {exc}")]) from None
    return M.scalar_metrics(series, status), series


def _metric_names(requested: list[str], series_list, rows=()) -> tuple[list[str], list[str]]:
    """(scalar metric names, series columns) to report: the obstacles' are those the rows have (a ground's
    force is none: metrics.scalar_metrics), the hazard maps' where the runs wrote them."""
    cols = set().union(*[set(s) for s in series_list if s is not None]) if series_list else set()
    labels = sorted({lab for s in series_list if s is not None for lab in M.obstacle_labels(s)})
    if rows:  # those the finished runs measured (a ground's force is not a metric)
        labels = [lab for lab in labels if any(f"peak_force:{lab}" in r for r in rows)]
    maps = [m for m in M.MAP_METRICS.values() if any(m in r for r in rows)]
    wanted = requested or ["runout", "height", "peak_force", "filtered_peak_force", "impulse", *maps,
                           *M.SERIES_DEFAULT]
    scalars, columns = [], []
    fronts = sorted({c[len("front_x_"):] for s in series_list if s is not None
                     for c in s if c.startswith("front_x_")})
    for name in wanted:
        if name == "runout":
            scalars.append("runout")
            if not requested:
                scalars += [f"runout:{f}" for f in fronts]  # each body's and material's, where there are several
        elif name.startswith("runout:") and name.partition(":")[2] in fronts:
            scalars.append(name)
        elif name == "height":
            if any(s is not None and "deposit_height" in s for s in series_list):
                scalars.append("height")
        elif name == "impact":  # the barrier's design numbers: every obstacle metric of each obstacle
            scalars += [f"{key}:{lab}" for lab in labels for key in OBSTACLE_SCALARS]
        elif name in OBSTACLE_SCALARS:
            scalars += [f"{name}:{lab}" for lab in labels]
        elif name.partition(":")[0] in OBSTACLE_SCALARS and name.partition(":")[2] in labels:
            scalars.append(name)  # one obstacle's: peak_force:LABEL, impulse:LABEL, alpha:LABEL ...
        elif name in M.MAP_METRICS.values():
            scalars.append(name)
        elif name in cols or name in M.SERIES_DEFAULT:
            columns.append(name)
    return scalars, columns


def check_metrics(requested: list[str]) -> None:
    bad = [m for m in requested if not m or "," in m or "=" in m]
    if bad:
        raise CaseError([("--metric", f"'{bad[0]}' is not a metric name; give one name per --metric")])


STUDY_FILES = {"runs", "study.csv", "study_summary.json", "study.png", "maps"}


def _prepare_folder(out: Path, args) -> None:
    prepare_folder(out, "study", resume=args.resume, overwrite=args.overwrite,
                   protect=((Path(args.case).resolve().parent, f"the case file {args.case}"),),
                   legacy=lambda f: holds_only(f, STUDY_FILES))
    (out / "runs").mkdir(exist_ok=True)


def _run(pool: Pool, case, jobs, quiet: bool, threads_wanted: int | None = None) -> dict:
    from distributed import as_completed

    threads = threads_per_run(pool.workers, len(jobs), threads_wanted)
    futures = {pool.submit(run_variant, case, str(d), sets, threads, name=v.name): v for v, d, sets in jobs}
    outcomes = {}
    bar = None
    if not quiet:
        from tqdm import tqdm

        bar = tqdm(total=len(futures), unit="variant", desc=f"study ({pool.workers} in flight, "
                                                               f"{threads} thread(s) each)")
    for fut in as_completed(futures):
        v = futures[fut]
        try:
            outcomes[v.name] = fut.result()
        except Exception as exc:  # the worker died twice: report, keep the others
            outcomes[v.name] = {"exit_code": -1, "error": f"worker lost: {exc}"}
        if bar is not None:
            bar.update(1)
            if outcomes[v.name]["exit_code"]:
                bar.write(f"{v.name} ({v.label()}) failed: {outcomes[v.name]['error'][-300:]}")
    if bar is not None:
        bar.close()
    return outcomes


def cmd_study(args) -> int:
    case = args.case
    raw = read_json(Path(case))
    check_metrics(args.metric)
    check_threads(args.threads)
    if args.samples < 1:
        raise CaseError([("--samples", "must be at least 1")])
    vary, samples = parse_vary(args.vary), parse_sample(args.sample)
    variants = build_plan(vary, samples, args.samples, args.seed)
    common = list(args.set) + ([] if args.keep_outputs else series_only(apply_overrides(raw, args.set)))
    for line in validate_all(case, variants, common):
        print(f"warning: {line}", file=sys.stderr)
    reference = load_reference(args.reference, bool(vary))
    out = Path(args.out or Path("studies") / raw.get("name", Path(case).stem))
    _prepare_folder(out, args)

    dirs = {v.name: out / "runs" / v.name for v in variants}
    todo = [(v, dirs[v.name], common + v.sets) for v in variants
            if not (args.resume and finished(dirs[v.name], variant_case(raw, common + v.sets)))]
    if len(todo) < len(variants):
        print(f"--resume: {len(variants) - len(todo)} of {len(variants)} variants already finished, kept")
    outcomes = {}
    if todo:
        workers = None if args.scheduler else min(args.workers or os.cpu_count() or 1, len(todo))
        with Pool(args.scheduler, workers) as pool:
            outcomes = _run(pool, str(Path(case).resolve()), todo, args.quiet, args.threads)

    pairs = [report.run_row(v, dirs[v.name], outcomes.get(v.name)) for v in variants]
    rows, series = [p[0] for p in pairs], [p[1] for p in pairs]
    scalar_names, series_names = _metric_names(args.metric, series, rows)
    ref_name = None
    if reference == "finest":
        i = report.finest(rows)
        if i is not None:
            ref_name = rows[i]["variant"]
            reference = ({k: rows[i][k] for k in scalar_names if k in rows[i]}, series[i])
        else:
            reference = None
    elif reference is not None:
        ref_name = args.reference
    if reference is not None:
        report.add_errors(rows, series, reference[0], reference[1], scalar_names, series_names)
    report.write_csv(out / "study.csv", rows)

    done = [dirs[r["variant"]] for r in rows if r["status"] == "finished"]
    try:
        maps = ensemble_maps(out, done)
    except ValueError as exc:
        maps = None
        print(f"warning: no ensemble maps: {exc}", file=sys.stderr)
    orders = report.convergence_orders(rows, list(vary), scalar_names, series_names)
    summary = {"case": str(case), "variants": len(rows), "finished": sum(r["status"] == "finished" for r in rows),
               "reference": ref_name, "varied": vary, "sampled": {k: f"{d}{tuple(a)}" for k, (d, a) in samples.items()},
               "seed": args.seed if samples else None, "orders": orders,
               "distribution": report.distribution(rows, scalar_names) if samples else {},
               **({"maps": maps} if maps else {})}
    atomic_write_json(out / "study_summary.json", json.loads(json.dumps(summary, default=str)))
    errs = [f"{n}_error" for n in scalar_names] + [f"{c}_l2_error" for c in series_names]
    try:
        made = report.plot_study(out / "study.png", rows, errs if reference is not None else [], scalar_names,
                                 f"{raw.get('name', case)}: reference {ref_name}" if ref_name else str(raw.get("name")))
    except ImportError:
        made = False
        print("study.png not drawn: install matplotlib (python -m pip install 'geompm[plot]')")
    _print_summary(rows, summary, errs, out, made, scalar_names)
    return 0 if summary["finished"] == len(rows) else 3


def shown(v: float, digits: int = 4) -> str:
    """A value with ``digits`` significant digits, but a map coordinate (|v| >= 1e4: an easting of 612 345.67 m)
    in full to the centimetre, never as 6.123e+05."""
    return f"{v:.2f}" if abs(v) >= 1e4 else f"{v:.{digits}g}"


def _print_summary(rows, summary, errs, out: Path, made: bool, scalars=()) -> None:
    print(f"{summary['finished']} of {summary['variants']} variants finished; reference: {summary['reference']}")
    for r in rows:
        e = "  ".join(f"{n}={r[n]:.3g}" for n in errs if isinstance(r.get(n), float) and math.isfinite(r[n]))
        wall = f"{r['wall_seconds']:.1f} s" if r.get("wall_seconds") is not None else "-"
        print(f"  {r['variant']}  {r['status'][:60]:<10}  {wall:>9}  {e}")
        values = "  ".join(f"{n}={shown(r[n], 5)}" for n in scalars if isinstance(r.get(n), float) and math.isfinite(r[n]))
        if values:
            print(f"         {r.get('label', '')}: {values}")
    for o in summary["orders"]:
        group = ", ".join(f"{k}={v}" for k, v in o["group"].items())
        print(f"observed order of convergence{' (' + group + ')' if group else ''}, h = {o['cell_sizes']}:")
        for k, v in o.items():
            if k not in ("group", "cell_sizes"):
                print(f"  {k}: {v:.2f}" if isinstance(v, float) and math.isfinite(v) else f"  {k}: not monotone")
    for name, d in summary["distribution"].items():
        print(f"{name}: mean {shown(d['mean'])}, sd {d['std']:.3g}, 5% {shown(d['p05'])}, median {shown(d['p50'])}, "
              f"95% {shown(d['p95'])} (n = {d['n']})")
    maps = summary.get("maps")
    if maps:
        print(f"ensemble maps of {maps['runs']} runs in {out / 'maps'}: probability of reach, and the 50th and 90th "
              f"percentiles of depth, speed and pressure; area reached by any run {maps['area_reached_by_any_m2']:.6g} "
              f"m2, by half {maps['area_reached_by_half_m2']:.6g} m2, by all {maps['area_reached_by_all_m2']:.6g} m2")
    print(f"wrote {out / 'study.csv'}" + (f", {out / 'study.png'}" if made else "") + f", {out / 'study_summary.json'}")
    sys.stdout.flush()
