"""The numerical envelope: small scenes at the extremes of each parameter (docs/numerical-envelope.md).

Each case asserts a stable run by harness.py's definition (no NaN or Inf,
kinetic energy never above E_k(0) + U_0 + W_g within 5%, every particle
inside the grid) or a refusal before the run.  The base scene is the source
study's soil column (section 3.2: rho 2650 kg/m3, E 0.84 MPa, nu 0.3,
phi 31 deg, c 0) at h = 0.02 m, Drucker-Prager, geostatic start.
"""

from __future__ import annotations

import pytest

from geompm.api import scene_from_dict
from geompm.cli import main
from geompm.errors import CaseError

from .harness import column, run

ELASTIC_DROP = {  # an elastic block dropped 4 cm onto the floor: it bounces, and nothing dissipates energy
    "materials.soil": {"model": "linear_elastic", "density": 2650.0, "youngs_modulus": 1e6, "poisson_ratio": 0.3},
    "bodies.0.initial_stress": "none", "bodies.0.geometry": {"type": "box", "min": [0.2, 0.04], "max": [0.4, 0.14]},
    "time.end": 1.0}
WATER = {"materials.soil": {"model": "newtonian", "density": 1000.0, "viscosity": 1e-6, "sound_speed": 20.0},
         "bodies.0.initial_stress": "none"}
IMPACT = {"bodies.0.velocity": [50.0, 0.0], "bodies.0.initial_stress": "none",
          "bodies.0.geometry": {"type": "box", "min": [0.2, 0.0], "max": [0.3, 0.1]},
          "time.end": 0.03, "grid.extent": [0.6, 1.0]}  # the elastic rebound splashes up to ~0.7 m by 0.03 s

SOIL = [  # (label, overrides): end times keep each run to a few thousand steps
    ("E = 1e3 Pa", {"materials.soil.youngs_modulus": 1e3}),
    ("E = 1e5 Pa", {"materials.soil.youngs_modulus": 1e5}),
    ("E = 1e8 Pa", {"materials.soil.youngs_modulus": 1e8, "time.end": 0.05}),
    ("E = 1e10 Pa", {"materials.soil.youngs_modulus": 1e10, "time.end": 0.005}),
    ("nu = 0", {"materials.soil.poisson_ratio": 0.0}),
    ("nu = 0.45", {"materials.soil.poisson_ratio": 0.45}),
    ("nu = 0.499", {"materials.soil.poisson_ratio": 0.499, "time.end": 0.1}),
    ("phi = 0", {"materials.soil.friction_angle": 0.0}),
    ("phi = 15", {"materials.soil.friction_angle": 15.0}),
    ("phi = 45", {"materials.soil.friction_angle": 45.0}),
    ("phi = 60", {"materials.soil.friction_angle": 60.0}),
    ("c = 1 MPa", {"materials.soil.cohesion": 1e6}),
    ("1 particle per cell", {"bodies.0.particles_per_cell": 1}),
    ("4x4 particles per cell", {"bodies.0.particles_per_cell": 4}),
    ("cfl = 0.1", {"time.cfl": 0.1, "time.end": 0.1}),
    ("cfl = 0.8", {"time.cfl": 0.8}),
    ("water, mu = 1e-6 Pa s", WATER),
    ("water, mu = 1e-6 Pa s, cfl = 0.6", {**WATER, "time.cfl": 0.6}),
    ("elastic drop, cfl = 0.8, 1 s", {**ELASTIC_DROP, "time.cfl": 0.8}),
    ("elastic drop, nu = 0.499", {**ELASTIC_DROP, "materials.soil.poisson_ratio": 0.499, "time.end": 0.2}),
    ("impact at 50 m/s", IMPACT),
    ("impact at 50 m/s, cfl = 0.8", {**IMPACT, "time.cfl": 0.8}),
    ("Cross, mu_0 = 1e4 mu_inf", {"materials.soil": {"model": "cross", "density": 2650.0, "sound_speed": 20.0,
                                                    "from_bingham": {"viscosity": 1.2, "yield_stress": 200.0}},
                                  "bodies.0.initial_stress": "none", "time.end": 0.01}),
]


def evp(model: str, **law) -> dict:
    """The column as a yield-stress fluid (rho0 2650 kg/m3, c 20 m/s) under the elasto-viscoplastic
    integration, G = rho0 c^2 / 4 = 265 kPa, over the whole collapse (0.3 s)."""
    mat = {"model": model, "density": 2650.0, "sound_speed": 20.0, "integration": "elastoviscoplastic", **law}
    return {"materials.soil": mat, "bodies.0.initial_stress": "none"}


def cross_ratio(ratio: float) -> dict:
    """Cross with mu_inf = 1.2 Pa s, mu_0 = ratio mu_inf, A = mu_0 / tau_B (tau_B = 200 Pa), m = 1."""
    return evp("cross", viscosity_infinity=1.2, viscosity_zero=1.2 * ratio, time_constant=1.2 * ratio / 200.0)


SOIL += [(f"Cross EVP, mu_0 = 1e{k} mu_inf", cross_ratio(10.0 ** k)) for k in range(2, 7)]
SOIL += [
    ("Bingham EVP, tau_B = 200 Pa", evp("bingham", viscosity=1.2, yield_stress=200.0)),
    ("Bingham EVP, tau_B = 1e5 Pa (stands)", evp("bingham", viscosity=1.2, yield_stress=1e5)),
    ("Herschel-Bulkley EVP, n = 0.5", evp("herschel_bulkley", consistency=5.0, flow_index=0.5, yield_stress=200.0,
                                          max_viscosity=1e4)),
    ("Herschel-Bulkley EVP, n = 1.5", evp("herschel_bulkley", consistency=5.0, flow_index=1.5, yield_stress=200.0,
                                          max_viscosity=1e4)),
]


