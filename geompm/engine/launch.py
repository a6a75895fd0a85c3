"""Refuse a run started as one of several MPI processes.

``mpiexec -n N geompm run CASE`` starts N copies of geompm.  A single run is
not distributed over processes (one process uses the machine's cores through
numba's threads; many cases run as processes side by side with ``geompm study``,
docs/speed-vs-accuracy.md), so each copy would run the whole case and write the
same run folder as the others.  ``check_single_process`` refuses
that before any work, naming the variable that showed it: ``PMI_SIZE``
(MPICH's and Intel MPI's launchers), ``OMPI_COMM_WORLD_SIZE`` (Open MPI) or
``MV2_COMM_WORLD_SIZE`` (MVAPICH).  A launcher's single process (N = 1) runs as usual.
"""

from __future__ import annotations

import os

from geompm.errors import CaseError

#: environment variables in which MPI launchers give the number of processes they started
MPI_SIZE_VARIABLES = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MV2_COMM_WORLD_SIZE")


def check_single_process(environ=None) -> None:
    """Raise CaseError if this process is one of several that an MPI launcher started."""
    environ = os.environ if environ is None else environ
    for name in MPI_SIZE_VARIABLES:
        value = environ.get(name, "").strip()
        if value.isdigit() and int(value) > 1:
            raise CaseError([(name, f"geompm was started as one of {int(value)} MPI processes ({name}={value}), "
                                    "but one run is not shared between processes: each would run the whole case "
                                    "and write the same run folder. Run it without mpiexec (one process uses "
                                    "every core through its threads; NUMBA_NUM_THREADS sets how many), or run "
                                    "several cases side by side with `geompm study` "
                                    "(docs/speed-vs-accuracy.md)")])
