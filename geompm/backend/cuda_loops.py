"""The CUDA backend's kernels around a plugin's per-item functions: one law source for CPU and GPU.

A law's ``particle_stress`` and a stage's ``node_rule``, ``node_image`` and
``particle_rule`` are the same ``@njit`` functions the CPU loops inline
(backend/cpu_loops.py, cpu_stage_loops.py).  Here each becomes the body of
a CUDA kernel, one thread per particle or node:

- on a GPU the kernel calls the CPU dispatcher itself, which numba-cuda
  compiles as a device function (with every ``@njit`` helper it calls), so
  the function must stay in the CUDA subset: no array creation, no
  ``np.linalg``, no Python objects;
- every kernel but ``each_kernel`` (the saturated scheme's, which holds no step) returns at once where
  ``halt[0]`` is set: a held batch that ended before its step (engine/held_step.py);
- under numba-cuda's simulator (``NUMBA_ENABLE_CUDASIM=1``) a kernel runs as
  Python, and a CPU dispatcher cannot take the simulator's array wrappers:
  the kernel calls it through ``simulator_call``, which hands it the numpy
  arrays underneath, so the compiled CPU function runs inside the simulated
  kernel.

A thread's ``work`` scratch and ``out`` accumulator are local arrays whose
sizes are compiled into the kernel (the stage's ``node_scratch`` and
reduction length); a thread adds its ``out`` into the pass's single row with
atomics, taking the maximum instead for the slots a stage lists in
``node_maxima`` / ``particle_maxima`` (contract/stages.py).  The kernels are made
per process (exec'd source, not cached on disk); each keeps the recipe that builds it again
(``__geompm_recipe__``), from which backend/cuda_ptx.py compiles it for a GPU without one.
"""

from __future__ import annotations

import functools
import math
import os
import re

from numba import cuda, float64, int64, njit

from geompm.kernels.step_end import END_ROW

_CACHE: dict = {}


def simulated() -> bool:
    return os.environ.get("NUMBA_ENABLE_CUDASIM", "0") not in ("", "0")


#: threads per block of every launch (the simulator runs each thread as a Python thread: fewer there)
THREADS = 32 if simulated() else 128


def simulator_call(fn):
    """fn, callable from a simulated kernel: the simulator's array wrappers unwrapped to numpy."""
    from numba.cuda.simulator.cudadrv.devicearray import FakeCUDAArray, FakeWithinKernelCUDAArray

    def host(a):
        if isinstance(a, FakeWithinKernelCUDAArray):
            a = a._item
        return a._ary if isinstance(a, FakeCUDAArray) else a

    def call(*args):
        return fn(*[host(a) for a in args])

    return call


def _device(fn):
    return simulator_call(fn) if simulated() else fn


#: a law's update of particle ``p`` (velocity gradient ``L``): its ``particle_stress`` (LAW_CALL), or that regularised
#: by a relaxation time (RELAXED_CALL: kernels/viscoplastic.py; cpu_loops.RELAXED), ``relax_r`` = dt / t_relax
LAW_CALL = '''law_stress(prm, dt, L, p_rho[p], p_stress[p], p_state[p])
'''
RELAXED_CALL = '''keep(p_stress[p], p_state[p], p_old[p])
law_stress(prm, dt, L, p_rho[p], p_stress[p], p_state[p])
relax(p_stress[p], p_state[p], p_old[p], law_predictor(prm, dt, L, p_rho[p], p_old[p]), relax_r)
'''
#: the arguments RELAXED_CALL takes beyond LAW_CALL's
RELAXED_ARGS = "p_old, relax_r, "

#: a law's stress kernel, a thread per particle of one material block, with the largest |L_ii|
LAW = '''
@cuda.jit
def {name}(prm, dt, p_L, p_rho, p_stress, p_state, {law_args}rate, halt):
    if halt[0] != 0.0:
        return
    p = cuda.grid(1)
    if p >= p_L.shape[0]:
        return
    L = p_L[p]
{law}    cuda.atomic.max(rate, 0, max(abs(L[0, 0]), max(abs(L[1, 1]), abs(L[2, 2]))))
'''

