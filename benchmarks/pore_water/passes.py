"""Time each pass of the saturated step (schemes/saturated/cpu.py, schemes/saturated/scheme.py) on the
bench scene saturated3d, warm, and the dry step of dp3d beside it, in ns per particle-step.

    python benchmarks/pore_water/passes.py [STEPS]

Each pass is timed where it runs inside whole steps (the generated loop of each per-item function, the
scatters, the backend's kernels); the sum is compared with a whole step. docs/pore-water.md, Speed and
memory.
"""

import json
import sys
import time
from pathlib import Path

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

HERE = Path(__file__).resolve().parents[1]


def timed(table, name, fn):
    """fn, its time added to table[name] at each call."""
    def call(*args, **kw):
        t = time.perf_counter()
        out = fn(*args, **kw)
        table[name] = table.get(name, 0.0) + time.perf_counter() - t
        return out
    return call


def saturated_passes(steps):
    """Every pass of the saturated scheme's steps timed where it runs: each per-item function's generated
    loop (Backend.each) by the function's name, the scatters, and the backend's own kernels."""
    sim = Simulation(scene_from_dict(json.loads((HERE / "saturated3d.json").read_text())))
    for _ in range(3):  # compile and settle
        sim.step(sim.stable_dt())
    be, wet = sim.backend, sim.backend.scheme_passes
    table = {}
    each = be.each
    be.each = lambda fn, n, *args: timed(table, fn.__name__, each)(fn, n, *args)
    wet._scatter = timed(table, "solid P2G (the dry kernel) and water P2G (scatter, chunk sum)", wet._scatter)
    wet._smooth_scatter = timed(table, "smoothing's scatter", wet._smooth_scatter)
    for name in ("grid_update", "g2p", "update_stress", "grid_stage", "particle_stages", "sort_particles"):
        setattr(be, name, timed(table, name, getattr(be, name)))
    for _ in range(steps):
        sim.step(sim.stable_dt())
    n = sim.state.n
    return {k: v / steps / n * 1e9 for k, v in table.items()}, n


def whole_step(case, steps):
    sim = Simulation(scene_from_dict(json.loads((HERE / case).read_text())))
    for _ in range(3):
        sim.step(sim.stable_dt())
    t = time.perf_counter()
    for _ in range(steps):
        sim.step(sim.stable_dt())
    return (time.perf_counter() - t) / steps / sim.state.n * 1e9


def main(steps=20):
    passes, n = saturated_passes(steps)
    print(f"saturated3d, {n} particles, {steps} steps, ns per particle-step:")
    for k, v in sorted(passes.items(), key=lambda kv: -kv[1]):
        print(f"  {v:8.1f}  {k}")
    print(f"  {sum(passes.values()):8.1f}  sum of the passes")
    print(f"whole step: saturated3d {whole_step('saturated3d.json', steps):.1f}, dp3d {whole_step('dp3d.json', steps):.1f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)
