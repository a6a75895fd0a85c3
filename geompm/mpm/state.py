"""Particle state as a structure of arrays.

n particles, d dimensions; shapes as below, SI units:

    p_x (n, d) position [m]          p_x0 (n, d) initial position [m]
    p_v (n, d) velocity [m/s]        p_C (n, d, d) APIC affine matrix [1/s]
    p_mass (n,) [kg]                 p_vol0, p_vol (n,) volume [m^d; m^2 per m in 2D]
    p_rho (n,) density [kg/m3]       p_stress (n, 6) Cauchy stress, Voigt (voigt.py) [Pa]
    p_L (n, 3, 3) velocity gradient [1/s]  (the deformation gradient is not stored:
        the volume is advanced by det(I + dt L) each step, kernels/volume.py)
    p_material (n,) int32            p_body (n,) int32
    p_id (n,) int64 stable particle id: its index in the assembled scene, carried
        through every re-ordering (spatial sort, deletion) and written with every output

A scheme adds the particle arrays it declares (schemes/base.Field; the saturated scheme's in
schemes/saturated/fields.py) as attributes of the state: ``arrays()`` lists them with the core's, so
the sort, the migration between ranks, the writers and the checkpoints carry them unchanged.

Particles are sorted by material: material k owns the contiguous block
``blocks[k] = (start, end)``; its state variables live in ``p_state[k]``
with shape (end - start, len(material.state_vars)).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class ParticleState:
    p_x: np.ndarray
    p_v: np.ndarray
    p_mass: np.ndarray
    p_vol0: np.ndarray
    p_material: np.ndarray
    p_body: np.ndarray
    p_stress: np.ndarray
    p_x0: np.ndarray = None
    p_C: np.ndarray = None
    p_vol: np.ndarray = None
    p_rho: np.ndarray = None
    p_L: np.ndarray = None
    p_id: np.ndarray = None
    blocks: list = field(default_factory=list)
    p_state: list = field(default_factory=list)
    sort_work: np.ndarray | None = None  # (n, 3) work buffer of sort_by_cell, made at the first sort

    def __post_init__(self):
        n, d = self.p_x.shape
        if self.p_x0 is None:
            self.p_x0 = self.p_x.copy()
        if self.p_C is None:
            self.p_C = np.zeros((n, d, d), self.p_x.dtype)
        if self.p_vol is None:
            self.p_vol = self.p_vol0.copy()
        if self.p_rho is None:
            self.p_rho = self.p_mass / self.p_vol
        if self.p_L is None:
            self.p_L = np.zeros((n, 3, 3), self.p_x.dtype)
        if self.p_id is None:
            self.p_id = np.arange(n, dtype=np.int64)

    @property
    def n(self) -> int:
        return self.p_x.shape[0]

    @property
    def dim(self) -> int:
        return self.p_x.shape[1]

    def arrays(self) -> dict[str, np.ndarray]:
        """Every per-particle array by name (for writers and checkpoints)."""
        return {k: v for k, v in vars(self).items() if k.startswith("p_") and isinstance(v, np.ndarray)}

    def nbytes(self) -> int:
        work = 0 if self.sort_work is None else self.sort_work.nbytes
        return sum(a.nbytes for a in self.arrays().values()) + sum(s.nbytes for s in self.p_state) + work

    @property
    def dtype(self):
        """The floating-point type of the state (solver.precision)."""
        return self.p_x.dtype

    def set_precision(self, precision: str) -> None:
        """Store every floating-point array as ``precision`` ('float64' or 'float32'); a float32 state
        is computed in float64 registers by the kernels and rounded when stored."""
        dtype = np.dtype(precision)
        for name, arr in self.arrays().items():
            if arr.dtype.kind == "f" and arr.dtype != dtype:
                setattr(self, name, np.ascontiguousarray(arr, dtype=dtype))
        self.p_state = [np.ascontiguousarray(sv, dtype=dtype) for sv in self.p_state]

    def sort_by_cell(self, origin, h) -> None:
        """Re-order every material block by grid cell (kernels/sort.py); blocks keep their extent."""
        from geompm.kernels.sort import cell_order

        if self.n == 0:
            return
        self.reorder(np.concatenate([cell_order(self.p_x, origin, h, a, b) for a, b in self.blocks]))

    def reorder(self, perm: np.ndarray, skip=(), states: bool = True) -> None:
        """Put particle perm[k] at row k, for a permutation that keeps every index inside its material
        block (the sort, the benchmark's shuffle).  ``skip`` names arrays left as they are and
        ``states=False`` leaves the state variables (a backend that holds and sorts them itself)."""
        from geompm.kernels.sort import SLAB, permute_in_place

        perm = np.ascontiguousarray(perm, dtype=np.int64)
        # in place: every array keeps its identity, so a view or reference held across steps (a probe's
        # p_state column, a stage's reference) stays attached to the state
        work = self.sort_work
        if work is None or work.shape[0] < self.n:
            work = self.sort_work = np.empty((self.n, SLAB))
        for name, arr in self.arrays().items():
            if name not in skip:
                permute_in_place(arr, perm, work)
        for (a, b), sv in zip(self.blocks if states else (), self.p_state):
            if sv.size:
                permute_in_place(sv, np.ascontiguousarray(perm[a:b] - a), work)

    def remove(self, mask: np.ndarray) -> None:
        """Delete the particles where ``mask`` is true, keeping the blocks per material contiguous."""
        keep = ~np.asarray(mask, bool)
        for name, arr in self.arrays().items():
            setattr(self, name, np.ascontiguousarray(arr[keep]))
        blocks, states, start = [], [], 0
        for (a, b), sv in zip(self.blocks, self.p_state):
            k = keep[a:b]
            states.append(np.ascontiguousarray(sv[k]))
            blocks.append((start, start + int(k.sum())))
            start = blocks[-1][1]
        self.blocks, self.p_state = blocks, states
