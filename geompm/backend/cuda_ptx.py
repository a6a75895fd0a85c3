"""The CUDA backend's kernels compiled ahead of time for a GPU architecture, on a machine without a GPU.

numba-cuda's simulator (``NUMBA_ENABLE_CUDASIM=1``) runs a kernel as Python and never types it, so a
per-item function that numba-cuda cannot compile for a device passes there and fails on the GPU: the
CUDA target has no ``np.sqrt`` of a scalar (its ufunc table holds the transcendental functions only),
no ``np.linalg``, no array creation.  This module closes that gap in two steps, each in its own process
(the simulator is chosen when numba-cuda is imported):

1. ``record`` (simulator): run scenes a few steps on the ``cuda`` backend and note each distinct kernel
   launch, with the numba types of its arguments and how to build the kernel again: a module-level
   kernel by its module and name, a generated one (backend/cuda_loops.py) by the recipe kept in its
   namespace, whose plugin functions are named by module and qualified name;
2. ``compile_launches`` (no simulator, no GPU; NVVM and NVRTC from the ``cuda-toolkit`` wheels): build
   each kernel again and compile it to PTX for the architecture (compute capability 9.0, the H100 and
   H200, unless told), with every ``@njit`` function it calls compiled as a device function, exactly
   as a GPU run would; then, where ``ptxas`` is found, to machine code, reading the registers per
   thread, spill stores and loads, stack frame and shared memory that set the kernel's occupancy.

Without a GPU, numba-cuda asks the current device for its compute capability when it compiles a
device function; ``offline`` answers with the target's.  Nothing here launches a kernel.
"""

from __future__ import annotations

import importlib
import json
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

#: the compute capability compiled for unless told (Hopper: H100, H200)
DEFAULT_CC = (9, 0)


# -- 1. recording, under the simulator -----------------------------------------------------------------
def function_ref(fn) -> list:
    """[module, qualified name] of a plugin's ``@njit`` function, checked to lead back to it."""
    py = getattr(fn, "py_func", fn)
    ref = [py.__module__, py.__qualname__]
    if resolve(ref) is not fn:
        raise ValueError(f"{ref[0]}.{ref[1]} does not name the function a kernel calls: give the @njit "
                         f"function a module-level name so a compiler process can import it")
    return ref


def resolve(ref):
    """The object that [module, qualified name] names."""
    if "<locals>" in ref[1]:
        raise ValueError(f"{ref[0]}.{ref[1]} is defined inside a function; a compiler process cannot import it")
    obj = importlib.import_module(ref[0])
    for part in ref[1].split("."):
        obj = getattr(obj, part)
    return obj


def encode_type(value) -> list:
    """A kernel argument's numba type, as JSON: ["array", dtype, ndim, layout], ["tuple", [item types]] (a
    stencil tag, kernels/stencil.py) or [scalar type name]."""
    import numba

    value = getattr(value, "_ary", value)  # the simulator's device array holds a numpy array
    if isinstance(value, np.ndarray):
        return ["array", str(value.dtype), int(value.ndim), numba.typeof(value).layout]
    if isinstance(value, tuple):
        return ["tuple", [encode_type(v) for v in value]]
    return [str(numba.typeof(value))]


def decode_type(code: list):
    from numba import types

    if code[0] == "array":
        return types.Array(numba_dtype(code[1]), code[2], code[3])
    if code[0] == "tuple":
        return types.Tuple([decode_type(c) for c in code[1]])
    return types.boolean if code[0] == "bool" else getattr(types, code[0])


def numba_dtype(name: str):
    from numba import from_dtype

    return from_dtype(np.dtype(name))


def kernel_ref(fn) -> dict:
    """How to build a launched kernel again: cuda_loops' recipe, or the module attribute."""
    recipe = fn.__globals__.get("__geompm_recipe__")
    if recipe is not None and recipe["kind"] == "merge":
        return {"kind": "merge", "image": function_ref(recipe["image"])}
    if recipe is not None:
        return dict(recipe, functions={alias: function_ref(f) for alias, f in recipe["functions"].items()})
    ref = [fn.__module__, fn.__qualname__]
    resolve(ref)
    return {"kernel": ref}


def record(run_scenes) -> list[dict]:
    """Call ``run_scenes()`` (which steps simulations on the cuda backend) with every kernel launch
    noted; returns the distinct launches [{"kernel": ..., "types": [...], "launches": n}]."""
    from numba.cuda.simulator import kernel as simulated_kernel

    seen: dict = {}
    launch = simulated_kernel.FakeCUDAKernel.__call__

    def noting(self, *args):
        if not self._device and not simulated_kernel._kernel_context:
            entry = {"kernel": kernel_ref(self.fn), "types": [encode_type(a) for a in args]}
            key = json.dumps(entry, sort_keys=True)
            seen.setdefault(key, dict(entry, launches=0))["launches"] += 1
        return launch(self, *args)

    simulated_kernel.FakeCUDAKernel.__call__ = noting
    try:
        run_scenes()
    finally:
        simulated_kernel.FakeCUDAKernel.__call__ = launch
    return list(seen.values())


