"""Closed-loop simulation: scenarios, the compiled engine, results."""

from ..wind import compile_wind
from .closed_loop import paper_gain, simulate
from .result import SimulationResult, list_results, load_result
from .scenario import ControlSettings, Limits, Scenario, load_scenario

__all__ = [
    "ControlSettings",
    "Limits",
    "Scenario",
    "SimulationResult",
    "compile_wind",
    "list_results",
    "load_result",
    "load_scenario",
    "paper_gain",
    "simulate",
]
