"""Saturated soil at the skeleton's time step: the two-phase step with the pore pressure implicit
(docs/pore-water.md, The semi-implicit step; the equations: projection.py).

The explicit step (scheme.py) is bounded by the undrained wave, sqrt((M + K_w/n) / rho_sat), about 1 500 m/s
with water's real bulk modulus.  Here the pressure's increment over the step solves one sparse symmetric
system on the grid's nodes (a pressure Poisson equation, incremental projection: Chorin 1968; the two-phase
form of Kularathna et al. 2021, IJNME 122:1277), so the step is bounded by the skeleton's own wave (the law's
speed at the dry density) and the flow: water may be incompressible (``fluid.bulk_modulus:
"incompressible"``).

    window -> p2g (the acting pressure p^n, total stress, both phases, fill, mixture) -> grid update
    -> stages before BOUNDARY -> relative velocity (drag implicit) -> BOUNDARY and OBSTACLE stages
    -> split -> project (the pressure's increment solved, both phases corrected, the stages again on the
    corrected mixture, split again) -> water G2P (velocity; the increment added to the pressure)
    -> solid G2P -> particle stages -> porosity -> effective-stress update

CPU and one process only: the solve is a scipy/pyamg solve of the whole window (docs/pore-water.md says why
the CUDA backend and MPI ranks refuse it).
"""

from __future__ import annotations

import math

from geompm.contract.stages import BOUNDARY
from geompm.kernels.shape import support
from geompm.schemes.saturated.scheme import Saturated


class SaturatedSemiImplicit(Saturated):
    name = "saturated_semi_implicit"
    description = ("saturated soil with the pore pressure implicit: the step of the skeleton, water's real or "
                   "infinite bulk modulus (docs/pore-water.md)")
    default = False
    splits_over_ranks = False
    incompressible_water = True
    #: the CPU's passes only (scipy and pyamg on the host)
    backend_modules = {"cpu": ("geompm.schemes.saturated.semi_implicit_cpu", "SemiImplicitCpu")}
    passes = ("window", "two_phase_p2g", "grid_update", "loads_and_damping", "relative_velocity", "contacts",
              "split", "project", "water_step", "g2p", "affine_flux", "particle_stages", "porosity", "stress_update")

    @classmethod
    def problems(cls, case, loaded):
        out = super().problems(case, loaded)
        if case.solver.backend not in cls.backend_modules:
            out.append(("solver.backend", f"the semi-implicit two-phase step runs on the CPU backend only (its "
                                          "pressure solve is scipy and pyamg on the host); use \"cpu\", or the "
                                          "explicit 'saturated' scheme on a GPU (docs/pore-water.md)"))
        return out

    @classmethod
    def warnings(cls, case):
        from geompm.schemes.saturated.checks import semi_implicit_warnings

        return semi_implicit_warnings(case)

    @classmethod
    def node_bytes(cls, dim: int, kind: int) -> int:
        """The pressure system per window node: the band of (2S - 1)^d coefficients (8 bytes each), the CSR
        rows (12 bytes per coefficient, at most the band's) and the smoothed-aggregation hierarchy (taken as the
        matrix again: operator complexity 1.04 measured, its prolongators besides; benchmarks/results/
        2026-12-05-issue53), plus ten nodal scalars; S = 2 / 3 / 4 for linear / quadratic / cubic shape functions."""
        width = (2 * support(kind) - 1) ** dim
        return 8 * width + 2 * 12 * width + 80

    def __init__(self, case=None, names=()):
        super().__init__(case, names)
        if self.water is not None:
            self.water.pressure_solver = case.solver.pressure_solver

    def after_stages(self, scene) -> None:
        from geompm.errors import CaseError

        super().after_stages(scene)
        periodic = [s.label for s in scene.stages if s.periodic_axes()]
        if periodic:
            raise CaseError([("boundaries", f"the periodic boundary '{periodic[0]}' is not supported by the "
                                            "semi-implicit two-phase step (its pressure system does not fold "
                                            "over the periodic images); use solver.update \"saturated\"")])

    def project(self, run, dt: float) -> None:
        """The pressure's increment solved on the grid, both phases corrected, the boundaries and obstacles
        once more on the corrected mixture, the phases split again."""
        def stages():
            run.grid_stages_run(run.view, dt, remap=True, phases=(BOUNDARY, math.inf))

        where = f"step {run.step_count + 1} (t = {run.time:.6g} s)"
        run.backend.scheme_passes.project(run.view, dt, stages, where)

    def water_step(self, run, dt: float) -> None:
        """The water's particle velocity from the corrected grid; the increment added to the pore pressure."""
        run.backend.scheme_passes.water_step(run.view, dt)

    def affine_flux(self, run, dt: float) -> None:
        """APIC: the flux divergence the particles' affine matrices carry taken off them
        (projection.affine_flux_one); nothing for the other transfers."""
        run.backend.scheme_passes.affine_flux()

    def wave_speed(self, scene, state, finite_only: bool = False, comm=None) -> float:
        """The skeleton's wave (the law's speed at the dry density), plus how much faster than the solid the
        water flows: the step's CFL adds the solid's speed (backend/timestep.py)."""
        from geompm.kernels.reduce import max_speed
        from geompm.schemes.saturated.speeds import skeleton_speeds

        skeleton, flow = skeleton_speeds(scene, state, self.water)
        solid = max_speed(state.p_v) if state.n else 0.0
        return skeleton + max(flow - solid, 0.0)

    def series(self, run) -> dict[str, float]:
        """The explicit scheme's series, and the last solve's ``pressure_iterations``, its relative residual
        ``pressure_residual`` and its ``pressure_solve_seconds`` (hierarchy included)."""
        out = super().series(run)
        s = run.backend.scheme_passes.solver
        out.update({"pressure_iterations": float(s.iterations), "pressure_residual": s.residual,
                    "pressure_solve_seconds": s.seconds})
        return out

    def timings(self, run) -> dict[str, float]:
        """The pressure solves so far: ``solve_s`` (seconds, hierarchy builds included), ``solves``,
        ``solve_iterations`` and ``hierarchy_builds``."""
        s = run.backend.scheme_passes.solver
        return {"solve_s": s.total_seconds, "solves": float(s.solves), "solve_iterations": float(s.total_iterations),
                "hierarchy_builds": float(s.builds)}

    def report(self, scene) -> list[str]:
        from geompm.schemes.saturated.report import semi_implicit_lines

        return semi_implicit_lines(scene, self.water)
