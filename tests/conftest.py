"""Shared fixtures: paths to the repository's cases and its reference data (tests/refdata, README there).

Under pytest-xdist (the README's command runs ``-n 2``) each worker gets its share of the cores as numba
threads, NUMBA_NUM_THREADS = cores // workers, set here before any test imports numba and inherited by
the runs tests start in subprocesses: two workers with a thread per core each would oversubscribe the
cores, which slows numba's parallel loops many times (decision 20). An exported NUMBA_NUM_THREADS wins.
"""

import os

import pytest

_WORKERS = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
if _WORKERS > 1 and "NUMBA_NUM_THREADS" not in os.environ:
    os.environ["NUMBA_NUM_THREADS"] = str(max(1, (os.cpu_count() or 1) // _WORKERS))

from tests.support.cases import REFDATA


@pytest.fixture
def refdata():
    if not REFDATA.is_dir():
        pytest.fail(f"reference data folder {REFDATA} is missing from the repository")
    return REFDATA


def pytest_collection_modifyitems(config, items):
    """Tests marked ``run_last`` go to the end, in their order: the CUDA simulator parity compares with the
    CPU backend on every law, whose loops the other tests have compiled into numba's on-disk cache by then
    (cold, the parity test compiles them itself: 197 s instead of 46 s warm, measured on 2 cores)."""
    items.sort(key=lambda item: item.get_closest_marker("run_last") is not None)

