"""Kept for compatibility: the Monte Carlo now lives in ``tetherheli.studies.montecarlo``
(configuration, draws, runner)."""

from .studies.montecarlo import (
    CONFIGURATIONS,
    MAX_RUNS,
    RESULT_FILES,
    Draw,
    MonteCarloConfig,
    draw,
    draw_seed,
    load_montecarlo,
    montecarlo_config_from_dict,
    run_montecarlo,
)

__all__ = [
    "CONFIGURATIONS",
    "MAX_RUNS",
    "RESULT_FILES",
    "Draw",
    "MonteCarloConfig",
    "draw",
    "draw_seed",
    "load_montecarlo",
    "montecarlo_config_from_dict",
    "run_montecarlo",
]
