"""Saturated soil in a case: `geompm validate` reports the pore water's step and consolidation coefficient,
and bad pore-water input is refused before any work with its JSON path (docs/pore-water.md, Case format).
"""

import copy
import json

import pytest

from geompm.cli import main
from geompm.errors import CaseError
from geompm.schema import parse_case

from tests.support.cases import CASES

TERZAGHI = json.loads((CASES / "terzaghi_consolidation.json").read_text())


def test_validate_reports_the_governing_wave_and_c_v(capsys):
    """The Terzaghi case: the undrained wave (1 268 m/s = sqrt((M + K_w/n)/rho_sat) with M = 131.9 MPa,
    K_w/n = 3.33 GPa, rho_sat = 2 155 kg/m3) sets the step, the explicit drag step 2 k/(n g) = 6.8e-4 s is
    reported, and c_v = k / (gamma_w (1/M + n/K_w)) = 12.94 m2/s with its 2.1 % loss against water's K_w."""
    assert main(["validate", str(CASES / "terzaghi_consolidation.json")]) == 0
    out = capsys.readouterr().out
    assert "set by the undrained wave" in out and "1268 m/s" in out
    assert "2 k / (n g) = 0.00068 s" in out
    assert "c_v = 12.94 m2/s" in out and "2.1 % smaller" in out


def _mutated(edit):
    case = copy.deepcopy(TERZAGHI)
    edit(case)
    return case


def _pw(case):
    return case["materials"]["soil"]["pore_water"]


@pytest.mark.parametrize("edit, path, words", [
    (lambda c: _pw(c).update(porosity=1.2), "materials.soil.pore_water.porosity", "must be < 1.0"),
    (lambda c: _pw(c).update(porosity=0.0), "materials.soil.pore_water.porosity", "must be > 0.0"),
    (lambda c: _pw(c).update(hydraulic_conductivity=-1e-3), "materials.soil.pore_water.hydraulic_conductivity",
     "must be > 0.0"),
    (lambda c: _pw(c).update(intrinsic_permeability=1e-10), "materials.soil.pore_water", "exactly one"),
    (lambda c: _pw(c).pop("hydraulic_conductivity"), "materials.soil.pore_water", "exactly one"),
    (lambda c: c["materials"]["soil"].update(model="newtonian", sound_speed=50.0, viscosity=1.0,
                                             youngs_modulus=None) or c["materials"]["soil"].pop("youngs_modulus")
     or c["materials"]["soil"].pop("poisson_ratio"), "materials.soil.pore_water", "fluid law"),
    (lambda c: c.update(gravity=[0.0, -9.81]) or c["bodies"][0]["pore_pressure"].update(water_table=5.0),
     "bodies.0.pore_pressure.water_table", "above the grid"),
    (lambda c: c["bodies"][0]["pore_pressure"].update(water_table=0.5), "bodies.0.pore_pressure.water_table",
     "needs gravity"),
    (lambda c: c["solver"].update(update="musl") if "solver" in c else c.update(solver={"update": "musl"}),
     "solver.update", "saturated"),
    (lambda c: _pw(c).update(cavitation_pressure=5e3), "materials.soil.pore_water.cavitation_pressure",
     "must be <= 0.0"),
    (lambda c: c["solver"].update(transfer="apic"), "solver.transfer", "unstable in motion"),
    (lambda c: _pw(c)["fluid"].update(bulk_modulus="incompressible"), "materials.soil.pore_water.fluid.bulk_modulus",
     "saturated_semi_implicit"),
    (lambda c: _pw(c)["fluid"].update(bulk_modulus=-1.0), "materials.soil.pore_water.fluid.bulk_modulus",
     "bulk modulus > 0 Pa"),
    (lambda c: _pw(c)["fluid"].update(bulk_modulus="water"), "materials.soil.pore_water.fluid.bulk_modulus",
     "or \"incompressible\""),
    (lambda c: c["solver"].update(update="saturated_semi_implicit", backend="cuda"), "solver.backend",
     "CPU backend only"),
    (lambda c: c["solver"].update(update="saturated_semi_implicit", pressure_solver={"tolerance": 0.0}),
     "solver.pressure_solver.tolerance", "must be > 0"),
    (lambda c: c["solver"].update(update="saturated_semi_implicit", pressure_solver={"tolerance": 1.0}),
     "solver.pressure_solver.tolerance", "must be < 1"),
    (lambda c: c["solver"].update(update="saturated_semi_implicit", pressure_solver={"max_iterations": 0}),
     "solver.pressure_solver.max_iterations", ">= 1"),
])
def test_bad_pore_water_input_is_refused_with_its_path(edit, path, words):
    """Each edit of the valid Terzaghi case is refused before any work, naming its JSON path."""
    with pytest.raises(CaseError) as err:
        parse_case(_mutated(edit), CASES)
    hits = [m for p, m in err.value.problems if p == path]
    assert hits and any(words in m for m in hits), err.value.problems


