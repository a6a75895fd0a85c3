"""Column collapse of the source study's soil (section 3.2), 2D plane strain, run to rest.

cases/column_collapse.json (Drucker-Prager) and cases/column_collapse_cross.json
(generalized Cross, mu_inf = 1.2 Pa s at h = 0.01 m): each must come to rest
(kinetic energy below 1e-3 of its peak at the end), keep its mass exactly
(rho0 x 0.2 m x 0.1 m = 53 kg per metre) and end with a finite, stable runout.

The DP deposit is also checked against the planar collapse scaling of Lube,
Huppert, Sparks & Freundt (2005) Phys. Rev. E 72:041301 for aspect ratio
a = H0/L0 = 0.5 < 1.8: (L_inf - L0)/L0 = 1.2 a and H_inf/H0 = 1
(tests/refdata/granular_collapse_scaling_laws.csv; confidence M there).
"""

import numpy as np
import pytest

from geompm.api import scene_from_file
from geompm.engine.scheduler import Simulation
from geompm.writers.deposit import deposit_front, deposit_height

from tests.support.cases import CASES

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


def test_drucker_prager_column_comes_to_rest():
    """cases/column_collapse.json (DP, FLIP with tau = 0.1 s) at its own h = 0.01 m: at rest by 1 s, mass kept,
    the top of the column (x < 0.1 L0, left untouched for a < 1.15, Lube et al. 2005) still at H0 within
    half a cell. The runout at one h is not compared with Lube here: see the convergence tests below."""
    sim, mass0, ke_peak, hist = _run("column_collapse.json")
    runout = _common(sim, mass0, ke_peak, hist)
    assert L0 < runout < 3 * L0
    st = sim.state
    back = st.p_x[:, 0] < 0.1 * L0
    height = st.p_x[back, 1].max() + 0.25 * sim.scene.grid.h  # top particle + half a particle spacing
    assert height / H0 == pytest.approx(1.0, abs=0.5 * sim.scene.grid.h / H0)


def _deposit(sets):
    """The DP column run to its end time, and its particles' solid areas m / rho0 [m^2]."""
    sim = Simulation(scene_from_file(CASES / "column_collapse.json", ["outputs=[]", *sets]))
    end = sim.scene.end_time
    while sim.time < end:
        sim.step(min(sim.stable_dt(), end - sim.time))
    return sim, sim.state.p_mass / RHO


def _front_height(sets, h0):
    """(front, height) [m] of the deposit: geompm.writers.deposit at a threshold of 0.05 H0, sampled every
    0.01 H0, as series.csv writes them for `geompm study` (benchmarks/convergence/lube_study.sh)."""
    sim, area = _deposit(sets)
    x = sim.state.p_x
    return deposit_front(x, area, 0.05 * h0, 0.01 * h0), deposit_height(x, area, 0.01 * h0, 0.05 * h0)


@pytest.mark.slow
def test_dp_runout_does_not_depend_on_the_step():
    """The cause of the drift under refinement (issue 15): APIC/PIC lose energy per step (test_transfer_
    dissipation.py), and the step is set by the elastic wave (c = 20 m/s), so lowering time.cfl alone
    shortened the APIC runout at h = 0.01 m from 0.547 to 0.447 (cfl 0.4 -> 0.1). With FLIP relaxed over
    tau = 0.1 s (the shipped case) the deposit front at cfl 0.4 and 0.1 agrees within 2 % (measured 0.3220 and
    0.3240 m: 0.6 %, since the psi-matched cone and Kirchhoff elasticity; 0.3285 and 0.3310 m before)."""
    base = ("time.end=0.8",)
    f4, _ = _front_height(base, H0)
    f1, _ = _front_height((*base, "time.cfl=0.1"), H0)
    assert f1 == pytest.approx(f4, rel=0.02), f"front {f4:.4f} m at cfl 0.4, {f1:.4f} m at cfl 0.1"


A05_SETS = ("bodies.0.geometry.max=[0.1,0.05]", "grid.extent=[0.27,0.06]", "time.end=0.35",
            "solver.flip_relaxation_time=0.0714")


@pytest.mark.slow
def test_dp_column_a05_converges_to_within_20_percent_of_lube():
    """a = H0/L0 = 0.5, L0 = 0.1 m (issue 15), tau = sqrt(H0/g) = 0.071 s, the coarser pair of the issue's
    grids H0/20 and H0/40, to t = 0.35 s (the fronts at 0.3 s, 0.35 s and 1 s are the same to 0.1 mm; the study
    runs to 1 s).  The two fronts differ by less than 3 % (measured 0.1725 and 0.1705 m: 1.2 %; H0/80 gives
    0.1710 m, docs/validation/column-collapse.md) and the heights by less than 3 % (0.0500 m at both: the top
    of a column with a < 1.15 is left untouched).  The H0/40 runout (L - L0)/L0 is within 20 % of Lube et al. (2005), 1.2 a = 0.60 (measured 0.705, +17.5 %;
    tests/refdata/granular_collapse_scaling_laws.csv).  Before the plane-strain cone was matched for
    psi = 0 it was 0.735 (+22.5 %), and with APIC the runout grew at every halving."""
    l0, h0 = 0.1, 0.05
    (f1, t1), (f2, t2) = (_front_height((*A05_SETS, f"grid.cell_size={h0 / n}"), h0) for n in (20, 40))
    assert f2 == pytest.approx(f1, rel=0.03) and t2 == pytest.approx(t1, rel=0.03), (f1, f2, t1, t2)
    assert (f2 - l0) / l0 == pytest.approx(1.2 * h0 / l0, rel=0.20), f"(L - L0)/L0 = {(f2 - l0) / l0:.3f}"


A2_SETS = ("bodies.0.geometry.max=[0.1,0.2]", "grid.extent=[0.63,0.24]", "time.end=1.0",
           "solver.flip_relaxation_time=0.143")


@pytest.mark.slow
def test_dp_column_a2_converges_to_within_20_percent_of_lube():
    """a = H0/L0 = 2, L0 = 0.1 m (issue 15), tau = sqrt(H0/g) = 0.143 s, the coarser pair of the issue's grids
    H0/20 and H0/40.  The two fronts differ by less than 3 % (measured 0.372 and 0.372 m; H0/80 and H0/160 give
    0.368 and 0.364 m) and the heights by less than 3 % (measured 0.1201 and 0.1171 m: 2.5 %; the height falls
    by about that much at each halving up to H0/80 and then settles, 0.1141 and 0.1150 m,
    docs/validation/column-collapse.md).  a = 2 lies between Lube et al.'s
    (2005) branches 1.2 a = 2.40 (a < 1.8) and 1.9 a^(2/3) = 3.02 (a > 2.8): the H0/40 runout (L - L0)/L0 is
    within 20 % of both (measured 2.72: +13 % and -10 %)."""
    l0, h0 = 0.1, 0.2
    (f1, t1), (f2, t2) = (_front_height((*A2_SETS, f"grid.cell_size={h0 / n}"), h0) for n in (20, 40))
    assert f2 == pytest.approx(f1, rel=0.03) and t2 == pytest.approx(t1, rel=0.03), (f1, f2, t1, t2)
    spread = (f2 - l0) / l0
    assert spread == pytest.approx(1.2 * 2, rel=0.2) and spread == pytest.approx(1.9 * 2 ** (2 / 3), rel=0.2), spread


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
