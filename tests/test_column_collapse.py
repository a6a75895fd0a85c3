"""Column collapse of the source study's soil (section 3.2), 2D plane strain, run to rest.

cases/column_collapse.json (Drucker-Prager) and cases/column_collapse_cross.json
(generalized Cross, mu_inf = 1.2 Pa s at h = 0.01 m): each must come to rest
(kinetic energy below 1e-3 of its peak at the end), keep its mass exactly
(rho0 x 0.2 m x 0.1 m = 53 kg per metre) and end with a finite, stable runout.

The DP deposit is also checked against the planar collapse scaling of Lube,
Huppert, Sparks & Freundt (2005) Phys. Rev. E 72:041301 for aspect ratio
a = H0/L0 = 0.5 < 1.8: (L_inf - L0)/L0 = 1.2 a and H_inf/H0 = 1
(shared/refdata/granular_collapse_scaling_laws.csv; confidence M there).
"""

import numpy as np
import pytest

from geompm.api import scene_from_file
from geompm.engine.scheduler import Simulation

from .conftest import CASES

L0, H0, RHO = 0.2, 0.1, 2650.0


def _run(case, sets=()):
    sim = Simulation(scene_from_file(CASES / case, sets))
    st = sim.state
    end = sim.scene.end_time
    mass0 = st.p_mass.sum()
    ke_peak, history = 0.0, []
    while sim.time < end:
        sim.step(min(sim.stable_dt(), end - sim.time))
        ke = 0.5 * float((st.p_mass * (st.p_v ** 2).sum(axis=1)).sum())
        ke_peak = max(ke_peak, ke)
        history.append((sim.time, ke, st.p_x[:, 0].max()))
    return sim, mass0, ke_peak, np.array(history)


def _common(sim, mass0, ke_peak, hist):
    st = sim.state
    assert np.isfinite(st.p_x).all() and np.isfinite(st.p_stress).all()
    assert st.p_mass.sum() == mass0 == pytest.approx(RHO * L0 * H0, rel=1e-12)
    assert (st.p_rho * st.p_vol).sum() == pytest.approx(mass0, rel=1e-12)
    assert hist[-1, 1] < 1e-3 * ke_peak, f"kinetic energy at the end {hist[-1, 1] / ke_peak:.2e} of the peak"
    late = hist[hist[:, 0] >= hist[-1, 0] - 0.2]
    h = sim.scene.grid.h
    assert np.ptp(late[:, 2]) < 0.2 * h, "the front still moves in the last 0.2 s"
    return hist[-1, 2]


def test_drucker_prager_column_matches_lube_scaling():
    sim, mass0, ke_peak, hist = _run("column_collapse.json")
    runout = _common(sim, mass0, ke_peak, hist)
    a = H0 / L0
    rel_runout = (runout - L0) / L0
    assert rel_runout == pytest.approx(1.2 * a, rel=0.15), f"(L-L0)/L0 = {rel_runout:.3f}, Lube: {1.2 * a:.3f}"
    height = sim.state.p_x[:, 1].max() + 0.25 * sim.scene.grid.h  # top particle + half a particle spacing
    assert height / H0 == pytest.approx(1.0, abs=0.1)


# The Cross case's explicit viscous step rho h^2 / (4 mu_0) makes it the suite's slowest test: 636 000 steps,
# 257 s on 2 cores at its own h = 0.01 m (issue 14).  At h = 0.02 m with the same parameters the step is 4x
# longer; the coarser column creeps longer (kinetic energy 1.6e-3 of its peak at 3.5 s, 9.6e-4 at 5 s), so
# it runs to 5.5 s: 250 000 steps, about 70 s, for the same assertions (rest, mass, finite runout).
CROSS_CHEAPER = ("grid.cell_size=0.02", "time.end=5.5", "outputs=[]")


@pytest.mark.slow
def test_cross_column_comes_to_rest():
    """cases/column_collapse_cross.json at h = 0.02 m, to t = 5.5 s: at rest (kinetic energy below 1e-3 of
    its peak, front still within 0.2 h over the last 0.2 s), mass kept exactly, runout between L0 and 3 L0."""
    sim, mass0, ke_peak, hist = _run("column_collapse_cross.json", CROSS_CHEAPER)
    runout = _common(sim, mass0, ke_peak, hist)
    assert L0 < runout < 0.6
