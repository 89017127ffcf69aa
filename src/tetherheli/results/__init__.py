"""Results: a run as an object (:class:`SimulationResult`), its files (CSV, Parquet, MCAP) and
their reading back.

The names below load on first use (PEP 562).
"""

from __future__ import annotations

from .._lazy import lazy_getattr

_HOMES = dict.fromkeys(("SimulationResult", "list_results", "load_result"), ".result")

__all__ = ["SimulationResult", "list_results", "load_result"]

__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
