"""The CUDA backend (backend/cuda.py; issue 21) without a GPU: numba-cuda's simulator against the CPU.

- The device's counting sort (backend/cuda_sort.py) equals the CPU's row for row on crowded random
  particles in 2D and 3D, and its prefix sum equals numpy's over three levels of blocks; every scene
  sorts at its first step (two of them at every step) and ends in the CPU's particle order.
- The tiled P2G (solver.p2g "tiled": a shared-memory tile per thread block) adds the same grid as the
  atomic one within 1e-12 (measured 4.8e-16) on blocks that fit the tile (2D, folded and split) and on
  blocks that take the fallback (a spread 3D cloud); two scenes run it end to end.
- The scenes and checks run in two processes, one per CI core (cuda_parity.py --part).
- Checkpoints across backends: 2 steps on cuda, a checkpoint, the third on the CPU (and the reverse)
  equal 3 steps on the CPU within 1e-9.
- float32 (solver.precision): two scenes in float32 (2D DP, and elastic through the tiled P2G) agree
  within 2e-4 on both backends (measured 1.4e-5 on a stress: the order of the P2G sums in float32, which
  the simulator's threads change from run to run; a wrong index or a missed term differs at O(1)).
- Parity: tests/cuda/cuda_parity.py runs 24 float64 tiny scenes (36-64 particles, 3 steps) on both backends in a
  subprocess with NUMBA_ENABLE_CUDASIM=1: every built-in law (and the mu_i plugin), both integrations
  of the yield fluids, PIC/APIC/FLIP/MLS, linear/quadratic/cubic, USL/MUSL, 2D and 3D, every
  built-in stage (walls, plane, periodic, Voellmy friction on both, both dampings, box/sphere/cylinder/STL/terrain obstacles
  with their recorded forces and the penetration guard), and saturated soil (schemes/saturated/cuda.py:
  a DP debris with pore water against an impermeable friction floor and a drained wall; its pore
  pressure and water velocity compared too, measured 4e-16).  Positions, velocities, stresses and
  densities must agree within 1e-9 relative (measured: <= 4.2e-13, the order of the atomics' sums),
  the series (kinetic energy, obstacle forces, the guard's deepest penetration, and the health check's
  sums: non-finite count, kinetic energy, energy released by gravity) within 1e-9 of the stage's largest
  value, read after the first and the last step only, so that the last step's time step, grid window and
  health sums come from the device's step-end tally (backend/cuda_tally.py) rather than from the host;
  the scenes must move and the obstacles must carry load, so that the comparison is not between two zeros.
- Refusals before any work, naming the JSON path: numba-cuda not installed, no GPU (and no
  simulator), a plugin that does not declare the cuda backend.
"""

import fcntl
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from geompm.api import scene_from_dict
from geompm.errors import CaseError
from geompm.materials.linear_elastic import LinearElastic

ROOT = Path(__file__).resolve().parents[2]
HAS_NUMBA_CUDA = __import__("importlib.util").util.find_spec("numba_cuda") is not None


def tiny_case(backend="cuda") -> dict:
    return {
        "name": "tiny", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 1.0], "cell_size": 0.1},
        "time": {"end": 0.1}, "gravity": [0.0, -9.81],
        "materials": {"m": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e5,
                            "poisson_ratio": 0.3}},
        "bodies": [{"material": "m", "geometry": {"type": "box", "min": [0.3, 0.0], "max": [0.6, 0.3]}}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "fixed"}],
        "solver": {"backend": backend},
    }


def two_parts(args: list, env: dict, record: Path | None = None) -> list[tuple[int, str, str]]:
    """``python ARGS --part K/2`` for K = 1 and 2 at once, one per CI core (with ``record``, each part also
    writes its kernel launches to record/launches-K.json); each part's exit code, stdout and stderr."""
    files = [(tempfile.TemporaryFile("w+"), tempfile.TemporaryFile("w+")) for _ in range(2)]
    parts = [subprocess.Popen([sys.executable, *args, "--part", f"{k}/2",
                               *(["--record", str(record / f"launches-{k}.json")] if record else [])],
                              env=env, stdout=out, stderr=err, text=True, cwd=ROOT)
             for k, (out, err) in zip((1, 2), files)]
    runs = []
    for proc, (out, err) in zip(parts, files):
        code = proc.wait(timeout=900)
        out.seek(0)
        err.seek(0)
        runs.append((code, out.read(), err.read()))
    return runs


