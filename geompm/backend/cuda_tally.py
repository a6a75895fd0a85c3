"""One device buffer for every number a CUDA step reduces, read by the host once per step.

A step's reductions (each stage pass's accumulator row, the law kernels' largest |L_ii|, and at the step's end
the particles' bounds, speeds, densities and health sums) each write into their own slots of one float64
array on the device.  ``read()`` copies the whole array to the host (one blocking copy) and ``reset()`` puts
every slot back to its starting value with one kernel launch (the starting values live on the device; no copy
from the host).  Slots are reserved by key on first use and keep their place for the run, so after the first
steps the layout no longer changes; a new key grows the array (a copy each way, once).

The host side of a reduction (a stage's ``grid_reduced``, the time step's inputs) is handed the slots' values
after ``read()``: backend/cuda.py runs it at the end of the step (``settle``).
"""

from __future__ import annotations

import numpy as np
from numba import cuda

from geompm.backend import cuda_kernels as K


@cuda.jit
def _restart(buf, start):
    i = cuda.grid(1)
    if i < buf.shape[0]:
        buf[i] = start[i]


class DeviceTally:
    """Keyed slots of one device array of float64 reductions (module docstring)."""

    def __init__(self):
        self._slots: dict = {}  # key -> (first index, count)
        self._start = np.zeros(0)  # each slot's starting value, on the host
        self._buf = self._start_dev = None

    def __len__(self) -> int:
        return self._start.shape[0]

    def reserve(self, key, start) -> slice:
        """The slots of ``key`` (as a slice of the array), reserved at ``start`` (a sequence of starting values)
        the first time the key is asked for; its values so far are kept when the array grows."""
        held = self._slots.get(key)
        if held is None:
            start = np.asarray(start, np.float64).ravel()
            first = len(self)
            held = self._slots[key] = (first, start.shape[0])
            now = self._buf.copy_to_host() if self._buf is not None else np.zeros(0)
            self._start = np.concatenate([self._start, start])
            self._buf = cuda.to_device(np.concatenate([now, start]))
            self._start_dev = cuda.to_device(self._start)
        return slice(held[0], held[0] + held[1])

    def where(self, key):
        """The slice of ``key``'s slots, or None where it has none."""
        held = self._slots.get(key)
        return None if held is None else slice(held[0], held[0] + held[1])

    def slots(self, key, start):
        """The device view of ``key``'s slots (``reserve``)."""
        s = self.reserve(key, start)
        return self._buf[s.start:s.stop]

    def view(self, where: slice):
        """The device view of the slots ``where`` (a slice ``reserve`` gave): taken after every key a launch needs is
        reserved, since a new key moves the array."""
        return self._buf[where.start:where.stop]

    def read(self) -> np.ndarray:
        """Every slot on the host: one copy, which waits for the device to finish what was launched before."""
        return self._buf.copy_to_host() if self._buf is not None else np.zeros(0)

    def reset(self) -> None:
        """Every slot back to its starting value (one launch, after the work launched before it)."""
        if self._buf is not None and len(self):
            _restart[K.blocks(len(self)), K.THREADS](self._buf, self._start_dev)
