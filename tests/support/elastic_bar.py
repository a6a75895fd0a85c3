"""The elastic bar of cases/elastic_bar.json run for three periods (tests/verification/test_elastic_bar.py;
tests/unit/test_precision.py compares float32 storage with it)."""

import functools

import numpy as np

from geompm.api import scene_from_file
from geompm.engine.scheduler import Simulation

from .cases import CASES


def _strain_energy(st, E):
    """sum V sigma:sigma / (2E) for nu = 0 (sigma = E eps component-wise)."""
    s = st.p_stress
    return float((st.p_vol * ((s[:, :3] ** 2).sum(axis=1) + 2 * (s[:, 3:] ** 2).sum(axis=1))).sum() / (2 * E))


@functools.lru_cache(maxsize=4)
def run_bar(sets=()):
    """Run the bar for 3 periods: measured and closed-form period [s], energy drift, t, v_cm (memoised
    per ``sets`` tuple: tests/unit/test_precision.py compares with the float64 run)."""
    scene = scene_from_file(CASES / "elastic_bar.json", list(sets))
    sim = Simulation(scene)
    st = scene.state
    E = scene.materials[0].params.youngs_modulus
    times, vcm, energy = [], [], []
    while sim.time < 30.0:
        sim.step(min(sim.stable_dt(), 30.0 - sim.time))
        times.append(sim.time)
        vcm.append(float((st.p_mass * st.p_v[:, 0]).sum() / st.p_mass.sum()))
        energy.append(0.5 * float((st.p_mass * (st.p_v ** 2).sum(axis=1)).sum()) + _strain_energy(st, E))
    t, vcm = np.array(times), np.array(vcm)
    # downward zero crossings of v_cm, linearly interpolated
    k = np.nonzero((vcm[:-1] > 0) & (vcm[1:] <= 0))[0]
    crossings = t[k] - vcm[k] * (t[k + 1] - t[k]) / (vcm[k + 1] - vcm[k])
    assert len(crossings) == 3
    period = np.diff(crossings).mean()
    exact = 4 * 25.0 / np.sqrt(E / 1.0)
    return period, exact, abs(energy[-1] - energy[0]) / energy[0], t, vcm
