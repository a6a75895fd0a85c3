"""``geompm bench``: particle-steps per second, memory and start-up of standard scenes.

Scenes are listed in ``benchmarks/scenes.json`` (name -> case, timed steps,
optional ``variants`` of ``--set`` overrides or other cases, a variant's
``"permute": true`` to shuffle its particles before timing, optional
``check``).  Each measurement runs in its own process
(``python -m geompm.bench.worker``) after a warm-up step; compilation is
excluded from the timing and reported as start-up seconds.  With
``cold_start`` a scene is also started once with an empty numba cache
(a temporary ``NUMBA_CACHE_DIR``) and once more from that cache: the cold and
warm start-up of docs/performance.md.

Checks printed under the table:
- ``spread``: time per particle-step from the smallest to the largest variant
  (linear cost: within 25 %);
- ``domain``: each variant's time against the first (grid work only where the
  particles are: within 20 %);
- ``mixed``: each ``<scene>/permuted`` variant (particles shuffled, the spatial
  sort on) against ``<scene>/ordered`` (seeding order): within 15 %, with the
  sort's own cost; ``<scene>/permuted_nosort`` shows what the sort buys;
- ``ratio``: each variant's ns per particle-step against the first's, and the share of its time its scheme's
  own solve took (Scheme.timings: the semi-implicit step's pressure solve).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from geompm.errors import CaseError

SPREAD_LIMIT = 0.25
DOMAIN_LIMIT = 0.20
MIXED_LIMIT = 0.15


def add_parser(sub) -> None:
    p = sub.add_parser("bench", help="benchmark standard scenes: particle-steps/s, memory, start-up",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", action="append", metavar="NAME", help="a scene of scenes.json (repeatable; default all)")
    p.add_argument("--dir", help="folder with scenes.json and the cases (default: ./benchmarks, else the repository's)")
    p.add_argument("--steps", type=int, help="timed steps for every scene, instead of each scene's own")
    p.add_argument("--json", action="store_true", help="one JSON object per measurement on its own line")
    p.add_argument("--no-cold", action="store_true", help="skip the cold/warm start-up measurements")
    p.add_argument("--list", action="store_true", help="list the scenes and exit")
    p.add_argument("--backend", choices=("cpu", "cuda"), help="run every scene on this solver.backend "
                   "(default: each case's own, cpu)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a value in every scene's case, "
                   "after the scene's own (e.g. grid.cell_size=0.0078125)")
    p.add_argument("--no-bandwidth", action="store_true", help="skip the machine's limits: the memory bandwidth (STREAM triad), the multiply-add rates and the roofline lines")
    p.set_defaults(func=cmd_bench)


def bench_dir(arg: str | None) -> Path:
    candidates = [Path(arg)] if arg else [Path("benchmarks"), Path(__file__).resolve().parents[2] / "benchmarks"]
    for d in candidates:
        if (d / "scenes.json").is_file():
            return d
    raise CaseError([("--dir", f"no scenes.json in {', '.join(str(c) for c in candidates)}; "
                               "run from the repository root or pass --dir")])


def measurements(name: str, spec: dict, folder: Path,
                 steps: int | None) -> list[tuple[str, str, list[str], int, bool]]:
    """(label, case path, --set list, steps, permute) for each measurement of a scene."""
    n = steps or int(spec["steps"])
    variants = spec.get("variants")
    if not variants:
        return [(name, str(folder / spec["case"]), [], n, False)]
    out = []
    for label, v in variants.items():
        if isinstance(v, dict):
            out.append((f"{name}:{label}", str(folder / v.get("case", spec.get("case"))), list(v.get("set", [])), n,
                        bool(v.get("permute", False))))
        else:
            out.append((f"{name}:{label}", str(folder / spec["case"]), list(v), n, False))
    return out


def run_worker(case: str, sets: list[str], steps: int, env_extra: dict | None = None, permute: bool = False) -> dict:
    """Run one measurement in a fresh process; the result, or {"error": ...}."""
    cmd = [sys.executable, "-m", "geompm.bench.worker", case, "--steps", str(steps)] + (["--permute"] if permute else [])
    for s in sets:
        cmd += ["--set", s]
    env = dict(os.environ, GEOMPM_BENCH_SPAWN=repr(time.time()), **(env_extra or {}))
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode:
        return {"error": (proc.stderr or proc.stdout).strip()[-800:]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def cold_and_warm(case: str, sets: list[str]) -> tuple[float, float]:
    """Start-up seconds with an empty numba cache, then from the cache that run filled (2 timed steps)."""
    with tempfile.TemporaryDirectory(prefix="geompm-cold-") as cache:
        env = {"NUMBA_CACHE_DIR": cache}
        cold = run_worker(case, sets, 2, env)
        warm = run_worker(case, sets, 2, env)
    if "error" in cold or "error" in warm:
        raise RuntimeError(cold.get("error") or warm.get("error"))
    return cold["startup_s"], warm["startup_s"]


HEADER = (f"{'scene':<18}{'particles':>10}{'nodes':>9}{'steps':>6}{'wall s':>8}{'p-steps/s':>11}"
          f"{'ns/p-step':>10}{'RSS MiB':>9}{'B/particle':>11}{'thr':>4}{'start s':>8}")


def row(label: str, r: dict) -> str:
    if "error" in r:
        return f"{label:<18} failed: {r['error'].splitlines()[-1] if r['error'] else ''}"
    start = f"{r['startup_s']:8.2f}"
    return (f"{label:<18}{r['particles']:>10}{r['active_nodes']:>9}{r['steps']:>6}{r['wall_s']:>8.2f}"
            f"{r['particle_steps_per_s']:>11.3g}{r['ns_per_particle_step']:>10.1f}"
            f"{r['peak_rss_bytes'] / 2**20:>9.0f}{r['bytes_per_particle']:>11.0f}{r['threads']:>4}{start}")


def ratio_lines(name: str, ok: list[tuple[str, dict]]) -> list[str]:
    """Each variant's ns per particle-step against the first's, and the share of its time its scheme's solve
    took (``scheme_timings``: the semi-implicit step's pressure solve) with its iterations per solve."""
    base_label, base = ok[0]
    lines = []
    for label, r in ok:
        t = r.get("scheme_timings") or {}
        text = f"{name}: {label} {r['ns_per_particle_step']:.0f} ns per particle-step"
        if label != base_label:
            text += f", {r['ns_per_particle_step'] / base['ns_per_particle_step']:.2f}x {base_label}'s"
        if t.get("solves"):
            text += (f"; the pressure solve {100 * t['solve_s'] / r['wall_s']:.0f} % of its time, "
                     f"{t['solve_iterations'] / t['solves']:.1f} CG iterations per solve, "
                     f"{t['hierarchy_builds']:.0f} hierarchies built")
        lines.append(text)
    return lines


def check_lines(name: str, spec: dict, results: list[tuple[str, dict]]) -> list[str]:
    ok = [(label, r) for label, r in results if "error" not in r]
    if len(ok) < 2 or not spec.get("check"):
        return []
    if spec["check"] == "spread":
        small = min(ok, key=lambda x: x[1]["particles"])
        large = max(ok, key=lambda x: x[1]["particles"])
        ratio = large[1]["ns_per_particle_step"] / small[1]["ns_per_particle_step"]
        verdict = "within" if abs(ratio - 1) <= SPREAD_LIMIT else "OUTSIDE"
        return [f"{name}: ns per particle-step {large[0]} / {small[0]} = {ratio:.3f} "
                f"({verdict} the {SPREAD_LIMIT:.0%} target)"]
    if spec["check"] == "mixed":
        return mixed_lines(name, dict(ok))
    if spec["check"] == "ratio":
        return ratio_lines(name, ok)
    base_label, base = ok[0]
    lines = []
    for label, r in ok[1:]:
        ratio = r["wall_s"] / base["wall_s"]
        vol = r["grid_cells"] / base["grid_cells"]
        verdict = "within" if ratio - 1 <= DOMAIN_LIMIT else "OUTSIDE"
        lines.append(f"{name}: {label} ({vol:.3g}x the grid cells of {base_label}) takes {ratio:.3f}x its time "
                     f"({verdict} the {DOMAIN_LIMIT:.0%} target)")
    return lines


def mixed_lines(name: str, by_label: dict) -> list[str]:
    lines = []
    for label, r in by_label.items():
        if not label.endswith("/permuted"):
            continue
        scene = label[: -len("/permuted")]
        ordered = by_label.get(f"{scene}/ordered")
        if ordered is None:
            continue
        ratio = r["ns_per_particle_step"] / ordered["ns_per_particle_step"]
        verdict = "within" if ratio - 1 <= MIXED_LIMIT else "OUTSIDE"
        unsorted = by_label.get(f"{scene}/permuted_nosort")
        extra = (f"; without the sort {unsorted['ns_per_particle_step'] / ordered['ns_per_particle_step']:.2f}x"
                 if unsorted else "")
        ns_step = r["ns_per_particle_step"]
        lines.append(f"{scene.split(':', 1)[-1]}: shuffled, then sorted every {r['sort_interval']} steps: "
                     f"{ratio:.3f}x the ordered time per particle-step ({verdict} the {MIXED_LIMIT:.0%} target){extra}; "
                     f"the sort of the shuffled order {r['first_sort_ns_per_particle']:.0f} ns per particle "
                     f"({r['first_sort_ns_per_particle'] / ns_step:.2f} steps); a later sort (order kept since) "
                     f"{r['sort_ns_per_particle']:.0f} ns over {r['sorts']} timed sorts, every {r['sort_interval']} "
                     f"steps {r['sort_ns_per_particle'] / ns_step / max(r['sort_interval'], 1):.1%} of the step time")
    return lines


def cmd_bench(args) -> int:
    folder = bench_dir(args.dir)
    scenes = json.loads((folder / "scenes.json").read_text())
    if args.list:
        for name, spec in scenes.items():
            print(f"{name}: {len(measurements(name, spec, folder, args.steps))} measurement(s)")
        return 0
    names = args.scene or list(scenes)
    unknown = [n for n in names if n not in scenes]
    if unknown:
        raise CaseError([("--scene", f"unknown scene {', '.join(unknown)}; choose from {', '.join(scenes)}")])
    if not args.json:
        print(HEADER)
    failed = False
    notes = []
    modelled = []  # (label, result) of the measurements whose scene has a flop and byte model
    for name in names:
        spec = scenes[name]
        results = []
        for label, case, sets, steps, permute in measurements(name, spec, folder, args.steps):
            sets = sets + list(args.set or []) + ([f"solver.backend={args.backend}"] if args.backend else [])
            r = run_worker(case, sets, steps, permute=permute)
            r["scene"] = label
            if spec.get("cold_start") and not args.no_cold and "error" not in r:
                r["cold_start_s"], r["warm_start_s"] = cold_and_warm(case, sets)
                notes.append(f"{label}: cold start {r['cold_start_s']:.1f} s (empty numba cache), "
                             f"warm start {r['warm_start_s']:.2f} s (from the cache)")
            failed |= "error" in r
            results.append((label, r))
            if "model" in spec and "error" not in r:
                r["roofline_flops"], r["roofline_bytes"] = spec["model"]["flops"], spec["model"]["bytes"]
                modelled.append((label, r))
            print(json.dumps(r) if args.json else row(label, r), flush=True)
        notes += check_lines(name, spec, results)
    if not args.no_bandwidth:
        from geompm.bench.peak import fma_rates
        from geompm.bench.stream import triad_bandwidth

        bw = triad_bandwidth()
        peaks = fma_rates()
        notes.append(f"memory bandwidth (STREAM triad, {_threads()} threads): {bw / 1e9:.1f} GB/s")
        notes.append(f"multiply-add rate ({_threads()} threads): scalar {peaks['scalar_flops_per_s'] / 1e9:.1f} GFLOP/s, "
                     f"vectorised L1 update {peaks['vector_flops_per_s'] / 1e9:.1f} GFLOP/s")
        if args.json:
            print(json.dumps({"scene": "bandwidth", "triad_bytes_per_s": bw, "threads": _threads(), **peaks}))
        for label, r in modelled:
            line = roofline(r, bw, peaks)
            notes.append(f"{label}: {line['text']}")
            if args.json:
                print(json.dumps({"scene": "roofline", "label": label,
                                  **{k: v for k, v in line.items() if k != "text"}}))
    if notes and not args.json:
        print()
        print("\n".join(notes))
    return 3 if failed else 0


def roofline(r: dict, triad: float, peaks: dict) -> dict:
    """How far a measurement is from the machine's limits: its modelled flops and bytes per particle-step
    (scenes.json "model") at its measured rate, against the triad bandwidth and the multiply-add rates."""
    rate = r["particle_steps_per_s"]
    flops, moved = r["roofline_flops"] * rate, r["roofline_bytes"] * rate
    out = {"flops_per_s": flops, "bytes_per_s": moved, "of_triad": moved / triad,
           "of_scalar_fma": flops / peaks["scalar_flops_per_s"], "of_vector_fma": flops / peaks["vector_flops_per_s"]}
    out["text"] = (f"{r['roofline_flops']} flops and {r['roofline_bytes']} bytes per particle-step (model): "
                   f"{flops / 1e9:.1f} GFLOP/s = {out['of_scalar_fma']:.0%} of the scalar multiply-add rate "
                   f"({out['of_vector_fma']:.0%} of the vectorised), {moved / 1e9:.1f} GB/s = "
                   f"{out['of_triad']:.0%} of the triad")
    return out


def _threads() -> int:
    import numba

    return numba.get_num_threads()
