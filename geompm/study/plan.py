"""The variants of a study: the product of ``--vary`` lists, times ``--sample`` draws.

    --vary grid.cell_size=0.02,0.01,0.005      every listed value (JSON, else text)
    --sample materials.soil.friction_angle=normal(31,2) --samples 64 --seed 1

Distributions (numpy's Generator, seeded, so a study is repeatable):
``normal(mean, sd)``, ``lognormal(mean, sd)`` (of the logarithm),
``uniform(low, high)``, ``triangular(low, mode, high)``.  Each variant is a
list of ``--set`` overrides applied to the base case.
"""

from __future__ import annotations

import itertools
import json
import re
from dataclasses import dataclass, field

import numpy as np

from geompm.errors import CaseError

DISTRIBUTIONS = {"normal": 2, "lognormal": 2, "uniform": 2, "triangular": 3}


@dataclass
class Variant:
    index: int
    values: dict = field(default_factory=dict)  # dotted path -> value

    @property
    def name(self) -> str:
        return f"v{self.index:03d}"

    @property
    def sets(self) -> list[str]:
        return [f"{k}={json.dumps(v)}" for k, v in self.values.items()]

    def label(self) -> str:
        return " ".join(f"{k.split('.')[-1]}={_short(v)}" for k, v in self.values.items())


def _short(v) -> str:
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def _value(text: str):
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def parse_vary(items: list[str]) -> dict[str, list]:
    out = {}
    for item in items:
        key, sep, rest = item.partition("=")
        values = [_value(t.strip()) for t in rest.split(",") if t.strip()]
        if not sep or not key or not values:
            raise CaseError([(f"--vary {item}", "must look like dotted.key=v1,v2,... e.g. grid.cell_size=0.02,0.01")])
        if key in out:
            raise CaseError([(f"--vary {key}", "given twice; list all its values in one --vary")])
        out[key] = values
    return out


def parse_sample(items: list[str]) -> dict[str, tuple[str, list[float]]]:
    out = {}
    for item in items:
        key, sep, rest = item.partition("=")
        m = re.fullmatch(r"\s*(\w+)\s*\(([^)]*)\)\s*", rest)
        hint = "must look like dotted.key=normal(31,2); distributions: " + ", ".join(
            f"{d}({n} numbers)" for d, n in DISTRIBUTIONS.items())
        if not sep or not key or m is None or m.group(1) not in DISTRIBUTIONS:
            raise CaseError([(f"--sample {item}", hint)])
        try:
            args = [float(a) for a in m.group(2).split(",")]
        except ValueError:
            raise CaseError([(f"--sample {item}", hint)]) from None
        dist = m.group(1)
        if len(args) != DISTRIBUTIONS[dist]:
            raise CaseError([(f"--sample {item}", f"{dist} takes {DISTRIBUTIONS[dist]} numbers, got {len(args)}")])
        if dist in ("normal", "lognormal") and args[1] < 0 or dist == "uniform" and args[1] < args[0] \
                or dist == "triangular" and not args[0] <= args[1] <= args[2]:
            raise CaseError([(f"--sample {item}", "the distribution's parameters are out of order or negative")])
        out[key] = (dist, args)
    return out


def draw(samples: dict, n: int, seed: int) -> list[dict]:
    """``n`` draws of every sampled parameter, one dict per draw."""
    rng = np.random.default_rng(seed)
    columns = {}
    for key, (dist, a) in samples.items():
        if dist == "normal":
            x = rng.normal(a[0], a[1], n)
        elif dist == "lognormal":
            x = rng.lognormal(a[0], a[1], n)
        elif dist == "uniform":
            x = rng.uniform(a[0], a[1], n)
        else:
            x = rng.triangular(a[0], a[1], a[2], n)
        columns[key] = [float(v) for v in x]
    return [{k: columns[k][i] for k in columns} for i in range(n)]


def build_plan(vary: dict[str, list], samples: dict, n_samples: int, seed: int) -> list[Variant]:
    keys = list(vary)
    grid = [dict(zip(keys, combo)) for combo in itertools.product(*(vary[k] for k in keys))] or [{}]
    draws = draw(samples, n_samples, seed) if samples else [{}]
    clash = set(vary) & set(samples)
    if clash:
        raise CaseError([(f"--sample {k}", "is also given to --vary; use one") for k in sorted(clash)])
    return [Variant(i, {**g, **d}) for i, (g, d) in enumerate(itertools.product(grid, draws))]
