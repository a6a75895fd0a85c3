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

from geompm.mpm.grid import GridBuffers
from geompm.kernels.chunks import G2P_CHUNKS, g2p_chunks
from geompm.kernels.grid_update import grid_update, grid_update_folded, momentum_to_velocity
from geompm.kernels.stencil import scheme_tag, stencil_tag
from geompm.kernels.transfer2d import g2p_2d, p2g_2d
from geompm.kernels.transfer3d import g2p_3d, p2g_3d
from geompm.kernels.vectorised import Vectorised
from geompm.contract.stages import DRY_NODE, FAR_NODE, GridStage, ParticleStage
from geompm.backend.base import Backend, mass_floor, relaxed_materials
from geompm.backend.cpu_loops import update_law_block
from geompm.backend.cpu_loops import block_loops
from geompm.backend.cpu_stage_loops import merge_loop, node_loop, particle_loop
from geompm.backend.item_loops import each_loop
from geompm.kernels.phreatic import total_stress
from geompm.kernels.reduce import cell_bounds

#: the transfer kernels of each dimension, compiled with LLVM's SLP vectoriser (kernels/vectorised.py)
TRANSFERS = {2: (Vectorised(p2g_2d), Vectorised(g2p_2d)), 3: (Vectorised(p2g_3d), Vectorised(g2p_3d))}


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
        self.buffers = GridBuffers(scene.grid, nchunks, split_force, scene.state.dtype)
        self.mass_eps = mass_floor(scene)
        #: largest |L_ii| [1/s] of the last stress update (its by-product), None before the first step
        self.max_rate = None
        for mat in scene.materials:
            block_loops(type(mat))  # generate (or load) every law's and stage's loops before the first step
        #: per material: whether solver.viscoplastic_time regularises its law (it has an elastic predictor)
        self.relaxed = relaxed_materials(scene)
        self._old = {}  # per material block: the relaxation's scratch rows (stress and state at the step's start)
        self._every_node = (np.full(scene.dim, -FAR_NODE, np.int64), np.full(scene.dim, FAR_NODE, np.int64))
        #: per stage: its loops and its accumulator and scratch rows, made once
        self._plans = {id(s): self._plan(s) for s in scene.stages}
        #: G2P's per-chunk bounds of the moved particles, and their box (lo, hi) until the particle stages
        #: have used it (None: unknown)
        self._box_rows = np.zeros((G2P_CHUNKS, 2, 3))
        self.p_box = None
        #: the scheme's own passes on this backend (schemes/base.Scheme.backend_passes)
        self.scheme_passes = scene.scheme.backend_passes(self)
        #: the stress the grid sees: the particles' own, or a water table's total stress (set_table_pressure)
        self._acting_stress = self._own_stress
        self.p_table_pressure = None
        self._total = np.zeros((0, 6), self.state.dtype)

    def host_state(self):
        return self.state

    def nbytes(self) -> int:
        return self.state.nbytes() + self.buffers.nbytes() + self.scheme_passes.nbytes()

    def window(self):
        if self._held is not None:  # a held batch's window (Backend.window)
            return super().window()
        return self.buffers.window(self.state.p_x)

    def particle_cells(self):
        g = self.scene.grid
        return cell_bounds(self.state.p_x, g.origin, 1.0 / g.h) if self.state.n else None

    def window_at(self, lo, nloc):
        return self.buffers.view(lo, nloc)

    def p2g(self, view, f_scale: float) -> None:
        """P2G; the force enters scaled by f_scale (split: 1 or 0; folded: dt or 0)."""
        st, g = self.state, self.scene.grid
        g_force = view.g_force if self.split_force else view.g_mom  # not written when folded
        self.p2g_kernel(self.tag, self.scheme, st.p_x, st.p_v, st.p_C, st.p_mass, st.p_vol, self._acting_stress(),
                        g.origin, g.h, g.kind, view.lo, view.nloc, self.buffers.c_grid, self.split_force,
                        f_scale, self.scene.apic_dinv, view.g_mass, view.g_mom, g_force)

    def set_table_pressure(self, p_table_pressure) -> None:
        self.p_table_pressure = p_table_pressure
        self._acting_stress = self._table_stress

    def _own_stress(self):
        return self.state.p_stress

    def _table_stress(self):
        """sigma' - (V0 / V) p I under a water table (kernels/phreatic.py)."""
        st = self.state
        if self._total.shape != st.p_stress.shape or self._total.dtype != st.p_stress.dtype:
            self._total = np.zeros_like(st.p_stress)
        total_stress(st.p_stress, self.p_table_pressure, st.p_vol, st.p_vol0, self._total)
        return self._total

    def grid_update(self, view, dt: float) -> None:
        gravity = self.scene.gravity
        if self.split_force:
            grid_update(view.g_mass, view.g_mom, view.g_force, gravity, dt, self.mass_eps, view.g_vel,
                        view.g_vel_old)
        else:
            grid_update_folded(view.g_mass, view.g_mom, gravity, dt, self.mass_eps, view.g_vel)

    def remap_velocity(self, view) -> None:
        momentum_to_velocity(view.g_mass, view.g_mom, self.mass_eps, view.g_vel)

    def g2p(self, view, dt: float, *, set_velocity: bool, move: bool, gradient: bool) -> None:
        st, sc, g = self.state, self.scene, self.scene.grid
        g_vel_old = view.g_vel_old if self.split_force else view.g_vel  # read by FLIP only
        ratio = sc.flip_ratio if sc.flip_tau is None else math.exp(-dt / sc.flip_tau)
        self.g2p_kernel(self.tag, self.scheme, st.p_x, st.p_v, st.p_C, st.p_L, st.p_vol, st.p_rho, st.p_mass,
                        view.g_vel, g_vel_old, g.origin, g.h, g.kind, view.lo, view.nloc, dt, ratio,
                        sc.apic_dinv, set_velocity, move, gradient, self._box_rows)
        self.p_box = None
        if move and st.n:
            rows, d = self._box_rows[:g2p_chunks(st.n)], sc.dim  # the kernel's own chunk count
            self.p_box = (rows[:, 0, :d].min(axis=0), rows[:, 1, :d].max(axis=0))

    def update_stress(self, dt: float) -> None:
        st = self.state
        rate = 0.0
        for k, (mat, (s, e), sv) in enumerate(zip(self.scene.materials, st.blocks, st.p_state)):
            if e > s:
                relax = None
                if self.relaxed[k]:
                    old = self._old.get(k)
                    if old is None or old.shape != (e - s, 6 + sv.shape[1]):
                        old = self._old[k] = np.zeros((e - s, 6 + sv.shape[1]))
                    relax = (old, dt / self.scene.viscoplastic_time)
                rate = max(rate, update_law_block(mat, dt, st.p_L[s:e], st.p_rho[s:e], st.p_stress[s:e], sv, relax))
        self.max_rate = rate

    def each_in_turn(self, n: int, calls, moves: bool = True) -> None:
        if n > 0:
            each_loop(tuple(fn for fn, _ in calls))(n, *(a for _, args in calls for a in args))

    def sort_particles(self) -> None:
        self.state.sort_by_cell(self.scene.grid.origin, self.scene.grid.h)

    @staticmethod
    def _stage_loops(cls):
        """The loops of a stage class: {'grid': ..., 'particle': ...} for the passes it has."""
        out = {}
        if issubclass(cls, GridStage):
            if (cls.node_rule is None) == (cls.node_image is None):
                raise TypeError(f"stage '{cls.name}' must define exactly one of node_rule and node_image (contract/stages.py)")
            out["grid"] = node_loop(cls.node_rule) if cls.node_rule is not None else merge_loop(cls.node_image)
        if issubclass(cls, ParticleStage):
            if cls.particle_rule is None:
                raise TypeError(f"stage '{cls.name}' must define particle_rule (contract/stages.py)")
            out["particle"] = particle_loop(cls.particle_rule)
        return out

    def _plan(self, stage) -> dict:
        cls, nc, d = type(stage), self.buffers.nchunks, self.scene.dim
        plan = self._stage_loops(cls)
        if issubclass(cls, GridStage):
            plan["node_out"] = np.zeros((nc, max(stage.node_reduction, 1)))  # a stage may size it in setup
            plan["node_spill"] = np.zeros_like(plan["node_out"])  # the rows of nodes another rank counts
            plan["node_work"] = np.zeros((nc, d + cls.node_scratch))
        if issubclass(cls, ParticleStage):
            plan["particle_out"] = np.zeros((nc, max(stage.particle_reduction, 1)))
            plan["particle_work"] = np.zeros((nc, max(cls.particle_scratch, 1)))
        return plan

    def _plan_of(self, stage) -> dict:
        plan = self._plans.get(id(stage))
        if plan is None:  # a stage added after the backend was made (a probe's)
            plan = self._plans[id(stage)] = self._plan(stage)
        return plan

    def grid_stage(self, stage, view, dt: float, time: float, remap: bool) -> None:
        args = stage.grid_args(dt, time, remap)
        if args is None:
            return
        plan = self._plan_of(stage)
        loop = plan["grid"]
        v_old = view.g_vel_old if view.g_vel_old is not None else view.g_vel
        if type(stage).node_image is not None:
            loop(args[0], view.lo, view.nloc, view.g_mass, view.g_vel, v_old, view.g_vel_old is not None,
                 self.buffers.nchunks)
            return
        prm, aux = args
        f = view.g_force if view.g_force is not None else view.g_vel
        wet = view.g_pore is not None
        pore = view.g_pore if wet else DRY_NODE
        box = stage.node_box(time)
        first, last = self._every_node if box is None else box
        out = plan["node_out"]
        out.fill(0.0)
        g = self.scene.grid
        for f_box, l_box, counted in self.domain.node_parts(first, last):
            into = out if counted else plan["node_spill"]
            loop(prm, aux, dt, g.origin, g.h, view.lo, view.nloc, f_box, l_box, view.g_mass, view.g_vel, v_old,
                 f, pore, wet, plan["node_work"], into)
        stage.grid_reduced(self.joined(out, stage.node_reduction), dt, time, remap)

    def particle_stages(self, stages, dt: float, time: float) -> None:
        """Every particle stage in order.  After a G2P that moved the particles, a stage whose
        ``particle_reach`` says it cannot reach their box is not run: its reduction is zero rows; the
        box then follows what each stage that runs says of the particles after it."""
        box, self.p_box = self.p_box, None
        for stage in stages:
            args = stage.particle_args(dt, time)
            if args is None:
                continue
            if box is not None:
                reach = stage.particle_reach(args[0], *box)
                if reach is None:
                    out = self._plan_of(stage)["particle_out"]
                    out.fill(0.0)
                    stage.particle_reduced(self.joined(out, stage.particle_reduction), dt, time)
                    continue
                box = reach if np.isfinite(reach[0]).all() and np.isfinite(reach[1]).all() else None
            self._particle_pass(stage, args, dt, time)

    def particle_stage(self, stage, dt: float, time: float) -> None:
        args = stage.particle_args(dt, time)
        if args is not None:
            self._particle_pass(stage, args, dt, time)

    def _particle_pass(self, stage, args, dt: float, time: float) -> None:
        prm, aux = args
        plan = self._plan_of(stage)
        loop, out, work = plan["particle"], plan["particle_out"], plan["particle_work"]
        out.fill(0.0)
        st = self.state
        for k in stage.particle_blocks(len(st.blocks)):
            s, e = st.blocks[k]
            if e > s:
                loop(prm, aux, dt, k, s, e, st.p_x, st.p_x0, st.p_v, st.p_C, st.p_mass, st.p_stress, work, out)
        stage.particle_reduced(self.joined(out, stage.particle_reduction), dt, time)

