"""MUSL, modified update stress last (Sulsky, Zhou & Schreyer 1995, Comput. Phys. Commun. 87:236).

After the grid update and the grid stages the particle velocities are updated first, re-mapped to the
grid (P2G of momentum only, halo summed), the grid stages act again on the re-mapped velocities, and the
velocity gradient and positions come from them:

    window -> P2G -> grid update -> grid stages -> G2P (velocity only) -> P2G (momentum) -> velocity
    -> grid stages (remap) -> G2P (positions, gradient) -> particle stages -> stress update
"""

from __future__ import annotations

from geompm.schemes.base import Scheme


class Musl(Scheme):
    name = "musl"
    description = "modified update stress last (Sulsky, Zhou & Schreyer 1995): velocities re-mapped before the gradient"
    passes = ("window", "load", "p2g", "grid_update_and_stages", "g2p_velocity", "remap", "grid_stages_remapped",
              "g2p_move_stages_and_stress_update")

    def g2p_velocity(self, run, dt: float) -> None:
        """The particles' velocities from the updated grid, nothing moved yet."""
        run.backend.g2p(run.view, dt, set_velocity=True, move=False, gradient=False)

    def remap(self, run, dt: float) -> None:
        """The particles' momentum back onto the grid (halo summed) and the grid velocity from it."""
        be, view = run.backend, run.view
        be.p2g(view, 0.0)
        run.halo((view.g_mass, view.g_mom))
        be.remap_velocity(view)

    def grid_stages_remapped(self, run, dt: float) -> None:
        """The grid stages again, on the re-mapped velocities."""
        run.grid_stages_run(run.view, dt, remap=True)

    def g2p_move(self, run, dt: float) -> None:
        """Positions, velocity gradients and volumes from the re-mapped velocities."""
        run.backend.g2p(run.view, dt, set_velocity=False, move=True, gradient=True)

    def g2p_move_stages_and_stress_update(self, run, dt: float) -> None:
        """``g2p_move``, ``particle_stages`` and ``stress_update`` (one launch per material block on a device
        backend: ``g2p_stages_and_stress_update``)."""
        self._particle_step(run, dt, False)
