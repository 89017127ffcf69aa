"""Studies built on many simulations: parameter sweeps (``sweep``) and the resumable Monte
Carlo of wind and parameter dispersions (``montecarlo``: configuration, draws, runner). They
return data; ``tetherheli.report`` writes and draws it.

The function ``sweep`` is not re-exported here: it would shadow the module
``tetherheli.studies.sweep``; use ``from tetherheli.studies.sweep import sweep``.
"""

from .._lazy import lazy_getattr

# the names below load on first use (PEP 562), so that importing one study (the command
# line's tether-study) does not import the Monte Carlo and its engine
_HOMES = {
    **dict.fromkeys(
        ("Draw", "MonteCarloConfig", "draw", "draw_seed", "load_montecarlo",
         "montecarlo_config_from_dict", "MonteCarloJob", "run_montecarlo_chunks"),
        ".montecarlo",
    ),
    **dict.fromkeys(
        ("METRICS", "SweepResult", "paper_cyclic_limit", "tension_bound"), ".sweep"
    ),
}  # fmt: skip

__all__ = [
    "METRICS",
    "Draw",
    "MonteCarloConfig",
    "MonteCarloJob",
    "SweepResult",
    "draw",
    "draw_seed",
    "load_montecarlo",
    "montecarlo_config_from_dict",
    "paper_cyclic_limit",
    "run_montecarlo_chunks",
    "tension_bound",
]


__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
