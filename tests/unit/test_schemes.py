"""The built-in schemes declare their passes by name (schemes/base.py): each name is a method of the scheme,
the lists are the published step orders, and `geompm validate` prints the scheme's list."""

from __future__ import annotations

import pytest

from geompm.cli import main
from geompm.contract import registry
from tests.support.cases import CASES


def test_every_registered_scheme_declares_passes_it_has():
    schemes = registry.available("schemes")
    assert {"usl", "musl", "saturated"} <= set(schemes)
    for name, info in schemes.items():
        cls = info.plugin
        assert cls.passes and cls.passes[0] == "window" and cls.passes[-1].endswith("stress_update"), name
        assert all(callable(getattr(cls, p, None)) for p in cls.passes), name


def test_the_step_orders_are_usl_musl_and_the_two_phase_one():
    """USL (Sulsky, Chen & Schreyer 1994): G2P after the grid stages, the stress last; MUSL (Sulsky, Zhou &
    Schreyer 1995): the velocities re-mapped and the stages applied again before positions and gradient; the
    saturated step: loads and damping before the relative velocity, the contacts after it, then the split, the
    water's step, and G2P with the particle stages and the laws last (the porosity after the laws: its
    ``after_particles``)."""
    s = registry.available("schemes")
    usl, musl, wet = s["usl"].plugin.passes, s["musl"].plugin.passes, s["saturated"].plugin.passes
    assert usl.index("grid_update_and_stages") < usl.index("g2p_stages_and_stress_update") == len(usl) - 1
    assert musl.index("g2p_velocity") < musl.index("remap") < musl.index("grid_stages_remapped") < \
        musl.index("g2p_move_stages_and_stress_update")
    assert wet.index("loads_and_damping") < wet.index("relative_velocity") < wet.index("contacts") < \
        wet.index("split") < wet.index("water_g2p") < wet.index("g2p_stages_and_stress_update") == len(wet) - 1
    assert "load" in usl and "load" not in wet  # a water table is refused with saturated soil


@pytest.mark.parametrize("case, scheme", [("elastic_bar", "usl"), ("terzaghi_consolidation", "saturated")])
def test_validate_prints_the_scheme_and_its_passes(case, scheme, capsys):
    assert main(["validate", str(CASES / f"{case}.json")]) == 0
    out = capsys.readouterr().out
    passes = " -> ".join(registry.available("schemes")[scheme].plugin.passes)
    assert f"scheme '{scheme}', a step's passes: {passes}" in out
