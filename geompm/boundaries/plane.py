"""Rigid plane at any orientation: an inclined bed or flume floor without tilting gravity.

The plane passes through ``point`` with unit ``normal`` pointing from the
plane into the material (the side where particles may be).  Every window node
whose signed distance (x_i - point) . n is <= ``contact_layer`` (0: on or
behind the plane) gets the contact rule of contact/rules.py (``slip``, ``fixed``, ``roller`` or
``friction`` with coefficient ``friction``).

``contact_layer`` > 0 also puts the nodes just in front of the plane in
contact.  With a layer of one cell a block at rest on the plane sticks down to
mu = 1.07 tan(theta) (tests/verification/test_boundaries.py); with 0 it needs about
mu = 1.18 tan(theta).  The price: a body arriving at the plane stops about one
cell earlier (closest approach of a dropped block: 1.2 cells with 0, 2.2 cells
with one cell), see docs/method.md, "Frictional contact".

After G2P a particle that still ended behind the plane is put back on it, so
none is ever deeper than round-off (the half-space of halfspace.py).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field, field_validator

from geompm.contact.voellmy_params import VoellmyParams
from geompm.contract.plugin import nonzero_vector, vector_length_problems
from geompm.boundaries.halfspace import HalfSpace


class PlaneParams(VoellmyParams):
    point: list[float] = Field(description="A point on the plane [m]")
    normal: list[float] = Field(description="Normal pointing from the plane into the material (any length)")
    condition: Literal["slip", "fixed", "friction", "roller", "voellmy"] = Field(
        "slip", description="Contact condition: 'slip' (free to separate), 'fixed' (no slip), 'friction' (Coulomb), "
        "'roller' (no normal motion either way, tangential free: a symmetry plane or a bonded smooth wall that "
        "holds tension), 'voellmy' (Coulomb 'friction' plus the turbulent term rho g u^2 / xi: contact/voellmy.py)")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (condition 'friction')")
    drainage: Literal["impermeable", "drained"] = Field(
        "impermeable", description="For saturated soil (materials' pore_water): 'impermeable' (no water flows "
        "across) or 'drained' (water leaves freely, p = 0 at the boundary; docs/pore-water.md)")
    contact_layer: float = Field(
        0.0, ge=0.0, description="Nodes with signed distance <= this [m] are in contact (0: on or behind)")

    _nonzero = field_validator("normal")(nonzero_vector)


class Plane(HalfSpace):
    name = "plane"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Rigid plane of any orientation (point, normal): slip, fixed or Coulomb friction"
    Params = PlaneParams

    @classmethod
    def check(cls, params, case):
        return vector_length_problems(params, case, ("point", "normal"))

    def setup(self, scene):
        super().setup(scene)
        n = np.asarray(self.params.normal, dtype=float)
        self.normal = n / np.linalg.norm(n)
        self.point = np.asarray(self.params.point, dtype=float)
        self.layer = self.params.contact_layer
        self.pack_halfspace()
