"""A time-step scheme from a third-party distribution: a module and a ``geompm.schemes`` entry point, no file of
geompm edited (docs/architecture.md, Where a change goes).

The test scheme is USL with one declared particle field, each particle's kinetic energy after the step, and a
series column of its largest value.  Selected by ``solver.update``, it runs the built-in USL's passes, so its
particles end where USL's do to the last bit; its field is allocated by the set-up, kept through the run and
written to the checkpoint; its column is the largest 1/2 m |v|^2 of the final state.
"""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest

from geompm.api import run as run_case
from geompm.contract import registry
from tests.support import fake_dist
from tests.support.cases import tiny_case

SCHEME = textwrap.dedent('''\
    import numpy as np

    from geompm.schemes.base import Field
    from geompm.schemes.usl import Usl


    class KineticUsl(Usl):
        name = "kinetic_usl"
        description = "test plugin: USL that keeps each particle's kinetic energy"
        default = False
        fields = (Field("p_ke", "", "J", "kinetic energy after the step"),)

        def step(self, run, dt):
            super().step(run, dt)
            st = run.state
            st.p_ke[:] = 0.5 * st.p_mass * (st.p_v ** 2).sum(axis=1)

        def series(self, run):
            return {"max_particle_ke": float(run.state.p_ke.max())}
    ''')


@pytest.fixture
def scheme_dist(tmp_path, monkeypatch):
    (tmp_path / "dist").mkdir()
    fake_dist.install(tmp_path / "dist", monkeypatch, "fake-geompm-scheme",
                      {"geompm.schemes": {"kinetic_usl": "fake_geompm_scheme:KineticUsl"}},
                      {"fake_geompm_scheme": SCHEME})
    yield
    registry.clear_cache()


def test_a_plugin_scheme_runs_by_name_with_its_field(scheme_dist, tmp_path):
    finals = {}
    for update in ("usl", "kinetic_usl"):
        case = tiny_case(name=update)
        case["solver"]["update"] = update
        case["outputs"] = [{"writer": "series", "interval": 0.0}]
        result = run_case(case, out=tmp_path / update, quiet=True)
        ckpt = sorted((tmp_path / update / "checkpoints").glob("step_*.npz"))[-1]
        with np.load(ckpt) as data:
            finals[update] = {k: data[k] for k in data.files if k.startswith("p_")}
        finals[update]["series"] = (tmp_path / update / "series.csv").read_text().splitlines()
        assert result.finished and result.status["steps"] > 10
    usl, mine = finals["usl"], finals["kinetic_usl"]
    assert np.array_equal(usl["p_x"], mine["p_x"]) and np.array_equal(usl["p_stress"], mine["p_stress"])
    assert "p_ke" not in usl and mine["p_ke"].shape == mine["p_mass"].shape
    ke = 0.5 * mine["p_mass"] * (mine["p_v"] ** 2).sum(axis=1)
    assert np.array_equal(mine["p_ke"], ke) and ke.max() > 0.0
    head = mine["series"][0].split(",")
    last = dict(zip(head, mine["series"][-1].split(",")))
    assert float(last["max_particle_ke"]) == pytest.approx(ke.max(), rel=1e-9)


def test_a_plugin_scheme_of_the_wrong_kind_is_refused(scheme_dist):
    """A dry scheme named for a case with pore water is refused at solver.update, naming the fitting one."""
    from geompm.errors import CaseError
    from geompm.schema.load import parse_case
    from tests.support.cases import CASES

    case = json.loads((CASES / "terzaghi_consolidation.json").read_text())
    case["solver"] = dict(case.get("solver", {}), update="kinetic_usl")
    with pytest.raises(CaseError) as err:
        parse_case(case, CASES)
    assert any(p == "solver.update" and "does not run saturated materials" in m and "saturated" in m
               for p, m in err.value.problems)
