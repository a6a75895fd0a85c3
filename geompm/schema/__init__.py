"""Case schema: pydantic models (``case``) and the two-pass loader (``load``)."""

from .case import Case
from .load import load_case, parse_case

__all__ = ["Case", "load_case", "parse_case"]
