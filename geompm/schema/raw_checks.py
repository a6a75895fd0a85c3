"""Checks on the raw JSON of a case before any model sees it: finite numbers, bounded nesting.

Python's ``json`` module reads ``NaN``, ``Infinity`` and ``-Infinity`` (which
are not JSON) and turns a literal such as ``1e999`` into infinity.  No key of
a geompm case gives infinity a meaning, so every number must be finite; each
offender is reported with its JSON path.  A real case is at most about six
levels deep (``bodies.0.geometry.vertices.3.1``); anything nested deeper than
``MAX_DEPTH`` is refused rather than handed to recursive validators.  The walk
is iterative, so a pathological file cannot exhaust Python's stack here.
"""

from __future__ import annotations

import math

from geompm.errors import join_path

MAX_DEPTH = 32
TOO_DEEP = f"nested more than {MAX_DEPTH} levels deep"


def _describe(value: float) -> str:
    if math.isnan(value):
        return "NaN"
    return "Infinity" if value > 0 else "-Infinity"


def raw_problems(raw) -> list[tuple[str, str]]:
    """(JSON path, message) for every non-finite or too-large number and for nesting beyond MAX_DEPTH."""
    problems = []
    stack = [((), raw)]
    while stack:
        path, node = stack.pop()
        if len(path) > MAX_DEPTH:
            problems.append((join_path(*path[:MAX_DEPTH]), TOO_DEEP + "; a geompm case needs at most "
                                                            "about 6"))
            continue
        if isinstance(node, dict):
            stack.extend((path + (k,), v) for k, v in reversed(list(node.items())))
        elif isinstance(node, list):
            stack.extend((path + (i,), v) for i, v in reversed(list(enumerate(node))))
        elif isinstance(node, float) and not math.isfinite(node):
            why = "" if math.isnan(node) else " (a literal beyond +/-1.8e308 reads as Infinity too)"
            problems.append((join_path(*path), f"must be a finite number, got {_describe(node)}{why}; "
                                               "give a real value"))
        elif isinstance(node, int) and not isinstance(node, bool):
            try:
                float(node)
            except OverflowError:
                problems.append((join_path(*path), f"the integer with {len(str(node))} digits is too large for "
                                                   "a double (at most about 1.8e308)"))
    return problems


def merge(first: list, second: list) -> list:
    """``first`` then the problems of ``second`` at paths that ``first`` does not name already."""
    seen = {p for p, _ in first}
    return list(first) + [(p, m) for p, m in second if p not in seen]
