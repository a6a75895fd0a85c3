"""Each MPI rank on the CUDA backend (one GPU per rank), under numba-cuda's simulator on 2 ranks
(docs/parallel.md): the halo sums travel through the host, the particles migrate through the host, and the
answers match the same case on the CUDA backend in one process to 1e-10.  No GPU is needed; on a machine
with GPUs the same code runs on the devices."""

from __future__ import annotations

import json

import pytest

from geompm.testing.verification.mpi_scenes import BOUND
from geompm.testing.verification import mpi_runs as mpi

#: a Drucker-Prager block thrown along a friction floor against a slip wall: 88 particles, 8 ms in 6 steps (4 of them
#: cross the cut between the two slabs; 16 s on two cores for both runs under the simulator, 47 s with 352 particles)
CASE = {"name": "cuda_ranks", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.6, 0.5], "cell_size": 0.1, "shape_function": "quadratic"},
        "time": {"end": 0.008, "cfl": 0.4}, "gravity": [0.0, -9.81],
        "solver": {"transfer": "apic", "backend": "cuda"},
        "materials": {"soil": {"model": "drucker_prager", "density": 2000.0, "youngs_modulus": 1.0e6,
                               "poisson_ratio": 0.3, "friction_angle": 30.0, "cohesion": 0.0,
                               "dilation_angle": 0.0}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.1, 0.0], "max": [1.2, 0.2]},
                    "particles_per_cell": 2, "velocity": [4.0, 0.0]}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "friction", "friction": 0.5},
                       {"type": "wall", "side": "x+", "condition": "slip"}],
        "outputs": [{"writer": "series", "interval": 0.0}]}


@pytest.mark.slow
def test_two_ranks_on_the_cuda_simulator_match_one(tmp_path):
    sim = {"NUMBA_ENABLE_CUDASIM": "1"}
    one = mpi.run(CASE, tmp_path / "r1", 1, env=sim)
    assert one.returncode == 0, one.stdout + one.stderr
    two = mpi.run(CASE, tmp_path / "r2", 2, env=sim)
    assert two.returncode == 0, two.stdout + two.stderr
    report = json.loads((tmp_path / "r2" / "run" / "status.json").read_text())["mpi"]
    assert report["particles_migrated"] > 0, report  # particles crossed the cut between the two slabs
    diff = mpi.differences(tmp_path / "r1" / "run", tmp_path / "r2" / "run")
    worst = max(diff, key=diff.get)
    assert diff[worst] <= BOUND, f"{worst} differs by {diff[worst]:.3g}"
