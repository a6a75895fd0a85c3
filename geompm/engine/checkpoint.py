"""Checkpoints: the complete state of a run in one file, written atomically.

``checkpoints/step_NNNNNNNNNN.npz`` holds every particle array (state.py),
each material's state variables (``p_state_<k>``) and a JSON ``meta`` string:
time, step, dt, the P2G chunk count (results are bit-identical for the same
count), the material blocks, the runner's output schedule, each writer's and
each stage's own state, and the wall time spent so far.  Files are written to
a temporary name, fsynced and renamed, so a kill never leaves a half-written
checkpoint; the newest ``keep`` are kept.  There is no random number state:
nothing in geompm draws random numbers during a run.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from geompm.version import __version__
from geompm.errors import CaseError
from geompm.files.atomic import atomic_path
from geompm.files.ownership import remove_file

FOLDER = "checkpoints"


def save(run_dir: Path, sim, runner_meta: dict, writers, keep: int = 2) -> Path:
    st = sim.state
    meta = {
        "geompm": __version__, "time": sim.time, "step": sim.step_count, "dt": sim.dt,
        "nchunks": sim.buffers.nchunks, "ranks": sim.domain.size, "blocks": [list(b) for b in st.blocks],
        "runner": runner_meta,
        "writers": [w.state() for w in writers],
        "stages": {s.label: s.state_dict() for s in sim.scene.stages},
    }
    arrays = dict(st.arrays())
    for k, sv in enumerate(st.p_state):
        arrays[f"p_state_{k}"] = sv
    folder = Path(run_dir) / FOLDER
    target = folder / f"step_{sim.step_count:010d}.npz"
    with atomic_path(target) as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, meta=np.array(json.dumps(meta)), **arrays)
    for old in sorted(folder.glob("step_*.npz"))[:-keep]:
        remove_file(old)
    return target


def newest(run_dir: Path) -> Path | None:
    found = sorted((Path(run_dir) / FOLDER).glob("step_*.npz"))
    return found[-1] if found else None


def read_meta(run_dir: Path) -> dict:
    """The JSON meta of the newest checkpoint only (npz members load lazily); CaseError if none."""
    return load(run_dir, arrays=False)[1]


def load(run_dir: Path, arrays: bool = True) -> tuple[dict, dict]:
    """(arrays, meta) of the newest checkpoint of a run folder; CaseError if there is none."""
    path = newest(run_dir)
    if path is None:
        raise CaseError([("", f"no checkpoint in '{Path(run_dir) / FOLDER}': the run cannot be resumed "
                              "(was it started with geompm 0.2 or later?)")])
    with np.load(path, allow_pickle=False) as data:
        meta = json.loads(str(data["meta"]))
        out = {k: data[k] for k in data.files if k != "meta"} if arrays else {}
    return out, meta


def restore(sim, arrays: dict, meta: dict) -> None:
    """Put a checkpoint's particles, time and stage states into a fresh Simulation of the same case."""
    st = sim.state
    for name in list(st.arrays()):
        setattr(st, name, np.ascontiguousarray(arrays[name]))
    st.blocks = [tuple(b) for b in meta["blocks"]]
    st.p_state = [np.ascontiguousarray(arrays[f"p_state_{k}"]) for k in range(len(st.blocks))]
    st.set_precision(sim.scene.precision)  # a checkpoint resumes in the precision of the case that resumes it
    sim.time, sim.step_count, sim.dt = meta["time"], meta["step"], meta["dt"]
    for s in sim.scene.stages:
        s.load_state(meta["stages"].get(s.label, {}))
