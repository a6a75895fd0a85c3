"""Particles packed for another rank and merged into a state, material blocks kept contiguous.

A packet holds every per-particle array of the state (``ParticleState.arrays``: position, velocity,
affine matrix, stress, ids, ...), each material's state variables (a law's plastic strain, ...) and how
many particles of each material block it carries, in block order.  ``merge`` puts a rank's kept particles
and the packets it received together block by block: the kept ones first, then each packet in rank order,
so the order is the same whatever the timing of the messages.
"""

from __future__ import annotations

import numpy as np


def pack(state, mask: np.ndarray) -> dict:
    """The particles where ``mask`` is true, as a packet (copies)."""
    mask = np.asarray(mask, bool)
    counts = [int(mask[a:b].sum()) for a, b in state.blocks]
    return {"counts": counts,
            "arrays": {name: arr[mask] for name, arr in state.arrays().items()},
            "states": [sv[mask[a:b]] for (a, b), sv in zip(state.blocks, state.p_state)]}


def nparticles(packet) -> int:
    return sum(packet["counts"]) if packet is not None else 0


def merge(state, keep: np.ndarray, packets) -> None:
    """Keep the particles where ``keep`` is true and add the packets' (None entries are skipped), block
    by block; the state's arrays are replaced (new sizes)."""
    keep = np.asarray(keep, bool)
    packets = [p for p in packets if p is not None and nparticles(p)]
    if not packets and keep.all():
        return
    offsets = [np.cumsum([0] + p["counts"]) for p in packets]
    nblocks = len(state.blocks)
    for name, arr in state.arrays().items():
        pieces = []
        for k, (a, b) in enumerate(state.blocks):
            pieces.append(arr[a:b][keep[a:b]])
            pieces += [p["arrays"][name][o[k]:o[k + 1]] for p, o in zip(packets, offsets)]
        setattr(state, name, np.ascontiguousarray(np.concatenate(pieces)) if pieces else arr[:0].copy())
    states, blocks, start = [], [], 0
    for k, (a, b) in enumerate(state.blocks):
        parts = [state.p_state[k][keep[a:b]]] + [p["states"][k] for p in packets]
        states.append(np.ascontiguousarray(np.concatenate(parts)))
        n = int(keep[a:b].sum()) + sum(p["counts"][k] for p in packets)
        blocks.append((start, start + n))
        start += n
    assert len(blocks) == nblocks
    state.blocks, state.p_state = blocks, states


def canonical(state) -> None:
    """Order each material block by particle id: the order a gathered state is written in, whatever the
    ranks it came from."""
    perm = np.concatenate([a + np.argsort(state.p_id[a:b], kind="stable") for a, b in state.blocks]) \
        if state.n else np.zeros(0, np.int64)
    if state.n and not (perm == np.arange(state.n)).all():
        state.reorder(perm)
