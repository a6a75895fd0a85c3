"""Python entry points: build a scene from a case file or dict and step it.

    from geompm.api import scene_from_file
    from geompm.engine.scheduler import Simulation
    sim = Simulation(scene_from_file("cases/elastic_bar.json"))
    while sim.time < 1.0:
        sim.step(sim.stable_dt())
"""

from __future__ import annotations

from pathlib import Path

from geompm.assemble import Scene, assemble
from geompm.schema.load import apply_overrides, load_case, parse_case


def scene_from_file(path: str | Path, sets=()) -> Scene:
    return assemble(load_case(path, sets))


def scene_from_dict(raw: dict, base_dir: str | Path = ".", sets=()) -> Scene:
    return assemble(parse_case(apply_overrides(raw, list(sets)), base_dir))
