"""Rigid wall on a face of the grid (``side`` x-, x+, y-, y+, z-, z+).

Acts on the nodes on and beyond the face (global index <= 0 for a '-' side,
>= ncells for a '+' side), with the unit normal pointing into the domain, by
the rule of contact/rules.py: ``fixed`` (no slip), ``slip`` (free to separate),
``friction`` (Coulomb, coefficient ``friction``) or ``roller`` (no normal motion either
way: a symmetry plane).  After G2P a particle that
ended beyond the face is put back on it.  A half-space (halfspace.py) through
the face, with a contact layer of h / 4 (the nodes lie on the face or whole
cells away from it); the backend visits only the slab of nodes on and beyond
the face (``node_box``).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from geompm.contact.voellmy_params import VoellmyParams
from geompm.contract.schedule import check_schedule
from geompm.contract.stages import FAR_NODE
from geompm.boundaries.halfspace import HalfSpace

SIDES = ("x-", "x+", "y-", "y+", "z-", "z+")


class WallParams(VoellmyParams):
    side: Literal["x-", "x+", "y-", "y+", "z-", "z+"] = Field(description="Face of the grid")
    condition: Literal["slip", "fixed", "friction", "roller", "voellmy"] = Field(
        "slip", description="Contact condition: 'slip' (free to separate), 'fixed' (no slip), 'friction' (Coulomb), "
        "'roller' (no normal motion either way, tangential free: a symmetry plane or a bonded smooth wall that "
        "holds tension), 'voellmy' (Coulomb 'friction' plus the turbulent term rho g u^2 / xi: contact/voellmy.py)")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (condition 'friction')")
    drainage: Literal["impermeable", "drained", "head"] = Field(
        "impermeable", description="For saturated soil (materials' pore_water): 'impermeable' (no water flows "
        "across), 'drained' (water leaves freely, p = 0 at the boundary) or 'head' (water flows freely across and "
        "the pore pressure at the boundary is the head's, rho_w |g| (H - z): groundwater fed from below or "
        "beside; docs/pore-water.md)")
    head: float | list[float] | None = Field(
        None, description="drainage 'head': the elevation H [m] of the water level that holds the pore pressure "
        "at the wall (along -gravity, in the case's coordinates), one value or one per head_times")
    head_times: list[float] = Field([0.0], min_length=1, max_length=1000,
                                    description="Times [s] of a head given as a list, non-decreasing; between two "
                                                "times H is linear")

    @model_validator(mode="after")
    def _head(self):
        if (self.drainage == "head") != (self.head is not None):
            raise ValueError("give 'head' [m] with drainage 'head', and only then")
        if isinstance(self.head, list):
            check_schedule(self.head_times, self.head, "head", "head")
        return self

    def head_schedule(self):
        """(times [s], heads [m]) of drainage 'head', None otherwise."""
        if self.head is None:
            return None
        if isinstance(self.head, list):
            return list(self.head_times), list(self.head)
        return [0.0], [float(self.head)]


class Wall(HalfSpace):
    name = "wall"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Rigid wall on a grid face: slip, fixed (no-slip) or Coulomb friction"
    Params = WallParams

    @classmethod
    def check(cls, params, case):
        if SIDES.index(params.side) // 2 >= case.dimension:
            return [("side", f"'{params.side}' does not exist in a {case.dimension}D case")]
        return []

    def setup(self, scene):
        super().setup(scene)
        axis = SIDES.index(self.params.side) // 2
        minus = self.params.side.endswith("-")
        n = int(scene.grid.ncells[axis])
        self.normal = np.zeros(scene.dim)
        self.normal[axis] = 1.0 if minus else -1.0
        self.point = scene.grid.origin.astype(float).copy()
        if not minus:
            self.point[axis] = scene.grid.upper[axis]
        self.layer = 0.25 * scene.grid.h
        self.first = np.full(scene.dim, -FAR_NODE, np.int64)
        self.last = np.full(scene.dim, FAR_NODE, np.int64)
        if minus:
            self.last[axis] = 0
        else:
            self.first[axis] = n
        self.pack_halfspace()

    def water_head(self):
        return self.params.head_schedule()

    def node_box(self, time):
        return self.first, self.last
