"""The equality table of docs/parallel.md: each scene of tests/mpi/test_same_answers.py on 1, 2 and 3 MPI
ranks (one numba thread each), and the largest relative difference of each field and series column
against the one-process run.

    python benchmarks/parallel/equality_table.py OUT_DIR [SCENE ...]
"""

from __future__ import annotations

import json
from pathlib import Path


from geompm.testing.verification.mpi_scenes import SCENES
from geompm.testing.verification import mpi_runs as mpi


def main(out: Path, only=()) -> None:
    rows = []
    for name, make in SCENES.items():
        if only and name not in only:
            continue
        case = make()
        assert mpi.run(case, out / name / "r1", 1).returncode == 0
        one = out / name / "r1" / "run"
        _, meta = mpi.final_state(one)
        guard = {k: v.get("particles_put_back") for k, v in meta["stages"].items() if "particles_put_back" in v}
        for ranks in (2, 3):
            done = mpi.run(case, out / name / f"r{ranks}", ranks)
            assert done.returncode == 0, done.stderr
            diff = mpi.differences(one, out / name / f"r{ranks}" / "run")
            fields = {k: diff[k] for k in (*mpi.FIELDS, *mpi.SCHEME_FIELDS, "p_u") if k in diff}
            worst_series = max((k for k in diff if k.startswith("series.")), key=diff.get)
            status = json.loads((out / name / f"r{ranks}" / "run" / "status.json").read_text())
            rows.append({"scene": name, "ranks": ranks, "steps": meta["step"], "particles": status["particles"],
                         "cuts": status["mpi"]["cuts"], **fields, "worst_series": worst_series,
                         "worst_series_diff": diff[worst_series], "guard_put_back_1rank": guard})
            print(json.dumps(rows[-1]))
    (out / ("equality.json" if not only else "equality_" + "_".join(only) + ".json")).write_text(
        json.dumps(rows, indent=1))


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", type=Path, help="folder for the runs and equality.json (made if missing)")
    parser.add_argument("scenes", nargs="*", choices=[[]] + list(SCENES), metavar="SCENE",
                        help=f"scenes to run (default all): {', '.join(SCENES)}")
    args = parser.parse_args()
    main(args.out, args.scenes)
