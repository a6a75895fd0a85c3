"""``geompm cuda-check CASE``: does every kernel a case needs compile for a GPU?  Answered without a GPU.

For the author of a law or stage plugin who has no GPU.  numba-cuda's simulator
runs kernels as Python and never types them, so it cannot say whether a
plugin's ``@njit`` function compiles as a CUDA device function (``np.sqrt`` of
a scalar does not).  This command runs the case for ``--steps`` steps on the
``cuda`` backend under the simulator, in a subprocess, recording every kernel
launch with its argument types; then it compiles each kernel to PTX for the
compute capability (9.0, H100/H200, unless told) with numba-cuda's compiler,
and to machine code with ptxas where installed (backend/cuda_ptx.py).  It prints
one line per kernel: compiled or numba-cuda's error, registers per thread, spill
and stack bytes, shared memory.  Exit 0 if all compile, 1 if any does not, 2 if
the case is refused or NVVM is missing (``pip install 'geompm[cuda]'`` brings
it).  Use ``--set grid.cell_size=...`` for a coarse grid: the simulator runs
each thread as Python, and the kernels' types do not depend on the grid.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from geompm.errors import CaseError


def add_parser(sub) -> None:
    p = sub.add_parser("cuda-check", help="compile every CUDA kernel a case needs for a GPU, without one",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("case")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a case value (a coarse grid.cell_size keeps the simulated steps short)")
    p.add_argument("--steps", type=int, default=2, help="steps simulated to record the launches (default 2)")
    p.add_argument("--cc", default="9.0", help="compute capability MAJOR.MINOR (default 9.0: H100, H200)")
    p.add_argument("--json", action="store_true", help="one JSON object per kernel")
    p.set_defaults(func=cmd_cuda_check)


def cmd_cuda_check(args) -> int:
    from geompm.backend.cuda_loops import simulated
    from geompm.backend.cuda_ptx import nvvm_missing
    from geompm.schema import load_case

    if simulated():
        raise CaseError([("--", "unset NUMBA_ENABLE_CUDASIM: compiling needs numba-cuda's compiler, not its "
                               "simulator (the recording step turns the simulator on by itself)")])
    try:
        cc = tuple(int(v) for v in args.cc.split("."))
        assert len(cc) == 2
    except (ValueError, AssertionError):
        raise CaseError([("--cc", f"'{args.cc}' is not MAJOR.MINOR, e.g. 9.0")]) from None
    if args.steps < 1:
        raise CaseError([("--steps", "must be at least 1")])
    load_case(args.case, args.set)  # the case's own errors, before any work
    missing = nvvm_missing()
    if missing:
        raise CaseError([("--", f"numba-cuda's compiler libraries (NVVM, NVRTC) are not found ({missing}); "
                               "install them with pip install 'geompm[cuda]'")])
    with tempfile.TemporaryDirectory(prefix="geompm-cuda-check-") as tmp:
        launches = Path(tmp) / "launches.json"
        cmd = [sys.executable, "-m", "geompm.cli.cuda_check", str(launches), args.case, str(args.steps), *args.set]
        rec = subprocess.run(cmd, env=dict(os.environ, NUMBA_ENABLE_CUDASIM="1"), capture_output=True, text=True)
        if rec.returncode:
            print(rec.stderr[-4000:], file=sys.stderr)
            print(f"error: the case did not run {args.steps} steps on the simulated cuda backend", file=sys.stderr)
            return 2
        for line in rec.stderr.splitlines():
            if line.startswith("note: "):
                print(line, file=sys.stderr)
        recorded = json.loads(launches.read_text())
    from geompm.backend.cuda_ptx import compile_launches, find_ptxas

    ptxas = find_ptxas()
    results = compile_launches(recorded, cc, ptxas)
    for r in results:
        print(json.dumps(r) if args.json else _line(r))
    bad = [r for r in results if not r["ok"]]
    if not args.json:
        where = f"compute capability {cc[0]}.{cc[1]}"
        print(f"{len(results) - len(bad)} of {len(results)} kernels compile for {where}"
              + ("" if ptxas else " (no ptxas found: registers not read)"))
    return 1 if bad else 0


def _line(r: dict) -> str:
    if not r["ok"]:
        return f"FAILED  {r['kernel']}  ({', '.join(r['types'])})\n        {r['error']}"
    figures = (f"{r['registers']:>4} registers, {r['spill_store_bytes']} B spilled, {r['stack_bytes']} B stack"
               + (f", {r['smem_bytes']} B shared" if r.get("smem_bytes") else "")) if "registers" in r else ""
    return f"ok      {r['kernel']:<48} {figures}"


def _record(out: str, case: str, steps: str, *sets: str) -> int:
    """The recording subprocess (simulator on): ``steps`` steps of the case on the cuda backend.  A plugin
    that does not declare the cuda backend yet is checked as if it did (this check is what an author runs
    before declaring it), with a note."""
    from geompm.contract import registry
    from geompm.api import scene_from_file
    from geompm.backend.cuda_ptx import record
    from geompm.engine.scheduler import Simulation
    from geompm.schema.load import BACKEND_KINDS

    for kind in BACKEND_KINDS:
        for name, info in registry.available(kind).items():
            if "cuda" not in info.plugin.backends:
                info.plugin.backends = (*info.plugin.backends, "cuda")
                print(f"note: {kind} '{name}' does not declare the cuda backend; checked as if it did",
                      file=sys.stderr)

    def run():
        sim = Simulation(scene_from_file(case, [*sets, "solver.backend=cuda", "outputs=[]"]))
        for _ in range(int(steps)):
            sim.step(sim.stable_dt())

    try:
        Path(out).write_text(json.dumps(record(run)))
    except CaseError as exc:
        for path, msg in exc.problems:
            print(f"  {path or '<case>'}: {msg}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(_record(*sys.argv[1:]))
