"""Base shape shared by every plugin (material, damping, boundary, obstacle, writer).

A plugin class has a ``name``, a one-line ``description`` and a pydantic
``Params`` model (``extra="forbid"``, SI units in the field descriptions,
physical bounds as validators).  ``check`` may add case-level problems that
need more than the plugin's own parameters (for example a wall side that does
not exist in 2D).
"""

from __future__ import annotations

from typing import ClassVar

from pydantic import BaseModel, ConfigDict


class Params(BaseModel):
    """Base for plugin parameter models: unknown keys are errors."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class Plugin:
    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    Params: ClassVar[type[BaseModel]] = Params

    @classmethod
    def check(cls, params, case) -> list[tuple[str, str]]:
        """Problems as (path relative to the plugin's entry, message)."""
        return []


def vector_length_problems(params, case, keys) -> list[tuple[str, str]]:
    """(key, message) for every vector parameter in ``keys`` whose length is not the case's dimension."""
    return [(k, f"must have {case.dimension} entries (one per dimension)")
            for k in keys if getattr(params, k) is not None and len(getattr(params, k)) != case.dimension]


def nonzero_vector(cls, v):
    """A pydantic field validator (``field_validator("normal")(nonzero_vector)``): a direction must not be
    the zero vector."""
    if v is not None and not any(abs(c) > 0 for c in v):
        raise ValueError("the normal must not be the zero vector")
    return v
