"""Atomic file writes: write a temporary file beside the target, fsync, rename.

A reader (or a crash) never sees a half-written file: it finds the old
content or the new one.  The file ends with the mode the user's umask gives
a new file (0o644 under umask 022), not mkstemp's private 0o600.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from geompm.files.ownership import register_made, remove_file


def user_mode(executable: bool = False) -> int:
    """The mode a new file gets under the process's umask: 0o666 (0o777 for an executable) less the
    umask, as open() and mkdir() would give it (0o644 under umask 022)."""
    mask = os.umask(0)
    os.umask(mask)
    return (0o777 if executable else 0o666) & ~mask


@contextmanager
def atomic_path(target: str | Path, suffix: str = ""):
    """Yield a temporary path; on success it replaces ``target`` atomically."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix or target.suffix, dir=target.parent)
    os.close(fd)
    register_made(tmp)
    try:
        yield Path(tmp)
        with open(tmp, "rb") as fh:
            os.fsync(fh.fileno())
        os.chmod(tmp, user_mode())  # mkstemp made it 0600: a colleague must be able to read the results
        os.replace(tmp, target)
        register_made(target)
    finally:
        if os.path.exists(tmp):
            remove_file(tmp)


def finite_or_none(obj):
    """``obj`` with every NaN or infinite float (numpy's too) replaced by None, recursively through dicts,
    lists and tuples: JSON has no NaN, and a strict reader (JavaScript, jq, Go) refuses Python's bare NaN."""
    if isinstance(obj, dict):
        return {k: finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_or_none(v) for v in obj]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def strict_json(obj, **kwargs) -> str:
    """JSON text of ``obj`` with NaN and infinities as null (finite_or_none); never a bare NaN."""
    return json.dumps(finite_or_none(obj), allow_nan=False, **kwargs)


def atomic_write_json(target: str | Path, obj, indent: int | None = 2) -> None:
    """An atomic write of ``obj`` as strict JSON (strict_json) with a final newline."""
    atomic_write_text(target, strict_json(obj, indent=indent) + "\n")


def atomic_write_text(target: str | Path, text: str) -> None:
    with atomic_path(target) as tmp:
        tmp.write_text(text)


def case_relative(base_dir: str | Path, relative: str) -> Path:
    """A file path from a case: absolute as given, else relative to the case file's folder."""
    p = Path(relative)
    return p if p.is_absolute() else Path(base_dir) / p


def unreadable_file(path: Path, shown: str) -> str | None:
    """Why ``path`` cannot be read as an input file, or None if it can."""
    if not path.is_file():
        return f"file '{shown}' not found (looked in {path.parent})"
    if not os.access(path, os.R_OK):
        return f"file '{shown}' exists but cannot be read (permissions); make it readable"
    return None
