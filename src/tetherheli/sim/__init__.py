"""Closed-loop simulation: scenarios, the compiled engine, results."""

from .result import SimulationResult, list_results, load_result
from .scenario import ControlSettings, Limits, Scenario, load_scenario
from .simulate import compile_wind, paper_gain, simulate

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