def test_a_saturated_flow_above_the_converged_cfl_is_warned():
    """The saturated APIC step converges in time on a flow only at cfl <= 0.1 (docs/pore-water.md: a 2D
    flume's front at 0.8 s 2.29 / 2.57 / 2.68 m at cfl 0.4 / 0.2 / 0.1): a saturated case above it is warned at
    time.cfl (not refused: consolidation is verified at 0.4), the shipped flow case is not, nor a PIC case."""
    def warned(case):
        return [p for p, _ in parse_case(case, CASES).warnings if p == "time.cfl"]

    def apic(c, cfl):
        c["time"].update(cfl=cfl)
        c["grid"].update(shape_function="quadratic")
        c["solver"].update(transfer="apic")

    assert warned(_mutated(lambda c: apic(c, 0.4))) == ["time.cfl"]
    assert warned(_mutated(lambda c: apic(c, 0.1))) == []
    assert warned(_mutated(lambda c: c["time"].update(cfl=0.4))) == []  # the shipped FLIP
    assert warned(_mutated(lambda c: c["time"].update(cfl=0.4) or c.setdefault("solver", {}).update(
        transfer="pic"))) == []
    assert warned(json.loads((CASES / "saturated_debris_obstacle.json").read_text())) == []


def test_a_semi_implicit_flow_above_the_converged_cfl_is_warned_whatever_its_transfer():
    """Under the semi-implicit step a spreading saturated flow loses pore pressure above cfl 0.1 with PIC too
    (docs/pore-water.md: a 2D block on a slip bed at cfl 0.4, mean p -291 against +55 Pa): the Terzaghi case
    with PIC at cfl 0.4 is warned at time.cfl under it and not under the explicit step; at cfl 0.1 not."""
    def warned(case):
        return [m for p, m in parse_case(case, CASES).warnings if p == "time.cfl"]

    def pic(c, cfl, update):
        c["time"].update(cfl=cfl)
        c.setdefault("solver", {}).update(transfer="pic", update=update)

    hits = warned(_mutated(lambda c: pic(c, 0.4, "saturated_semi_implicit")))
    assert len(hits) == 1 and "semi-implicit" in hits[0] and "whatever the transfer" in hits[0], hits
    assert warned(_mutated(lambda c: pic(c, 0.4, "saturated"))) == []
    assert warned(_mutated(lambda c: pic(c, 0.1, "saturated_semi_implicit"))) == []


def test_apic_with_linear_hats_is_warned_in_a_dry_case():
    """APIC with linear hats, refused for saturated soil (above), is warned at solver.transfer in a dry case
    (a quasi-static strength reduction is verified with it) and not with FLIP: the free-flight block
    (benchmarks/envelope/free_flight.py) leaves the grid at 0.13 s with it, its kinetic energy kept within
    4e-10 by FLIP."""
    dry = _mutated(lambda c: c["materials"]["soil"].pop("pore_water") and c["bodies"][0].pop("pore_pressure"))
    dry["solver"]["transfer"] = "apic"
    hits = [m for p, m in parse_case(dry, CASES).warnings if p == "solver.transfer"]
    assert len(hits) == 1 and "unstable in motion" in hits[0] and "'flip'" in hits[0], hits
    dry["solver"]["transfer"] = "flip"
    assert [p for p, _ in parse_case(dry, CASES).warnings if p == "solver.transfer"] == []


def test_validate_reports_the_semi_implicit_step(capsys):
    """The Terzaghi case with water's K_w = 2.2e9 Pa, semi-implicit: the skeleton's wave (266.7 m/s =
    sqrt(M / rho_d), M = 131.9 MPa, rho_d = 1 855 kg/m3) sets the step, and the explicit step's undrained wave
    sqrt((M + K_w/n) / rho_sat) = 1 861 m/s would take 6.98 times more steps; c_v with K_w 13.21 m2/s,
    13.45 m2/s incompressible."""
    assert main(["validate", str(CASES / "terzaghi_consolidation.json"), "--set",
                 "solver.update=saturated_semi_implicit", "--set",
                 "materials.soil.pore_water.fluid.bulk_modulus=2.2e9"]) == 0
    out = capsys.readouterr().out
    assert "pore water: semi-implicit" in out and "266.7 m/s" in out and "1861 m/s" in out
    assert "6.98 times more steps" in out and "c_v = 13.21 m2/s" in out and "13.45 m2/s with incompressible" in out


def test_a_periodic_axis_is_refused_by_the_semi_implicit_step():
    """The flowing strip (periodic along x) with the semi-implicit step: CaseError at set-up, before any step,
    naming the boundary and the explicit scheme that runs it."""
    from geompm.api import scene_from_dict
    from geompm.testing.verification.flowing_strip import strip_case

    case = strip_case(0.04)
    case["solver"]["update"] = "saturated_semi_implicit"
    with pytest.raises(CaseError) as err:
        scene_from_dict(case)
    assert any(p == "boundaries" and "periodic" in m and "saturated" in m for p, m in err.value.problems)


def test_a_pressure_solve_that_does_not_converge_stops_with_exit_3(tmp_path, caplog):
    """The Terzaghi case, semi-implicit, allowed one CG iteration to a relative residual of 1e-12: `geompm run`
    stops at the first step with exit 3, the message naming the step and the residual, and the run folder's
    status.json says it failed."""
    case = copy.deepcopy(TERZAGHI)
    case["solver"].update(update="saturated_semi_implicit", pressure_solver={"max_iterations": 1, "tolerance": 1e-12})
    path = tmp_path / "case.json"
    path.write_text(json.dumps(case))
    out = tmp_path / "run"
    rc = main(["run", "--quiet", "--out", str(out), str(path)])
    err = caplog.text
    assert rc == 3, err
    assert "did not converge at step 1" in err and "relative residual" in err, err
    status = json.loads((out / "status.json").read_text())
    assert status["finished"] is False and "did not converge" in status["reason"], status
