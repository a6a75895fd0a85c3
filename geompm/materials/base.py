"""The material plugin shape.

A material is a ``Plugin`` with:

- ``Params``: pydantic model of its parameters (SI units, bounds as validators);
- ``state_vars``: names of its per-particle state variables (``p_state (n, k)``);
- ``pack(params) -> float64[:]``: the parameters as a flat array for the kernels;
- ``stress_kernel(prm, dt, p_L, p_rho, p_stress, p_state)``: a numba function that
  updates the stress of a contiguous block of particles in place, given the
  velocity gradient ``p_L (n, 3, 3)`` [1/s] and current density ``p_rho (n,)``;
- ``wave_speed_kernel(prm, p_rho) -> float``: the largest speed [m/s] at which
  information travels in the block (elastic P-wave or acoustic), for the CFL step;
- ``kinematic_viscosity()``: the largest mu/rho [m2/s], for the viscous step limit
  dt <= h^2 / (2 d nu) (zero for rate-independent laws);
- ``k0()``: the at-rest earth pressure coefficient sigma_h / sigma_v used for
  geostatic initial stress;
- ``stiffness()``: the modulus E [Pa] used by artificial damping, zeta = xi/h sqrt(E/rho).

The scheduler sorts particles by material and calls ``update_stress`` once per
material block: one compiled loop per law, no per-particle dispatch.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from pydantic import Field

from ..plugin import Params, Plugin


class MaterialParams(Params):
    density: float = Field(gt=0, description="Initial (reference) mass density rho0 [kg/m3]")


class Material(Plugin):
    Params: ClassVar[type[MaterialParams]] = MaterialParams
    state_vars: ClassVar[tuple[str, ...]] = ()
    #: whether stress depends on the deformation rate (then stress can change at zero L)
    rate_dependent: ClassVar[bool] = False

    def __init__(self, params):
        self.params = params
        self.prm = np.ascontiguousarray(self.pack(params), dtype=np.float64)

    # -- to be provided by each law -------------------------------------------------
    @classmethod
    def pack(cls, params) -> np.ndarray:
        raise NotImplementedError

    stress_kernel = None
    wave_speed_kernel = None

    @classmethod
    def example_params(cls):
        """A representative, valid parameter set: the conformance suite runs the law with it."""
        raise NotImplementedError(f"material '{cls.name}' must define example_params() for geompm.testing")

    def k0(self) -> float:
        raise NotImplementedError(f"material '{self.name}' defines no K0 for geostatic stress")

    def stiffness(self) -> float:
        raise NotImplementedError

    def kinematic_viscosity(self) -> float:
        return 0.0

    def warnings(self) -> list[str]:
        """What `geompm validate` and `geompm run` should warn about this law's parameters, each a
        full sentence (the caller names the material's JSON path)."""
        return []

    # -- used by the engine ------------------------------------------------------------
    @property
    def density(self) -> float:
        return float(self.params.density)

    def initial_state(self, n: int) -> np.ndarray:
        return np.zeros((n, len(self.state_vars)))

    def update_stress(self, dt, p_L, p_rho, p_stress, p_state) -> None:
        type(self).stress_kernel(self.prm, dt, p_L, p_rho, p_stress, p_state)

    def wave_speed(self, p_rho) -> float:
        return float(type(self).wave_speed_kernel(self.prm, p_rho))
