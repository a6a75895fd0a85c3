"""The material plugin shape.

A material is a ``Plugin`` with:

- ``Params``: pydantic model of its parameters (SI units, bounds as validators);
- ``state_vars``: names of its per-particle state variables (``p_state (n, k)``);
- ``layout``: the names of its packed parameters (contract/layout.py), read in the kernels as
  ``prm[LAYOUT.name]``;
- ``pack(params) -> dict``: those parameters by name (SI units), derived from ``Params``;
- ``particle_stress(prm, dt, L, rho, s, state)``: an ``@njit`` function (no explicit
  signature) that updates ONE particle's Cauchy stress ``s (6,)`` (Voigt, tension
  positive) [Pa] and state ``state (k,)`` in place, from its velocity gradient
  ``L (3, 3)`` [1/s] and current density ``rho`` [kg/m3].  It allocates nothing,
  calls no LAPACK and touches no Python object, so numba inlines it into the
  backend's loop over the block (backend/cpu_loops.py) and a GPU compiler can take
  it as a device function;
- ``particle_wave_speed(prm, rho) -> float``: an ``@njit`` function, the speed [m/s]
  at which information travels through a particle of density ``rho`` (elastic P-wave
  or acoustic), for the CFL step.  It must be monotone in ``rho``: the backend
  evaluates it at the block's lowest and highest density and takes the larger;
- ``kinematic_viscosity()``: the largest mu/rho [m2/s], for the viscous step limit
  dt <= h^2 / (2 d nu) (zero for rate-independent laws);
- ``k0()``: the at-rest earth pressure coefficient sigma_h / sigma_v used for
  geostatic initial stress;
- ``stiffness()``: the modulus E [Pa] used by artificial damping, zeta = xi/h sqrt(E/rho).

Particles are sorted by material; the backend runs one compiled loop per
material block: no per-particle dispatch, and the law never owns a loop.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from pydantic import Field

from geompm.contract.plugin import Params, Plugin
from geompm.contract.layout import pack_in_layout, param_layout
from geompm.materials.plausible import DENSITY


class MaterialParams(Params):
    density: float = Field(gt=0, description="Initial (reference) mass density rho0 [kg/m3]")

    def with_porosity(self, porosity: float):
        """The parameters a saturated material's law runs with, its pores holding water at the initial
        ``porosity``: ``density`` (the grain density rho_s) becomes the skeleton's dry density
        (1 - n0) rho_s, the solids' mass per volume its particles carry.  A law with a state tied to the
        porosity sets it too (critical_state_sand.py)."""
        return self.model_copy(update={"density": (1.0 - porosity) * self.density})

    def saturation_checks(self, porosity: float | None) -> tuple[list, list]:
        """(problems, warnings), each a list of (field, sentence), for the parameters against the material's
        pore water (``porosity`` n0, None for a dry material): the case check refuses the problems and warns
        the warnings, named ``materials.<name>.<field>``."""
        return [], []


class Material(Plugin):
    Params: ClassVar[type[MaterialParams]] = MaterialParams
    state_vars: ClassVar[tuple[str, ...]] = ()
    #: a fluid has no grain skeleton: it cannot carry pore water (schema/pore_water.py refuses the pair)
    fluid: ClassVar[bool] = False
    #: whether stress depends on the deformation rate (then stress can change at zero L)
    rate_dependent: ClassVar[bool] = False
    #: whether the law has a shear strength that `geompm stability` divides by a factor F (strength_reduced)
    strength_reduction: ClassVar[bool] = False

    #: the backends whose compilation of particle_stress has been checked (geompm plugins lists them;
    #: a case on another backend is refused): a law in the CUDA subset (math.* not np.* on scalars, no
    #: array creation, no np.linalg, no Python objects), checked against the CPU under numba-cuda's
    #: simulator (tests/cuda/cuda_parity.py) and compiled for a GPU (tests/cuda/cuda_compile.py), may add "cuda"
    backends: ClassVar[tuple[str, ...]] = ("cpu",)
    #: names of the packed parameters (contract/layout.py)
    layout: ClassVar = param_layout("density")
    #: parameter ranges outside which a value looks like a wrong unit (plausible.py): warned, never refused
    plausible: ClassVar[tuple] = (DENSITY,)
    #: the per-particle @njit functions (module docstring)
    particle_stress: ClassVar = None
    particle_wave_speed: ClassVar = None
    #: the law's elastic predictor, an @njit ``(prm, dt, L, rho, s) -> Voigt 6-tuple`` (the stress the law
    #: would reach if the step stayed elastic), or None: a law that gives it is regularised by
    #: ``solver.viscoplastic_time`` (kernels/viscoplastic.py); one without runs inviscid
    elastic_predictor: ClassVar = None

    def __init__(self, params):
        self.params = params
        self.prm = pack_in_layout(self.layout, self.pack(params), f"material '{self.name}'")

    # -- to be provided by each law -------------------------------------------------
    @classmethod
    def pack(cls, params) -> dict:
        """The kernel parameters by layout name, computed from the validated ``params``."""
        raise NotImplementedError

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

    def alternatives(self) -> list[tuple[str, "Material"]]:
        """The same law under another integration, as (the JSON setting that selects it, the law so
        set): `geompm validate` reports the time step each would take (engine/estimate.py).  None (an
        empty list) by default; the yield-stress fluids offer the other of explicit and elasto-viscoplastic."""
        return []

    @classmethod
    def at_cell_size(cls, params, cell_size: float):
        """The parameters the law runs with on cells of ``cell_size`` [m]: ``params`` unchanged, except for a
        law regularised by the cell size (a softening law's strain thresholds, softening.py).  setup calls
        it before the law is made, so the packed parameters hold the scaled values."""
        return params

    @classmethod
    def strength_reduced(cls, params, factor: float) -> dict:
        """The parameters (by name, as the case's JSON spells them) that give the law's shear strength
        divided by ``factor`` (docs/slope-stability.md); only a law that sets ``strength_reduction``."""
        raise NotImplementedError(f"material '{cls.name}' has no strength to reduce")

    def warnings(self) -> list[str]:
        """What `geompm validate` and `geompm run` should warn about this law's parameters, each a
        full sentence (the caller names the material's JSON path)."""
        return []

    # -- used by the engine ------------------------------------------------------------
    @property
    def density(self) -> float:
        return float(self.params.density)

    def initial_stress_checks(self, stress: np.ndarray) -> tuple[list, list]:
        """(problems, warnings), each a list of (parameter, sentence), for the law's block of particles at their
        initial effective stress ``stress`` (n, 6) [Pa]: a law whose state follows from the stress (a
        preconsolidation pressure, modified_cam_clay.py) says here what would start outside its range.  The
        assembly refuses the problems and warns the warnings, named ``materials.<name>.<parameter>``, before
        any step; a law may also set stress-dependent packed parameters here (its wave speed's stress)."""
        return [], []

    def initial_state(self, n: int) -> np.ndarray:
        return np.zeros((n, len(self.state_vars)))

