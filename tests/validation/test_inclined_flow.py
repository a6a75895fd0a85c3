"""Section 3.1 of the source study (shared design notes, restated in docs/validation/seed-inclined-flow.md):
the 3D Drucker-Prager granular column down a 10 degree incline, at the source's two coarser meshes.

The source reports that the kinetic energy K*(T*) converges to within 5 % over h = 0.02, 0.01 and
0.005 m and that the fronts agree.  This test runs cases/inclined_flow.json to T* = 3 (t = 0.36 s, past
the K* peak at T* ~ 1.2 and into the deceleration) at h = 0.02 and 0.01 m and asserts:
- the K* peaks of the two meshes within 5 % of each other, the source's claim (measured: 0.0291 and
  0.0304, 4.3 %);
- the peak itself between 0.02 and 0.05 and the front past X* = 0.5 at T* = 3 at both meshes, i.e. the
  column does accelerate and run out rather than stall or run away.
The fronts are not asserted to agree: at T* = 3 they are 0.817 and 0.913 (10.5 % apart), and at the end
0.999, 1.069 and 0.975 at h = 0.02, 0.01, 0.005 m, not converging (the doc gives the measurements and
the artificial damping's share, zeta = xi sqrt(E/rho) / h growing fourfold from the coarsest to the
finest mesh).
"""

from __future__ import annotations

import numpy as np
import pytest

from geompm.cli import main
from geompm.study.metrics import read_series

from tests.support.cases import CASES


@pytest.mark.slow
def test_coarse_pair_agrees_on_the_kinetic_energy_peak(tmp_path):
    out = {}
    for h in (0.02, 0.01):
        run = tmp_path / f"h{h}"
        assert main(["run", str(CASES / "inclined_flow.json"), "--set", f"grid.cell_size={h}", "--set",
                     "time.end=0.36", "--set", "outputs=[{\"writer\": \"series\", \"interval\": 0.01, "
                     "\"normalise\": {\"length\": 0.2, \"height\": 0.14, \"origin\": [0, 0, 0], "
                     "\"direction\": [1, 0, 0]}}]", "--quiet", "--out", str(run)]) == 0
        s = read_series(run / "series.csv")
        out[h] = (float(s["K_star"].max()), float(np.interp(3.0, s["T_star"], s["X_star"])))
    (k2, x2), (k1, x1) = out[0.02], out[0.01]
    assert 0.02 < k2 < 0.05 and 0.02 < k1 < 0.05
    assert abs(k2 - k1) / k1 < 0.05, out
    assert x2 > 0.5 and x1 > 0.5, out
