"""The CPU backend's loops over a material block, generated from the law's per-particle functions.

A law gives two ``@njit`` functions for one particle (materials/base.py):

    particle_stress(prm, dt, L, rho, s, state)   # L (3, 3), s (6,), state (k,) views; in place
    particle_wave_speed(prm, rho) -> float        # [m/s]

and the backend owns the loops that run them over a block:

    stress_block(prm, dt, p_L, p_rho, p_stress, p_state) -> max |L_ii| over the block
    wave_speed_block(prm, p_rho) -> float     the law's speed at the block's lowest and highest
                                              density, the larger of the two

The stress loop returns the largest stretching rate |L_ii| of the block as a
by-product (the particles' L is in cache there), for the next step's
strain-increment limit (backend/timestep.py), which would otherwise cost a
pass of its own over p_L (3 ns per particle, 4 % of a dp2d step); the three
diagonal entries cost 0.8 ns per particle there, all nine 2.1 ns.  The wave
speed is evaluated at two densities only, so ``particle_wave_speed`` must be
monotone in the density (elastic: decreasing; Tait: increasing;
``geompm.testing`` checks it): a per-particle evaluation of the Tait speed,
a power per particle, cost 107 ns per particle on fluid3d, more than the
rest of the step.

The law's functions are compiled into the loops with the law's own fastmath
flags, and the loops are written as a module per law so numba caches them
(backend/codegen.py).
"""

from __future__ import annotations

from geompm.backend.codegen import loops

#: the loops over a block, around ``law_stress`` and ``law_wave`` (the law's functions, inlined)
BODY = '''
@njit(parallel=True, fastmath={fm_law_stress}, cache=True)
def stress_block(prm, dt, p_L, p_rho, p_stress, p_state):
    rate = 0.0  # max |L_ii| over the block, for the next step's strain-increment limit
    for p in prange(p_L.shape[0]):
        L = p_L[p]
        law_stress(prm, dt, L, p_rho[p], p_stress[p], p_state[p])
        rate = max(rate, max(abs(L[0, 0]), max(abs(L[1, 1]), abs(L[2, 2]))))
    return rate


@njit(parallel=True, cache=True)
def wave_speed_block(prm, p_rho):
    lo = np.inf
    hi = -np.inf
    for p in prange(p_rho.shape[0]):
        lo = min(lo, p_rho[p])
        hi = max(hi, p_rho[p])
    if hi < lo:
        return 0.0
    return max(law_wave(prm, lo), law_wave(prm, hi))
'''


#: the stress loop regularised by a relaxation time (kernels/viscoplastic.py), for a law with an elastic predictor
RELAXED = '''
@njit(parallel=True, fastmath={fm_law_stress}, cache=True)
def relaxed_block(prm, dt, p_L, p_rho, p_stress, p_state, p_old, r):
    rate = 0.0
    for p in prange(p_L.shape[0]):
        L = p_L[p]
        keep(p_stress[p], p_state[p], p_old[p])
        law_stress(prm, dt, L, p_rho[p], p_stress[p], p_state[p])
        relax(p_stress[p], p_state[p], p_old[p], law_predictor(prm, dt, L, p_rho[p], p_old[p]), r)
        rate = max(rate, max(abs(L[0, 0]), max(abs(L[1, 1]), abs(L[2, 2]))))
    return rate
'''


def relaxed_loop(law):
    """The stress loop of a law with ``elastic_predictor``, Duvaut-Lions regularised (kernels/viscoplastic.py)."""
    from geompm.kernels.viscoplastic import keep_one, relax_one

    return loops("law_relaxed", {"law_stress": law.particle_stress, "law_predictor": law.elastic_predictor,
                                 "keep": keep_one, "relax": relax_one}, RELAXED, ("relaxed_block",))[0]


def block_loops(law):
    """(stress_block, wave_speed_block) of a material class."""
    stress, wave = law.particle_stress, law.particle_wave_speed
    if stress is None or wave is None:
        raise TypeError(f"material '{law.name}' must define particle_stress and particle_wave_speed "
                        "(docs/how-to/write-a-material-plugin.md)")
    return loops("law", {"law_stress": stress, "law_wave": wave}, BODY, ("stress_block", "wave_speed_block"))


def update_law_block(mat, dt, p_L, p_rho, p_stress, p_state, relax=None) -> float:
    """Advance the stress of a block of particles of material ``mat`` in place through its law's loop (the one
    the engine runs); returns the block's largest stretching rate |L_ii| [1/s].  ``relax``: (p_old scratch
    (n, 6 + state width), dt / tau) for the viscoplastic regularisation of a law with an elastic predictor."""
    if relax is not None:
        return float(relaxed_loop(type(mat))(mat.prm, dt, p_L, p_rho, p_stress, p_state, relax[0], relax[1]))
    return float(block_loops(type(mat))[0](mat.prm, dt, p_L, p_rho, p_stress, p_state))


def law_wave_speed(mat, p_rho) -> float:
    """Largest wave speed [m/s] of material ``mat`` over a block of particles with densities ``p_rho``."""
    return float(block_loops(type(mat))[1](mat.prm, p_rho))
