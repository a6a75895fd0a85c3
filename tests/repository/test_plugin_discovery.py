"""Entry-point discovery finds a third-party distribution and survives a broken one.

A test-only distribution (a ``.dist-info`` folder with ``entry_points.txt`` on
sys.path, exactly what pip installs) registers one working material and one
whose module does not exist.  Nothing in geompm is edited.
"""

import json
import textwrap
import warnings

import numpy as np
import pytest

from geompm.contract import registry
from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.backend.cpu_loops import law_wave_speed

from tests.support.cases import tiny_case


@pytest.fixture
def fake_dist(tmp_path, monkeypatch):
    info = tmp_path / "fake_geompm_plugin-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fake-geompm-plugin\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(textwrap.dedent("""\
        [geompm.materials]
        stiff_elastic = fake_geompm_plugin:StiffElastic
        broken_law = fake_geompm_missing_module:Nope
        """))
    (tmp_path / "fake_geompm_plugin.py").write_text(textwrap.dedent("""\
        from geompm.materials.linear_elastic import LinearElastic

        class StiffElastic(LinearElastic):
            '''Linear elasticity with the modulus doubled (test plugin).'''
            name = "stiff_elastic"
            description = "test plugin: linear elastic with 2 E"

            @classmethod
            def pack(cls, params):
                prm = super().pack(params)
                prm["lam"] *= 2.0
                prm["G"] *= 2.0
                return prm
        """))
    monkeypatch.syspath_prepend(str(tmp_path))
    registry.clear_cache()
    yield
    registry.clear_cache()


def test_third_party_plugin_is_found_and_broken_one_warns(fake_dist):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mats = registry.available("materials")
    assert "stiff_elastic" in mats and mats["stiff_elastic"].package == "fake-geompm-plugin"
    assert "linear_elastic" in mats  # built-ins still there
    assert "broken_law" not in mats
    msgs = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert any("broken_law" in m and "fake-geompm-plugin" in m for m in msgs), msgs


def test_third_party_law_runs_in_a_case(fake_dist):
    """The plugin's packed parameters reach the kernel: wave speed is sqrt(2) x the built-in's."""
    speeds = []
    for model in ("linear_elastic", "stiff_elastic"):
        case = tiny_case()
        case["materials"]["soil"]["model"] = model
        sim = Simulation(scene_from_dict(json.loads(json.dumps(case))))
        speeds.append(law_wave_speed(sim.scene.materials[0], sim.state.p_rho))
        for _ in range(5):
            sim.step(sim.stable_dt())
        assert np.isfinite(sim.state.p_stress).all()
    assert speeds[1] / speeds[0] == pytest.approx(np.sqrt(2.0), rel=1e-12)


def test_unknown_name_lists_installed_and_suggests():
    msg = registry.unknown_name_message("newtonain", ["newtonian", "linear_elastic"])
    assert "did you mean 'newtonian'" in msg and "linear_elastic" in msg
