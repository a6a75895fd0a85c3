"""Runs of a case on 1, 2 and 3 MPI ranks (mpiexec of the MPICH wheel beside this python) and their
comparison, particle by particle through the ids (docs/parallel.md, "Same answers")."""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

#: the fields compared particle by particle
FIELDS = ("p_x", "p_v", "p_stress", "p_vol", "p_C")
#: a scheme's fields compared where the runs have them (schemes/saturated/fields.py)
SCHEME_FIELDS = ("p_vw", "p_pore", "p_pore_carried", "p_n", "p_drained")


def mpiexec() -> Path:
    """The mpiexec installed with geompm's test extra (the mpich wheel puts it beside python)."""
    path = Path(sys.executable).parent / "mpiexec"
    assert path.is_file(), f"{path} is missing: the test extra installs mpich (pip install -e '.[test]')"
    return path


def run(case: dict, folder: Path, ranks: int, *extra: str, resume: Path | None = None,
        timeout: float = 900, env: dict | None = None) -> subprocess.CompletedProcess:
    """`geompm run` of ``case`` into ``folder / 'run'`` (or ``--resume`` of the run folder ``resume``) on
    ``ranks`` processes (1: no launcher), one numba thread each; the finished process."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "case.json"
    if not path.exists():
        path.write_text(json.dumps(case))
    where = ["--resume", str(resume)] if resume is not None else ["--out", str(folder / "run")]
    cli = [sys.executable, "-m", "geompm.cli", "run", str(path), *where, "--quiet", *extra]
    cmd = cli if ranks == 1 else [str(mpiexec()), "-n", str(ranks), *cli]
    env = dict(os.environ, NUMBA_NUM_THREADS="1", **(env or {}))
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def final_state(run_dir: Path) -> tuple[dict, dict]:
    """(per-particle arrays ordered by particle id, meta) of the run's newest checkpoint."""
    newest = sorted((Path(run_dir) / "checkpoints").glob("step_*.npz"))[-1]
    with np.load(newest) as data:
        meta = json.loads(str(data["meta"]))
        order = np.argsort(data["p_id"], kind="stable")
        return {k: data[k][order] for k in data.files if k.startswith("p_")}, meta


def series(run_dir: Path) -> tuple[list[str], np.ndarray]:
    with open(Path(run_dir) / "series.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


def relative(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |a| (the absolute difference where a is all zero)."""
    scale = float(np.abs(a).max()) if a.size else 0.0
    diff = float(np.abs(a - b).max()) if a.size else 0.0
    return diff / scale if scale > 0.0 else diff


def differences(one: Path, many: Path) -> dict[str, float]:
    """Largest relative difference of each compared field (and of the displacements, ``p_u``) and of each
    series column (beyond the csv's printed resolution) between two runs of the same case; the particle
    ids and the step counts must match (asserted)."""
    a, meta_a = final_state(one)
    b, meta_b = final_state(many)
    assert meta_a["step"] == meta_b["step"], (meta_a["step"], meta_b["step"])
    assert np.array_equal(a["p_id"], b["p_id"]), "the runs hold different particles"
    out = {k: relative(a[k], b[k]) for k in FIELDS + tuple(f for f in SCHEME_FIELDS if f in a)}
    out["p_u"] = relative(a["p_x"] - a["p_x0"], b["p_x"] - b["p_x0"])  # displacements: map coordinates hide them
    head_a, rows_a = series(one)
    head_b, rows_b = series(many)
    assert head_a == head_b and rows_a.shape == rows_b.shape
    for j, c in enumerate(head_a):
        group = [k for k, other in enumerate(head_a) if vector_of(other) == vector_of(c)] if vector_of(c) else [j]
        scale = float(np.abs(rows_a[:, group]).max())
        diff = float(np.maximum(np.abs(rows_a[:, j] - rows_b[:, j]) - printed_unit(rows_a[:, j]), 0.0).max())
        out[f"series.{c}"] = diff / scale if scale > 0.0 else diff
    return out


def printed_unit(values: np.ndarray) -> np.ndarray:
    """One unit of the tenth significant digit of each value: series.csv's resolution (writers/series.py
    prints %.10g), by which two values that differ in the 16th digit may differ when printed."""
    mag = np.abs(values)
    return np.where(mag > 0.0, 10.0 ** (np.floor(np.log10(np.where(mag > 0.0, mag, 1.0))) - 9), 0.0) * 1.000001


def vector_of(column: str) -> str | None:
    """The vector a series column is a component of ('dam_f' for dam_fx ... dam_ft, 'dam_m' for dam_mx ...),
    or None.  A component is compared against the vector's largest component: one that vanishes by
    symmetry (the dam's z-force on the flume's mid-plane) is itself round-off in one process (1e-7 N m
    against a force of 1e4 N), and its relative difference to itself would say nothing."""
    head, _, tail = column.rpartition("_")
    if head and tail in ("fx", "fy", "fz", "fn", "ft", "mx", "my", "mz"):
        return f"{head}_{tail[0]}"
    return None
