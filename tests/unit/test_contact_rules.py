"""The velocity rule every rigid surface applies to a node (contact/rules.py), one velocity at a time."""

from __future__ import annotations

import numpy as np
import pytest

from geompm.contact.rules import CONDITIONS, apply_condition, effective_mu

NORMAL = np.array([0.0, 1.0])  # into the material


@pytest.mark.parametrize("condition, towards, away", [
    ("slip", [3.0, 0.0], [3.0, 2.0]),       # one-sided: separating keeps its normal velocity
    ("roller", [3.0, 0.0], [3.0, 0.0]),     # two-sided: no normal motion either way, tangential free
    ("fixed", [0.0, 0.0], [0.0, 0.0]),
    ("friction", [1.0, 0.0], [3.0, 2.0]),   # mu = 1: |v_t| 3 loses mu |v_n| = 2; separating is free
])
def test_each_condition_on_a_node_moving_towards_and_away_from_the_surface(condition, towards, away):
    for v0, expected in (([3.0, -2.0], towards), ([3.0, 2.0], away)):
        v = np.array(v0)
        apply_condition(v, NORMAL, 0, CONDITIONS[condition], 1.0)
        assert v.tolist() == expected, (condition, v0, v.tolist())


def _pore_row(p, sxx, syy, szz=0.0, sxy=0.0, syz=0.0, sxz=0.0):
    return np.array([p, sxx, syy, szz, sxy, syz, sxz])


@pytest.mark.parametrize("row, normal, expected", [
    # sigma_n = 20 kPa (compression), p_b = 5 kPa: lambda = 0.25, mu (1 - lambda) = 0.45
    (_pore_row(5e3, -1e3, -20e3), [0.0, 1.0], 0.6 * 0.75),
    # the normal along x reads sigma_xx: sigma_n = 10 kPa, p_b = 5 kPa -> 0.3
    (_pore_row(5e3, -10e3, -20e3), [1.0, 0.0], 0.3),
    # a 45 degree normal: sigma_n = (sxx + syy)/2 + sxy = -(-10 - 20 + 2 * 5)/2 = 10 kPa (sxy = +5 kPa relieves it)
    (_pore_row(5e3, -10e3, -20e3, sxy=5e3), [2 ** -0.5, 2 ** -0.5], 0.3),
    # water carrying the whole normal stress (liquefied) or more: no friction
    (_pore_row(20e3, 0.0, -20e3), [0.0, 1.0], 0.0),
    (_pore_row(5e3, 0.0, 1e3), [0.0, 1.0], 0.0),   # the node in tension
    # suction adds no friction; a dry node's row of zeros leaves mu as it is
    (_pore_row(-5e3, 0.0, -20e3), [0.0, 1.0], 0.6),
    (_pore_row(0.0, 0.0, 0.0), [0.0, 1.0], 0.6),
])
def test_friction_on_the_effective_normal_force(row, normal, expected):
    """contact/rules.effective_mu: mu (N - p_b A) / N = mu (1 - p_b / sigma_n) with sigma_n = -n . sigma n
    (compression positive), lambda held in [0, 1] (Terzaghi's principle at the contact; docs/pore-water.md,
    Friction on effective stress)."""
    n = np.array(normal)
    assert effective_mu(0.6, row, n, 0, 2) == pytest.approx(expected, rel=1e-12, abs=1e-15)


def test_effective_friction_in_3d_reads_the_out_of_plane_components():
    """A 3D normal (0, 0.6, 0.8): sigma_n = 0.36 syy + 0.64 szz + 2 * 0.48 syz = -(0.36 * -10 + 0.64 * -30 + 0.96 * 2)
    kPa = 20.88 kPa; p_b = 5.22 kPa gives lambda = 0.25."""
    row = _pore_row(5.22e3, -99e3, -10e3, szz=-30e3, sxy=7e3, syz=2e3, sxz=9e3)
    n = np.array([0.0, 0.6, 0.8])
    assert effective_mu(1.0, row, n, 0, 3) == pytest.approx(0.75, rel=1e-12)
