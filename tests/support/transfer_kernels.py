"""The transfer kernels under test, all called with the reference signature of tests/support/reference_transfer.py.

``generic``: the dimension-generic reference (separate private-grid arrays, a
``with_force`` flag).  ``specialised``: the 2D/3D kernels the scheduler runs,
with their compile-time stencil tag and interleaved private grids, split-force
mode (force in its own columns), wrapped to take the same arguments.
"""

import numpy as np

from geompm.backend.cpu import TRANSFERS
from geompm.kernels.chunks import G2P_CHUNKS
from geompm.kernels.stencil import SCHEMES, scheme_tag, stencil_tag

from .reference_transfer import g2p as generic_g2p
from .reference_transfer import p2g as generic_p2g


def _specialised(dim):
    fast_p2g, fast_g2p = TRANSFERS[dim]

    def p2g(x, v, C, m, vol, sig, origin, h, kind, lo, nloc, c_mass, c_mom, c_force, with_force,
            g_mass, g_mom, g_force):
        c_grid = np.zeros((c_mass.shape[0], c_mass.shape[1], 1 + 2 * dim))
        fast_p2g(stencil_tag(kind), scheme_tag("apic"), x, v, C, m, vol, sig, origin, h, kind, lo, nloc, c_grid,
                 True, 1.0 if with_force else 0.0, 0.0, g_mass, g_mom, g_force)

    def g2p(x, *args):
        """The reference's arguments, its run-time ``mode`` (args[14]) turned into the scheme tag, and the
        rows of the moved particles' box that the specialised kernel fills."""
        kind, mode = args[10], args[14]
        fast_g2p(stencil_tag(kind), scheme_tag(SCHEMES[mode]), x, *args[:14], *args[15:],
                 np.zeros((G2P_CHUNKS, 2, 3)))

    return p2g, g2p


def kernels(impl, dim):
    """(p2g, g2p) of the reference ("generic") or of the scheduler ("specialised")."""
    return (generic_p2g, generic_g2p) if impl == "generic" else _specialised(dim)
