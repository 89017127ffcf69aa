"""The report layer: it turns runs and studies into output folders, tables, pages and figures
(drawing through ``viz``); the studies below it return data.

``paper``
    the paper's job (``run_paper``, Sec. VI), one scenario's run (``write_run``), a
    comparison (``write_comparison``) and the sensing runs (``run_sensing``);
``sweep``
    a parameter sweep's folder (``write_sweep``);
``cyclic_limit``
    the cyclic-limit search's folder (``write_limit_search``);
``montecarlo``
    a Monte Carlo's job and its results folder (``run_montecarlo``);
``tether_study``
    the tether study's job and its folder (``run_tether_study``, ``write_tether_study``).

The names below load on first use (PEP 562): the command line's parser imports none of them.
"""

from __future__ import annotations

from .._lazy import lazy_getattr

_HOMES = {
    **dict.fromkeys(
        (
            "PAPER_CLAIM_PERCENT",
            "RUN_KEYS",
            "SCENARIO_FILE",
            "SENSING_OUTAGE",
            "SENSING_RUNS",
            "paper_summary",
            "run_paper",
            "run_sensing",
            "run_status",
            "sensing_scenario",
            "write_comparison",
            "write_run",
        ),
        ".paper",
    ),
    "write_sweep": ".sweep",
    "write_limit_search": ".cyclic_limit",
    **dict.fromkeys(
        ("FIGURE_KINDS", "RESULT_FILES", "result_files", "run_montecarlo"), ".montecarlo"
    ),
    **dict.fromkeys(("run_tether_study", "write_tether_study"), ".tether_study"),
}

__all__ = sorted(_HOMES)

__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
