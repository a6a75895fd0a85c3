"""The wet bed of cases/wet_bed_entrainment.json at rest: saturated at p = 0 (pore_pressure.hydrostatic
false, as the tensiometers of Iverson et al. 2011, Nature Geoscience 4:116, read before release), its
skeleton carrying the water's weight too.  The flow over it is measured, not validated
(docs/validation/wet-bed-entrainment.md)."""

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing.verification.cases import shipped_case
from geompm.testing.verification.wet_bed import bed_case


def test_a_bed_saturated_at_zero_pressure_starts_on_its_full_weight():
    """The bed (h = 0.04 m, 31 degree flume, geostatic in the slope's frame: surface_normal [0, 1]) at t = 0:
    every particle is saturated at p = 0 and the effective stress normal to the bed at its lowest row is the
    whole saturated weight rho_sat g cos(31) depth within 2 % (rho_sat = (1 - n) rho_s + n rho_w =
    2 020 kg/m3; a buoyant start, as below a water table, would give 52 % of it), with the infinite slope's
    shear, tan(31) times it."""
    case = bed_case(0.04, "wet", 0.2)
    case["bodies"] = case["bodies"][1:]
    case["obstacles"] = []
    sim = Simulation(scene_from_dict(case, base_dir=shipped_case("wet_bed_entrainment.json").parent))
    st = sim.state
    assert np.all(st.p_sat == 1.0) and np.all(st.p_pore == 0.0)
    low = st.p_x[:, 1] < st.p_x[:, 1].min() + 1e-9
    depth = 0.08 - st.p_x[low, 1]
    full = 2020.0 * 9.81 * np.cos(np.radians(31.0)) * depth
    assert np.allclose(-st.p_stress[low, 1], full, rtol=0.02), (-st.p_stress[low, 1][:3], full[:3])
    assert np.allclose(np.abs(st.p_stress[low, 3]), np.tan(np.radians(31.0)) * full, rtol=0.02)
