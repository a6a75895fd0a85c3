"""The material kernel contract (materials/base.py, contract/layout.py, backend/cpu_loops.py; issue 17).

A law is two per-particle @njit functions; the backend writes the loop that runs them over a block
as a module in its kernel folder (so numba caches it) or, for a law that cannot be imported by name,
as an uncached closure: both give the same stresses.  Parameters are read by name from a layout that
``pack`` must fill exactly.  geompm never replaces a loop file it did not write.
"""

import numpy as np
import pytest
from numba import njit

from geompm.backend import codegen, cpu_loops
from geompm.materials.drucker_prager import DP, DruckerPrager, dp_stress
from geompm.contract.layout import pack_in_layout, param_layout
from geompm.materials.plasticity import ELASTIC
from geompm.testing import update_stress


def _shear_block(n=32):
    rng = np.random.default_rng(0)
    L = np.zeros((n, 3, 3))
    L[:, 0, 1] = rng.uniform(5.0, 50.0, n)
    L[:, 1, 1] = rng.uniform(-5.0, 5.0, n)
    stress = np.zeros((n, 6))
    stress[:, :3] = -1e4
    return L, np.full(n, 2650.0), stress


def test_layouts_name_the_slots_and_extend_each_other():
    assert DP[:3] == ELASTIC == (0, 1, 2)
    assert DP.alpha == 3 and DP.dilation_cutoff == 7 and len(DP) == 10
    with pytest.raises(ValueError, match="duplicate"):
        param_layout(ELASTIC, "G")


def test_pack_must_fill_the_layout_exactly():
    with pytest.raises(TypeError, match=r"missing \['G'\], unexpected \['shear'\]"):
        pack_in_layout(ELASTIC, {"density": 1.0, "lam": 2.0, "shear": 3.0}, "mine")


def test_a_law_defined_in_a_function_runs_through_the_uncached_loop():
    """The same DP arithmetic behind a closure-defined function: the backend cannot import it by name,
    builds the loop in-process, and the stresses equal the module-level law's to the bit."""
    @njit
    def local_dp(prm, dt, L, rho, s, state):
        dp_stress(prm, dt, L, rho, s, state)

    class LocalDP(DruckerPrager):
        name = "local_dp"
        particle_stress = local_dp

    assert not codegen.importable(local_dp) and codegen.importable(dp_stress)
    out = []
    for law in (DruckerPrager, LocalDP):
        mat = law(DruckerPrager.example_params())
        L, rho, stress = _shear_block()
        state = mat.initial_state(len(rho))
        for _ in range(20):
            update_stress(mat, 1e-3, L, rho, stress, state)
        out.append((stress, state))
    assert out[0][1][:, 0].max() > 0  # it yielded
    np.testing.assert_array_equal(out[1][0], out[0][0])
    np.testing.assert_array_equal(out[1][1], out[0][1])


def test_the_stress_loop_reports_the_largest_stretching_rate():
    """max |L_ii| (the strain-increment limit's input): here the |L_yy| up to 5 1/s, not the shear
    L_xy up to 50 1/s, which changes no volume."""
    mat = DruckerPrager(DruckerPrager.example_params())
    L, rho, stress = _shear_block()
    rate = update_stress(mat, 1e-3, L, rho, stress, mat.initial_state(len(rho)))
    assert rate == np.abs(np.diagonal(L, axis1=1, axis2=2)).max() and rate < 5.0 < np.abs(L).max()


def test_a_loop_file_geompm_did_not_write_is_never_replaced(tmp_path):
    foreign = tmp_path / "loop_x.py"
    foreign.write_text("print('mine')\n")
    with pytest.raises(RuntimeError, match="not written by geompm"):
        codegen.write_if_changed(foreign, codegen.HEADER + "x = 1\n")
    assert foreign.read_text() == "print('mine')\n"
    ours = tmp_path / "loop_y.py"
    codegen.write_if_changed(ours, codegen.HEADER + "x = 1\n")
    codegen.write_if_changed(ours, codegen.HEADER + "x = 2\n")
    assert ours.read_text().endswith("x = 2\n")


def test_the_generated_loop_names_the_law_and_its_source_digest():
    stress_block, _ = cpu_loops.block_loops(DruckerPrager)
    path = stress_block.py_func.__code__.co_filename
    text = open(path).read()
    assert text.startswith(codegen.HEADER)
    assert "geompm.materials.drucker_prager.dp_stress" in text and "sha256" in text
    assert DP.lam == 1  # the layout the loop's law reads
