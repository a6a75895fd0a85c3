"""Weakly compressible Newtonian fluid.

    sigma = -P I + 2 mu (D - tr(D)/3 I)
    P = rho0 c^2 / r ((rho / rho0)^r - 1)        (Tait EOS, see tait.py)

mu dynamic viscosity [Pa s], D = sym(L) [1/s].  The stress is computed anew
from the current density and rate each step (no stress history), so it is
objective by construction.  Viscous time-step limit dt <= rho h^2 / (2 d mu).
"""

from __future__ import annotations

from numba import njit
from pydantic import Field

from geompm.materials.base import MaterialParams
from geompm.materials.fluid import set_fluid_stress
from geompm.contract.layout import param_layout
from geompm.materials.tait import EOS, TaitFluid, eos_pressure

#: packed parameters: EOS, dynamic viscosity mu [Pa s]
NEWTONIAN = param_layout(EOS, "viscosity")


class NewtonianParams(MaterialParams):
    viscosity: float = Field(ge=0, description="Dynamic viscosity mu [Pa s]")
    sound_speed: float = Field(gt=0, description="Artificial sound speed c of the Tait EOS [m/s]")
    eos_exponent: float = Field(7.0, ge=1.0, le=15.0, description="Exponent r of the Tait EOS [-]")


@njit(fastmath=True, cache=True)
def newtonian_stress(prm, dt, L, rho, s, state):
    """One particle's Newtonian stress -P(rho) I + 2 mu D'; s (6,) in place."""
    set_fluid_stress(s, L, eos_pressure(prm, rho), prm[NEWTONIAN.viscosity])


class Newtonian(TaitFluid):
    name = "newtonian"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Weakly compressible Newtonian fluid: Tait EOS pressure plus viscous stress"
    Params = NewtonianParams
    layout = NEWTONIAN
    particle_stress = newtonian_stress

    @classmethod
    def pack(cls, params):
        return cls.pack_eos(params, viscosity=params.viscosity)

    @classmethod
    def example_params(cls):
        return cls.Params(density=1000.0, viscosity=1.0e-3, sound_speed=35.0)

    def kinematic_viscosity(self) -> float:
        return float(self.params.viscosity / self.params.density)
