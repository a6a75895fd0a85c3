"""Case schema: pydantic models (``case``) and the two-pass loader (``load``)."""

from geompm.schema.case import Case
from geompm.schema.load import load_case, parse_case

__all__ = ["Case", "load_case", "parse_case"]
