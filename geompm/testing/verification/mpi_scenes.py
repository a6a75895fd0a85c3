"""The scenes that tests/mpi/test_same_answers.py and benchmarks/parallel/equality_table.py run in one process
and on 2 and 3 MPI ranks (docs/parallel.md, Same answers), each about 200 steps, and the bound on every
relative difference."""

from __future__ import annotations

import json

import numpy as np

from geompm.testing.verification.cases import CASES
from geompm.testing.verification.saturated_columns import hydrostatic_case
from geompm.testing.verification.slopes import infinite_slope_case, rising_table_case

#: the bound on every relative difference
BOUND = 1e-10


def shipped(name: str, **sets) -> dict:
    """cases/<name>.json with the dotted keys of ``sets`` replaced."""
    case = json.loads((CASES / f"{name}.json").read_text())
    for path, value in sets.items():
        node = case
        keys = path.split(".")
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = value
    return case


def absolute(case: dict) -> dict:
    """Relative file paths made absolute, so that the case runs from a temporary folder."""
    base = CASES
    for item in case.get("obstacles", []) + case.get("bodies", []):
        for holder in (item, item.get("geometry", {})):
            for key in ("file", "dem"):
                if isinstance(holder.get(key), str):
                    holder[key] = str((base / holder[key]).resolve())
    return case


def series_every_step(case: dict) -> dict:
    case["outputs"] = [{"writer": "series", "interval": 0.0}]
    return case


def with_hdf5(case: dict) -> dict:
    case["outputs"] = case["outputs"] + [{"writer": "hdf5", "interval": 0.02}]
    return case


def main_job() -> dict:
    """The main job (debris on the 35 degree flume against the STL slit dam, cases/debris_obstacle.json)
    with the debris block moved 2 m down the slope, 0.15 m short of the dam, and thrown at it at 4 m/s
    along the slope: the dam's grid contact and its particle guard act within the 200 steps."""
    case = shipped("debris_obstacle", **{"time.end": 0.1})
    body = case["bodies"][0]
    s, c = 2.0, np.array([0.819152, -0.573576])
    body["geometry"]["vertices"] = [list(np.round(np.array(v) + s * c, 6)) for v in body["geometry"]["vertices"]]
    body["velocity"] = [4.0 * c[0], 4.0 * c[1], 0.0]
    case["outputs"] = [o for o in case["outputs"] if o["writer"] in ("series", "surfaces")]
    return absolute(case)


def periodic_slope() -> dict:
    """The infinite slope under a rising water table (slopes.rising_table_case: Drucker-Prager,
    20 degrees, periodic along x, geostatic effective stress, artificial damping), 0.05 m cells: the slabs
    are cut along y, the one axis that is not periodic, and every rank's window holds the periodic ghosts.
    (Cundall's local damping is left out: on a body at rest it takes the sign of velocities of round-off
    size, and one process on 1 and on 2 threads already differs by 3e-3 after 4 steps; docs/parallel.md.)"""
    case = rising_table_case(0.05, rise=(0.0, 0.4, 0.1, 1.0), end=0.11)
    case["outputs"] = [{"writer": "series", "interval": 0.0, "displacement": True}]
    return case


def saturated_column() -> dict:
    """The saturated hydrostatic column (saturated_columns.hydrostatic_case: elastic skeleton, n = 0.4,
    impermeable base, slip walls, geostatic and hydrostatic at t = 0) at h = 0.05 m, without its local damping
    (at rest it amplifies round-off, see local_damping), 203 steps: the slabs cut the column along its height."""
    case = hydrostatic_case(0.05, 0.0076)
    case["damping"] = []
    case["outputs"] = [{"writer": "series", "interval": 0.0}]
    return case


def saturated_main_job() -> dict:
    """The saturated main job (cases/saturated_debris_obstacle.json: saturated debris against the STL dam),
    about 200 steps."""
    case = shipped("saturated_debris_obstacle", **{"time.end": 0.0062})
    case["outputs"] = [o for o in case["outputs"] if o["writer"] == "series"]
    return absolute(case)


SCENES = {
    "saturated_column": saturated_column,
    "terzaghi": lambda: shipped("terzaghi_consolidation", **{"time.end": 0.0032}),
    "saturated_main_job": saturated_main_job,
    "dam_break": lambda: shipped("dam_break", **{"time.end": 0.0086}),
    "dp_column": lambda: with_hdf5(shipped("column_collapse", **{"time.end": 0.038})),
    "main_job": main_job,
    "periodic_slope": periodic_slope,
    "local_damping": lambda: series_every_step(infinite_slope_case(0.05, end=0.11)),
    "terrain": lambda: absolute(shipped("terrain_debris_flow", **{"time.end": 3.6, "grid.cell_size": 2.0})),
}
