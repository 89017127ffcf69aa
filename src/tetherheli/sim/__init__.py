"""Closed-loop simulation: scenarios, the compiled engine, results.

The names below load on first use (PEP 562): importing ``tetherheli.sim.result`` or
``tetherheli.sim.scenario`` alone (the command line's parser, the analysis) does not import
the compiled engine.
"""

from __future__ import annotations

import importlib
from typing import Any

_HOMES = {
    "compile_wind": "..wind",
    "simulate": ".closed_loop",
    **dict.fromkeys(("SimulationResult", "list_results", "load_result"), ".result"),
    **dict.fromkeys(("ControlSettings", "Limits", "Scenario", "load_scenario"), ".scenario"),
    **dict.fromkeys(("EngineSetup", "engine_setup", "paper_gain"), ".setup"),
}

__all__ = [
    "ControlSettings",
    "EngineSetup",
    "Limits",
    "Scenario",
    "SimulationResult",
    "compile_wind",
    "engine_setup",
    "list_results",
    "load_result",
    "load_scenario",
    "paper_gain",
    "simulate",
]


def __getattr__(name: str) -> Any:
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_HOMES[name], __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
