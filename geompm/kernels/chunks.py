"""The private per-chunk grids of the race-free P2G (kernels/transfer3d.py), and G2P's chunks.

Each chunk of particles scatters into its own grid, interleaved per node
(``c_grid (nchunks, >= nn, 1 + d or 1 + 2d)``); the grids are then summed in
chunk order, so the result depends on the chunk count only.
"""

from numba import njit, prange

#: the most particle chunks of a G2P pass: enough to balance any core count (kernels/transfer3d.py)
G2P_CHUNKS = 64 * 8
#: numba options of a parallel loop's body written as a function of its own (the P2G chunks, the 2D G2P's).
#: A ``prange`` body is typed twice and goes through numba's parfor passes, whose copy propagation is
#: quadratic in the body's basic blocks; a function of its own skips them (the first P2G compile: 3.8-5.0
#: against 5.1-7.1 s in 3D).  ``forceinline`` has LLVM inline it back into the loop's gufunc (a plain call
#: ran the 3D P2G 1.1-1.25x slower); ``error_model="numpy"`` is the gufunc's own model.  The 3D G2P is not
#: written so: split, it ran 1.4x slower whatever the options; it compiles only its scheme's gather instead
#: (transfer3d._gather_scheme; docs/performance.md).
CHUNK_BODY = {"fastmath": True, "error_model": "numpy", "forceinline": True, "cache": True}
#: the sentinel of an empty chunk's box [m]: finite, because the transfer kernels' fastmath assumes no
#: infinities
FAR = 1e300


@njit(cache=True)
def g2p_chunks(n):
    """The chunks of a G2P pass over n particles: contiguous ranges, each with its row of the particles'
    box (``p_box``)."""
    return max(1, min(n, G2P_CHUNKS))


@njit(cache=True)
def zero_rows(g, nn, width):
    """Zero the first ``width`` columns of the first nn rows of one chunk's interleaved grid."""
    for i in range(nn):
        for a in range(width):
            g[i, a] = 0.0


@njit(parallel=True, fastmath=True, cache=True)
def sum_interleaved(c_grid, split, g_mass, g_mom, g_force):
    """Sum the interleaved private grids ``c_grid (nchunks, >= nn, 1 + 2d)`` in chunk order.

    Columns: 0 mass, 1..d momentum, d+1..2d force (only when ``split``; a folded P2G
    has already added dt f to the momentum and leaves g_force untouched).
    """
    nchunks = c_grid.shape[0]
    nn, d = g_mom.shape
    for i in prange(nn):
        m = 0.0
        for c in range(nchunks):
            m += c_grid[c, i, 0]
        g_mass[i] = m
        for a in range(d):
            mv = 0.0
            for c in range(nchunks):
                mv += c_grid[c, i, 1 + a]
            g_mom[i, a] = mv
            if split:
                f = 0.0
                for c in range(nchunks):
                    f += c_grid[c, i, 1 + d + a]
                g_force[i, a] = f
