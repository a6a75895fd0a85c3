"""The excess pore pressure's hydrostatic reference follows the flow's own free surface
(schemes/saturated/surface.py; docs/pore-water.md, Outputs): p_h = rho_w |g| max(0, z_s - d_wt - z), z_s the
particle's column's surface now, d_wt its water table's depth below the surface at set-up."""

from types import SimpleNamespace

import numpy as np
import pytest

from geompm.schemes.saturated.fields import PoreWater
from geompm.schemes.saturated.kernels import WATER
from geompm.schemes.saturated.surface import across, column_surface


def _water():
    table = np.zeros((1, len(WATER)))
    table[0, WATER.rho_w] = 1000.0
    return PoreWater(table=table, wet=[True], up=np.array([0.0, 1.0]), g=9.81,
                     grid=(np.array([0.0, -200.0]), np.array([4.0, 300.0]), 0.1))


def _column(x0, base, height, spacing=0.05):
    """Two columns of particles on a lattice of ``spacing``: x in [x0, x0 + 0.2), y in [base, base + height)."""
    xs = x0 + spacing * (np.arange(int(round(0.2 / spacing))) + 0.5)
    ys = base + spacing * (np.arange(int(round(height / spacing))) + 0.5)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    x = np.c_[X.ravel(), Y.ravel()]
    n = len(x)
    return SimpleNamespace(p_x=x, p_vol0=np.full(n, spacing ** 2), p_sat=np.ones(n), p_material=np.zeros(n, int),
                           n=n, p_wt=np.full(n, base + height), p_pore=np.zeros(n))


def test_a_column_moved_100_m_down_keeps_its_hydrostatic_reference():
    """A 1 m saturated column whose table was its top at set-up, then found 100 m lower (a flow that has
    descended): the reference is rho_w g (depth below its own surface), 9 810 Pa at 1 m, not the 990 kPa a
    table fixed at the release's elevation gives; a water table 0.3 m below the top at set-up stays 0.3 m
    below the surface."""
    pw = _water()
    st = _column(1.0, 10.0, 1.0)
    st.p_wt_depth = pw.table_depth(st)
    assert np.allclose(st.p_wt_depth, 0.0)
    st.p_x[:, 1] -= 100.0
    p_h = pw.hydrostatic(st)
    depth = (10.0 + 1.0 - 100.0) - st.p_x[:, 1]
    assert np.allclose(p_h, 1000.0 * 9.81 * depth)
    assert p_h.max() == pytest.approx(1000.0 * 9.81 * 0.975)
    low = _column(1.0, 10.0, 1.0)
    low.p_wt = np.full(low.n, 10.7)
    low.p_wt_depth = pw.table_depth(low)
    assert np.allclose(low.p_wt_depth, 0.3)
    low.p_x[:, 1] -= 100.0
    assert np.allclose(pw.hydrostatic(low), 1000.0 * 9.81 * np.maximum(10.7 - 100.0 - low.p_x[:, 1], 0.0))


def test_columns_take_their_own_surface_and_ranks_share_it():
    """Two columns of different heights side by side each read their own surface (the highest particle plus
    half its spacing); a maximum over the ranks (comm_max) lifts a column cut between two ranks to its top."""
    a, b = _column(0.0, 0.0, 1.0), _column(2.0, 0.0, 0.4)
    x = np.vstack([a.p_x, b.p_x])
    spacing = np.full(len(x), 0.05)
    zs = column_surface(x, spacing, np.array([0.0, 1.0]), np.array([0.0, 0.0]), np.array([4.0, 2.0]), 0.1)
    assert np.allclose(zs[:a.n], 1.0) and np.allclose(zs[a.n:], 0.4)
    lower = a.p_x[:, 1] < 0.5  # this rank holds the column's lower half; another rank its top
    other = column_surface(a.p_x[~lower], spacing[:(~lower).sum()], np.array([0.0, 1.0]), np.array([0.0, 0.0]),
                           np.array([4.0, 2.0]), 0.1)
    assert np.allclose(other, 1.0)
    shared = []
    column_surface(a.p_x[~lower], spacing[:(~lower).sum()], np.array([0.0, 1.0]), np.array([0.0, 0.0]),
                   np.array([4.0, 2.0]), 0.1, comm_max=lambda t: shared.append(t.copy()) or t)
    mine = column_surface(a.p_x[lower], spacing[:lower.sum()], np.array([0.0, 1.0]), np.array([0.0, 0.0]),
                          np.array([4.0, 2.0]), 0.1, comm_max=lambda t: np.maximum(t, shared[0]))
    assert np.allclose(mine, 1.0)


def test_the_columns_run_across_any_gravity():
    """A basis across the upward direction is orthonormal and normal to it, in 2D and 3D."""
    for up in (np.array([0.0, 1.0]), np.array([0.6, 0.8]), np.array([0.0, 0.0, 1.0]),
               np.array([1.0, 2.0, 2.0]) / 3.0):
        b = across(up)
        assert b.shape == (len(up) - 1, len(up))
        assert np.allclose(b @ up, 0.0) and np.allclose(b @ b.T, np.eye(len(up) - 1))


def test_a_body_with_a_sloping_top_starts_hydrostatic_below_its_own_surface():
    """A saturated 2D wedge (top rising from y = 0.5 to 1.0 m over 2 m, tan b = 0.25) without a water table:
    each particle starts at p = rho_w g (y_s - y) below its own column's top (columns one cell wide, so
    within rho_w g (h tan b + s) = 736 Pa of the surface above it, h = 0.1 m, s = 0.05 m), not below a
    level table at the wedge's highest point, which would put the low end's base under 0.5 m more water
    (4.9 kPa) than it has; the geostatic effective stress under it stays compressive."""
    from geompm.api import scene_from_dict

    case = {"name": "wedge", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [2.0, 1.2], "cell_size": 0.1, "shape_function": "quadratic"},
            "time": {"end": 0.1}, "gravity": [0.0, -9.81],
            "materials": {"soil": {"model": "linear_elastic", "density": 2650.0, "youngs_modulus": 1e7,
                                   "poisson_ratio": 0.3,
                                   "pore_water": {"porosity": 0.4, "hydraulic_conductivity": 1e-4}}},
            "bodies": [{"material": "soil", "particles_per_cell": 2, "initial_stress": "geostatic",
                        "geometry": {"type": "polygon", "vertices": [[0, 0], [2, 0], [2, 1.0], [0, 0.5]]}}]}
    st = scene_from_dict(case).state
    surface = 0.5 + 0.25 * st.p_x[:, 0]
    head = st.p_pore / (1000.0 * 9.81)
    assert np.abs(head - (surface - st.p_x[:, 1])).max() < 0.25 * 0.1 + 0.05
    low = (st.p_x[:, 0] < 0.1) & (st.p_x[:, 1] < 0.05)
    assert head[low].max() < 0.5 + 0.05  # the low end's base: its own 0.5 m, not the wedge's 1.0 m
    assert st.p_stress[:, 1].max() < 0.0
