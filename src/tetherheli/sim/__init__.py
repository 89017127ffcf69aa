"""Closed-loop simulation: scenarios, the compiled engine, results."""

from ..wind import compile_wind
from .closed_loop import simulate
from .result import SimulationResult, list_results, load_result
from .scenario import ControlSettings, Limits, Scenario, load_scenario
from .setup import EngineSetup, engine_setup, paper_gain

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
