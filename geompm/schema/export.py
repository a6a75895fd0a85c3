"""The JSON Schema of the case format (``geompm schema``).

The core keys come from the pydantic models.  Plugin parameters are open
objects in the core schema; the schema of every installed plugin's ``Params``
is attached under ``$defs`` (``material.<name>``, ``boundary.<name>``, ...) so
editors can look them up.
"""

from __future__ import annotations

from .. import registry
from .case import Case


def case_json_schema() -> dict:
    schema = Case.model_json_schema()
    defs = schema.setdefault("$defs", {})
    for kind, label in (("materials", "material"), ("boundaries", "boundary"), ("obstacles", "obstacle"),
                        ("damping", "damping"), ("writers", "writer")):
        for name, info in sorted(registry.available(kind).items()):
            defs[f"{label}.{name}"] = info.plugin.Params.model_json_schema()
    schema["$id"] = "https://geompm.example/schemas/case.schema.json"
    return schema
