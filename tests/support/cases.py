"""Paths to the repository's cases and reference data, and a small valid case to mutate in tests."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "cases"
REFDATA = ROOT / "tests" / "refdata"  # each file cites its source (README there)

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
