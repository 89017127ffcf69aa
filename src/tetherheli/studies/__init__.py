"""Studies built on many simulations: parameter sweeps (``sweep``) and the resumable Monte
Carlo of wind and parameter dispersions (``montecarlo``: configuration, draws, runner).

The function ``sweep`` is not re-exported here: it would shadow the module
``tetherheli.studies.sweep``; use ``from tetherheli.studies.sweep import sweep``.
"""

from .montecarlo import (
    Draw,
    MonteCarloConfig,
    draw,
    draw_seed,
    load_montecarlo,
    montecarlo_config_from_dict,
    run_montecarlo,
)
from .sweep import METRICS, SweepResult, paper_cyclic_limit, tension_bound, write_sweep

__all__ = [
    "METRICS",
    "Draw",
    "MonteCarloConfig",
    "SweepResult",
    "draw",
    "draw_seed",
    "load_montecarlo",
    "montecarlo_config_from_dict",
    "paper_cyclic_limit",
    "run_montecarlo",
    "tension_bound",
    "write_sweep",
]
