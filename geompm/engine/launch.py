"""How many processes an MPI launcher started for this run, and their communicator.

``mpiexec -n N geompm run CASE`` starts N copies of geompm; ``world`` joins them into one run
(parallel/slabs.py, docs/parallel.md).  The launcher says how many it started in its environment:
``PMI_SIZE`` (MPICH's and Intel MPI's launchers), ``OMPI_COMM_WORLD_SIZE`` (Open MPI) or
``MV2_COMM_WORLD_SIZE`` (MVAPICH).  When it started more than one, mpi4py must be installed (the
``[mpi]`` extra) and see the same number of processes; otherwise each copy would run the whole case into
the same run folder, so the run is refused before any work.
"""

from __future__ import annotations

import os

from geompm.errors import CaseError

#: environment variables in which MPI launchers give the number of processes they started
MPI_SIZE_VARIABLES = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MV2_COMM_WORLD_SIZE")


def launched(environ=None) -> tuple[int, str]:
    """(processes the launcher started, the variable that says so); (1, "") outside a launcher."""
    environ = os.environ if environ is None else environ
    for name in MPI_SIZE_VARIABLES:
        value = environ.get(name, "").strip()
        if value.isdigit() and int(value) > 1:
            return int(value), name
    return 1, ""


def world(environ=None):
    """The communicator of the processes a launcher started (parallel/comm.MpiComm), or None for one
    process; CaseError when several were started but mpi4py is missing or sees another number."""
    size, name = launched(environ)
    if size == 1:
        return None
    where = f"{name}={size}"
    try:
        from mpi4py import MPI
    except ImportError:
        raise CaseError([(name, f"geompm was started as one of {size} MPI processes ({where}) but mpi4py is "
                                "not installed, so the processes cannot share the run and each would run the "
                                "whole case: pip install 'geompm[mpi]' (mpi4py and MPICH from PyPI, "
                                "docs/parallel.md), or run without mpiexec")]) from None
    from geompm.parallel.comm import MpiComm

    comm = MpiComm(MPI.COMM_WORLD)
    if comm.size != size:
        raise CaseError([(name, f"the launcher started {size} processes ({where}) but mpi4py's MPI sees "
                                f"{comm.size}: mpi4py was built for another MPI than the mpiexec that started "
                                "geompm. Start it with the mpiexec of the environment geompm is installed in "
                                "(pip install 'geompm[mpi]' puts one beside python)")])
    return comm
