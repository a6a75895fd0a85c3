"""Device work arrays kept from one use to the next (backend/cuda.py): the spatial sort's scratch and the spare
of each particle array that the sort gathers into, so that a sort allocates nothing once its arrays have reached
the sizes the run needs.

An allocation is a cuMemAlloc, and numba-cuda frees device arrays in batches (over 10 pending), each cuMemFree
of such memory "may perform implicit synchronization" (CUDA Driver API, cuMemFree): a sort that put every
particle array in a new one (about 20 arrays) made the host wait at the next batch of frees.  A CUDA graph also
replays the pointers it was captured with (bench/cuda_replay.py).

``scratch(key, shape, dtype)``: the first elements of a flat device array kept per key, grown by a quarter when
too small (as the grid window's arrays), viewed in ``shape``; what one use wrote the next overwrites (the
stream orders the two).  ``spare(key, shape, dtype, busy)``: an array of ``shape`` and ``dtype`` that is not
``busy``, one of a pair kept per key: the sort gathers an array into its spare, and the array it replaced is
the next sort's spare.
"""

from __future__ import annotations

import numpy as np
from numba import cuda


class Scratch:
    def __init__(self):
        self._flat: dict = {}
        self._pairs: dict = {}

    def __call__(self, key, shape, dtype):
        shape = (int(shape),) if np.ndim(shape) == 0 else tuple(int(s) for s in shape)
        size, dtype = int(np.prod(shape, dtype=np.int64)), np.dtype(dtype)
        flat = self._flat.get(key)
        if flat is None or flat.dtype != dtype or flat.shape[0] < size:
            flat = self._flat[key] = cuda.device_array(int(size * 1.25) + 64, dtype)
        return flat[:size].reshape(shape)

    def spare(self, key, shape, dtype, busy=None):
        shape, dtype = tuple(int(s) for s in shape), np.dtype(dtype)
        pair = [a for a in self._pairs.get(key, ()) if a.shape == shape and a.dtype == dtype]
        for a in pair:
            if a is not busy:
                return a
        new = cuda.device_array(shape, dtype)
        self._pairs[key] = tuple(pair[:1]) + (new,)
        return new

    def nbytes(self) -> int:
        return sum(a.nbytes for a in self._flat.values()) + sum(a.nbytes for p in self._pairs.values() for a in p)
