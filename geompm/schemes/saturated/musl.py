"""Saturated soil in MUSL order (Sulsky, Zhou & Schreyer 1995, Comput. Phys. Commun. 87:236; the two-phase
form: both phases' momenta re-mapped before the gradients, as in Bandara & Soga 2015, Computers and
Geotechnics 63:199).  docs/pore-water.md, MUSL.

The saturated step (scheme.py) up to the split, then:

    -> water G2P (velocity, affine matrix) -> solid G2P (velocity only)
    -> remap: both phases' momenta P2G, halo summed, the mixture and the relative velocity,
       BOUNDARY and OBSTACLE stages again (remap), split again (walls' water rules, nothing advanced)
    -> pressure step from the divergences of the re-mapped velocities
    -> solid G2P (positions, velocity gradient, volume) -> particle stages -> porosity -> stress update
"""

from __future__ import annotations

import math

from geompm.contract.stages import BOUNDARY
from geompm.schemes.musl import Musl
from geompm.schemes.saturated.scheme import Saturated


class SaturatedMusl(Saturated):
    name = "saturated_musl"
    description = "saturated soil in MUSL order: both phases re-mapped before the gradients (docs/pore-water.md)"
    default = False
    passes = ("window", "two_phase_p2g", "grid_update", "loads_and_damping", "relative_velocity", "contacts",
              "split", "water_velocity", "g2p_velocity", "remap", "pressure_step", "g2p_move_stages_and_stress_update")

    g2p_velocity = Musl.g2p_velocity
    g2p_move_stages_and_stress_update = Musl.g2p_move_stages_and_stress_update

    def water_velocity(self, run, dt: float) -> None:
        """The water's particle velocity and affine matrix from the updated grid."""
        run.backend.scheme_passes.water_velocity(run.view, dt)

    def remap(self, run, dt: float) -> None:
        """Both phases' momenta back onto the grid, the boundaries and obstacles again, the phases split."""
        def stages():
            run.grid_stages_run(run.view, dt, remap=True, phases=(BOUNDARY, math.inf))

        run.backend.scheme_passes.remap(run.view, run.halo, stages)

    def pressure_step(self, run, dt: float) -> None:
        """The pore pressure's step from the re-mapped velocities' divergences."""
        run.backend.scheme_passes.pressure_step(run.view, dt, run.halo)
