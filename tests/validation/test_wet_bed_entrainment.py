"""The wet bed of cases/wet_bed_entrainment.json at rest: saturated at p = 0 (pore_pressure.hydrostatic
false, as the tensiometers of Iverson et al. 2011, Nature Geoscience 4:116, read before release), its
skeleton carrying the water's weight too; and the sign of the experiment's contrast between a wet and a
dry bed (docs/validation/wet-bed-entrainment.md: measured, not validated)."""

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing.verification.cases import shipped_case
from geompm.testing.verification.wet_bed import bed_case, run


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


@pytest.mark.slow
def test_over_a_wet_bed_the_bed_is_mobilised_and_the_momentum_doubles():
    """Iverson et al. 2011's sign at h = 0.04 m to t = 1 s (benchmarks/pore_water/wet_bed.py): over the wet bed
    more than half of its 1 050 kg/m moves more than 5 cm down the slope (measured 713, and 776 at h = 0.02 m)
    and the peak momentum along the slope is more than 1.5 times the dry bed's (measured 345 against 183;
    364 against 184 at 0.02 m); over the dry bed nothing moves 5 cm and the debris's front ends no farther.
    Not converged: at h = 0.0267 m neither bed moves (docs/validation/wet-bed-entrainment.md)."""
    wet, dry = run(0.04, "wet", end=1.0), run(0.04, "dry", end=1.0)
    assert wet["entrained"] > 525.0, wet["entrained"]
    assert dry["entrained"] == 0.0, dry["entrained"]
    assert wet["peak_momentum"] > 1.5 * dry["peak_momentum"], (wet["peak_momentum"], dry["peak_momentum"])
    assert wet["runout"] >= dry["runout"], (wet["runout"], dry["runout"])
