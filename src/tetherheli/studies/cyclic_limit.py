"""The smallest cyclic authority a design needs: the smallest symmetric limit tmax_MR1,2 on
the cyclic torques tMR1, tMR2 (eq 40) that keeps a metric, by default the peak position
deviation, within a fraction of the unlimited run's (``minimum_cyclic_limit``).

"The run completes" is no design criterion: just above the limit at which the saturated
attitude loop loses the helicopter a run may complete with a 20 m excursion, and the set of
limits that complete is not an interval (free simulation 1 completes at 4.31-4.325 N m, fails
at 4.33-4.34, completes from 4.345). The criterion here is "completes and metric <= (1 +
within) x the unlimited run's metric", searched robustly:

1. a grid scan of the limits (one compiled batch);
2. the bracket is the last grid interval [g_(i-1), g_i] such that the criterion holds at g_i
   and at every larger grid value, and fails at g_(i-1) (``bracket_from_above``);
3. bisection inside it to the tolerance (``bisect_criterion``), keeping the criterion false
   at lo and true at hi.

The answer is the interval [lo, hi]: the criterion fails at lo, holds at hi and at every grid
value above hi. A failure between grid values above hi is not seen: the grid's spacing is the
resolution of that statement, the tolerance that of the interval.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InfeasibleError, ParameterError
from ..progress import Progress
from ..results.result import SummaryRepr
from ..scenario import Scenario
from .sweep import METRICS, _evaluate, _prepare_points, _with

__all__ = [
    "LimitSearch",
    "bisect_criterion",
    "bracket_from_above",
    "minimum_cyclic_limit",
]

PARAMETER = "actuators.cyclic_limit"


def bracket_from_above(meets: np.ndarray) -> int | None:
    """The smallest index i such that ``meets[i:]`` all hold (grid ascending); None when the
    last one fails. i == 0: the criterion holds at every grid value.

    Parameters
    ----------
    meets : array_like of bool, shape (n,)
        The criterion at each grid value, ascending.

    Returns
    -------
    int or None
        The index, or None.
    """
    meets = np.asarray(meets, dtype=bool)
    if meets.size == 0 or not meets[-1]:
        return None
    failing = np.flatnonzero(~meets)
    return 0 if failing.size == 0 else int(failing[-1]) + 1


def bisect_criterion(
    lo: float, hi: float, criterion: Callable[[float], bool], tol: float
) -> tuple[float, float, list[tuple[float, bool]]]:
    """Bisection of [lo, hi] (criterion false at lo, true at hi) until hi - lo <= tol; the
    final (lo, hi), still false at lo and true at hi, and every (value, result) evaluated.

    Parameters
    ----------
    lo, hi : float
        The bracket (criterion false at lo, true at hi), in the searched unit.
    criterion : callable
        value -> bool.
    tol : float
        The final width, > 0.

    Returns
    -------
    lo, hi : float
        The final bracket.
    evaluated : list of (float, bool)
        Every value tried and its result, in order.
    """
    if not (math.isfinite(tol) and tol > 0):
        raise ParameterError("tol", tol, "a tolerance > 0")
    evaluated: list[tuple[float, bool]] = []
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        ok = bool(criterion(mid))
        evaluated.append((mid, ok))
        if ok:
            hi = mid
        else:
            lo = mid
    return lo, hi, evaluated


@dataclass(frozen=True, repr=False)
class LimitSearch(SummaryRepr):
    """The result of ``minimum_cyclic_limit``.

    Parameters
    ----------
    scenario_name : str
        The searched scenario's name.
    metric_name : str
        The metric (``sweep.METRICS``).
    within : float
        The allowed relative increase of the metric.
    tolerance : float
        The interval's width [N m].
    reference : float
        The metric of the run without cyclic limits.
    threshold : float
        (1 + within) x reference.
    lo, hi : float or None
        The interval [N m]: the criterion fails at lo and holds at hi and at every grid value
        above; lo None: it holds at every grid value (the minimum is below the grid); hi None:
        it fails at the largest grid value (no answer within the grid).
    values : ndarray, shape (n,)
        Every limited run's limit [N m], in the order run (grid first, then the bisection).
    metric : ndarray, shape (n,)
        Its metric (NaN if it did not complete).
    statuses : tuple of str
        Its status message.
    meets : ndarray, shape (n,), bool
        Whether it meets the criterion.
    n_grid : int
        How many of the runs are the grid's.
    configuration : dict of str to object, optional
        The searched scenario as plain data (``Scenario.to_dict``).
    """

    scenario_name: str
    metric_name: str
    within: float
    tolerance: float
    reference: float
    threshold: float
    lo: float | None
    hi: float | None
    values: np.ndarray
    metric: np.ndarray
    statuses: tuple[str, ...]
    meets: np.ndarray
    n_grid: int
    configuration: dict[str, Any] = field(default_factory=dict)

    def _summary_rows(self) -> list[tuple[str, str]]:
        return [
            ("scenario", self.scenario_name),
            ("metric", f"{self.metric_name}: reference {self.reference:.4g}, threshold "
                       f"{self.threshold:.4g} (+{100 * self.within:g} %)"),
            ("minimum cyclic limit", self.interval_text()),
            ("runs", f"{self.values.size} ({self.n_grid} on the grid)"),
        ]  # fmt: skip

    def interval_text(self) -> str:
        """The answer in words, e.g. "4.375-4.380 N m".

        Returns
        -------
        str
            The interval, or why there is none.
        """
        if self.hi is None:
            return f"none up to {self.values[: self.n_grid].max():g} N m"
        if self.lo is None:
            return f"<= {self.hi:g} N m (below the grid)"
        return f"{self.lo:.3f}-{self.hi:.3f} N m"

    def as_dict(self) -> dict[str, Any]:
        """The search as a JSON-friendly record (summary.json).

        Returns
        -------
        dict of str to object
            The fields, the grid and the interval in words (NaN written as null).
        """
        return {
            "scenario": self.scenario_name,
            "parameter": PARAMETER,
            "metric": self.metric_name,
            "within": self.within,
            "tolerance": self.tolerance,
            "reference_metric": self.reference,
            "threshold": self.threshold,
            "lo": self.lo,
            "hi": self.hi,
            "interval": self.interval_text(),
            "grid": self.values[: self.n_grid].tolist(),
            "values": self.values.tolist(),
            "metric_values": [None if not np.isfinite(m) else float(m) for m in self.metric],
            "statuses": list(self.statuses),
            "meets": [bool(m) for m in self.meets],
            "configuration": self.configuration,
        }


def minimum_cyclic_limit(
    scenario: Scenario,
    grid: np.ndarray,
    *,
    within: float = 0.10,
    metric: str = "peak_q1",
    tol: float = 1e-3,
    progress: bool = False,
    workers: int | None = None,
    controller: str | None = None,
) -> LimitSearch:
    """The smallest symmetric cyclic limit tmax_MR1,2 [N m] (eq 40) with which ``scenario``
    completes and its ``metric`` (``sweep.METRICS``) stays within (1 + ``within``) times the
    run without cyclic limits, as an interval found by a grid scan and bisection (see the
    module docstring). ``grid``: limits > 0 [N m], at least 2; ``tol``: the interval's width;
    ``progress``: the runs done on stderr (``tetherheli.progress``; the total counts the
    longest bisection); ``workers``: threads of the batches (default: all CPUs).

    Parameters
    ----------
    scenario : Scenario
        The scenario to search.
    grid : ndarray
        Limits > 0 [N m], at least 2.
    within : float, optional
        Allowed relative increase of the metric (default 0.10).
    metric : str, optional
        One of ``sweep.METRICS`` (default "peak_q1", [m]).
    tol : float, optional
        The interval's width [N m] (default 1e-3).
    progress : bool, optional
        Show progress on stderr (default False).
    workers : int, optional
        Threads of the batches (default all CPUs).
    controller : str, optional
        Fly every run (the reference included) under this controller
        (``controllers.with_controller``); default: the scenario's own.

    Returns
    -------
    LimitSearch
        The interval and every run made.
    """
    if controller is not None:
        from .controllers import with_controller

        scenario = with_controller(scenario, controller)
    with Progress("sweep --find-min", 1, "runs", enabled=progress) as bar:
        return _search(scenario, grid, within, metric, tol, bar, workers)


def _search(
    scenario: Scenario,
    grid: np.ndarray,
    within: float,
    metric: str,
    tol: float,
    bar: Progress,
    workers: int | None,
) -> LimitSearch:
    if metric not in METRICS:
        raise ParameterError("metric", metric, f"one of {sorted(METRICS)}")
    if not (math.isfinite(within) and within >= 0):
        raise ParameterError("within", within, "a fraction >= 0")
    if not (math.isfinite(tol) and tol > 0):
        raise ParameterError("tol", tol, "a tolerance > 0 [N m]")
    grid = np.unique(np.asarray(grid, dtype=float))
    if grid.size < 2 or not np.all(np.isfinite(grid)) or grid[0] <= 0:
        raise ParameterError("grid", grid.tolist(), "at least 2 distinct finite limits > 0")
    bisections = math.ceil(math.log2(max(float(np.diff(grid).max()) / tol, 1.0)))
    bar.set_total(1 + grid.size + bisections)

    reference_scenario = _with(scenario, PARAMETER, math.inf)
    ref_status = [""]
    ref, ref_ok = _evaluate([reference_scenario], ref_status, metric, bar, workers)
    if not ref_ok[0]:
        raise InfeasibleError(
            "scenario",
            scenario.name,
            f"a run that completes without cyclic limits (it ends: {ref_status[0]})",
        )
    reference = float(ref[0])
    threshold = (1.0 + within) * reference

    values: list[float] = []
    metrics: list[float] = []
    statuses: list[str] = []
    meets: list[bool] = []

    def run(points: np.ndarray) -> np.ndarray:
        scenarios, st = _prepare_points(scenario, PARAMETER, points)
        out, completed = _evaluate(scenarios, st, metric, bar, workers)
        ok = np.array(completed) & (out <= threshold)
        values.extend(points.tolist())
        metrics.extend(out.tolist())
        statuses.extend(st)
        meets.extend(ok.tolist())
        return ok

    grid_ok = run(grid)
    i = bracket_from_above(grid_ok)
    lo: float | None
    hi: float | None
    if i is None:
        lo, hi = float(grid[-1]), None
    elif i == 0:
        lo, hi = None, float(grid[0])
    else:
        lo, hi, _ = bisect_criterion(
            float(grid[i - 1]), float(grid[i]), lambda v: bool(run(np.array([v]))[0]), tol
        )
    bar.update_to(bar.total)
    return LimitSearch(
        scenario.name,
        metric,
        within,
        tol,
        reference,
        threshold,
        lo,
        hi,
        np.array(values),
        np.array(metrics),
        tuple(statuses),
        np.array(meets, dtype=bool),
        int(grid.size),
        configuration=scenario.to_dict(),
    )
