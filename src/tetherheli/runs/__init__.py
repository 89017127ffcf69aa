"""Runs: a scenario's set-up for the engine (model, trim, gain, packed arrays), one run
(:func:`simulate`), many runs (:func:`run_batch`, threads or Dask).

The names below load on first use (PEP 562).
"""

from __future__ import annotations

from .._lazy import lazy_getattr

_HOMES = {
    "simulate": ".closed_loop",
    **dict.fromkeys(("BatchResult", "run_batch"), ".batch"),
    **dict.fromkeys(("EngineSetup", "engine_setup"), ".setup"),
    "paper_gain": ".start",
}

__all__ = ["BatchResult", "EngineSetup", "engine_setup", "paper_gain", "run_batch", "simulate"]

__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
