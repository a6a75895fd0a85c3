"""Named positions of a plugin's packed parameters (a law's, a stage's).

A law's or a stage's per-item function reads its parameters from one float64
array ``prm`` (a flat array is what every backend can hand to a kernel: a CPU
loop, a GPU device function).  The positions are never written as bare
numbers: each law or stage declares its layout once,

    DP = param_layout(ELASTIC, "alpha", "k", "beta", "tension_cutoff", "dilation_cutoff")

and reads ``prm[DP.alpha]``.  A layout is a namedtuple of ints, which numba
freezes as compile-time constants, so a named read costs exactly what
``prm[3]`` did.  ``pack(params)`` returns a dict with the layout's names as
keys (every key, no other); ``Material`` turns it into the array in layout
order and names any key that is missing or unexpected.

Layouts extend one another: a law whose wave speed is the elastic one
(plasticity.py) starts from ``ELASTIC`` so ``prm[ELASTIC.lam]`` is the same slot
in every such law.
"""

from __future__ import annotations

from collections import namedtuple


def param_layout(*parts):
    """A layout from names and earlier layouts (their names first, in order)."""
    names: list[str] = []
    for part in parts:
        names.extend(part._fields if hasattr(part, "_fields") else [part])
    if len(set(names)) != len(names):
        raise ValueError(f"duplicate parameter names in layout {names}")
    cls = namedtuple("ParamLayout", names)
    return cls(*range(len(names)))


def pack_in_layout(layout, values: dict, owner: str):
    """The float64 array of ``values`` in ``layout`` order; a TypeError names a missing or extra key."""
    import numpy as np

    want = list(layout._fields)
    missing = [k for k in want if k not in values]
    extra = [k for k in values if k not in want]
    if missing or extra:
        raise TypeError(f"{owner}: the packed parameters must be exactly the layout's keys {want}; "
                        f"missing {missing}, unexpected {extra}")
    return np.array([float(values[k]) for k in want], dtype=np.float64)