#: consecutive node-rule stages of one class that share their ``aux`` (the walls of a box) in one pass: a thread per
#: node of the union of their node boxes (``u0``, ``un``, window-relative), each stage's rule where its own box
#: (``boxes[g]``: first node and count per axis) holds the node, in stage order (a rule changes only its own node)
NODE_GROUP = '''
@cuda.jit
def node_group_kernel(prms, aux, dt, origin, h, lo, nloc, boxes, u0, un, total, g_mass, g_vel, g_vel_old, g_force,
                      g_pore, wet, outs, halt):
    if halt[0] != 0.0:
        return
    q = cuda.grid(1)
    if q >= total:
        return
    d = g_vel.shape[1]
    c = cuda.local.array(3, int64)
    rem = q
    for a in range(d - 1, -1, -1):
        c[a] = u0[a] + rem % un[a]
        rem //= un[a]
    idx = 0
    for a in range(d):
        idx = idx * nloc[a] + c[a]
{rules}'''

#: the grid update (cuda_kernels.update_node) and then NODE_GROUP's rules, a thread per node of the window: the
#: update changes only its own node, so this is the update's pass and the stages' one after the other
UPDATE_GROUP = '''
@cuda.jit
def update_group_kernel(g_mom, g_force_u, gravity, mass_eps, split, g_vel_old_u, prms, aux, dt, origin, h, lo, nloc,
                        boxes, g_mass, g_vel, g_vel_old, g_force, g_pore, wet, outs, halt):
    if halt[0] != 0.0:
        return
    idx = cuda.grid(1)
    if idx >= g_mass.shape[0]:
        return
    update_node(idx, g_mass, g_mom, g_force_u, gravity, dt, mass_eps, split, g_vel, g_vel_old_u)
    d = g_vel.shape[1]
    c = cuda.local.array(3, int64)
    rem = idx
    for a in range(d - 1, -1, -1):
        c[a] = rem % nloc[a]
        rem //= nloc[a]
{rules}'''

#: the rules of NODE_GROUP and UPDATE_GROUP at node ``idx`` (window cell ``c``)
GROUP_RULES = '''    m = g_mass[idx]
    if m <= 0.0:
        return
    x = cuda.local.array(3, float64)
    for a in range(d):
        x[a] = origin[a] + (lo[a] + c[a]) * h
{scratch_and_acc}    for g in range(prms.shape[0]):
        inside = True
        for a in range(d):
            if c[a] < boxes[g, 0, a] or c[a] >= boxes[g, 0, a] + boxes[g, 1, a]:
                inside = False
        if inside:
            for r in range({slots}):
                acc[r] = 0.0
            node_rule(prms[g], aux, dt, x[:d], m, g_vel[idx], g_vel_old[idx], g_force[idx], g_pore[idx if wet else 0],
                      work[:{used}], acc)
            out = outs[g]
{flush}'''

#: the rules of one run of particle stages of one class that share their ``aux`` (the walls of a box) on particle
#: ``p``: each stage's rule in stage order, each stage's parameters a row of ``prms`` and its accumulator a row of
#: ``outs`` (a rule changes only its own particle, so this is the stages' passes one after the other)
RULES = '''for g in range(prms.shape[0]):
    for r in range({slots}):
        acc[r] = 0.0
    particle_rule(prms[g], aux, dt, k, p_x[p], p_x0[p], p_v[p], p_C[p], p_mass[p], p_stress[p], work[:{used}], acc)
    out = outs[g]
{flush}'''

#: a particle rule's pass (RULES) over the particles start..end of one block, a thread per particle
GROUP = '''
@cuda.jit
def group_kernel(prms, aux, dt, k, start, end, p_x, p_x0, p_v, p_C, p_mass, p_stress, outs, halt):
    if halt[0] != 0.0:
        return
    p = start + cuda.grid(1)
    if p >= end:
        return
{scratch_and_acc}{rules}'''

#: G2P, the particle stages' rules and the law on one material block's particles (every array the block's slice),
#: a thread per particle, then the block's step-end row: G2P reads the grid alone, a particle rule changes its own
#: particle, the law reads and writes its own, so this is the passes ``g2p``, ``particle_stages`` and
#: ``update_stress`` and the step-end reduction one after the other.  ``{runs}``: each run of particle stages of one
#: class (RULES, ``on<r>`` whether it acts on this block); ``{law}``: LAW_CALL or RELAXED_CALL.
#: No thread returns before the step-end row: its reduction synchronises the thread block.
PARTICLE_STEP = '''
@cuda.jit
def particle_step_kernel(S, mode, p_x, p_x0, p_v, p_C, p_L, p_vol, p_rho, p_mass, p_stress, p_state, g_vel, g_vel_old,
                         origin, h, kind, lo, nloc, dt, flip_ratio, dinv, set_velocity, k, {run_args}prm, {law_args}rate,
                         gravity, row, halt):
    if halt[0] != 0.0:
        return
    t = cuda.threadIdx.x
    p = cuda.grid(1)
    ends = cuda.shared.array((THREADS, END_ROW), float64)
    end_start(ends, t)
{locals}    if p < p_x.shape[0]:
        g2p_particle(p, S, mode, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old, origin, h, kind, lo, nloc,
                     dt, flip_ratio, dinv, set_velocity, True, True)
        L = p_L[p]
{runs}{law}        cuda.atomic.max(rate, 0, max(abs(L[0, 0]), max(abs(L[1, 1]), abs(L[2, 2]))))
        particle_row(p, p_x, p_x0, p_v, p_rho, p_stress, p_mass, gravity, ends[t])
    end_add(ends, t, row)
'''