@pytest.fixture(scope="module")
def simulated_parity(tmp_path_factory, request):
    """tests/cuda/cuda_parity.py's tiny scenes and checks under the simulator, in two processes: their JSON rows
    (the checks first, from the last part) and the files of kernel launches they recorded.  Run once per test
    session: under pytest-xdist the first worker to ask runs them (on both cores) and the other reads its rows,
    in the session's shared temporary folder, instead of running them again beside it."""
    worker = getattr(request.config, "workerinput", None)
    shared = tmp_path_factory.getbasetemp()
    shared = shared.parent if worker is not None else shared  # the xdist workers' common folder
    folder, rows = shared / "cuda-parity-launches", shared / "cuda-parity-rows.json"
    with open(shared / "cuda-parity.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        if not rows.exists():
            folder.mkdir(exist_ok=True)
            runs = two_parts([str(ROOT / "tests" / "cuda" / "cuda_parity.py"), "--steps", "3"],
                             dict(os.environ, NUMBA_ENABLE_CUDASIM="1"), record=folder)
            for code, _, err in runs:
                assert code == 0, err[-3000:]
            lines = runs[1][1].splitlines() + runs[0][1].splitlines()
            rows.write_text(json.dumps([json.loads(line) for line in lines if line.startswith("{")]))
    return json.loads(rows.read_text()), sorted(folder.glob("launches-*.json"))


@pytest.mark.slow
@pytest.mark.run_last
@pytest.mark.skipif(not HAS_NUMBA_CUDA, reason="numba-cuda is not installed (pip install 'geompm[cuda]')")
def test_cuda_backend_matches_the_cpu_on_every_law_and_stage_under_the_simulator(simulated_parity):
    rows = list(simulated_parity[0])
    check = rows.pop(0)
    assert check["check"] == "sort" and all(check["sort_equal"]) and check["scan_equal"], check
    resume = rows.pop(0)
    assert resume["check"] == "resume"
    for way in ("cuda_then_cpu", "cpu_then_cuda"):
        assert resume[f"{way}_steps"] == 3
        for field, diff in resume[way].items():
            assert diff < 1e-9, f"checkpoint {way}: {field} differs by {diff:.2e} from 3 steps on the CPU"
    tiled = rows.pop(0)
    assert tiled["check"] == "tiled"
    for name, fits in (("2d_folded", True), ("2d_split", True), ("3d_spread", False)):
        r = tiled[name]
        # the data send every 2D block through the tile and every 3D block to the fallback (counted on the host
        # from the same bounding boxes the kernel takes), so both paths are compared with the atomic kernel
        assert r["blocks_tiled"] == (r["blocks"] if fits else 0), (name, r)
        assert r["diff"] < 1e-12 and r["mass"] > 1.0, (name, r)
    held = rows.pop(0)  # every batch ended by the device's check (fraction 1): tests/cuda/test_held_step_cuda.py
    assert held["check"] == "held"
    r = held["elastic_apic_quadratic_usl"]
    assert r["steps_cpu"] == r["steps_cuda"] == list(range(1, 6)), r
    assert r["clock"] < 1e-15 and r["fields"] < 1e-9, r
    assert len(rows) >= 20
    for r in rows:
        name = r["scene"]
        f32 = name.endswith("_float32")
        assert r["dtype"] == (["float32"] * 2 if f32 else ["float64"] * 2), name
        assert r["same_order"], f"{name}: the device sort ordered the particles differently from the CPU's"
        # float32: both backends round the same float64 arithmetic to float32; the P2G sums' order differs
        tol = 2e-4 if f32 else 1e-9
        assert r["steps"] == [3, 3] and r["time"][0] == pytest.approx(r["time"][1], rel=1e-12 if not f32 else 1e-6), name
        for field, diff in r["fields"].items():
            assert diff < tol, f"{name}: {field} differs by {diff:.2e} relative"
        for col, diff in r["series"].items():
            assert diff < tol, f"{name}: series column {col} differs by {diff:.2e} relative"
        assert r["max_displacement"] > 1e-6, f"{name}: nothing moved"
        forces = {k: v for k, v in r["last_row"].items() if k.endswith("_fn")}
        for k, v in forces.items():
            assert v > 1.0, f"{name}: {k} = {v} N: the obstacle carries no load, the comparison is empty"
        if name.endswith("_guard"):
            depth = [v for k, v in r["last_row"].items() if k.endswith("_max_depth")]
            assert depth and max(depth) > 1e-3, f"{name}: the guard did not act"


def has_nvvm() -> bool:
    from geompm.backend.cuda_ptx import nvvm_missing

    return nvvm_missing() is None


def cuda_functions() -> dict:
    """label -> plugin, for every function of every installed plugin that declares the cuda backend."""
    from geompm.contract import registry
    from geompm.backend.cuda_ptx import function_ref

    out = {}
    for group, attrs in (("materials", ("particle_stress",)),
                         *((g, ("node_rule", "particle_rule", "node_image")) for g in ("damping", "boundaries",
                                                                                       "obstacles"))):
        for name, info in registry.available(group).items():
            if "cuda" in info.plugin.backends:
                for attr in attrs:
                    fn = getattr(info.plugin, attr, None)
                    if fn is not None:
                        out[function_ref(fn)[1]] = f"{group}.{name}.{attr}"
    return out


@pytest.mark.slow
@pytest.mark.run_last
@pytest.mark.skipif(not HAS_NUMBA_CUDA, reason="numba-cuda is not installed (pip install 'geompm[cuda]')")
@pytest.mark.skipif(not has_nvvm(), reason="NVVM/NVRTC not installed (the test extra's cuda-toolkit wheels)")
def test_every_kernel_compiles_for_an_h200_without_a_gpu(simulated_parity):
    """The simulator runs kernels as Python and never types them: np.sqrt of a scalar (which the CUDA
    target lacks) passed it in dp_stress and mu_i_stress, np.floor in the obstacles' lattice lookup.  Here
    every distinct kernel launch the parity scenes made (tests/cuda/cuda_compile.py; 75 kernel/type lists) is
    compiled by numba-cuda to PTX for compute capability 9.0 (H100/H200) with every plugin function as a
    device function, then by ptxas to machine code.  Asserted: each compiles; every function of every
    plugin that declares the cuda backend and every kernel of backend/cuda_kernels.py and cuda_sort.py is
    among them; no kernel spills registers (measured: none; the most registers are the obstacles' node group,
    168 per thread, the saturated water G2P, 164, and Drucker-Prager's and Herschel-Bulkley's particle pass
    (cuda_loops.PARTICLE_STEP), 159; the most shared memory the tiled P2G's, 28.7 kB)."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    runs = two_parts([str(ROOT / "tests" / "cuda" / "cuda_compile.py"), *map(str, simulated_parity[1])], env)
    results = [json.loads(line) for _, out, _ in runs for line in out.splitlines() if line.startswith("{")]
    failed = [f"{r['kernel']} ({', '.join(r['types'])}): {r['error']}" for r in results if not r["ok"]]
    assert not failed, "kernels numba-cuda cannot compile for the GPU:\n" + "\n".join(failed)
    for code, _, err in runs:
        assert code == 0, err[-3000:]
    compiled = {r["kernel"] for r in results}  # "p2g", "law:drucker_prager.dp_stress", "merge:periodic_image"
    functions = {part.rsplit(".", 1)[-1] for k in compiled for part in k.split(":", 1)[-1].split(",")}
    missing = [plugin for fn, plugin in cuda_functions().items() if fn not in functions]
    assert not missing, f"declared for cuda but not compiled by any parity scene: {missing}"
    own = {name for f in ("cuda_kernels.py", "cuda_sort.py")
           for name in re.findall(r"@cuda\.jit\s*\ndef (\w+)", (ROOT / "geompm" / "backend" / f).read_text())}
    assert len(own) >= 15 and own <= compiled, f"kernels no scene launched: {sorted(own - compiled)}"
    assert len(results) >= 40
    with_stats = [r for r in results if "registers" in r]
    assert len(with_stats) == len(results), [r.get("ptxas_error") for r in results if "registers" not in r]
    spills = {r["kernel"]: r["spill_store_bytes"] for r in with_stats if r["spill_store_bytes"]}
    assert not spills, f"register spills (bytes stored): {spills}"


def test_cuda_without_numba_cuda_is_refused_at_solver_backend(monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "numba_cuda" else real(name, *a))
    with pytest.raises(CaseError) as err:
        scene_from_dict(tiny_case())
    assert err.value.problems[0][0] == "solver.backend"
    assert "pip install 'geompm[cuda]'" in str(err.value)


@pytest.mark.skipif(not HAS_NUMBA_CUDA, reason="numba-cuda is not installed")
def test_cuda_without_a_gpu_is_refused_unless_simulated(monkeypatch):
    from numba import cuda

    if cuda.is_available():
        pytest.skip("this machine has a GPU")
    monkeypatch.delenv("NUMBA_ENABLE_CUDASIM", raising=False)
    with pytest.raises(CaseError) as err:
        scene_from_dict(tiny_case())
    assert err.value.problems[0][0] == "solver.backend"
    assert "NUMBA_ENABLE_CUDASIM=1" in str(err.value) and "no CUDA GPU" in str(err.value)


def test_a_plugin_not_checked_on_cuda_is_refused_by_name(monkeypatch):
    """A law whose class does not list 'cuda' in ``backends`` is refused at its model path, before the
    backend question (here with the simulator set, so that only the plugin is at fault)."""
    monkeypatch.setattr(LinearElastic, "backends", ("cpu",))
    monkeypatch.setenv("NUMBA_ENABLE_CUDASIM", "1")
    if not HAS_NUMBA_CUDA:
        pytest.skip("numba-cuda is not installed")
    with pytest.raises(CaseError) as err:
        scene_from_dict(tiny_case())
    paths = [p for p, _ in err.value.problems]
    assert paths == ["materials.m.model"], err.value.problems
    assert "'linear_elastic' runs on the cpu backend(s), not on solver.backend 'cuda'" in str(err.value)
    scene_from_dict(tiny_case("cpu"))  # the same case on the CPU is fine
