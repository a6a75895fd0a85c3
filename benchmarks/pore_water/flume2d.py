"""A 2D twin of the saturated main job (cases/saturated_debris_obstacle.json without the dam and the side
walls, plane strain): the front and the pore pressure every 0.1 s to 1.2 s (docs/pore-water.md, The main
job, saturated), at cfl 0.4 unless time.cfl is set.

    python benchmarks/pore_water/flume2d.py [--dry] [--pic-water] [--raw-pressure] [--end=T] [KEY=VALUE ...]

--dry: the debris dry at the same total density (2000 kg/m3); --pic-water: the water without its affine
matrix (the first version); --raw-pressure: the grid sees the particles' own pressure while the increment
is smoothed (the first version); --end=T: run to T s (default 1.2). KEY=VALUE overrides the case as `geompm run --set`.
"""

import json
import sys
import time
from pathlib import Path

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.schema.load import apply_overrides

ROOT = Path(__file__).resolve().parents[2]


def flume2d(dry: bool, sets) -> dict:
    c = json.loads((ROOT / "cases" / "saturated_debris_obstacle.json").read_text())
    c["dimension"] = 2
    c["grid"] = {"origin": [0, 0], "extent": [3.6, 2.4], "cell_size": 0.05, "shape_function": "quadratic"}
    c["gravity"] = [0, -9.81]
    c["boundaries"] = [
        {"type": "plane", "point": [0.0, 2.2], "normal": [0.573576, 0.819152], "condition": "friction",
         "friction": 0.4},
        {"type": "wall", "side": "y-", "condition": "friction", "friction": 0.4},
        {"type": "wall", "side": "x-", "condition": "slip"}, {"type": "wall", "side": "x+", "condition": "slip"}]
    c.pop("obstacles")
    c["outputs"] = []
    c["time"]["cfl"] = 0.4  # the default; the 3D case runs at 0.1 (docs/pore-water.md)
    c["bodies"][0]["geometry"].pop("extrude")
    if dry:
        c["materials"]["debris"].pop("pore_water")
        c["materials"]["debris"]["density"] = 2000.0
    return apply_overrides(c, list(sets))


def raw_pressure_p2g(wet):
    """The first version's P2G: the grid sees the carried pressure itself."""
    original = wet.p2g

    def p2g(view):
        st = wet.cpu.state
        st.p_pore[:] = st.p_pore_carried
        smoothing, wet.smoothing = wet.smoothing, False
        try:
            original(view)
        finally:
            wet.smoothing = smoothing
    wet.p2g = p2g


def main(argv):
    flags = {a for a in argv if a.startswith("--") and "=" not in a}
    end = float(next((a.split("=", 1)[1] for a in argv if a.startswith("--end=")), 1.2))
    sim = Simulation(scene_from_dict(flume2d("--dry" in flags, [a for a in argv if not a.startswith("--")]),
                                     base_dir=ROOT / "cases"))
    wet = getattr(sim.backend, "saturated", None)
    if wet is not None and "--pic-water" in flags:
        wet.affine = False
    if wet is not None and "--raw-pressure" in flags:
        raw_pressure_p2g(wet)
    t0, due = time.perf_counter(), 0.1
    while sim.time < end - 1e-9:
        sim.step(sim.stable_dt())
        if sim.time >= due:
            st = sim.state
            line = f"t {sim.time:.2f} steps {sim.step_count} front {st.p_x[:, 0].max():.2f} m"
            if hasattr(st, "p_pore"):  # a field of the saturated scheme (schemes/saturated/fields.py)
                p = st.p_pore
                line += f"  p max {p.max():8.0f} min {p.min():8.0f} Pa  p99 |p| {np.percentile(abs(p), 99):7.0f} Pa"
            print(line, flush=True)
            due += 0.1
    print(f"wall {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
