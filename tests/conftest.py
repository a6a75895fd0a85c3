"""Shared fixtures: paths to the repository's cases and its reference data (tests/refdata, README there)."""

import pytest

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

