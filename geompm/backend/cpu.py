"""The CPU backend: numba kernels over numpy arrays, parallel over every core.

Its arrays are host arrays already, so ``host_state()`` is the particle state
itself.  The kernels: 2D or 3D P2G/G2P (kernels/transfer2d.py, transfer3d.py)
specialised at compile time on the stencil support and the transfer scheme
(kernels/stencil.py); the grid update (kernels/grid_update.py); one generated
loop per material law (backend/cpu_loops.py); the spatial sort
(kernels/sort.py); one generated loop per stage function (backend/cpu_stage_loops.py).
"""

from __future__ import annotations

import math

import numpy as np

from ..engine.grid import GridBuffers
from ..kernels.grid_update import grid_update, grid_update_folded, momentum_to_velocity
from ..kernels.stencil import scheme_tag, stencil_tag
from ..kernels.transfer2d import g2p_2d, p2g_2d
from ..kernels.transfer3d import g2p_3d, p2g_3d
from ..stages import GridStage, ParticleStage
from .base import Backend
from .cpu_loops import block_loops
from .cpu_stage_loops import merge_loop, node_loop, particle_loop

#: the transfer kernels of each dimension
TRANSFERS = {2: (p2g_2d, g2p_2d), 3: (p2g_3d, g2p_3d)}


