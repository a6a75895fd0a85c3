"""The slip surface read from a failed trial's plastic strain rate (geompm/stability/slip.py).

A synthetic field with a known band: particles on a lattice a quarter cell apart, their rate a Gaussian of the
distance to a circle (the toe circle of a limit-equilibrium analysis) plus a weaker background; the surface the
column search returns must lie on the circle to a tenth of a cell in 2D, and on a sphere's cap in 3D.
"""

from __future__ import annotations

import numpy as np

from geompm.stability.slip import slip_surface


def _lattice(dim, lo, hi, step):
    axes = [np.arange(a + step / 2, b, step) for a, b in zip(lo, hi)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)


def test_circle_in_2d():
    h = 0.5
    x = _lattice(2, (0.0, 0.0), (30.0, 10.0), h / 2)
    xc, yc, r = 20.0, 24.0, 22.0
    d = np.hypot(x[:, 0] - xc, x[:, 1] - yc) - r
    rate = np.exp(-(d / h) ** 2) + 0.01 * np.exp(-((x[:, 1] - 9.0) / 0.3) ** 2)
    pts = slip_surface(x, rate, 2, h)
    on = pts[(pts[:, 0] > 5.0) & (pts[:, 0] < 28.0)]  # where the band lies inside the lattice
    assert len(on) >= 40
    expected = yc - np.sqrt(r ** 2 - (on[:, 0] - xc) ** 2)
    assert np.abs(on[:, 1] - expected).max() < 0.1 * h


def test_sphere_cap_in_3d():
    h = 1.0
    x = _lattice(3, (0.0, 0.0, 0.0), (12.0, 12.0, 6.0), h / 2)
    c, r = np.array([6.0, 6.0, 12.0]), 10.0
    d = np.linalg.norm(x - c, axis=1) - r
    rate = np.exp(-(d / h) ** 2)
    pts = slip_surface(x, rate, 3, h)
    near = np.hypot(pts[:, 0] - 6.0, pts[:, 1] - 6.0) < 3.0
    expected = c[2] - np.sqrt(r ** 2 - (pts[near, 0] - 6.0) ** 2 - (pts[near, 1] - 6.0) ** 2)
    assert near.sum() >= 16
    assert np.abs(pts[near, 2] - expected).max() < 0.15 * h


def test_no_plastic_flow_gives_no_surface():
    x = _lattice(2, (0.0, 0.0), (2.0, 1.0), 0.25)
    assert slip_surface(x, np.zeros(len(x)), 2, 0.5).shape == (0, 2)
