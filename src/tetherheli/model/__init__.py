"""The mechanical model: Kane derivation, generated numeric code, dynamics, trim, linearization.

Names are imported lazily so that ``model.derive`` and ``model.codegen`` can run without the
(possibly stale) generated code.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .dynamics import INPUT, OUTPUT, FreeHelicopter, TetheredHelicopter, state_index
    from .linearization import EXPORT_INPUTS, LinearModel, discretize_zoh, linearize
    from .trim import TrimPoint, hover_trim

_LAZY = {
    "INPUT": ".dynamics",
    "OUTPUT": ".dynamics",
    "FreeHelicopter": ".dynamics",
    "TetheredHelicopter": ".dynamics",
    "state_index": ".dynamics",
    "EXPORT_INPUTS": ".linearization",
    "LinearModel": ".linearization",
    "discretize_zoh": ".linearization",
    "linearize": ".linearization",
    "TrimPoint": ".trim",
    "hover_trim": ".trim",
}

__all__ = [
    "EXPORT_INPUTS",
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
    mod = importlib.import_module(module, __name__)
    # bind every name of that module at once (no submodule bears a name of ``_LAZY``: the
    # linearization lives in ``.linearization``, so its import cannot shadow ``linearize``)
    for other, where in _LAZY.items():
        if where == module:
            globals()[other] = getattr(mod, other)
    return globals()[name]
