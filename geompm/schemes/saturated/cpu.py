"""The saturated scheme's passes on the CPU backend: host arrays, and the scatters into private grids per
chunk of particles (schemes/saturated/cpu_scatter.py) with the solid's P2G the dry kernel's on the total
stress.  The pass order and every other pass: schemes/saturated/passes.py.
"""

from __future__ import annotations

import numpy as np

from geompm.schemes.saturated import cpu_scatter
from geompm.schemes.saturated.passes import SaturatedPasses
from geompm.schemes.saturated.kernels import WATER_WIDTH


class SaturatedCpu(SaturatedPasses):
    def __init__(self, cpu, water):
        self.nchunks = cpu.buffers.nchunks
        super().__init__(cpu, water)

    def _zeros(self, shape):
        return np.zeros(shape)

    def _on_device(self, array):
        return np.ascontiguousarray(array, dtype=np.float64)

    def _on_device_int(self, array):
        return np.ascontiguousarray(array, dtype=np.int64)

    def _grid(self, cap):
        super()._grid(cap)
        self.c_w = np.zeros((self.nchunks, cap, WATER_WIDTH))  # the scatters' private grids, one per chunk

    def _arrays(self):
        return super()._arrays() + (self.c_w,)

    def particles(self):
        return self.be.state

    def window_index(self, view):
        return view.lo, view.nloc

    def _scatter(self, view, lo, nloc, P) -> None:
        cpu, g, nn = self.be, self.scene.grid, view.g_mass.shape[0]
        cpu.p2g_kernel(cpu.tag, cpu.scheme, P.p_x, P.p_v, P.p_C, P.p_mass, P.p_vol, self.p_total, g.origin, g.h,
                       g.kind, lo, nloc, cpu.buffers.c_grid, True, 1.0, self.scene.apic_dinv, view.g_mass,
                       view.g_mom, view.g_force)
        cpu_scatter.water_p2g(cpu.tag, P.p_x, P.p_vw, P.p_Cw, self.affine, self.p_wmass, self.p_drag, P.p_vol, P.p_n,
                              P.p_pore, P.p_sat, P.p_material, self.table, self.p_total, g.origin, g.h, g.kind, lo, nloc,
                              self.c_w[:, :nn], self.g_w[:nn])
        cpu_scatter.sum_chunks(self.c_w[:, :nn], self.g_w[:nn])

    def _smooth_scatter(self, view, lo, nloc, P, p_val) -> None:
        g, nn = self.scene.grid, view.g_mass.shape[0]
        cpu_scatter.smooth_scatter(self.be.tag, P.p_x, p_val, P.p_drained, P.p_vol, g.origin, g.h, g.kind, lo, nloc,
                                   self.c_w[:, :nn], self.g_vp[:nn])
