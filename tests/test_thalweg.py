"""The thalweg (writers/thalweg.py): the line of steepest descent over a rough DEM and the distance along it."""

import math

import numpy as np
import pytest

from geompm.writers.thalweg import runout_along, thalweg


def _channel(angle_deg, p0, n=200, noise=0.3, seed=3):
    """A V-shaped channel on 1 m cells through ``p0`` [m] along a line at ``angle_deg`` to x, falling 0.3 m per
    metre along it with sides of slope 0.35 and smoothed random relief of ``noise`` m (as the shipped site's,
    cases/terrain/make_site.py): (ground (n, n), unit axis, unit normal)."""
    a = math.radians(angle_deg)
    axis, normal = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
    X, Y = np.meshgrid(np.arange(n) + 0.5, np.arange(n) + 0.5, indexing="ij")
    rel = np.stack([X - p0[0], Y - p0[1]], axis=-1)
    z = 100.0 - 0.3 * (rel @ axis) + 0.35 * np.abs(rel @ normal)
    r = np.random.default_rng(seed).normal(size=z.shape)
    for _ in range(6):
        r = (r + np.roll(r, 1, 0) + np.roll(r, -1, 0) + np.roll(r, 1, 1) + np.roll(r, -1, 1)) / 5.0
    return z + noise * r / r.std(), axis, normal


@pytest.mark.parametrize("angle, p0", [(0.0, (10.0, 100.0)), (30.0, (10.0, 20.0))])
def test_the_thalweg_follows_a_rough_channel_and_its_length_is_the_channels(angle, p0):
    """Started on a channel's axis, the path stays within 3 cells of it across 0.3 m relief (plain D8 on the rough
    ground ends in the first hollow, or wanders 1.9 times longer on the shipped site), and the distance along it
    to the cell 100 m down the axis is that 100 m within 3 % (D8's staircase, up to 8 % longer, removed)."""
    z, axis, normal = _channel(angle, p0)
    start = tuple(int(k) for k in np.floor(np.asarray(p0) + 10.0 * axis))
    path, dist = thalweg(z, 1.0, 1.0, start)
    pts = np.asarray(path) + 0.5 - np.asarray(p0)
    assert np.abs(pts @ normal).max() < 3.0 and len(path) > 120
    along = pts @ axis - pts[0] @ axis
    k = int(np.argmin(np.abs(along - 100.0)))
    reached = np.zeros(z.shape, bool)
    reached[path[k]] = True
    assert runout_along(path, dist, reached) == pytest.approx(along[k], rel=0.03)
    assert runout_along(path, dist, np.zeros(z.shape, bool)) is None
