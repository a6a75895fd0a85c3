"""Energy trace of the dilatant column (issue 16): per-step plastic work, elastic energy and the fastest particle.

    python benchmarks/envelope/energy_trace.py PSI H [--reference-density] [--set KEY=VALUE ...]

Runs cases/column_collapse.json with materials.soil.dilation_angle = PSI and grid.cell_size = H and
prints every 200 steps (and every step once a particle exceeds 3 m/s): kinetic energy, the energy
gravity released, the elastic energy sum V (p^2 / (2K) + s:s / (4G)), the summed numerical plastic
work V (sigma_n : D dt - dW_e) and its negative part, and the fastest particle's position, density,
pressure and state. ``--reference-density`` restores the wave speed of before issue 16,
sqrt((lambda + 2G) / rho0). This is the probe behind the cause in docs/numerical-envelope.md ("Dilatancy").
"""
import sys
from pathlib import Path

import numpy as np
from geompm.api import scene_from_file
from geompm.engine.scheduler import Simulation

sys.path.insert(0, str(Path(__file__).resolve().parent))
from dilatancy_sweep import use_reference_density  # noqa: E402
psi, h = float(sys.argv[1]), float(sys.argv[2])
reference = "--reference-density" in sys.argv
extra = [a for a in sys.argv[3:] if a not in ("--set", "--reference-density")]
sets = [f"materials.soil.dilation_angle={psi}", f"grid.cell_size={h}", "time.end=0.8"] + extra
sc = scene_from_file(Path(__file__).resolve().parents[2] / "cases" / "column_collapse.json", sets)
sim = Simulation(sc)
st = sim.state
mat = sc.materials[0]
prm, E = mat.prm, mat.layout
rho0, lam, G = prm[E.density], prm[E.lam], prm[E.G]
K = lam + 2*G/3
if reference:
    use_reference_density(mat)
def we(s):
    m = s[:, :3].sum(1)/3
    dev2 = ((s[:, :3]-m[:, None])**2).sum(1) + 2*(s[:, 3:]**2).sum(1)
    return 0.5*(9*m*m/(9*K)) + dev2/(4*G)   # 1/2 p^2/K + s:s/(4G)
def sym_dot(s, L):
    D = 0.5*(L+np.transpose(L, (0, 2, 1)))
    return s[:,0]*D[:,0,0]+s[:,1]*D[:,1,1]+s[:,2]*D[:,2,2]+2*(s[:,3]*D[:,0,1]+s[:,4]*D[:,1,2]+s[:,5]*D[:,0,2])
Wp = np.zeros(st.n); neg = 0.0; pos = 0.0
g = 9.81
PE0 = (st.p_mass*st.p_x[:,1]).sum()*g
E_el0 = (we(st.p_stress)*st.p_vol).sum()
step = 0
hist = []
while sim.time < 0.8:
    dt = sim.stable_dt()
    s_old = st.p_stress.copy(); we_old = we(s_old)
    sim.step(dt)
    vol = st.p_vol
    w_in = sym_dot(s_old, st.p_L)*dt  # per unit volume (sigma_n : D dt)
    dwe = we(st.p_stress) - we_old
    dp = (w_in - dwe)*vol   # numerical plastic dissipation [J]
    Wp += dp
    neg += dp[dp < 0].sum(); pos += dp[dp > 0].sum()
    step += 1
    ke = 0.5*(st.p_mass*(st.p_v**2).sum(1)).sum()
    vmax = np.sqrt((st.p_v**2).sum(1)).max()
    if step % 200 == 0 or vmax > 3:
        PE = (st.p_mass*st.p_x[:,1]).sum()*g
        Eel = (we(st.p_stress)*st.p_vol).sum()
        i = np.argmax((st.p_v**2).sum(1))
        print(f"step {step} t={sim.time:.4f} dt={dt:.2e} KE={ke:.4f} dPE={PE0-PE:.4f} Eel={Eel:.4f} Dplast={Wp.sum():.4f} neg={neg:.4f} "
              f"vmax={vmax:.2f} i={i} x={st.p_x[i]} rho={st.p_rho[i]:.0f} p={-st.p_stress[i,:3].mean():.1f} Wp_i={Wp[i]:.2e} state={sc.state.p_state[0][i]}", flush=True)
    if vmax > 10: break
