"""Shared fixtures: paths to the repository's cases and its reference data (tests/refdata, README there)."""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "cases"
REFDATA = ROOT / "tests" / "refdata"  # each file cites its source (README there)


@pytest.fixture
def refdata():
    if not REFDATA.is_dir():
        pytest.fail(f"reference data folder {REFDATA} is missing from the repository")
    return REFDATA


def tiny_case(**over) -> dict:
    """A small valid 2D case (elastic block on a slip floor) to mutate in tests."""
    case = {
        "name": "tiny",
        "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 1.0], "cell_size": 0.1},
        "time": {"end": 0.05, "cfl": 0.4},
        "gravity": [0.0, -9.81],
        "solver": {"transfer": "apic", "update": "usl"},
        "materials": {"soil": {"model": "linear_elastic", "density": 2000.0,
                               "youngs_modulus": 1.0e6, "poisson_ratio": 0.3}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.2, 0.0], "max": [0.6, 0.4]},
                    "particles_per_cell": 2}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "slip"}],
        "outputs": [{"writer": "vtu", "interval": 0.01}, {"writer": "series", "interval": 0.0}],
    }
    case.update(over)
    return case


def pytest_collection_modifyitems(config, items):
    """Tests marked ``run_last`` go to the end, in their order: the CUDA simulator parity compares with the
    CPU backend on every law, whose loops the other tests have compiled into numba's on-disk cache by then
    (cold, the parity test compiles them itself: 197 s instead of 46 s warm, measured on 2 cores)."""
    items.sort(key=lambda item: item.get_closest_marker("run_last") is not None)

