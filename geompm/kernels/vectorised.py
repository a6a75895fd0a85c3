"""Kernels compiled with LLVM's SLP vectoriser on.

numba leaves LLVM's superword-level-parallelism (SLP) vectoriser off by default
(``numba.core.config.SLP_VECTORIZE = 0``; the loop vectoriser stays on).  In the
transfer kernels it is what packs the updates of one node (mass and three
momentum components, or three velocity components) into one SIMD multiply-add:
with it the 3D P2G's node updates compile to 4-wide ``vfmadd...pd`` on ymm
registers, and without it they are all scalar.  Measured on the 2-core
development machine (docs/performance.md, issue 38): the MLS P2G took 33 against
54-63 ns per particle, and the whole step 0.89-0.96 of its time without it
(interleaved runs, five scenes).

``Vectorised(dispatcher)`` calls the dispatcher with the setting on, so that
any compilation the call triggers (the first call of each signature, the
parallel loop's body included) runs with it, and restores numba's own value
after: other numba code in the process is not affected.  numba reads the
setting when it builds each compilation's pass pipeline.  Its on-disk cache
does not record it, so these kernels must be called only through their
``Vectorised`` wrapper (backend/cpu.py ``TRANSFERS``); code loaded from the
cache runs as it was compiled.  The packed lanes do the scalar code's
arithmetic: every shipped case's series is unchanged to the last bit
(docs/performance.md).
"""

from __future__ import annotations

from numba.core import config


class Vectorised:
    """A numba dispatcher called with LLVM's SLP vectoriser on (restored after the call)."""

    def __init__(self, dispatcher):
        self.dispatcher = dispatcher
        self.__name__ = getattr(dispatcher, "__name__", "kernel")
        self.__doc__ = dispatcher.__doc__

    def __call__(self, *args):
        old = config.SLP_VECTORIZE
        config.SLP_VECTORIZE = 1
        try:
            return self.dispatcher(*args)
        finally:
            config.SLP_VECTORIZE = old
