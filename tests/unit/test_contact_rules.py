"""The velocity rule every rigid surface applies to a node (contact/rules.py), one velocity at a time."""

from __future__ import annotations

import numpy as np
import pytest

from geompm.contact.rules import CONDITIONS, apply_condition

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
