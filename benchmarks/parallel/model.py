"""The scaling model of docs/parallel.md, from the measurements of measure.sh, projected to 8, 64 and 512
ranks on a 100 Gb/s network for dp3d at 128 and 256 cells per side (1.6M and 13M particles).

    python benchmarks/parallel/model.py RESULTS_DIR

The step time of P ranks, one core each (Hockney's t = alpha + m / beta for every message):

    T(P) = t_p N / P_busy (1 + i(P)) + f                      compute, the slowest rank
         + 2 (o_swap + alpha + B / beta)                       halo: a swap with each neighbour
         + k (o_coll + alpha ceil(log2 P) + P m / beta)        k small collectives (reductions, bounds)
         + 2 (o_shift + alpha)                                 migration to the neighbours
    E(P) = (t_p N + f) / (P T(P))

t_p [s per particle-step] and f [s per step] come from one rank at two sizes (dp3d at 26k and 204k
particles); o_swap, o_coll, o_shift are mpi4py's cost per call measured on this machine's loopback
(comm_costs.py; they include its latency, so the network's alpha is added on top); k is the collectives
per step counted in the 2-rank runs (plus the runner loop's two); B the halo bytes per neighbour, measured at 204k (3 node layers of
the window's cross-section, 4 values per node) and scaled with the cross-section (h^-2); m = 160 bytes.
Slabs hold at least 4 cells and the cuts follow the particles, so only P_busy = min(P, L / 4) ranks hold
particles (L: the cell layers the particles span along the split axis); i(P) = P_busy / (2 L) is the
imbalance of cutting at cell layers.  alpha = 2 us and beta = 12.5 GB/s (100 Gb/s).
"""

from __future__ import annotations

import json
import math
import statistics
import sys
from pathlib import Path

ALPHA, BETA = 2e-6, 12.5e9
M_BYTES = 160.0


def median_step(folder: Path, label: str, ranks: int) -> float:
    files = sorted(folder.glob(f"{label}_r{ranks}_*.json"))
    return statistics.median(json.loads(f.read_text())["seconds_per_step"] for f in files)


def main(folder: Path) -> None:
    big = json.loads(next(folder.glob("dp3d_r1_*.json")).read_text())
    small = json.loads((folder / "dp3d26k_r1_1.json").read_text())
    t_big, t_small = median_step(folder, "dp3d", 1), median_step(folder, "dp3d26k", 1)
    n_big, n_small = big["particles"], small["particles"]
    t_p = (t_big - t_small) / (n_big - n_small)
    f = t_small - t_p * n_small
    two = [json.loads(p.read_text()) for p in sorted(folder.glob("dp3d_r2_*.json"))]
    rank0 = two[0]["per_rank"][0]
    calls = rank0["calls_per_step"]
    # the window's bounds (comm.stack, counted from measure.sh's second run on) and the runner loop's
    # particle count and stop check (run(), not advance(): two more per step)
    k = sum(v for name, v in calls.items() if name in ("sum", "max", "min", "rows", "gather", "stack")) \
        + (0 if "stack" in calls else 1) + 2
    b_204k = rank0["bytes_sent_per_step"]  # on two ranks each rank has one neighbour: the bytes to it
    costs = json.loads((folder / "comm_costs.json").read_text())["seconds_per_call"]
    o_coll = statistics.mean(costs[name] for name in ("sum of 4 numbers", "rows (1, 20)"))
    o_swap = next(v for name, v in costs.items() if name.startswith("swap"))
    o_shift = costs["all-to-all of empty packets"]  # an upper bound of a pickled sendrecv of None
    measured = {"t_p_ns": t_p * 1e9, "f_ms": f * 1e3, "collectives_per_step": k, "halo_bytes_per_neighbour_204k": b_204k,
                "o_coll_us": o_coll * 1e6, "o_swap_us": o_swap * 1e6, "o_shift_us": o_shift * 1e6,
                "speedup_2_ranks": {lab: median_step(folder, lab, 1) / median_step(folder, lab, 2)
                                    for lab in ("dp3d", "mainjob", "mainjob_h025")}}
    layers_204k = round(0.6 * 64)

    def step(n, layers, halo, p):
        """(step time, its compute part) of P ranks by the model of the module docstring."""
        busy = min(p, layers // 4)
        comp = t_p * n / busy * (1 + busy / (2 * layers)) + f
        t_halo = 2 * (o_swap * halo / b_204k + ALPHA + halo / BETA)
        t_coll = k * (o_coll + ALPHA * math.ceil(math.log2(p)) + p * M_BYTES / BETA)
        return comp + t_halo + t_coll + 2 * (o_shift + ALPHA), comp, busy

    measured["dp3d_2_ranks_ms"] = {"measured_median": median_step(folder, "dp3d", 2) * 1e3,
                                   "measured_all": [json.loads(p.read_text())["seconds_per_step"] * 1e3
                                                    for p in sorted(folder.glob("dp3d_r2_*.json"))],
                                   "model_loopback": step(n_big, layers_204k, b_204k, 2)[0] * 1e3}
    def blocks(n, side, p):
        """The same model for a 3D block partition (not built; what the slabs' limit costs): the particles'
        box (0.4 x 0.6 x 0.4 of the cube) cut into p blocks, each swapping 3 node layers of its six faces
        with its neighbours (26 messages, edges and corners included)."""
        cells = [0.4 * side, 0.6 * side, 0.4 * side]
        per = [c / round(p ** (1 / 3)) for c in cells]
        faces = 2 * (per[0] * per[1] + per[1] * per[2] + per[0] * per[2])
        halo = 3 * faces * 4 * 8
        comp = t_p * n / p * 1.05 + f
        return comp + 26 * (o_swap * halo / 26 / b_204k + ALPHA) + halo / BETA \
            + k * (o_coll + ALPHA * math.ceil(math.log2(p)) + p * M_BYTES / BETA) + 26 * (o_shift + ALPHA)

    scenes = {"1.6M (dp3d, 128 cells per side)": (1.6e6, 128), "13M (dp3d, 256 cells per side)": (13.1e6, 256)}
    rows = []
    for name, (n, side) in scenes.items():
        layers = round(0.6 * side)  # the block spans 0.6 of the unit cube along y, the split axis
        halo = b_204k * (side / 64) ** 2
        t1 = t_p * n + f
        for p in (2, 8, 64, 512):
            t, comp, busy = step(n, layers, halo, p)
            rows.append({"scene": name, "ranks": p, "busy_ranks": busy, "step_ms": t * 1e3,
                         "compute_ms": comp * 1e3, "exchange_ms": (t - comp) * 1e3,
                         "halo_bytes_per_rank": 2 * halo, "efficiency": t1 / (p * t),
                         "blocks_efficiency_not_built": t1 / (p * blocks(n, side, p))})
    out = {"measured": measured, "network": {"alpha_s": ALPHA, "beta_bytes_per_s": BETA}, "projection": rows}
    (folder / "model.json").write_text(json.dumps(out, indent=1))
    print(json.dumps(measured, indent=1))
    for r in rows:
        print(f"{r['scene']:34s} P={r['ranks']:4d} busy={r['busy_ranks']:3d} step={r['step_ms']:8.2f} ms "
              f"(exchange {r['exchange_ms']:.2f} ms) halo {r['halo_bytes_per_rank'] / 1e6:.2f} MB E={r['efficiency']:.2f}"
              f" (3D blocks, not built: {r['blocks_efficiency_not_built']:.2f})")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
