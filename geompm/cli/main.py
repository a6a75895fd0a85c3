"""Command line: ``geompm run | validate | info | plot | study | calibrate | bench | plugins | schema``.

Exit codes: 0 success, 2 invalid case or arguments (nothing computed),
3 the simulation became unphysical, 130 interrupted.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from geompm.contract import registry
from geompm.version import __version__
from geompm.errors import CaseError
from geompm.files.atomic import atomic_write_text
from geompm.files.ownership import may_write
from geompm.bench.command import add_parser as bench_parser
from geompm.cli.cuda_check import add_parser as cuda_check_parser
from geompm.study.calibrate import add_parser as calibrate_parser
from geompm.stability.command import add_parser as stability_parser
from geompm.study.command import add_parser as study_parser



def _load(args):
    from geompm.engine.first_step import check_output_intervals
    from geompm.schema import load_case
    from geompm.setup.assemble import assemble

    loaded = load_case(args.case, getattr(args, "set", None) or [])
    try:
        scene = assemble(loaded)
        check_output_intervals(scene, loaded.case.outputs)
        return loaded, scene
    except CaseError as exc:
        exc.warnings = exc.warnings or loaded.warnings
        raise


def cmd_validate(args) -> int:
    from geompm.backend.timestep import below_dt_min
    from geompm.engine.first_step import first_step_estimate, fixed_step_problem, stage_warnings, viscous_warning

    from geompm.mpm.memory import peak_rss

    loaded, scene = _load(args)
    problem = fixed_step_problem(scene)
    if problem:
        raise CaseError([problem], warnings=loaded.warnings)
    mem, nodes, dt = first_step_estimate(scene)
    held = peak_rss()  # the scene seeded, the laws' first loops compiled: what a run starts from
    cells = int(scene.grid.ncells.prod())
    print(f"case '{scene.name}' is valid: {scene.dim}D, {scene.state.n} particles, "
          f"{cells} grid cells ({'x'.join(str(c) for c in scene.grid.ncells)}, h = {scene.grid.h:g} m), "
          f"~{nodes} active nodes")
    steps = f"~{scene.end_time / dt:.0f} steps" if dt > 0.0 else "no step can be taken"
    print(f"estimated memory {mem / 2**20:.1f} MiB for the run's arrays; this check held {held / 2**20:.0f} MiB with "
          f"the scene seeded (a run peaks 0-20 % above it: docs/terrain.md); first time step {dt:.3g} s, "
          f"{steps} to t = {scene.end_time:g} s")
    if below_dt_min(scene, dt):
        print(f"warning: the first time step is below time.dt_min = {scene.dt_min:g} s: `geompm run` would stop "
              "before the first step (exit 3); the wave speed sqrt(E/rho), the viscosity and time.cfl set it")
    _step_limits(scene)
    scheme = scene.scheme
    print(f"scheme '{scheme.name}', a step's passes: {' -> '.join(scheme.passes)}")
    for line in scheme.report(scene):
        print(line)
    if scene.held_step is not None:
        n, fraction, margin = scene.held_step
        print(f"held step: up to {n} steps at {fraction:g} of the stable step, each checked before it is taken "
              f"(particles within {margin} cells of where a batch began): ~{1 / fraction - 1:.0%} more steps, one "
              "read of a device backend per batch (docs/performance.md, The held step)")
    for source in scene.inflows:
        print(source.describe())
    if scene.strength_trigger is not None:
        times, factors, ids = scene.strength_trigger
        names = ", ".join(scene.material_names[k] for k in ids)
        points = ", ".join(f"{f:g} at {t:g} s" for t, f in zip(times, factors))
        print(f"strength trigger: the strength of {names} divided by F = {points} (linear between, held outside)")
    if scene.water_table is not None:
        print(scene.water_table.describe(scene.material_names))
    loading = loaded.case.gravity_loading
    if loading is not None:
        print(f"gravity loading before the event: drained, local damping {loading.alpha:g}, held at t = 0, until the "
              f"unbalanced-force ratio is below {loading.tolerance:g} (at most {loading.max_time:g} s), then "
              "displacements reset")
    viscous_warning(loaded, scene, print)
    stage_warnings(scene, print, loaded)
    return 0


def _step_limits(scene) -> None:
    """Which limit sets the step, and what each material's other integration would make of it (the
    viscous warning repeats those when viscosity governs)."""
    from geompm.engine.estimate import step_report

    if scene.dt_fixed is not None:
        print(f"the time step is fixed: time.dt = {scene.dt_fixed:g} s")
        return
    rep = step_report(scene)
    print(rep.governing())
    if not rep.viscous_governs:
        for alt in rep.alternatives:
            print(alt.sentence(rep.dt, scene.end_time))


def cmd_run(args) -> int:
    from geompm.api import run

    return run(args.case, out=args.out, overrides=args.set or [], resume=args.resume, overwrite=args.overwrite,
               quiet=args.quiet).exit_code


def _run_dir_arg(path) -> Path:
    run_dir = Path(path)
    if not (run_dir / "series.csv").is_file():
        raise CaseError([("RUN_DIR", f"'{run_dir}' is not a geompm run folder (no series.csv); give a folder "
                                     "that `geompm run` wrote (runs/<case name> by default)")])
    return run_dir


def cmd_info(args) -> int:
    from geompm.engine import checkpoint

    if (Path(args.run_dir) / "stability.json").is_file():
        from geompm.stability.report import print_info

        print_info(Path(args.run_dir))
        return 0
    run_dir = _run_dir_arg(args.run_dir)
    case = json.loads((run_dir / "case.json").read_text())
    status_file = run_dir / "status.json"
    status = json.loads(status_file.read_text()) if status_file.is_file() else None
    lines = (run_dir / "series.csv").read_text().splitlines()
    cols, last = lines[0].split(","), dict(zip(lines[0].split(","), lines[-1].split(",")))
    print(f"run folder   {run_dir}")
    print(f"case         {case.get('name')} ({case.get('dimension')}D): {case.get('description', '')[:100]}")
    if status is None:
        ck = checkpoint.newest(run_dir)
        print("status       NOT FINISHED: no status.json, the process was killed; "
              + (f"newest checkpoint {ck.name}, resume with --resume" if ck else "no checkpoint"))
    else:
        state = "finished" if status["finished"] else f"NOT FINISHED ({status['reason'][:200]})"
        print(f"status       {state}")
        print(f"particles    {status['particles']}" + (f" ({status['deleted_particles']} deleted)"
                                                        if status["deleted_particles"] else ""))
        print(f"wall time    {status['wall_seconds']:.1f} s")
        if "mpi" in status:
            m = status["mpi"]
            print(f"MPI ranks    {m['ranks']}, slabs along {m['split_axis']} cut at cells {m['cuts']}, rebalanced "
                  f"{m['rebalanced']} times; particles per rank at the end {m['particles_per_rank']}")
        for name, o in status["obstacles"].items():
            unit = "N" if case.get("dimension") == 3 else "N/m"
            print(f"peak force   {name}: {o['peak_force']:.4g} {unit} at t = {o['peak_time']:.4g} s")
            if "peak_pressure" in o:
                at = ", ".join(f"{c:.3f}" for c in o["peak_pressure_at"])
                print(f"hot spot     {name}: face pressure {o['peak_pressure']:.4g} Pa at ({at}) m, "
                      f"t = {o['peak_pressure_time']:.4g} s")
            for line in impact_lines(name, o, unit):
                print(line)
    print(f"simulated    t = {float(last['time']):.6g} s of {case['time']['end']:g} s, {last['step']} steps")
    _print_runout(run_dir, case)
    outs = [name for name, present in (("VTU/PVD", (run_dir / "particles.pvd").is_file()),
                                       ("surfaces", (run_dir / "surfaces.pvd").is_file()),
                                       ("HDF5", (run_dir / "results.h5").is_file())) if present]
    print(f"outputs      series.csv ({len(lines) - 1} rows, {len(cols)} columns)" + "".join(f", {o}" for o in outs))
    maps = run_dir / "maps" / "summary.json"
    if maps.is_file():
        m = json.loads(maps.read_text())
        print(f"hazard maps  impact area {m['impact_area_m2']:.4g} m2 (depth >= {m['depth_threshold']:g} m), "
              f"deposit {m['deposit_volume_m3']:.4g} m3 of {m['source_volume_m3']:.4g} m3 released, "
              f"peak pressure {m['peak_pressure_Pa'] / 1e3:.4g} kPa, peak speed {m['peak_speed_m_s']:.3g} m/s")
        if m.get("travel_angle_deg") is not None:
            print(f"travel       runout {m['runout_length_m']:.4g} m, drop H = {m['drop_height_m']:.4g} m, "
                  f"H/L = {m['drop_height_m'] / m['runout_length_m']:.3f} (travel angle {m['travel_angle_deg']:.3g} deg)")
        if m.get("runout_thalweg_m") is not None:
            print(f"thalweg      runout {m['runout_thalweg_m']:.4g} m along the line of steepest descent from the "
                  "release's top")
    return 0


def impact_lines(name: str, o: dict, unit: str) -> list[str]:
    """`geompm info`'s design lines of one obstacle from its status.json entry (contact/impact.py,
    contact/impact_design.py): nothing before first contact."""
    if "filtered_peak_force" not in o:
        return []
    out = [f"filtered     {name}: peak {o['filtered_peak_force']:.4g} {unit} (moving average over "
           f"{o['force_window'] * 1e3:.3g} ms, window ending t = {o['filtered_peak_time']:.4g} s; first contact "
           f"t = {o['first_contact']:.4g} s)",
           f"impulse      {name}: {o['impulse']:.4g} {unit} s since first contact; load at the end "
           f"{o['final_force']:.4g} {unit} (window average)"]
    if "pressure_centre_height" in o:
        out.append(f"profile      {name}: {len(o['pressure_profile'])} bands of pressure over the height at the filtered "
                   f"peak, resultant {o['pressure_centre_height']:.3g} m above the lowest loaded face")
    if "probe_depth" in o:
        out.append(f"approach     {name}: probe '{o['probe']}' depth h = {o['probe_depth']:.4g} m, speed v = "
                   f"{o['probe_speed']:.4g} m/s, rho = {o['probe_density']:.4g} kg/m3, width w = "
                   f"{o['design_width']:.4g} m" + (f", Fr = {o['froude']:.3g}" if "froude" in o else ""))
    if "hydrostatic_ratio" in o:
        out.append(f"design       {name}: alpha = F / (rho v^2 h w) = {o['alpha']:.3g} (Kwan 2012: 2.5 rigid); "
                   f"k = F / (rho g h^2 w / 2) = {o['hydrostatic_ratio']:.3g} (Lichtenhahn 1973: 2.8-4.4)")
    return out


def _print_runout(run_dir: Path, case: dict) -> None:
    """The runout at the last series row: each body's front (and each material's) with where it started;
    the slide is the body whose front moved furthest, not the ground it rests on."""
    from geompm.study.metrics import body_fronts, moving_front, read_series

    series = read_series(run_dir / "series.csv")
    moving = moving_front(series)
    if moving is None:
        print(f"runout       front x = {float(series['front_x'][-1]):.3f} m at the last series row")
        return
    bodies = case.get("bodies") or []
    for col, first, last in body_fronts(series):
        name = col[len("front_x_"):]
        if name.startswith("body") and name[4:].isdigit() and int(name[4:]) < len(bodies):
            label = f"bodies.{name[4:]} ({bodies[int(name[4:])].get('material')})"
        else:
            label = f"material {name}"
        mark = "   <- the runout (the front that moved furthest)" if col == moving[0] else ""
        print(f"runout       {label}: front x = {last:.3f} m (from {first:.3f} m, moved {last - first:+.3f} m){mark}")


def cmd_plot(args) -> int:
    from geompm.plots.run import PNG_NAMES

    run_dir = _run_dir_arg(args.run_dir)
    out = Path(args.output) if args.output else run_dir / "plots"
    taken = [str(out / n) for n in PNG_NAMES if not may_write(out / n)]
    if taken:
        raise CaseError([("--output", f"{taken[0]} exists and geompm did not make it; it is not overwritten. "
                                      "Choose another -o folder")])
    try:
        from geompm.plots.run import plot_run

        made = plot_run(run_dir, args.output)
    except ImportError as exc:
        raise CaseError([("", f"plotting needs matplotlib ({exc}); install it with "
                              "python -m pip install 'geompm[plot]'")]) from None
    for png in made:
        print(f"wrote {png}")
    return 0


def cmd_plugins(args) -> int:
    from geompm.schema.load import BACKEND_KINDS

    for kind in registry.GROUPS:
        plugins = registry.available(kind)
        print(f"{registry.GROUPS[kind]}:")
        for name, info in sorted(plugins.items()):
            backends = getattr(info.plugin, "backends", None) if kind in BACKEND_KINDS else None
            on = f" (backends: {', '.join(backends)})" if backends else ""
            print(f"  {name:<16} [{info.package}] {registry.describe(info.plugin)}{on}")
    return 0


def cmd_schema(args) -> int:
    from geompm.schema.export import case_json_schema

    schema = case_json_schema(built_in_only=not args.installed)
    text = json.dumps(schema, indent=2) + "\n"
    if args.output:
        if not may_write(args.output) and not _is_case_schema(Path(args.output), schema["$id"]):
            raise CaseError([("--output", f"'{args.output}' exists and is not a geompm case schema; it is not "
                                          "overwritten. Choose another file")])
        atomic_write_text(args.output, text)
    else:
        sys.stdout.write(text)
    return 0


def _is_case_schema(path: Path, schema_id: str) -> bool:
    """True if ``path`` holds a geompm case schema (an older `geompm schema -o`), which may be replaced."""
    try:
        return path.is_file() and json.loads(path.read_text()).get("$id") == schema_id
    except (OSError, ValueError, AttributeError):
        return False


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="geompm", description="Material Point Method for geotechnical hazards")
    ap.add_argument("--version", action="version", version=f"geompm {__version__}")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="run a case")
    p.add_argument("case")
    p.add_argument("--out", help="run folder (default runs/<case name>)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a case value, e.g. grid.cell_size=0.01")
    p.add_argument("--overwrite", action="store_true", help="replace an existing run folder")
    p.add_argument("--quiet", action="store_true", help="no progress bar; only warnings and errors on the terminal")
    p.add_argument("--resume", metavar="RUN_DIR", help="continue the run in RUN_DIR from its newest checkpoint")
    p.set_defaults(func=cmd_run)
    p = sub.add_parser("validate", help="check a case and print its size")
    p.add_argument("case")
    p.add_argument("--set", action="append", metavar="KEY=VALUE")
    p.set_defaults(func=cmd_validate)
    p = sub.add_parser("info", help="summarise a run folder (or a stability folder: its factor of safety)")
    p.add_argument("run_dir")
    p.set_defaults(func=cmd_info)
    p = sub.add_parser("plot", help="PNGs of a run: series, obstacle forces, 2D deposit, hazard maps")
    p.add_argument("run_dir")
    p.add_argument("-o", "--output", help="folder for the PNGs (default RUN_DIR/plots)")
    p.set_defaults(func=cmd_plot)
    study_parser(sub)
    stability_parser(sub)
    calibrate_parser(sub)
    bench_parser(sub)
    cuda_check_parser(sub)
    p = sub.add_parser("plugins", help="list installed plugins")
    p.set_defaults(func=cmd_plugins)
    p = sub.add_parser("schema", help="print the case JSON Schema (or write it with -o)")
    p.add_argument("-o", "--output", help="write to this file, e.g. schemas/case.schema.json")
    p.add_argument("--installed", action="store_true",
                   help="also the third-party plugins installed here (default: geompm's own, as schemas/case.schema.json)")
    p.set_defaults(func=cmd_schema)
    return ap


def _one_line(text: str) -> str:
    """``text`` with every non-printable character (newlines, U+0085, U+2028, controls) escaped, so that
    one problem is one line whatever keys and values a case holds."""
    return "".join(c if c.isprintable() else ascii(c)[1:-1] for c in str(text))


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except CaseError as exc:
        refused = all(path.startswith("--") or path.isupper() for path, _ in exc.problems)  # an option or argument
        print("error: refused:" if refused else "error: the case is not valid:", file=sys.stderr)
        for path, msg in exc.problems:
            print(f"  {_one_line(path) or '<case>'}: {_one_line(msg)}", file=sys.stderr)
        for path, msg in exc.warnings:  # indented like the problems: every line after the heading is "  path: ..."
            print(f"  warning: {path}: {_one_line(msg)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted; output written so far is kept", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
