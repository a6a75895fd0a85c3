"""Strong scaling over MPI ranks on this machine: a case stepped on 1 rank (no launcher) or under
``mpiexec -n N``, one numba thread per rank, with the time of each exchange and the bytes sent per step.

    NUMBA_NUM_THREADS=1 python benchmarks/parallel/scaling.py benchmarks/dp3d.json --steps 60 OUT.json
    NUMBA_NUM_THREADS=1 mpiexec -n 2 python benchmarks/parallel/scaling.py benchmarks/dp3d.json --steps 60 OUT.json

The first ``--warm`` steps compile and settle and are not timed; then ``--steps`` steps are timed as the
runner takes them (time-step reduction, health check, domain check included).  Each rank times its own
halo sums, particle migration, window exchange and every other collective call (stacked reductions,
maxima, gathers), and counts the bytes it sent point to point.  Rank 0 writes one JSON: per rank the
seconds per step of the step and of each exchange, the particles it holds, the halo nodes and bytes per
step, and the machine.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path


def timed(obj, name, bucket, calls):
    """Wrap method ``name`` of ``obj`` so that its wall time adds to bucket[name] and its calls to
    calls[name]."""
    inner = getattr(obj, name)

    def wrapper(*args, **kwargs):
        t = time.perf_counter()
        try:
            return inner(*args, **kwargs)
        finally:
            bucket[name] = bucket.get(name, 0.0) + time.perf_counter() - t
            calls[name] = calls.get(name, 0) + 1
    setattr(obj, name, wrapper)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("out")
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--warm", type=int, default=10)
    ap.add_argument("--set", action="append", default=[])
    args = ap.parse_args()

    import numba

    from geompm.engine.launch import world
    from geompm.engine.runner import Runner
    from geompm.engine.scheduler import Simulation
    from geompm.parallel.whole import WHOLE
    from geompm.schema.load import load_case
    from geompm.setup.assemble import assemble

    comm = world()
    scene = assemble(load_case(args.case, args.set))
    domain = WHOLE
    if comm is not None:
        from geompm.parallel.slabs import Slabs

        domain = Slabs(comm, scene)
    sim = Simulation(scene, domain=domain)
    runner = Runner(sim, None, [], progress=False)
    runner.start()
    for _ in range(args.warm):
        runner.advance(1e9)
    bucket: dict[str, float] = {}
    calls: dict[str, int] = {}
    if comm is not None:
        for name in ("before_step", "window", "sum_halo", "stable_dt"):
            timed(domain, name, bucket, calls)
        for name in ("sum", "max", "min", "rows", "gather", "stack", "exchange", "swap", "shift"):
            timed(domain.comm, name, bucket, calls)
        comm.barrier()
        before = domain.measured()
    t0 = time.perf_counter()
    for _ in range(args.steps):
        runner.advance(1e9)
    wall = time.perf_counter() - t0
    n = sim.state.n
    mine = {"rank": domain.rank, "particles": n, "seconds_per_step": wall / args.steps,
            "exchange_seconds_per_step": {k: v / args.steps for k, v in bucket.items()},
            "calls_per_step": {k: v / args.steps for k, v in calls.items()}}
    if comm is not None:
        after = domain.measured()
        mine.update({k + "_per_step": (after[k] - before[k]) / args.steps
                     for k in ("halo_nodes", "bytes_sent", "all_bytes_sent", "sent_particles")})
        mine["window_nodes"] = int(sim.view.g_mass.shape[0])
        mine["cuts"] = [int(c) for c in domain.cuts]
    parts = domain.comm.gather_root(mine)
    if domain.comm.is_root:
        total = sum(p["particles"] for p in parts)
        slowest = max(p["seconds_per_step"] for p in parts)
        out = {"case": args.case, "sets": args.set, "ranks": domain.size, "steps": args.steps,
               "particles": total, "seconds_per_step": slowest,
               "ns_per_particle_step": slowest / total * 1e9, "threads_per_rank": numba.get_num_threads(),
               "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
               "per_rank": parts}
        Path(args.out).write_text(json.dumps(out, indent=1))
        print(json.dumps({k: out[k] for k in ("ranks", "particles", "seconds_per_step", "ns_per_particle_step")}))


if __name__ == "__main__":
    main()
