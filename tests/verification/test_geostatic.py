"""Geostatic initial stress and gravity equilibrium of a laterally confined elastic column.

Closed form (tests/refdata/analytic_selfweight_column_K0.csv): for a column of
height H under gravity, sigma_v(z) = -rho g (H - z) and sigma_h = K0 sigma_v
with K0 = nu / (1 - nu).  Started from that state, between slip walls, the
column must stay at rest; started from zero stress it falls and oscillates
with a dynamic overshoot to 2x the static settlement rho g H^2 / (2 M),
M = E (1 - nu) / ((1 + nu)(1 - 2 nu)).
"""

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

RHO, E, NU, H, G = 2000.0, 1.0e7, 0.3, 1.0, 9.81


def _column(initial_stress):
    return {
        "name": "column", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [0.4, 1.2], "cell_size": 0.05},
        "time": {"end": 1.0, "cfl": 0.4}, "gravity": [0.0, -G],
        "materials": {"soil": {"model": "linear_elastic", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [0.4, H]},
                    "particles_per_cell": 2, "initial_stress": initial_stress}],
        "boundaries": [{"type": "wall", "side": s, "condition": "slip"} for s in ("x-", "x+", "y-")],
    }


def test_geostatic_stress_matches_k0_profile():
    st = scene_from_dict(_column("geostatic")).state
    z = st.p_x[:, 1]
    sv = -RHO * G * (H - z)
    np.testing.assert_allclose(st.p_stress[:, 1], sv, rtol=1e-12)
    np.testing.assert_allclose(st.p_stress[:, 0], NU / (1 - NU) * sv, rtol=1e-12)
    np.testing.assert_allclose(st.p_stress[:, 2], NU / (1 - NU) * sv, rtol=1e-12)  # plane strain sigma_zz
    assert np.abs(st.p_stress[:, 3:]).max() == 0.0


@pytest.mark.parametrize("shape,bound", [("linear", 0.05), ("quadratic", 0.05), ("cubic", 0.10)])
def test_geostatic_column_stays_at_rest(shape, bound):
    """Top settlement stays below ``bound`` x the static value rho g H^2 / 2M; the unstressed column overshoots.

    Measured (h = 0.05 m, 2x2 particles per cell): linear 0 (particles at the
    sub-cell centres integrate the linear stress profile exactly), quadratic 4.5%,
    cubic 6.2% of the static settlement.  The cubic bound is wider because geompm's cubic B-spline is
    the uniform one, not modified at the domain walls (Steffen, Kirby & Berzins 2008,
    Int. J. Numer. Meth. Eng. 76:922), so the stress divergence near the floor is
    integrated less exactly.
    """
    M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
    static = RHO * G * H ** 2 / (2 * M)
    peaks = {}
    for init in ("geostatic", "none"):
        case = _column(init)
        case["grid"]["shape_function"] = shape
        sim = Simulation(scene_from_dict(case))
        st = sim.state
        top = st.p_x[:, 1] > H - 0.05
        period = 4 * H / np.sqrt(M / RHO)
        settle = 0.0
        while sim.time < 1.5 * period:
            sim.step(sim.stable_dt())
            settle = max(settle, abs((st.p_x[top, 1] - st.p_x0[top, 1]).mean()))
        peaks[init] = settle
    assert peaks["geostatic"] < bound * static, peaks
    # sudden gravity: dynamic settlement peaks near twice the static one
    assert 1.6 * static < peaks["none"] < 2.4 * static, (peaks, static)


@pytest.mark.parametrize("scale", [10, 2**40])
def test_column_ids_sort_like_unique_rows(scale):
    """assemble._column_ids, the fast replacement of np.unique(keys, axis=0) that bins particles into
    columns for the overburden, gives the same partition in the same order as np.unique's inverse: on
    random negative and positive column indices, and past int64 (a span of 2^40 per axis, the fallback)."""
    from geompm.setup.assemble import _column_ids

    rng = np.random.default_rng(3)
    keys = rng.integers(-scale, scale, size=(5000, 3))
    keys[::7] = keys[1::7][: len(keys[::7])]  # shared columns
    ids = _column_ids(keys)
    expected = np.unique(keys, axis=0, return_inverse=True)[1].ravel()
    assert np.array_equal(np.unique(ids, return_inverse=True)[1].ravel(), expected)
