"""MUSL, modified update stress last (Sulsky, Zhou & Schreyer 1995, Comput. Phys. Commun. 87:236).

After the grid update and the grid stages the particle velocities are updated first, re-mapped to the
grid (P2G of momentum only, halo summed), the grid stages act again on the re-mapped velocities, and the
velocity gradient and positions come from them:

    P2G -> grid update -> grid stages -> G2P (velocity only) -> P2G (momentum) -> velocity
    -> grid stages (remap) -> G2P (positions, gradient) -> particle stages -> stress update
"""

from __future__ import annotations

from geompm.schemes.base import Scheme


class Musl(Scheme):
    name = "musl"
    description = "modified update stress last (Sulsky, Zhou & Schreyer 1995): velocities re-mapped before the gradient"

    def step(self, run, dt: float) -> None:
        be = run.backend
        view = run.begin(dt)
        be.g2p(view, dt, set_velocity=True, move=False, gradient=False)
        be.p2g(view, 0.0)
        run.domain.sum_halo(view, (view.g_mass, view.g_mom))
        be.remap_velocity(view)
        run.grid_stages_run(view, dt, remap=True)
        be.g2p(view, dt, set_velocity=False, move=True, gradient=True)
        run.end(view, dt)
