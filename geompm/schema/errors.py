"""Turn pydantic ValidationErrors into (JSON path, plain message) pairs.

For an unknown key the message names the closest valid key at that place in
the case, found by walking the pydantic model along the error's location.
"""

from __future__ import annotations

import difflib
import types
import typing

from pydantic import BaseModel, ValidationError

from geompm.errors import join_path

_SHORT = {
    "greater_than": "must be > {gt}",
    "greater_than_equal": "must be >= {ge}",
    "less_than": "must be < {lt}",
    "less_than_equal": "must be <= {le}",
    "missing": "required key is missing",
    "float_parsing": "must be a number",
    "float_type": "must be a number",
    "int_parsing": "must be an integer",
    "int_type": "must be an integer",
    "int_from_float": "must be a whole number",
    "list_type": "must be a list",
    "dict_type": "must be an object",
    "model_type": "must be an object",
    "string_type": "must be a string",
    "finite_number": "must be a finite number",
}


def _unwrap(annotation):
    """Candidate model/container types behind Optional/Union/Annotated."""
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _unwrap(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType):
        out = []
        for arg in typing.get_args(annotation):
            out.extend(_unwrap(arg))
        return out
    return [annotation]


def _step(annotation, key):
    """Type found one level down from ``annotation`` at ``key`` (or None)."""
    for cand in _unwrap(annotation):
        origin = typing.get_origin(cand)
        if origin in (list, tuple) and isinstance(key, int):
            return typing.get_args(cand)[0]
        if origin is dict and isinstance(key, str):
            return typing.get_args(cand)[1]
        if isinstance(cand, type) and issubclass(cand, BaseModel) and key in cand.model_fields:
            return cand.model_fields[key].annotation
    return None


def _is_union_tag(annotation, key) -> bool:
    """pydantic puts the discriminator value in the location of union errors."""
    cands = [c for c in _unwrap(annotation) if isinstance(c, type) and issubclass(c, BaseModel)]
    if len(cands) < 2:
        return False
    for cand in cands:
        field = cand.model_fields.get("type")
        if field is not None and key in typing.get_args(field.annotation):
            return True
    return False


def _models_at(root: type[BaseModel], loc) -> tuple[list, list]:
    """(clean location, candidate models) of the object holding loc[-1]."""
    ann = root
    clean = []
    for key in loc[:-1]:
        if _is_union_tag(ann, key):
            ann = next(
                c for c in _unwrap(ann)
                if isinstance(c, type) and issubclass(c, BaseModel)
                and key in typing.get_args(c.model_fields["type"].annotation)
            )
            continue
        clean.append(key)
        ann = _step(ann, key) if ann is not None else None
    if loc:
        clean.append(loc[-1])
    models = [c for c in _unwrap(ann) if isinstance(c, type) and issubclass(c, BaseModel)] if ann else []
    return clean, models


def _describe(models, key) -> str:
    for m in models:
        field = m.model_fields.get(key)
        if field is not None and field.description:
            return f" ({field.description})"
    return ""


def format_validation_error(exc: ValidationError, root: type[BaseModel], prefix=()) -> list[tuple[str, str]]:
    """List of (dotted JSON path, message) for every error in ``exc``."""
    problems = []
    for err in exc.errors():
        loc = tuple(err["loc"])
        clean, models = _models_at(root, loc)
        path = join_path(*prefix, *clean)
        etype = err["type"]
        ctx = err.get("ctx", {}) or {}
        if etype == "extra_forbidden":
            key = str(loc[-1])
            valid = sorted({f for m in models for f in m.model_fields})
            close = difflib.get_close_matches(key, valid, n=1, cutoff=0.5)
            hint = f"did you mean '{close[0]}'?" if close else f"valid keys: {', '.join(valid)}"
            problems.append((path, f"unknown key '{key}'; {hint}"))
            continue
        if etype in _SHORT:
            msg = _SHORT[etype].format(**ctx)
        elif etype == "literal_error":
            msg = f"must be one of {ctx.get('expected', '')}, got {err.get('input')!r}"
        elif etype == "string_pattern_mismatch" and loc == ("name",):
            msg = ("a run name is letters, digits, '_', '-' and '.', and does not start with '.' (it names the "
                   "folder runs/<name>)")
        elif etype == "union_tag_invalid":
            msg = f"unknown type {ctx.get('tag')!r}; must be one of {ctx.get('expected_tags')}"
        else:
            msg = err["msg"]
            if msg.startswith("Value error, "):
                msg = msg[len("Value error, "):]
        if etype not in ("missing",) and "input" in err and not isinstance(err["input"], (dict, list)):
            msg += f" (got {err['input']!r})"
        if etype == "missing" and loc:
            msg += _describe(models, loc[-1])
        problems.append((path, msg))
    return problems