#: one run of PARTICLE_STEP (RULES where ``on``), its names (RUN_NAMES) suffixed by the run's place; its scratch
#: and accumulator are ACCUMULATOR's, made in ``{locals}``
RUN_NAMES = ("particle_rule", "prms", "aux", "outs", "on", "work", "acc", "out")

EACH = '''
@cuda.jit
def each_kernel(n, {args}):
    i = cuda.grid(1)
    if i < n:
{calls}'''

MERGE = '''
@cuda.jit
def merge_kernel(prm, lo, nloc, g_mass, g_vel, g_vel_old, fold_old, halt):
    if halt[0] != 0.0:
        return
    g = cuda.grid(1)
    if g < g_vel.shape[0]:
        merge_node(prm, lo, nloc, g_mass, g_vel, g_vel_old, fold_old, g)
'''


#: a thread's scratch and zeroed accumulator, and the accumulator added into the pass's row (the maxima
#: slots taken as a maximum): the same in the node and the particle kernel
ACCUMULATOR = '''    work = cuda.local.array({scratch}, float64)
    acc = cuda.local.array({slots}, float64)
    for r in range({slots}):
        acc[r] = 0.0
'''
FLUSH = '''    for r in range({slots}):
        if acc[r] != 0.0:
            if {maxima_test}:
                cuda.atomic.max(out, r, acc[r])
            else:
                cuda.atomic.add(out, r, acc[r])
'''


def _indented(text: str, indent: str) -> str:
    return "".join(indent + line for line in text.splitlines(keepends=True))


def _pass_source(template: str, scratch: int, slots: int, maxima, indent: str = "") -> str:
    keys = dict(scratch=max(scratch, 1), used=scratch, slots=max(slots, 1),
                maxima_test=" or ".join(f"r == {int(i)}" for i in maxima) if maxima else "False")
    return template.format(scratch_and_acc=ACCUMULATOR.format(**keys), flush=_indented(FLUSH.format(**keys), indent),
                           **keys)


def _rules(scratch: int, slots: int, maxima, indent: str) -> str:
    """RULES with its accumulator's flush, every line indented by ``indent``."""
    return _indented(_pass_source(RULES, scratch, slots, maxima), indent)


def _kernel(kind: str, name: str, source: str, functions: dict):
    key = (kind, source, tuple(functions.items()))
    if key not in _CACHE:
        namespace = {"cuda": cuda, "float64": float64, "int64": int64, "math": math, "THREADS": THREADS,
                     "END_ROW": END_ROW,
                     "__geompm_recipe__": {"kind": kind, "name": name, "source": source, "functions": functions}}
        namespace.update({alias: _device(fn) for alias, fn in functions.items()})
        exec(source, namespace)
        _CACHE[key] = namespace[name]
    return _CACHE[key]


def _law_parts(law, relaxed: bool):
    """(the law's call, its extra arguments, the functions it calls) of LAW_CALL or RELAXED_CALL."""
    functions = {"law_stress": law.particle_stress}
    if not relaxed:
        return LAW_CALL, "", functions
    from geompm.kernels.viscoplastic import keep_one, relax_one

    functions.update(law_predictor=law.elastic_predictor, keep=keep_one, relax=relax_one)
    return RELAXED_CALL, RELAXED_ARGS, functions


def _law_kernel(kind: str, name: str, law, relaxed: bool):
    call, args, functions = _law_parts(law, relaxed)
    source = LAW.replace("{name}", name).replace("{law_args}", args).replace("{law}", _indented(call, "    "))
    return _kernel(kind, name, source, functions)


def stress_kernel(law):
    return _law_kernel("law", "stress_kernel", law, False)


def relaxed_kernel(law):
    """The stress kernel of a law with ``elastic_predictor``, Duvaut-Lions regularised."""
    return _law_kernel("law_relaxed", "relaxed_kernel", law, True)


