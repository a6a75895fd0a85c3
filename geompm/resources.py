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


def peak_rss() -> int:
    """Peak resident memory of this process so far [bytes] (Linux reports ru_maxrss in KiB)."""
    import resource
    import sys

    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(rss if sys.platform == "darwin" else rss * 1024)
