"""The JSON Schema of the case format (``geompm schema``).

The core keys come from the pydantic models.  Plugin parameters are open
objects in the core schema; the schema of every installed plugin's ``Params``
is attached under ``$defs`` (``material.<name>``, ``boundary.<name>``, ...) so
editors can look them up.  ``built_in_only`` keeps geompm's own plugins: the
committed schemas/case.schema.json is that one, so it does not depend on what
else is installed where it was generated.
"""

from __future__ import annotations

from geompm.contract import registry
from geompm.schema.case import Case


def case_json_schema(built_in_only: bool = False) -> dict:
    schema = Case.model_json_schema()
    defs = schema.setdefault("$defs", {})
    for kind, label in (("materials", "material"), ("boundaries", "boundary"), ("obstacles", "obstacle"),
                        ("damping", "damping"), ("writers", "writer")):
        for name, info in sorted(registry.available(kind).items()):
            if built_in_only and info.package != "geompm":
                continue
            defs[f"{label}.{name}"] = info.plugin.Params.model_json_schema()
    schema["$id"] = "https://geompm.example/schemas/case.schema.json"
    return schema
