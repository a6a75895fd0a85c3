"""The explicit MPM step: a fixed sequence of kernels plus the case's stages.

USL (update stress last), one step:
    P2G (mass, momentum, internal force) -> grid update (+ gravity)
    -> grid stages (boundaries, obstacles, grid damping)
    -> G2P (velocity, affine matrix, position, velocity gradient, F, volume)
    -> particle stages (particle damping) -> stress update per material block
MUSL (Sulsky, Zhou & Schreyer 1995): after the grid update, particle
velocities are updated first, re-mapped to the grid, the grid stages are
applied again, and the velocity gradient and positions come from the
re-mapped velocities.

Only the stages the case asks for are in the lists; a case without damping
has no damping pass.
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels.grid_update import grid_update, grid_update_folded, momentum_to_velocity
from ..kernels.reduce import kinetic_energy, max_coordinate
from ..kernels.transfer2d import g2p_2d, p2g_2d
from ..kernels.stencil import stencil_tag
from ..kernels.transfer3d import g2p_3d, p2g_3d
from ..stages import GridStage, ParticleStage
from .grid import GridBuffers
from .timestep import stable_dt

#: the transfer kernels of each dimension: 2D cases run 2D kernels (kernels/transfer.py is the
#: dimension-generic reference they are tested against)
TRANSFERS = {2: (p2g_2d, g2p_2d), 3: (p2g_3d, g2p_3d)}


#: transfer modes (assemble.TRANSFER_MODE): FLIP needs the pre-update grid velocity; MLS
#: takes its force and velocity gradient from the APIC inertia D (kernels/stencil.py)
FLIP_MODE, MLS_MODE = 2, 3


class Simulation:
    def __init__(self, scene, nchunks: int | None = None):
        self.scene = scene
        self.state = scene.state
        self.p2g, self.g2p = TRANSFERS[scene.dim]
        self.tag = stencil_tag(scene.grid.kind)
        # periodic folding first (it merges ghost nodes), then damping; boundaries and obstacles
        # must have the last word on grid velocities
        periodic = [b for b in scene.boundaries if getattr(b, "merges_nodes", False)]
        others = [b for b in scene.boundaries if not getattr(b, "merges_nodes", False)]
        stages = periodic + scene.damping + others + scene.obstacles
        self.grid_stages = [s for s in stages if isinstance(s, GridStage)]
        self.particle_stages = [s for s in stages if isinstance(s, ParticleStage)]
        # the nodal force and pre-update velocity are kept apart only when something reads them
        self.split_force = scene.transfer_mode == FLIP_MODE or any(
            s.needs_split_force for s in self.grid_stages)
        self.buffers = GridBuffers(scene.grid, nchunks, self.split_force)
        self.mls_dinv = scene.apic_dinv if scene.transfer_mode == MLS_MODE else 0.0
        self.mass_eps = 1e-9 * float(self.state.p_mass.min())
        self.time = 0.0
        self.step_count = 0
        self.dt = 0.0
        self.view = None

    def stable_dt(self) -> float:
        return stable_dt(self.scene, self.state)

    def _g2p(self, view, dt, set_velocity, move, gradient):
        st, sc, g = self.state, self.scene, self.scene.grid
        g_vel_old = view.g_vel_old if self.split_force else view.g_vel  # read by FLIP only
        ratio = sc.flip_ratio if sc.flip_tau is None else math.exp(-dt / sc.flip_tau)
        self.g2p(self.tag, st.p_x, st.p_v, st.p_C, st.p_L, st.p_vol, st.p_rho, st.p_mass,
            view.g_vel, g_vel_old, g.origin, g.h, g.kind, view.lo, view.nloc, dt,
            sc.transfer_mode, ratio, sc.apic_dinv, set_velocity, move, gradient)

    def _p2g(self, view, f_scale):
        """P2G; the force enters scaled by f_scale (split: 1 or 0; folded: dt or 0)."""
        st, g, b = self.state, self.scene.grid, self.buffers
        g_force = view.g_force if self.split_force else view.g_mom  # not written when folded
        self.p2g(self.tag, st.p_x, st.p_v, st.p_C, st.p_mass, st.p_vol, st.p_stress, g.origin,
            g.h, g.kind, view.lo, view.nloc, b.c_grid, self.split_force, f_scale, self.mls_dinv,
            view.g_mass, view.g_mom, g_force)

    def step(self, dt: float) -> None:
        st, sc = self.state, self.scene
        view = self.buffers.window(st.p_x)
        if self.split_force:
            self._p2g(view, 1.0)
            grid_update(view.g_mass, view.g_mom, view.g_force, sc.gravity, dt, self.mass_eps,
                        view.g_vel, view.g_vel_old)
        else:
            self._p2g(view, dt)
            grid_update_folded(view.g_mass, view.g_mom, sc.gravity, dt, self.mass_eps, view.g_vel)
        for stage in self.grid_stages:
            stage.apply_grid(view, dt, self.time, False)
        if sc.musl:
            self._g2p(view, dt, True, False, False)
            self._p2g(view, 0.0)
            momentum_to_velocity(view.g_mass, view.g_mom, self.mass_eps, view.g_vel)
            for stage in self.grid_stages:
                stage.apply_grid(view, dt, self.time, True)
            self._g2p(view, dt, False, True, True)
        else:
            self._g2p(view, dt, True, True, True)
        for stage in self.particle_stages:
            stage.apply_particles(st, dt, self.time)
        for mat, (s, e), sv in zip(sc.materials, st.blocks, st.p_state):
            if e > s:
                mat.update_stress(dt, st.p_L[s:e], st.p_rho[s:e], st.p_stress[s:e], sv)
        self.view = view
        self.dt = dt
        self.time += dt
        self.step_count += 1

    def series_row(self) -> dict[str, float]:
        """The quantities of one series.csv row at the current state."""
        st = self.state
        row = {
            "time": self.time,
            "step": self.step_count,
            "dt": self.dt,
            "kinetic_energy": kinetic_energy(st.p_mass, st.p_v),
            "front_x": max_coordinate(st.p_x, 0),
        }
        for stage in self.grid_stages + self.particle_stages:
            row.update(stage.series())
        return row

    def total_momentum(self) -> np.ndarray:
        return (self.state.p_mass[:, None] * self.state.p_v).sum(axis=0)
