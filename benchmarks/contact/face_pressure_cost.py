"""Cost of the face pressures and of the surfaces writer (issue 20), on cases/debris_obstacle.json.

    python benchmarks/contact/face_pressure_cost.py [STEPS]

The scene is assembled twice, without and with the ``surfaces`` writer (which makes the obstacles spread
their force on their faces); each is stepped from the same state (a checkpoint-free warm-up of 1500 steps
so that the debris is on the dam), then STEPS steps are timed in alternating blocks of 50 so that both see
the same machine.  Printed: set-up seconds (the face-id lattices), seconds per step both ways and their
difference per step, and the seconds of one surfaces write (all stages: walls, plane, dam).
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

from geompm.setup.assemble import assemble
from geompm.engine.scheduler import Simulation
from geompm.schema import load_case

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "debris_obstacle.json"


def scene(with_surfaces: bool):
    raw = json.loads(CASE.read_text())
    raw["outputs"] = [o for o in raw["outputs"] if o["writer"] != "surfaces" or with_surfaces]
    tmp = Path(tempfile.mkdtemp()) / "case.json"
    raw["obstacles"][0]["file"] = str(CASE.parent / raw["obstacles"][0]["file"])
    tmp.write_text(json.dumps(raw))
    t0 = time.perf_counter()
    sc = assemble(load_case(str(tmp), []))
    return sc, time.perf_counter() - t0


def main(steps: int = 1000) -> None:
    sims, setup = {}, {}
    for on in (False, True):
        sc, setup[on] = scene(on)
        sims[on] = Simulation(sc)
        for _ in range(1500):
            sims[on].step(sims[on].stable_dt())
    spent = {False: 0.0, True: 0.0}
    for _ in range(steps // 50):
        for on in (False, True):
            sim = sims[on]
            t0 = time.perf_counter()
            for _ in range(50):
                sim.step(sim.stable_dt())
            spent[on] += time.perf_counter() - t0
    sim = sims[True]
    writer = [w for w in sim.scene.writers if w.name == "surfaces"][0]
    with tempfile.TemporaryDirectory() as d:
        writer.open(Path(d), sim)
        writer.write(sim)  # the first write also writes the still surfaces
        t0 = time.perf_counter()
        for _ in range(5):
            writer.write(sim)
        write = (time.perf_counter() - t0) / 5
    ob = sim.scene.obstacles[0]
    n = sim.state.n
    print(f"particles {n}, dam faces {len(ob.face_area)}, t = {sim.time:.3f} s after {sim.step_count} steps")
    print(f"set-up: {setup[False]:.2f} s without faces, {setup[True]:.2f} s with (face-id lattices)")
    per = {k: v / steps for k, v in spent.items()}
    print(f"step: {per[False] * 1e3:.3f} ms without, {per[True] * 1e3:.3f} ms with faces: "
          f"+{(per[True] - per[False]) * 1e3:.3f} ms (+{per[True] / per[False] - 1:.1%})")
    print(f"surfaces write (every stage, the dam's pressures): {write * 1e3:.1f} ms per output")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1000)
