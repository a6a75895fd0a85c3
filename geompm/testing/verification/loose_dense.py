"""The loose-versus-dense slope (cases/loose_vs_dense_slope.json) run and summarised: when it fails, how fast it
then moves, and what its pore pressure and solid fraction do (docs/validation/loose-vs-dense-slope.md).

Failure is the first time the mean down-slope speed of the soil exceeds 1 cm/s (the experiment's dense slips
averaged 0.2 cm/s); the speeds are those of the soil above the toe wall's top (y > 0.2 m) and upslope of it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

CASE = Path(__file__).resolve().parents[3] / "cases" / "loose_vs_dense_slope.json"
FAIL_SPEED = 0.01  # m/s


def run_slope(porosity: float, cell: float = 0.1, end: float | None = None, every: float = 0.1,
              case_path: Path = CASE, log=None) -> dict:
    """Run the case at ``porosity`` and cell size ``cell``; rows every ``every`` s of (t, mean down-slope speed
    of the soil upslope of the toe wall, largest down-slope speed, mean pore pressure and solid fraction of the
    soil within 0.15 m of the bed, mean solid fraction, mean excess pore pressure between 0.15 and 0.35 m above
    the bed (over the layer the head holds) over the head's hydrostatic rho_w g (H(t) - z)), the failure time and what follows it: the largest speed within
    1 s of failure, the mean speed from failure to the end, the base's excess pressure at failure and its
    lowest and highest after it."""
    raw = json.loads(Path(case_path).read_text())
    raw["materials"]["soil"]["pore_water"]["porosity"] = porosity
    raw["grid"]["cell_size"] = cell
    if end is not None:
        raw["time"]["end"] = end
    end = raw["time"]["end"]
    scene = scene_from_dict(raw, base_dir=Path(case_path).parent)
    from geompm.engine.run_case import settle
    from geompm.schema.load import parse_case

    loading = settle(scene, parse_case(raw, Path(case_path).parent).case.gravity_loading)
    sim = Simulation(scene)
    wall = next(b for b in raw["boundaries"] if b.get("drainage") == "head")
    up = -np.asarray(raw["gravity"], float) / np.linalg.norm(raw["gravity"])
    g = float(np.linalg.norm(raw["gravity"]))
    rows, t_next = [], 0.0
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))
        if sim.time >= t_next - 1e-12:
            st = sim.state
            x, y = st.p_x[:, 0], st.p_x[:, 1]
            upper = x < 3.0
            base = y < 0.15
            above = (y > 0.15) & (y < 0.35) & (x < 3.0)  # over the held layer at the bed
            phi = st.p_state[0][:, 2]
            level = float(np.interp(sim.time, wall["head_times"], wall["head"]))
            static = np.maximum(1000.0 * g * (level - st.p_x @ up), 0.0)
            row = (sim.time, float(st.p_v[upper, 0].mean()), float(st.p_v[:, 0].max()),
                   float(st.p_pore[base].mean()), float(phi[base].mean()), float(phi.mean()),
                   float((st.p_pore - static)[above].mean()))
            rows.append(row)
            if log is not None:
                log(row)
            t_next += every
    rows = np.array(rows)
    moving = np.nonzero(rows[:, 1] > FAIL_SPEED)[0]
    out = {"porosity": porosity, "cell": cell, "rows": rows, "failed": bool(len(moving)), "loading": loading}
    if len(moving):
        k = int(moving[0])
        t_f = rows[k, 0]
        after = rows[(rows[:, 0] >= t_f) & (rows[:, 0] <= t_f + 1.0)]
        out.update(t_fail=float(t_f), peak_1s=float(after[:, 2].max()), mean_after=float(rows[k:, 1].mean()),
                   p_at_fail=float(rows[k, 3]), p_end=float(rows[-1, 3]), phi_end=float(rows[-1, 5]),
                   excess_at_fail=float(rows[k, 6]), excess_min_after=float(rows[k:, 6].min()),
                   excess_max_after=float(rows[k:, 6].max()))
    return out
