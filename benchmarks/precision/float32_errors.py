"""What solver.precision "float32" costs in accuracy (issue 21, point 3), at three grids per case.

    python benchmarks/precision/float32_errors.py [bar|dambreak|column ...] > float32_errors.csv

The float32 state (mpm/state.py set_precision) is stored in float32 and computed in float64
registers, on the CPU backend as on the CUDA one (the same kernels' arithmetic: only the order of the
P2G sums differs), so the errors measured here on the CPU are those of a float32 GPU run.  For each
case and cell size h, one float64 and one float32 run; one CSV row each:

- bar: cases/elastic_bar.json (L = 25 m, c = 10 m/s), first-mode period from the downward zero
  crossings of the centre-of-mass velocity over 3 periods (as tests/verification/test_elastic_bar.py); the
  reference is the closed form 4 L / c = 10 s.
- dambreak: cases/dam_break.json to t = 0.25 s (T = t sqrt(2g/a) = 3.5), the surge front Z = x_max/a;
  the reference is Martin & Moyce (1952), a = 2.25 in, n^2 = 2 (tests/refdata), largest relative
  error for T <= 3; also the largest |Z32 - Z64| over the run.
- column: cases/column_collapse.json (DP, a = 0.5, L0 = 0.2 m) to t = 0.8 s, the deposit front
  (geompm.writers.deposit, thickness threshold 0.05 H0, sampled every 0.01 H0) as (L - L0)/L0; the
  reference is Lube et al. (2005), 1.2 a = 0.60 (tests/refdata/granular_collapse_scaling_laws.csv).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402
from geompm.writers.deposit import deposit_front  # noqa: E402

CASES = ROOT / "cases"
REF = ROOT.parent / "shared" / "refdata"
PRECISIONS = ("float64", "float32")


def _sim(case, h, precision, *sets):
    sets = ["outputs=[]", f"grid.cell_size={h}", f"solver.precision={precision}", *sets]
    return Simulation(scene_from_file(CASES / case, sets))


def _run(sim, end, each=None):
    while sim.time < end:
        sim.step(min(sim.stable_dt(), end - sim.time))
        if each is not None:
            each(sim)


def bar(h, precision):
    sim = _sim("elastic_bar.json", h, precision)
    st, t, vcm = sim.state, [], []

    def record(s):
        t.append(s.time)
        vcm.append(float((st.p_mass * st.p_v[:, 0]).sum() / st.p_mass.sum()))

    _run(sim, 30.0, record)
    t, vcm = np.array(t), np.array(vcm)
    k = np.nonzero((vcm[:-1] > 0) & (vcm[1:] <= 0))[0]
    cross = t[k] - vcm[k] * (t[k + 1] - t[k]) / (vcm[k + 1] - vcm[k])
    period = float(np.diff(cross).mean())
    return sim, {"value": period, "reference": 10.0, "error": period / 10.0 - 1.0}, None


def dambreak(h, precision):
    a, g = 0.1, 9.81
    sim = _sim("dam_break.json", h, precision)
    T, Z = [0.0], [float(sim.state.p_x[:, 0].max()) / a]

    def record(s):
        T.append(s.time * np.sqrt(2 * g / a))
        Z.append(float(s.state.p_x[:, 0].max()) / a)

    _run(sim, 0.25, record)
    T, Z = np.array(T), np.array(Z)
    ref = np.genfromtxt(REF / "dambreak_martin_moyce1952_n2_2_a2.25in.csv", delimiter=",", skip_header=3)
    ref = ref[ref[:, 0] <= 3.0]
    rel = np.interp(ref[:, 0], T, Z) / ref[:, 1] - 1
    k = int(np.argmax(np.abs(rel)))
    return sim, {"value": float(np.interp(ref[k, 0], T, Z)), "reference": float(ref[k, 1]),
                 "error": float(rel[k])}, (T, Z)


def column(h, precision):
    l0, h0, rho = 0.2, 0.1, 2650.0
    sim = _sim("column_collapse.json", h, precision, "time.end=0.8")
    _run(sim, 0.8)
    x = sim.state.p_x.astype(np.float64)
    front = deposit_front(x, sim.state.p_mass.astype(np.float64) / rho, 0.05 * h0, 0.01 * h0)
    runout = (front - l0) / l0
    return sim, {"value": runout, "reference": 0.6, "error": runout / 0.6 - 1.0}, None


CASES_RUN = {"bar": (bar, (0.5, 0.25, 0.125)), "dambreak": (dambreak, (0.01, 0.005, 0.0025)),
             "column": (column, (0.02, 0.01, 0.005))}


def main(names):
    print("case,h_m,precision,particles,steps,wall_s,value,reference,error_vs_reference,"
          "diff_vs_float64,max_front_diff", flush=True)
    for name in names or CASES_RUN:
        fn, grids = CASES_RUN[name]
        for h in grids:
            base, curve64 = None, None
            for precision in PRECISIONS:
                t0 = time.perf_counter()
                sim, r, curve = fn(h, precision)
                wall = time.perf_counter() - t0
                if precision == "float64":
                    base, curve64 = r["value"], curve
                diff = r["value"] / base - 1.0
                front = ""
                if curve is not None and curve64 is not None and precision != "float64":
                    front = f"{np.abs(np.interp(curve64[0], curve[0], curve[1]) - curve64[1]).max():.3e}"
                print(f"{name},{h},{precision},{sim.state.n},{sim.step_count},{wall:.1f},{r['value']:.6f},"
                      f"{r['reference']:.6f},{r['error']:+.5f},{diff:+.3e},{front}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