class CpuBackend(Backend):
    name = "cpu"

    def __init__(self, scene, split_force: bool, nchunks: int | None = None):
        self.scene = scene
        self.state = scene.state
        self.split_force = split_force
        self.p2g_kernel, self.g2p_kernel = TRANSFERS[scene.dim]
        self.tag = stencil_tag(scene.grid.kind)
        self.scheme = scheme_tag(scene.transfer)
        self.flip = scene.transfer == "flip"
        self.buffers = GridBuffers(scene.grid, nchunks, split_force)
        self.mass_eps = 1e-9 * float(self.state.p_mass.min()) if self.state.n else 0.0
        #: largest |L_ii| [1/s] of the last stress update (its by-product), None before the first step
        self.max_rate = None
        for mat in scene.materials:
            block_loops(type(mat))  # generate (or load) every law's and stage's loops before the first step
        for stage in scene.boundaries + scene.damping + scene.obstacles:
            self._stage_loops(type(stage))

    def host_state(self):
        return self.state

    def nbytes(self) -> int:
        return self.state.nbytes() + self.buffers.nbytes()

    def window(self):
        return self.buffers.window(self.state.p_x)

    def p2g(self, view, f_scale: float) -> None:
        """P2G; the force enters scaled by f_scale (split: 1 or 0; folded: dt or 0)."""
        st, g = self.state, self.scene.grid
        g_force = view.g_force if self.split_force else view.g_mom  # not written when folded
        self.p2g_kernel(self.tag, self.scheme, st.p_x, st.p_v, st.p_C, st.p_mass, st.p_vol, st.p_stress,
                        g.origin, g.h, g.kind, view.lo, view.nloc, self.buffers.c_grid, self.split_force,
                        f_scale, self.scene.apic_dinv, view.g_mass, view.g_mom, g_force)

    def grid_update(self, view, dt: float) -> None:
        gravity = self.scene.gravity
        if self.split_force:
            grid_update(view.g_mass, view.g_mom, view.g_force, gravity, dt, self.mass_eps, view.g_vel,
                        view.g_vel_old)
        else:
            grid_update_folded(view.g_mass, view.g_mom, gravity, dt, self.mass_eps, view.g_vel)

    def remap_velocity(self, view) -> None:
        momentum_to_velocity(view.g_mass, view.g_mom, self.mass_eps, view.g_vel)

    def g2p(self, view, dt: float, set_velocity: bool, move: bool, gradient: bool) -> None:
        st, sc, g = self.state, self.scene, self.scene.grid
        g_vel_old = view.g_vel_old if self.split_force else view.g_vel  # read by FLIP only
        ratio = sc.flip_ratio if sc.flip_tau is None else math.exp(-dt / sc.flip_tau)
        self.g2p_kernel(self.tag, self.scheme, st.p_x, st.p_v, st.p_C, st.p_L, st.p_vol, st.p_rho, st.p_mass,
                        view.g_vel, g_vel_old, g.origin, g.h, g.kind, view.lo, view.nloc, dt, ratio,
                        sc.apic_dinv, set_velocity, move, gradient)

    def update_stress(self, dt: float) -> None:
        st = self.state
        rate = 0.0
        for mat, (s, e), sv in zip(self.scene.materials, st.blocks, st.p_state):
            if e > s:
                rate = max(rate, mat.update_stress(dt, st.p_L[s:e], st.p_rho[s:e], st.p_stress[s:e], sv))
        self.max_rate = rate

    def sort_particles(self) -> None:
        self.state.sort_by_cell(self.scene.grid.origin, self.scene.grid.h)

    @staticmethod
    def _stage_loops(cls):
        """The loops of a stage class: {'grid': ..., 'particle': ...} for the passes it has."""
        out = {}
        if issubclass(cls, GridStage):
            if (cls.node_rule is None) == (cls.node_image is None):
                raise TypeError(f"stage '{cls.name}' must define exactly one of node_rule and node_image (stages.py)")
            out["grid"] = node_loop(cls.node_rule) if cls.node_rule is not None else merge_loop(cls.node_image)
        if issubclass(cls, ParticleStage):
            if cls.particle_rule is None:
                raise TypeError(f"stage '{cls.name}' must define particle_rule (stages.py)")
            out["particle"] = particle_loop(cls.particle_rule)
        return out

    def _rows(self, width: int) -> np.ndarray:
        return np.zeros((self.buffers.nchunks, max(width, 1)))

    def grid_stage(self, stage, view, dt: float, time: float, remap: bool) -> None:
        args = stage.grid_args(dt, time, remap)
        if args is None:
            return
        cls = type(stage)
        loop = self._stage_loops(cls)["grid"]
        v_old = view.g_vel_old if view.g_vel_old is not None else view.g_vel
        if cls.node_image is not None:
            loop(args[0], view.lo, view.nloc, view.g_mass, view.g_vel, v_old, view.g_vel_old is not None,
                 self.buffers.nchunks)
            return
        prm, aux = args
        f = view.g_force if view.g_force is not None else view.g_vel
        b0, bn = _window_box(stage.node_box(time), view)
        out = self._rows(cls.node_reduction)
        g = self.scene.grid
        loop(prm, aux, dt, g.origin, g.h, view.lo, view.nloc, b0, bn, view.g_mass, view.g_vel, v_old, f,
             self._rows(self.scene.dim + cls.node_scratch), out)
        stage.grid_reduced(out, dt, time, remap)

    def particle_stage(self, stage, dt: float, time: float) -> None:
        args = stage.particle_args(dt, time)
        if args is None:
            return
        prm, aux = args
        cls = type(stage)
        loop = self._stage_loops(cls)["particle"]
        st = self.state
        out = self._rows(cls.particle_reduction)
        work = self._rows(cls.particle_scratch)
        for k in stage.particle_blocks(len(st.blocks)):
            s, e = st.blocks[k]
            if e > s:
                loop(prm, aux, dt, k, s, e, st.p_x, st.p_x0, st.p_v, st.p_C, st.p_mass, st.p_stress, work, out)
        stage.particle_reduced(out, dt, time)


def _window_box(box, view):
    """A stage's global node box as (first window index, extent) per axis, clipped to the window."""
    if box is None:
        return np.zeros_like(view.lo), view.nloc.copy()
    first, last = box
    b0 = np.clip(np.asarray(first, np.int64) - view.lo, 0, view.nloc)
    b1 = np.clip(np.asarray(last, np.int64) - view.lo + 1, 0, view.nloc)
    return b0, np.maximum(b1 - b0, 0)