def particle_kernel(rule, scratch: int, slots: int, maxima=()):
    """The kernel of GROUP around ``rule`` (looked up per pass: cached by its arguments, no source formatted)."""
    return _particle_kernel(rule, scratch, slots, tuple(maxima))


def node_group_kernel(rule, scratch: int, slots: int, maxima=()):
    """The kernel of NODE_GROUP around ``rule`` (cached as ``particle_kernel``): a group of stages, or one stage's
    pass over one part of its node box."""
    return _node_group_kernel(rule, scratch, slots, tuple(maxima))


@functools.cache
def _node_group_kernel(rule, scratch, slots, maxima):
    rules = _pass_source(GROUP_RULES, scratch, slots, maxima, "        ")
    return _kernel("node_group", "node_group_kernel", NODE_GROUP.replace("{rules}", rules), {"node_rule": rule})


@functools.cache
def update_group_kernel(rule, scratch: int, slots: int, maxima, update):
    """The kernel of UPDATE_GROUP around ``rule``, ``update`` the grid update's per-node function
    (cuda_kernels.update_node, handed in: that module imports this one)."""
    rules = _pass_source(GROUP_RULES, scratch, slots, tuple(maxima), "        ")
    return _kernel("update_group", "update_group_kernel", UPDATE_GROUP.replace("{rules}", rules),
                   {"node_rule": rule, "update_node": update})


@functools.cache
def _particle_kernel(rule, scratch, slots, maxima):
    source = _pass_source(GROUP.replace("{rules}", _rules(scratch, slots, maxima, "    ")), scratch, slots, maxima)
    return _kernel("particle", "group_kernel", source, {"particle_rule": rule})


@functools.cache
def particle_step_kernel(law, relaxed: bool, runs: tuple, kernels: tuple):
    """The kernel of PARTICLE_STEP for material law ``law`` (Duvaut-Lions regularised where ``relaxed``) and the
    particle-stage ``runs`` ((rule, scratch, slots, maxima) each, in order); ``kernels`` are cuda_kernels'
    (g2p_particle, end_start, end_add), handed in as ``update_group_kernel``'s ``update``."""
    from geompm.kernels.step_end import particle_row

    g2p, start, add = kernels
    law_call, law_args, functions = _law_parts(law, relaxed)
    functions.update({"g2p_particle": g2p, "end_start": start, "end_add": add, "particle_row": particle_row})
    local, body, args = "", "", ""
    for r, (rule, scratch, slots, maxima) in enumerate(runs):
        one = (_pass_source("{scratch_and_acc}", scratch, slots, maxima),
               "        if on:\n" + _rules(scratch, slots, maxima, "            "))
        one = [re.sub(rf"\b({'|'.join(RUN_NAMES)})\b", rf"\g<1>{r}", part) for part in one]
        local, body = local + one[0], body + one[1]
        args += "".join(f"{name}{r}, " for name in ("prms", "aux", "outs", "on"))
        functions[f"particle_rule{r}"] = rule
    law_source = _indented(law_call, "        ")
    source = PARTICLE_STEP
    for key, text in (("{locals}", local), ("{runs}", body), ("{law}", law_source), ("{run_args}", args),
                      ("{law_args}", law_args)):
        source = source.replace(key, text)
    return _kernel("particle_step", "particle_step_kernel", source, functions)


@functools.cache
def each_kernel(fns: tuple):
    """One thread per item calling a scheme's per-item functions ``fns`` in turn, each ``fn(i, *its args)``
    (backend/item_loops.py: the CPU's loop around the same calls)."""
    from geompm.backend.item_loops import item_calls

    args, calls, functions = item_calls(fns, "        ")
    return _kernel("each", "each_kernel", EACH.format(args=args, calls=calls), functions)


def merge_kernel(image):
    """Around cpu_stage_loops.MERGE_NODE, the CPU pass's own per-node body (an @njit function that calls
    ``node_image`` itself: under the simulator that function, not the image, is the one unwrapped)."""
    from geompm.backend.cpu_stage_loops import MERGE_NODE

    key = ("merge", image)
    if key not in _CACHE:
        namespace = {"cuda": cuda, "njit": njit, "node_image": image,
                     "__geompm_recipe__": {"kind": "merge", "image": image}}
        exec(MERGE_NODE.replace(", cache=True", ""), namespace)
        namespace["merge_node"] = _device(namespace["merge_node"])
        exec(MERGE, namespace)
        _CACHE[key] = namespace["merge_kernel"]
    return _CACHE[key]
