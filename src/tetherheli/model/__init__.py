"""The mechanical model: Kane derivation, generated numeric code, dynamics, trim, linearization.

Names are imported lazily so that ``model.derive`` and ``model.codegen`` can run without the
(possibly stale) generated code.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .dynamics import INPUT, OUTPUT, FreeHelicopter, TetheredHelicopter, state_index
    from .linearize import LinearModel, discretize_zoh, linearize
    from .trim import TrimPoint, hover_trim

_LAZY = {
    "INPUT": ".dynamics",
    "OUTPUT": ".dynamics",
    "FreeHelicopter": ".dynamics",
    "TetheredHelicopter": ".dynamics",
    "state_index": ".dynamics",
    "LinearModel": ".linearize",
    "discretize_zoh": ".linearize",
    "linearize": ".linearize",
    "TrimPoint": ".trim",
    "hover_trim": ".trim",
}

__all__ = [
    "INPUT",
    "OUTPUT",
    "FreeHelicopter",
    "LinearModel",
    "TetheredHelicopter",
    "TrimPoint",
    "discretize_zoh",
    "hover_trim",
    "linearize",
    "state_index",
]


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'tetherheli.model' has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value
