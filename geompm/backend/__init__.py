"""Backends: where the particle and grid arrays live and the step's kernels run.

``solver.backend`` names one (schema); ``make_backend`` looks it up in
``BACKENDS``.  The scheduler (engine/scheduler.py) drives a step through the
backend's methods only (backend/base.py); health checks, writers and
checkpoints read the particle arrays through ``Backend.host_state()`` at the
times they run.  ``cpu`` (numba, every core) and ``cuda`` (numba-cuda, backend/cuda.py; the
optional extra ``geompm[cuda]``, imported only when a case asks for it).
"""

from geompm.backend.base import Backend
from geompm.backend.cpu import CpuBackend

BACKENDS: dict[str, type[Backend]] = {CpuBackend.name: CpuBackend}


def make_backend(scene, split_force: bool, nchunks: int | None = None) -> Backend:
    if scene.backend == "cuda" and "cuda" not in BACKENDS:  # numba-cuda is an optional extra: imported on use
        from geompm.backend.cuda import CudaBackend

        BACKENDS["cuda"] = CudaBackend
    return BACKENDS[scene.backend](scene, split_force, nchunks)
