"""`mpiexec -n 3 geompm run` of a case whose grid cannot hold three slabs exits with code 2 on every
rank before any folder is made, naming the split axis and the largest rank count (docs/parallel.md)."""

from __future__ import annotations

from geompm.testing.verification import mpi_runs as mpi
from tests.support.cases import tiny_case


def test_more_ranks_than_slabs_of_four_cells_are_refused(tmp_path):
    case = tiny_case()  # 10 x 10 cells of 0.1 m
    done = mpi.run(case, tmp_path, 3)
    assert done.returncode == 2, done.stdout + done.stderr
    assert "3 MPI ranks need at least 12 cells along the split axis x" in done.stderr
    assert "run on at most 2 ranks" in done.stderr
    assert not (tmp_path / "run").exists()
    done = mpi.run(case, tmp_path, 2)
    assert done.returncode == 0, done.stdout + done.stderr
