"""USL, update stress last: the explicit MPM step of a dry scene (docs/method.md).

    [spatial sort every solver.sort_interval steps] window -> the water table's pressure, if any
    -> P2G (mass, momentum, internal force) -> halo sum -> grid update (+ gravity)
    -> grid stages (loads, damping, boundaries, obstacles) in phase order
    -> G2P (velocity, affine matrix, position, velocity gradient, volume)
    -> particle stages (particle damping, penetration guard) -> stress update per material block

Sulsky, Chen & Schreyer (1994), Comput. Methods Appl. Mech. Engrg. 118:179.
"""

from __future__ import annotations

from geompm.schemes.base import Scheme


class Usl(Scheme):
    name = "usl"
    description = "update stress last (Sulsky, Chen & Schreyer 1994): the default explicit step"
    default = True
    passes = ("window", "load", "p2g", "grid_update_and_stages", "g2p_stages_and_stress_update")
