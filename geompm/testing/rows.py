"""A benchmark's result rows: printed as one JSON line each and appended to a JSON-lines file, so that a long
study keeps every row it finished (benchmarks/)."""

from __future__ import annotations

import json


def emit(row: dict, out=None) -> None:
    """Print ``row`` as one JSON line and append it to ``out`` (a path, or None)."""
    line = json.dumps(row)
    print(line, flush=True)
    if out:
        with open(out, "a") as fh:
            fh.write(line + "\n")
