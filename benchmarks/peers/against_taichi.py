"""Issue 38's targets in one run: geompm's bench scenes against the Taichi peer, interleaved, with float32
storage and one thread beside them.

    python benchmarks/peers/against_taichi.py [--peer-python PATH] [--rounds 3] [--steps 100]

``--peer-python`` is a Python with taichi installed (default: this one; ``pip install -e '.[bench]'``).
Each round runs, in an order that alternates between rounds so that a drift of the machine falls on both:

- ``geompm bench --scene fluid3d --scene fluid3d_mls --scene dp3d_mls`` (2 threads, float64);
- the same with ``--set solver.precision=float32`` (float32 storage);
- the same with ``NUMBA_NUM_THREADS=1``;
- the Taichi peer (benchmarks/peers/taichi_fluid3d.py) with ``--scheme usl`` and ``--scheme mls``, float64,
  on all cores, and ``--scheme mls --threads 1``.

Each geompm run also measures the machine's limits over its threads (the bench's triad and scalar
multiply-add rate, in GB/s and GFLOP/s), so the 2-thread scaling of the machine itself stands beside the
step's.  Prints every run's figures as they come, then the median of each over the rounds and the ratios
the issue names: fluid3d_mls / Taichi mls (target >= 4x), fluid3d (APIC) / Taichi usl (>= 4x), dp3d_mls /
Taichi mls (>= 3x), float32 against float64, 2 threads against 1 (>= 1.8x).  Speed ratios are peer time /
geompm time, so above 1 means geompm is faster.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENES = ("fluid3d", "fluid3d_mls", "dp3d_mls")
PEER = ROOT / "benchmarks" / "peers" / "taichi_fluid3d.py"


def geompm_runs(steps: int, sets: list[str], env: dict) -> dict[str, float]:
    """ns per particle-step of each scene of SCENES, from one ``geompm bench --json`` run, and the machine's
    limits that the bench measures in the same run: ``triad`` [GB/s] and ``scalar`` multiply-add rate
    [GFLOP/s] over the run's threads."""
    cmd = [sys.executable, "-m", "geompm.cli", "bench", "--no-cold", "--json", "--steps",
           str(steps), "--dir", str(ROOT / "benchmarks")]
    for s in SCENES:
        cmd += ["--scene", s]
    for s in sets:
        cmd += ["--set", s]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout
    found = {}
    for line in out.splitlines():
        if line.startswith("{"):
            r = json.loads(line)
            if "ns_per_particle_step" in r:
                found[r["scene"].split(":")[0]] = r["ns_per_particle_step"]
            elif r.get("scene") == "bandwidth":
                found["triad"] = r["triad_bytes_per_s"] / 1e9
                found["scalar"] = r["scalar_flops_per_s"] / 1e9
    return found


def peer_run(python: str, scheme: str, steps: int, threads: int) -> float:
    """ns per particle-step of the Taichi peer."""
    cmd = [python, str(PEER), "--scheme", scheme, "--steps", str(steps)]
    if threads:
        cmd += ["--threads", str(threads)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    rate = float(re.search(r"([0-9.e+]+) particle-steps/s", out).group(1))
    return 1e9 / rate


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--peer-python", default=sys.executable)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--steps", type=int, default=100)
    a = ap.parse_args()
    env2 = dict(os.environ)
    env2.pop("NUMBA_NUM_THREADS", None)
    env1 = dict(env2, NUMBA_NUM_THREADS="1")
    jobs = {
        "geompm f64": lambda: geompm_runs(a.steps, [], env2),
        "geompm f32": lambda: geompm_runs(a.steps, ["solver.precision=float32"], env2),
        "geompm f64 1 thread": lambda: geompm_runs(a.steps, [], env1),
        "taichi": lambda: {"usl": peer_run(a.peer_python, "usl", a.steps, 0),
                           "mls": peer_run(a.peer_python, "mls", a.steps, 0),
                           "mls 1 thread": peer_run(a.peer_python, "mls", a.steps, 1)},
    }
    got = {k: [] for k in jobs}
    names = list(jobs)
    for r in range(a.rounds):
        for name in (names if r % 2 == 0 else names[::-1]):
            res = jobs[name]()
            got[name].append(res)
            print(f"round {r + 1} {name}: " + ", ".join(f"{k} {v:.1f}" for k, v in res.items()), flush=True)
    med = {name: {k: statistics.median(run[k] for run in runs) for k in runs[0]} for name, runs in got.items()}
    print("\nmedians over", a.rounds, "rounds (ns per particle-step; triad GB/s, scalar GFLOP/s):")
    for name, vals in med.items():
        print(f"  {name}: " + ", ".join(f"{k} {v:.1f}" for k, v in vals.items()))
    g, f32, one, t = med["geompm f64"], med["geompm f32"], med["geompm f64 1 thread"], med["taichi"]
    print("\nratios (peer time / geompm time; target in brackets):")
    print(f"  fluid3d_mls vs Taichi mls: {t['mls'] / g['fluid3d_mls']:.2f}x (>= 4)")
    print(f"  fluid3d (APIC) vs Taichi usl: {t['usl'] / g['fluid3d']:.2f}x (>= 4)")
    print(f"  dp3d_mls vs Taichi mls: {t['mls'] / g['dp3d_mls']:.2f}x (>= 3)")
    for s in SCENES:
        print(f"  {s}: float32 storage {g[s] / f32[s]:.2f}x float64; 2 threads {one[s] / g[s]:.2f}x 1 thread "
              f"(>= 1.8)")
    print(f"  Taichi mls: 2 threads {t['mls 1 thread'] / t['mls']:.2f}x 1 thread")
    print(f"  the machine: scalar multiply-add rate, 2 threads {g['scalar'] / one['scalar']:.2f}x 1 thread; "
          f"triad {g['triad'] / one['triad']:.2f}x")
    print(json.dumps({"median_ns_per_particle_step": med}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
