"""Closed-loop simulation: scenarios, the compiled engine, results.

The names below load on first use (PEP 562): importing ``tetherheli.sim.result`` or
``tetherheli.sim.scenario`` alone (the command line's parser, the analysis) does not import
the compiled engine.
"""

from __future__ import annotations

from .._lazy import lazy_getattr

_HOMES = {
    "compile_wind": "..wind",
    "simulate": ".closed_loop",
    **dict.fromkeys(("SimulationResult", "list_results", "load_result"), ".result"),
    **dict.fromkeys(("ControlSettings", "Limits", "Scenario", "load_scenario"), ".scenario"),
    **dict.fromkeys(("EngineSetup", "engine_setup"), ".setup"),
    "paper_gain": ".start",
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


__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