@pytest.mark.parametrize("label, over", SOIL, ids=[s[0] for s in SOIL])
def test_stable_at_the_extremes(label, over):
    """Stable by the harness's definition, with the energy bound checked after every step."""
    out = run(column(**over))
    assert out.finite, f"{label}: NaN or Inf at step {out.steps}"
    assert out.inside, f"{label}: a particle left the grid at t = {out.time:.4g} s"
    assert out.energy_ratio <= 1.05, f"{label}: kinetic energy {out.energy_ratio:.3f} x what the run can supply"
    assert out.time == pytest.approx(column(**over)["time"]["end"])


def test_cohesive_column_stands():
    """c = 1 MPa: the 0.1 m column is far inside its strength (Rankine critical height 4c/(rho g)
    tan(45 + phi/2) ~ 300 m), so it must stand: the toe moves less than 1 mm and stays elastic."""
    out = run(column(**{"materials.soil.cohesion": 1e6}))
    assert out.front_x - 0.195 < 1e-3


def test_cfl_above_the_limit_is_refused_and_would_gain_energy():
    """cfl = 0.9 is refused with the limit named; forced past validation, the elastic drop shows why:
    at cfl = 1.0 its kinetic energy exceeds what gravity supplied (ratio > 1.05; measured 1279 before a
    particle leaves the grid, 3.24 before the Kirchhoff elasticity of issue 15, 1.79 before issue 17) while cfl = 0.8 stays within. Since the wave speed follows the current density (issue 16) the drop
    also holds at 0.9 (0.986; it gained 2.7 x before): the limit 0.8 keeps a margin."""
    with pytest.raises(CaseError) as exc:
        scene_from_dict(column(**{**ELASTIC_DROP, "time.cfl": 0.9}))
    assert "above the stable limit 0.8" in str(exc.value.problems)
    out = run(column(**ELASTIC_DROP), cfl=1.0)
    assert out.energy_ratio > 1.05
    assert run(column(**ELASTIC_DROP), cfl=0.8).energy_ratio < 1.0


def test_impact_at_50_m_s_is_stopped_by_the_wall_without_crushing_the_block():
    """A block launched at 50 m/s into a slip wall 0.3 m away (E = 0.84 MPa, c = 0: the dynamic pressure
    rho v^2 = 6.6 MPa is eight times E).  The wall holds it (no particle past x = 0.6 m, checked every step),
    no energy is created (kinetic energy <= 1.0 x the 33.1 kJ/m it starts with, measured 1.0000) and the
    block is compressed, not annihilated: the densest particle stays below 100 rho0 (measured 26.7 rho0;
    the elastic energy of the Kirchhoff law, (lambda + 2G) eps^2 / 2 with eps = ln(rho / rho0), matches the
    kinetic energy at 11 rho0 on average).  DP has no cap, so the compressed block rebounds elastically and
    keeps 12 % of its energy at 0.03 s (measured 4.0 kJ/m).  Before the Kirchhoff elasticity of issue 15
    the constant-modulus law let the force V sigma of a compressed particle vanish with its volume: the run
    "stopped at the wall" with densities of 3e31 rho0."""
    out = run(column(**IMPACT))
    assert out.finite and out.inside and out.energy_ratio <= 1.0 + 1e-9
    assert out.front_x <= 0.6 + 0.05 * 0.02
    assert out.rho_max < 100 * 2650
    assert out.kinetic_energy < 0.5 * 0.5 * 2650 * 0.01 * 50 ** 2


def test_cross_source_viscosity_reports_time_step_and_remedy(tmp_path, capsys):
    """The source's mu_0 = 1e4 mu_inf at h = 0.01 m: validate names the viscous step
    rho h^2 / (4 mu_0) = 2650 * 1e-4 / (4 * 12000) = 5.52e-6 s, the step count to 3.5 s (633 962),
    a measured run time and the remedies, and still exits 0 (the run is valid, only slow)."""
    import json

    from .harness import ROOT

    case = json.loads((ROOT / "cases" / "column_collapse_cross.json").read_text())
    path = tmp_path / "cross.json"
    path.write_text(json.dumps(case))
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    assert "set by viscosity: mu = 1.2e+04 Pa s" in out and "5.52e-06 s" in out
    assert "633,962 steps" in out and "on this machine" in out and "Remedies" in out


def test_validate_names_the_limit_and_what_the_other_integration_would_take(tmp_path, capsys):
    """The Cross column under "integration": "elastoviscoplastic": validate says the wave limit sets the
    step, cfl h / c_P with the P-wave speed c_P = sqrt(c^2 + 4 G / (3 rho0)), G = rho0 c^2 / 4:
    0.4 * 0.01 / sqrt(400 + 133.3) = 1.732e-4 s, and that the explicit integration would be held to its
    viscous limit 5.52e-6 s, 31.4x shorter.  For the explicit case the first remedy is the reverse."""
    import json

    from .harness import ROOT

    case = json.loads((ROOT / "cases" / "column_collapse_cross.json").read_text())
    case["materials"]["soil"]["integration"] = "elastoviscoplastic"
    path = tmp_path / "evp.json"
    path.write_text(json.dumps(case))
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    assert "set by the wave limit cfl h / (c + |v|) = 0.000173 s (viscous limit: none)" in out
    assert 'with "integration": "explicit" the step would be 5.52e-06 s, set by the viscous limit (31.4x shorter' in out
    path.write_text((ROOT / "cases" / "column_collapse_cross.json").read_text())
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    assert 'Remedies: (1) materials.soil: with "integration": "elastoviscoplastic" the step would be 0.000173 s' in out
    assert "(31.4x longer: 20,207 steps" in out
