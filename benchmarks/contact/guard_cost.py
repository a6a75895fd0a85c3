"""Cost of the particle-level contact guard (issue 15, point 1) in ns per particle-step.

    python benchmarks/contact/guard_cost.py [--steps 60] [--case benchmarks/obstacle3d.json]

Runs the case (default: geompm bench's obstacle3d scene, 3D, an STL pillar in front of a
collapsing block) through the Python API, times every obstacle's particle pass that runs (the guard,
through the CPU backend's ``_particle_pass``; a pass the backend skips, ParticleStage.particle_reach, costs
nothing and is counted) apart from the whole step, after 5 warm-up steps
(compilation), and prints both per particle-step with the share of the step that the guard takes.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402
from geompm.obstacles.base import RigidObstacle  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--case", default=str(ROOT / "benchmarks" / "obstacle3d.json"))
    ap.add_argument("--set", action="append", default=[])
    a = ap.parse_args()
    sim = Simulation(scene_from_file(a.case, ["outputs=[]", *a.set]))
    guards = [s for s in sim.scene.obstacles if isinstance(s, RigidObstacle)]
    spent = [0.0]
    skipped = [0]
    be = sim.backend
    inner, stages = be._particle_pass, be.particle_stages

    def timed(stage, *args):
        t0 = time.perf_counter()
        inner(stage, *args)
        if stage in guards:
            spent[0] += time.perf_counter() - t0
            skipped[0] -= 1

    def counted(every, dt, t):
        skipped[0] += sum(s in guards for s in every)
        stages(every, dt, t)
    be._particle_pass, be.particle_stages = timed, counted
    for _ in range(5):
        sim.step(sim.stable_dt())
    spent[0] = 0.0
    skipped[0] = 0
    t0 = time.perf_counter()
    for _ in range(a.steps):
        sim.step(sim.stable_dt())
    wall = time.perf_counter() - t0
    ps = sim.state.n * a.steps
    print(f"{a.case}: {sim.state.n} particles, {len(guards)} guarded obstacle(s), {a.steps} steps")
    print(f"step  {1e9 * wall / ps:.1f} ns per particle-step")
    print(f"guard {1e9 * spent[0] / ps:.1f} ns per particle-step ({100 * spent[0] / wall:.1f} % of the step); "
          f"{skipped[0]} of {a.steps * len(guards)} guard passes skipped (the particles' box beside the lattice)")


if __name__ == "__main__":
    main()
