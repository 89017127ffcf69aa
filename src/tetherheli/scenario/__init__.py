"""Scenarios: the schema of a run's TOML (its tables and keys), the strict loader, the checks
joining fields, and the generator of the scenario reference page.

The names below load on first use (PEP 562): importing the command line's parser does not
import the engine.
"""

from __future__ import annotations

from .._lazy import lazy_getattr

_HOMES = dict.fromkeys(
    ("ControlSettings", "Limits", "Scenario", "load_scenario", "paper_scenario"), ".core"
)

__all__ = ["ControlSettings", "Limits", "Scenario", "load_scenario", "paper_scenario"]

__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
