"""Run variants on Dask distributed, each as an ordinary ``geompm run`` in its own folder.

Each Dask task starts ``python -m geompm.cli run CASE --set ... --out RUN_DIR``
in a subprocess, with NUMBA_NUM_THREADS set, so a variant that blows up or is
killed takes nothing else with it and leaves a run folder that ``geompm info``
reads and ``--resume`` continues.  Without ``--scheduler`` a LocalCluster of
threads starts inside this process (the work is in the subprocesses); with
``--scheduler tcp://HOST:PORT`` the tasks go to that cluster, whose workers
need geompm installed and the case and study folders on a shared file system.
"""

from __future__ import annotations

import json
import logging
import os
import subprocess
import sys
import uuid
from pathlib import Path

from geompm.schema.load import apply_overrides


def finished(run_dir: Path, raw_case: dict) -> bool:
    """A finished run of exactly this case is in ``run_dir``."""
    status, saved = run_dir / "status.json", run_dir / "case.json"
    if not (status.is_file() and saved.is_file()):
        return False
    try:
        return json.loads(status.read_text()).get("finished") is True and json.loads(saved.read_text()) == raw_case
    except (OSError, json.JSONDecodeError):
        return False


def run_variant(case: str, run_dir: str, sets: list[str], threads: int) -> dict:
    """Run one variant to its end (resuming from its checkpoint if it has one); return its outcome.

    Executed on a Dask worker.  Returns {"run_dir", "exit_code", "error"}; a
    failed run is reported, not raised, so the other variants go on.
    """
    run_dir = Path(run_dir)
    cmd = [sys.executable, "-m", "geompm.cli", "run", case, "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    if (run_dir / "case.json").is_file() and any((run_dir / "checkpoints").glob("step_*.npz")):
        cmd += ["--resume", str(run_dir)]
    else:
        cmd += ["--out", str(run_dir), "--overwrite"]
    env = dict(os.environ, NUMBA_NUM_THREADS=str(threads))
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    tail = (proc.stderr.strip() or proc.stdout.strip()).splitlines()[-3:]
    return {"run_dir": str(run_dir), "exit_code": proc.returncode,
            "error": "" if proc.returncode == 0 else " | ".join(tail)[-600:]}


def variant_case(raw: dict, sets: list[str]) -> dict:
    """The case JSON a variant runs, as its run folder's case.json records it."""
    return json.loads(json.dumps(apply_overrides(raw, sets)))


class Pool:
    """A Dask client: LocalCluster sized to the machine, or an existing scheduler."""

    def __init__(self, scheduler: str | None = None, workers: int | None = None):
        from distributed import Client, LocalCluster

        cores = os.cpu_count() or 1
        if scheduler:
            self.cluster = None
            self.client = Client(scheduler)
            self.workers = max(1, len(self.client.scheduler_info().get("workers", {})))
        else:
            self.workers = workers or cores
            logging.getLogger("distributed").setLevel(logging.WARNING)
            self.cluster = LocalCluster(n_workers=1, threads_per_worker=self.workers, processes=False,
                                        dashboard_address=":0", silence_logs=logging.WARNING)
            self.client = Client(self.cluster)

    def submit(self, fn, *args, name: str):
        """Run ``fn(*args)`` on a worker; retried once if the worker is lost."""
        return self.client.submit(fn, *args, key=f"{name}-{uuid.uuid4().hex[:8]}", pure=False, retries=1)

    def close(self):
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def threads_per_run(workers: int, n_runs: int, requested: int | None = None) -> int:
    """Numba threads for each run: ``requested`` (--threads) if given; else NUMBA_NUM_THREADS if the user
    exported it (numba's own meaning: threads per process, so each run gets that many); else the machine's
    cores shared among the runs in flight, so that they fill the cores once."""
    if requested:
        return requested
    env = os.environ.get("NUMBA_NUM_THREADS", "").strip()
    if env.isdigit() and int(env) > 0:
        return int(env)
    cores = os.cpu_count() or 1
    return max(1, cores // max(1, min(workers, n_runs)))


def add_threads_option(parser) -> None:
    """--threads N of `geompm study` and `geompm calibrate`."""
    parser.add_argument("--threads", type=int, metavar="N",
                        help="numba threads of each run (default: NUMBA_NUM_THREADS if set, else the CPU cores "
                             "shared among the runs in flight); workers x threads should not exceed the cores")


def check_threads(threads: int | None) -> None:
    from geompm.errors import CaseError

    if threads is not None and threads < 1:
        raise CaseError([("--threads", f"{threads} is not a thread count; give 1 or more")])
