"""Memory: what a case will need, and what the machine has.

Particle state per particle (state.py): p_x, p_x0, p_v (3 d), p_C (d^2),
p_L (9), p_stress (6), mass, vol0, vol, rho (4) in float64, and two
int32 ids; material state variables come on top (a few per particle).  Grid
per active node: one private (mass, momentum d, force d) copy per P2G chunk
plus the shared mass, momentum, force, velocity and old velocity.
"""

from __future__ import annotations

import os

import numba
import numpy as np


def particle_bytes(dim: int, state_vars: int = 4) -> int:
    return 8 * (3 * dim + dim * dim + 9 + 6 + 4 + state_vars) + 8


def grid_bytes(nodes: int, dim: int, chunks: int | None = None) -> int:
    chunks = chunks or numba.get_num_threads()
    return nodes * 8 * (chunks * (1 + 2 * dim) + 1 + 4 * dim)


def window_nodes(lo, hi, h) -> int:
    """Nodes of the grid window around the box [lo, hi] (stencil margin included)."""
    span = (np.asarray(hi, float) - np.asarray(lo, float)) / h + 4
    return int(np.prod(np.ceil(np.maximum(span, 1.0))))


def available_memory() -> int | None:
    """Bytes the OS can give a new allocation (MemAvailable on Linux); None if unknown."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


#: environment variable that caps the memory a case may plan for, e.g. "2G", "500M" or bytes; the default is
#: the memory the OS says is available (MemAvailable)
MEMORY_ENV = "GEOMPM_MAX_MEMORY"
_UNITS = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}


def memory_cap() -> tuple[int | None, str]:
    """(bytes one case may plan for, where that figure comes from): GEOMPM_MAX_MEMORY if set and below
    the available memory, else the available memory; None if neither is known."""
    from geompm.errors import CaseError

    have = available_memory()
    text = os.environ.get(MEMORY_ENV, "").strip().upper().removesuffix("B").removesuffix("I")
    if not text:
        return have, "available"
    try:
        unit = text[-1] if text[-1] in _UNITS else ""
        cap = int(float(text[:len(text) - len(unit)]) * _UNITS[unit])
    except (ValueError, IndexError):
        raise CaseError([(MEMORY_ENV, f"'{os.environ[MEMORY_ENV]}' is not a size; give bytes or a number with "
                                      "K, M, G or T, e.g. 2G")]) from None
    if have is not None and have < cap:
        return have, "available"
    return cap, f"the {MEMORY_ENV} cap"


def require_memory(nbytes: float, json_path: str, what: str, remedy: str) -> None:
    """Refuse (CaseError, exit 2) an allocation sized from the case before it is made, when it would need
    more than memory_cap(): the JSON path, the gigabytes, and what to change."""
    from geompm.errors import CaseError

    cap, source = memory_cap()
    if cap is not None and nbytes > cap:
        raise CaseError([(json_path, f"{what} would need {nbytes / 2**30:.3g} GiB, more than the "
                                     f"{cap / 2**30:.3g} GiB {source}; {remedy}")])


def peak_rss() -> int:
    """Peak resident memory of this process so far [bytes] (Linux reports ru_maxrss in KiB)."""
    import resource
    import sys

    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(rss if sys.platform == "darwin" else rss * 1024)
