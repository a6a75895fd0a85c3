"""Command line: ``geompm run | validate | plugins | schema``.

Exit codes: 0 success, 2 invalid case or arguments (nothing computed),
3 the simulation became unphysical, 130 interrupted.
"""

from __future__ import annotations

import argparse
import json
import logging
import shutil
import sys
from pathlib import Path

from . import __version__, registry
from .errors import CaseError, SimulationError

log = logging.getLogger("geompm")


def _setup_logging(run_dir: Path | None = None):
    log.setLevel(logging.INFO)
    log.handlers.clear()
    term = logging.StreamHandler(sys.stdout)
    term.setFormatter(logging.Formatter("%(message)s"))
    log.addHandler(term)
    if run_dir is not None:
        fh = logging.FileHandler(run_dir / "run.log", mode="a")
        fh.setFormatter(logging.Formatter("%(asctime)s %(message)s"))
        log.addHandler(fh)


def _load(args):
    from .assemble import assemble
    from .schema import load_case

    loaded = load_case(args.case, getattr(args, "set", None) or [])
    return loaded, assemble(loaded)


def _estimate(scene) -> tuple[float, int, float]:
    """(bytes of memory, active grid nodes, first time step [s])."""
    import numba
    import numpy as np

    from .engine.timestep import stable_dt

    st = scene.state
    span = (st.p_x.max(axis=0) - st.p_x.min(axis=0)) / scene.grid.h + 4
    nodes = int(np.prod(np.ceil(span)))
    d = scene.dim
    grid_bytes = nodes * 8 * (numba.get_num_threads() * (1 + 2 * d) + 1 + 4 * d)
    return st.nbytes() + grid_bytes, nodes, stable_dt(scene, st)


def cmd_validate(args) -> int:
    _, scene = _load(args)
    mem, nodes, dt = _estimate(scene)
    cells = int(scene.grid.ncells.prod())
    print(f"case '{scene.name}' is valid: {scene.dim}D, {scene.state.n} particles, "
          f"{cells} grid cells ({'x'.join(str(c) for c in scene.grid.ncells)}, h = {scene.grid.h:g} m), "
          f"~{nodes} active nodes")
    print(f"estimated memory {mem / 2**20:.1f} MiB, first time step {dt:.3g} s, "
          f"~{scene.end_time / dt:.0f} steps to t = {scene.end_time:g} s")
    return 0


def cmd_run(args) -> int:
    from .engine.runner import run
    from .engine.scheduler import Simulation
    from .writers.series import SeriesWriter

    loaded, scene = _load(args)
    run_dir = Path(args.out) if args.out else Path("runs") / scene.name
    if run_dir.exists() and any(run_dir.iterdir()):
        if not args.overwrite:
            raise CaseError([("", f"run folder '{run_dir}' already exists; use --overwrite or --out DIR")])
        shutil.rmtree(run_dir)
    run_dir.mkdir(parents=True, exist_ok=True)
    (run_dir / "case.json").write_text(json.dumps(loaded.raw, indent=2) + "\n")
    _setup_logging(run_dir)
    mem, nodes, dt = _estimate(scene)
    log.info(f"geompm {__version__}: case '{scene.name}', {scene.dim}D, {scene.state.n} particles, "
             f"h = {scene.grid.h:g} m, end time {scene.end_time:g} s, first dt {dt:.3g} s -> {run_dir}")
    writers = list(scene.writers)
    if not any(isinstance(w, SeriesWriter) for w in writers):
        writers.append(SeriesWriter(SeriesWriter.Params(), 0.0))
    sim = Simulation(scene)
    try:
        summary = run(sim, run_dir, writers, progress=not args.quiet)
    except SimulationError as exc:
        log.error(f"run stopped at step {sim.step_count}, t = {sim.time:.6g} s: {exc}")
        return 3
    for stage in scene.boundaries + scene.obstacles + scene.damping:
        if stage.summary():
            log.info(stage.summary())
    log.info(f"done: {summary.steps} steps to t = {summary.sim_time:.6g} s in {summary.wall_seconds:.2f} s wall, "
             f"{summary.particle_steps_per_second:.3g} particle-steps/s")
    return 0


def cmd_plugins(args) -> int:
    for kind in registry.GROUPS:
        plugins = registry.available(kind)
        print(f"{registry.GROUPS[kind]}:")
        for name, info in sorted(plugins.items()):
            print(f"  {name:<16} [{info.package}] {registry.describe(info.plugin)}")
    return 0


def cmd_schema(args) -> int:
    from .schema.export import case_json_schema

    text = json.dumps(case_json_schema(), indent=2) + "\n"
    if args.output:
        Path(args.output).write_text(text)
    else:
        sys.stdout.write(text)
    return 0


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="geompm", description="Material Point Method for geotechnical hazards")
    ap.add_argument("--version", action="version", version=f"geompm {__version__}")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="run a case")
    p.add_argument("case")
    p.add_argument("--out", help="run folder (default runs/<case name>)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a case value, e.g. grid.cell_size=0.01")
    p.add_argument("--overwrite", action="store_true", help="replace an existing run folder")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_run)
    p = sub.add_parser("validate", help="check a case and print its size")
    p.add_argument("case")
    p.add_argument("--set", action="append", metavar="KEY=VALUE")
    p.set_defaults(func=cmd_validate)
    p = sub.add_parser("plugins", help="list installed plugins")
    p.set_defaults(func=cmd_plugins)
    p = sub.add_parser("schema", help="print the case JSON Schema (or write it with -o)")
    p.add_argument("-o", "--output", help="write to this file, e.g. schemas/case.schema.json")
    p.set_defaults(func=cmd_schema)
    return ap


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except CaseError as exc:
        print("error: the case is not valid:", file=sys.stderr)
        for path, msg in exc.problems:
            print(f"  {path or '<case>'}: {msg}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted; output written so far is kept", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
