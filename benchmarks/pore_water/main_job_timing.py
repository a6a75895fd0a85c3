"""The main job's wall time, dry against saturated (docs/pore-water.md, The semi-implicit step): one case run
to END s without writers, after its first step (the compilation, reported apart), printing one JSON line:
steps, wall seconds, the scheme's own solve totals (Scheme.timings: the semi-implicit step's pressure solves,
their CG iterations and hierarchies) and the peak resident memory.  Run the cases one after the other on an
idle machine.

    python benchmarks/pore_water/main_job_timing.py CASE END [KEY=VALUE ...]
"""

import json
import sys
import time
from pathlib import Path

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.mpm.memory import peak_rss
from geompm.schema.load import apply_overrides, read_json


def main(argv):
    case, end, sets = Path(argv[0]), float(argv[1]), argv[2:]
    raw = apply_overrides(read_json(case), list(sets))
    raw["outputs"] = []
    sim = Simulation(scene_from_dict(raw, base_dir=str(case.resolve().parent)))
    t0 = time.perf_counter()
    sim.step(sim.stable_dt())
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))
    wall = time.perf_counter() - t0
    print(json.dumps({"case": str(case), "sets": sets, "end": end, "particles": sim.state.n, "steps": sim.step_count,
                      "first_step_s": round(first, 2), "wall_s": round(wall, 2),
                      "ms_per_step": round(1e3 * wall / max(sim.step_count - 1, 1), 3),
                      "front_x": float(sim.state.p_x[:, 0].max()), "peak_rss_mib": round(peak_rss() / 2 ** 20),
                      **sim.scene.scheme.timings(sim)}))


if __name__ == "__main__":
    main(sys.argv[1:])
