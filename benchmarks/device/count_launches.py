"""Count what each CUDA step asks of the host (geompm/bench/cuda_counts.py): kernel launches, numpy arrays
handed to kernels (implicit round trips), copies each way, synchronisations, per step, for the bench scenes
(coarsened for the simulator), the softening scenes, the saturated one and a scene that sorts its particles every
step (an obstacle with its guard).

    NUMBA_ENABLE_CUDASIM=1 python benchmarks/device/count_launches.py [--steps 3] [--cells 8] [--held N] [--replay]
        [SCENE ...]
    python benchmarks/device/count_launches.py ...      (on a GPU: the same counts, the real host time)

Each step is taken as `geompm run` takes it: the time step, the step, the health and domain checks.  Prints one
table row and one JSON line per scene: the counts per step, the wall time per step, and the host's own time per
step (the wall time less the time inside kernel launches: under the simulator the kernels run as Python inside
them; on a device launches return at once and the host's time includes its waits at blocking copies); under the
simulator also the host's time alone (geompm/bench/cuda_host.py: launches that return at once, ``--host-steps``
steps three times)."""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from collections import Counter
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(ROOT / "tests" / "cuda"))


def bench_scenes(cells: int) -> dict:
    """name -> (case file, --set list) of the bench scenes at ``cells`` cells per side (along the short side
    of dp2d)."""
    sizes = {name: 1.0 / cells for name in ("fluid3d", "dp3d", "obstacle3d", "saturated3d")}
    sizes["dp2d"] = 0.15 / cells  # 0.6 x 0.15 m
    return {name: (ROOT / "benchmarks" / f"{name}.json", [f"grid.cell_size={h}"]) for name, h in sizes.items()}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--steps", type=int, default=3)
    ap.add_argument("--cells", type=int, default=8, help="cells per side of the bench scenes (default 8)")
    ap.add_argument("--sites", action="store_true", help="also list each copy's and launch's calling line")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="sets",
                    help="override in every scene (solver.particle_pass=separate)")
    ap.add_argument("--replay", action="store_true", help="also compare each step's launches with the previous "
                    "step's (geompm/bench/cuda_replay.py): could the step be replayed as a CUDA graph")
    ap.add_argument("--host-steps", type=int, default=0, help="under the simulator, also time this many steps "
                    "three times with every launch returning at once (geompm/bench/cuda_host.py; default: not)")
    ap.add_argument("--held", type=int, default=0, help="solver.held_step.steps: hold the step for up to this "
                    "many steps (engine/held_step.py); default: every step the stable one")
    args = ap.parse_args(argv)
    from cuda_parity import scenes as parity_scenes

    from geompm.api import scene_from_dict
    from geompm.bench.cuda_counts import KINDS, step_counts
    from geompm.bench.cuda_host import host_only
    from geompm.engine.scheduler import Simulation
    from geompm.errors import CaseError

    folder = Path(tempfile.mkdtemp())
    tiny = parity_scenes(folder)
    chosen = {**bench_scenes(args.cells),
              **{k: tiny[k] for k in ("mohr_coulomb_softening_trigger", "drucker_prager_softening_2d",
                                      "drucker_prager_cylinder_sorted")}}
    names = args.scenes or list(chosen)
    print(f"{'scene':<32}{'particles':>10}" + "".join(f"{k:>10}" for k in KINDS) + f"{'wall ms':>10}{'host ms':>10}"
          + f"{'steps':>7}{'batches':>8}{'host-only ms':>14}")
    for name in names:
        spec = chosen[name]
        if isinstance(spec, tuple):
            raw = json.loads(Path(spec[0]).read_text())
            base, sets = spec[0].parent, spec[1]
        else:
            raw = json.loads(json.dumps(spec))
            raw.pop("parity_place", None)  # the parity run's own key (tests/cuda/cuda_parity.py)
            base, sets = folder, []
        raw.setdefault("solver", {})["backend"] = "cuda"
        if args.held:
            raw["solver"]["held_step"] = {"steps": args.held}
        try:
            scene = scene_from_dict(raw, base, sets + args.sets)
        except CaseError as exc:  # a scene that refuses held steps (the saturated scheme): the reason, not a count
            print(f"{name:<32}refused: {exc.problems[0][0]}: {exc.problems[0][1]}", flush=True)
            continue
        sim = Simulation(scene)
        sim.distribute()
        sites = Counter() if args.sites else None
        reasons = Counter() if args.replay else None
        r = step_counts(sim, args.steps, sites, reasons)
        r["host_only_per_step"] = host_only(sim, args.host_steps) if args.host_steps else None
        alone = "-" if r["host_only_per_step"] is None else f"{1e3 * r['host_only_per_step']:.3f}"
        print(f"{name:<32}{scene.state.n:>10}" + "".join(f"{r[k]:>10.1f}" for k in KINDS)
              + f"{1e3 * r['wall_per_step']:>10.1f}{1e3 * r['host_per_step']:>10.2f}{r['steps']:>7}{r['batches']:>8}"
              + f"{alone:>14}")
        print(json.dumps({"scene": name, "particles": scene.state.n, **r}), flush=True)
        for (what, where), k in sorted((sites or {}).items(), key=lambda kv: -kv[1]):
            print(f"    {k / args.steps:6.1f} per step  {what:<14} {where}")
        if reasons is not None:
            pairs = max(r["batches"] or r["steps"], 2) - 1
            unit = "batch" if r["batches"] else "step"
            for key, what in (("previous", f"the previous {unit}"), ("two_back", f"the {unit} before that")):
                if r["replay"][key] is not None:
                    print(f"    against {what}: " + ", ".join(f"{k} {v:.1f}" for k, v in r["replay"][key].items()))
            for (kernel, name, kind), k in sorted(reasons.items(), key=lambda kv: (-kv[1], kv[0])):
                print(f"    {k / pairs:6.1f} per {unit:<5} {kind:<8} {kernel}: {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
