"""Time each pass of the saturated step (schemes/saturated/cpu.py, schemes/saturated/scheme.py) on the
bench scene saturated3d, warm, and the dry step of dp3d beside it, in ns per particle-step.

    python benchmarks/pore_water/passes.py [STEPS]

The passes are run in the order of one step, each timed on its own; the sum is compared with a whole
step. docs/pore-water.md, Speed and memory.
"""

import json
import sys
import time
from pathlib import Path

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

HERE = Path(__file__).resolve().parents[1]


def no_halo(arrays):
    """One process: no neighbour's partial sums to add."""


def timed(table, name, fn, *args, **kw):
    t = time.perf_counter()
    fn(*args, **kw)
    table[name] = table.get(name, 0.0) + time.perf_counter() - t


def p2g_parts(table, wet, view):
    """SaturatedCpu.p2g, pass by pass."""
    from geompm.schemes.saturated import kernels as tp

    cpu, st, g, pw = wet.cpu, wet.cpu.state, wet.scene.grid, wet.pw
    wet._particles()
    nn = wet._nodes(view)
    if wet.smoothing:
        timed(table, "p2g: pore pressure seen through the grid (a P2G and a G2P)", wet._smooth, view, no_halo,
              st.p_pore_carried, st.p_pore)
    timed(table, "p2g: total stress, water mass, drag (prepare)", tp.prepare, st.p_stress, st.p_pore, st.p_n,
          st.p_sat, st.p_vol, st.p_material, pw.table, wet.p_total, wet.p_wmass, wet.p_drag)
    timed(table, "p2g: solid P2G (the dry kernel)", cpu.p2g_kernel, cpu.tag, cpu.scheme, st.p_x, st.p_v, st.p_C,
          st.p_mass, st.p_vol, wet.p_total, g.origin, g.h, g.kind, view.lo, view.nloc, cpu.buffers.c_grid, True,
          1.0, wet.scene.apic_dinv, view.g_mass, view.g_mom, view.g_force)
    timed(table, "p2g: water P2G", tp.water_p2g, cpu.tag, st.p_x, st.p_vw, st.p_Cw, wet.affine, wet.p_wmass, wet.p_drag, st.p_vol,
          st.p_n, st.p_pore, st.p_sat, st.p_material, pw.table, g.origin, g.h, g.kind, view.lo, view.nloc,
          wet.c_w[:, :nn], wet.g_w[:nn])
    timed(table, "p2g: water chunk sum", tp.sum_chunks, wet.c_w[:, :nn], wet.g_w[:nn])
    timed(table, "p2g: node fill", tp.node_fill, wet.g_w[:nn], pw.walls, g.origin, g.h, view.lo, view.nloc,
          g.h ** wet.scene.dim, wet.g_fill[:nn])
    timed(table, "p2g: node mixture", tp.node_mixture, view.g_mass, view.g_mom, wet.g_w[:nn], cpu.mass_eps,
          wet.g_rel[:nn])


def water_parts(table, wet, view, dt):
    """SaturatedCpu.water_g2p, pass by pass."""
    from geompm.schemes.saturated import kernels as tp

    st, g, nn, pw = wet.cpu.state, wet.scene.grid, view.g_vel.shape[0], wet.pw
    timed(table, "water G2P", tp.water_g2p, wet.cpu.tag, st.p_x, st.p_vw, st.p_Cw, wet.affine, wet.scene.apic_dinv,
          wet.p_divw, wet.p_divs, wet.p_fill, wet.g_vw[:nn], view.g_vel, wet.g_fill[:nn], g.origin, g.h, g.kind,
          view.lo, view.nloc)
    timed(table, "pressure increment", tp.flag_drained, wet.p_fill, st.p_sat, st.p_n, st.p_material, pw.table,
          st.p_drained)
    timed(table, "pressure increment", tp.pressure_increment, wet.p_dp, wet.p_divw, wet.p_divs, st.p_n,
          st.p_material, pw.table, dt)
    dp = wet.p_dp
    if wet.smoothing:
        timed(table, "increment seen through the grid (a P2G and a G2P)", wet._smooth, view, no_halo, wet.p_dp,
              wet.p_dps)
        dp = wet.p_dps
    timed(table, "pressure increment", tp.add_increment, st.p_pore_carried, st.p_pore, dp, st.p_drained)


def saturated_passes(steps):
    sim = Simulation(scene_from_dict(json.loads((HERE / "saturated3d.json").read_text())))
    for _ in range(3):  # compile and settle
        sim.step(sim.stable_dt())
    be, wet, cpu = sim.backend, sim.backend.passes, sim.backend
    table = {}
    for _ in range(steps):
        dt = sim.stable_dt()
        view = be.window()
        p2g_parts(table, wet, view)
        timed(table, "grid update", be.grid_update, view, dt)
        for stage in sim.grid_stages:
            timed(table, "grid stages", be.grid_stage, stage, view, dt, sim.time, False)
        timed(table, "node_relative + snapshot", wet.snapshot, view, dt)
        timed(table, "node_split", wet.split, view, dt)
        water_parts(table, wet, view, dt)
        timed(table, "solid G2P", be.g2p, view, dt, set_velocity=True, move=True, gradient=True)
        for stage in sim.particle_stages:
            timed(table, "particle stages", be.particle_stage, stage, dt, sim.time)
        timed(table, "porosity", wet.porosity)
        timed(table, "stress update", cpu.update_stress, dt)
        sim.time += dt
        sim.step_count += 1
    n = sim.state.n
    return {k: v / steps / n * 1e9 for k, v in table.items()}, n


def whole_step(case, steps):
    sim = Simulation(scene_from_dict(json.loads((HERE / case).read_text())))
    for _ in range(3):
        sim.step(sim.stable_dt())
    t = time.perf_counter()
    for _ in range(steps):
        sim.step(sim.stable_dt())
    return (time.perf_counter() - t) / steps / sim.state.n * 1e9


def main(steps=20):
    passes, n = saturated_passes(steps)
    print(f"saturated3d, {n} particles, {steps} steps, ns per particle-step:")
    for k, v in sorted(passes.items(), key=lambda kv: -kv[1]):
        print(f"  {v:8.1f}  {k}")
    print(f"  {sum(passes.values()):8.1f}  sum of the passes")
    print(f"whole step: saturated3d {whole_step('saturated3d.json', steps):.1f}, dp3d {whole_step('dp3d.json', steps):.1f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)