# -- 2. compiling, without a GPU -----------------------------------------------------------------------
def offline(cc: tuple) -> None:
    """Let numba-cuda compile device functions with no GPU present: the 'current device' it asks for
    a compute capability is the target."""
    from numba.cuda import dispatcher

    class Target:
        compute_capability = tuple(cc)

    dispatcher.get_current_device = lambda: Target


def rebuild(ref: dict):
    """The kernel (a numba-cuda dispatcher) that a recorded reference names."""
    from geompm.backend import cuda_loops

    if "kernel" in ref:
        return resolve(ref["kernel"])
    if ref["kind"] == "merge":
        return cuda_loops.merge_kernel(resolve(ref["image"]))
    functions = {alias: resolve(r) for alias, r in ref["functions"].items()}
    return cuda_loops._kernel(ref["kind"], ref["name"], ref["source"], functions)


def kernel_label(ref: dict) -> str:
    if "kernel" in ref:
        return ref["kernel"][1]
    if ref["kind"] == "merge":
        return "merge:" + ref["image"][1]
    return ref["kind"] + ":" + ",".join(r[0].rsplit(".", 1)[-1] + "." + r[1] for r in ref["functions"].values())


def nvvm_missing() -> str | None:
    """Why numba-cuda could not compile here (NVVM or NVRTC not found), or None."""
    try:
        from cuda.pathfinder import load_nvidia_dynamic_lib

        for lib in ("nvvm", "nvrtc"):
            load_nvidia_dynamic_lib(lib)
    except Exception as exc:  # numba-cuda or the CUDA compiler libraries are not installed
        return f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
    return None


def find_ptxas() -> str | None:
    """The ptxas of the toolkit wheels NVVM comes from (the same PTX version), else the one on PATH."""
    try:
        from cuda.pathfinder import find_nvidia_binary_utility

        found = find_nvidia_binary_utility("ptxas")
    except Exception:  # no cuda-pathfinder, or no ptxas in the wheels it knows
        found = None
    return found or shutil.which("ptxas")


_USED = re.compile(r"Used (\d+) registers")
_FRAME = re.compile(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads")
_SMEM = re.compile(r"(\d+) bytes smem")


def machine_code_stats(ptx: str, cc: tuple, ptxas: str) -> dict:
    """ptxas -v on the kernel's PTX: registers per thread, stack frame, spills and static shared memory
    of its entry function."""
    with tempfile.TemporaryDirectory(prefix="geompm-ptx-") as tmp:
        src = Path(tmp) / "kernel.ptx"
        src.write_text(ptx)
        arch = f"sm_{cc[0]}{cc[1]}"
        res = subprocess.run([ptxas, f"-arch={arch}", "-v", str(src), "-o", str(Path(tmp) / "kernel.cubin")],
                             capture_output=True, text=True, timeout=600)
    if res.returncode:
        return {"ptxas_error": res.stderr.strip().splitlines()[-1] if res.stderr.strip() else "failed"}
    # the entry function's block: from "Compiling entry function" to the next "Compiling"
    text = res.stderr
    start = text.find("Compiling entry function")
    block = text[start:]
    nxt = block.find("Compiling", 10)
    block = block if nxt < 0 else block[:nxt]
    out = {}
    if (m := _USED.search(block)):
        out["registers"] = int(m.group(1))
    if (m := _FRAME.search(block)):
        out["stack_bytes"], out["spill_store_bytes"], out["spill_load_bytes"] = (int(g) for g in m.groups())
    if (m := _SMEM.search(block)):
        out["smem_bytes"] = int(m.group(1))
    return out


def compile_launches(launches: list[dict], cc: tuple = DEFAULT_CC, ptxas: str | None = None) -> list[dict]:
    """Compile each recorded launch to PTX for ``cc`` (and to machine code with ``ptxas``); one result
    per launch: the kernel, its argument types, ``ok`` or the error numba-cuda gave, and the figures."""
    from numba import cuda

    offline(cc)
    results = []
    for entry in launches:
        ref = entry["kernel"]
        out = {"kernel": kernel_label(ref), "types": [" ".join(map(str, t)) for t in entry["types"]]}
        t0 = time.perf_counter()
        try:
            kern = rebuild(ref)
            sig = tuple(decode_type(t) for t in entry["types"])
            ptx, _ = cuda.compile_ptx(kern.py_func, sig, cc=tuple(cc))
        except Exception as exc:  # reported per kernel: the point is to list every kernel that fails
            out.update(ok=False, error=f"{type(exc).__name__}: {first_lines(str(exc))}")
        else:
            out.update(ok=True, ptx_bytes=len(ptx))
            if ptxas:
                out.update(machine_code_stats(ptx, cc, ptxas))
        out["compile_s"] = round(time.perf_counter() - t0, 2)
        results.append(out)
    return results


def first_lines(text: str, n: int = 6) -> str:
    lines = [ln for ln in text.strip().splitlines() if ln.strip()]
    return " | ".join(lines[:n])
