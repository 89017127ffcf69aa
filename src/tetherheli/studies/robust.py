"""Robustness of the controllers: each controller designed on the nominal
plant and flown on the Monte Carlo's dispersed plants (``montecarlo_compare``), and the
smallest cyclic limit each one needs (``controller_cyclic_limits``).

Monte Carlo comparison. Draw i is the Monte Carlo's own (``montecarlo.draw`` with
``draw_seed(seed, i)``: wind and plant dispersed, the dispersed plant's own hover trim); it is
flown free under the paper's controller (the reference the tether is judged against) and
tethered under every controller, each designed on the file's nominal parameters
(``simulate(design_params=...)``, as ``run_batch`` does in ``tetherheli montecarlo``). With
imperfect ``[sensors]`` each draw gets its own sensor noise: the scenario's ``seed`` becomes
the first word of ``SeedSequence(seed, spawn_key=(i, 1))`` (the turbulence's stream is
(i, 0)); with the tether as position source the free reference flies on the GNSS of the
same presets. With ``eq40`` the cyclic torques saturate at eq 40's limit of the *nominal*
parameters (an actuator's authority, not redrawn with the plant).

Every run is measured by ``controllers.controller_metrics``; a run that fails in flight or
whose plant cannot be set up is a failure, counted and placed in the failing tail of the
percentiles (``montecarlo.statistics.with_failures``, ``tail_percentile``). The paired
reduction against the free helicopter is ``statistics.paired_reduction`` per draw; a draw whose
free run failed has no reference and no reduction: the reductions' percentiles cover the other
draws, and a controller's status counts the draws without a reference.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .._validation import check_integer
from ..errors import TetherheliError
from ..resources import check_memory
from ..results.result import SummaryRepr
from ..scenario.core import Scenario
from .controllers import CONTROLLER_METRICS, eq40_saturated, fly, with_controller
from .montecarlo import MonteCarloConfig, draw, draw_seed
from .montecarlo.config import MAX_RUNS
from .montecarlo.draws import free_reference
from .montecarlo.statistics import paired_reduction, tail_percentile, with_failures

__all__ = [
    "FREE",
    "PERCENTILES",
    "REDUCED",
    "MonteCarloComparison",
    "check_comparison_memory",
    "controller_cyclic_limits",
    "montecarlo_compare",
    "run_threads",
    "thread_count",
]

#: the label of the free helicopter's runs (the paper's free law)
FREE = "free"
#: the percentiles reported [%]: the median and the failing tail
PERCENTILES = (50.0, 95.0)
#: the metrics whose paired reduction against the free helicopter is reported
REDUCED = ("peak_q1", "peak_q2", "rms_q1", "rms_q2")
#: the numeric measures summarised by percentiles (``CONTROLLER_METRICS`` but the flags)
_MEASURES = tuple(m for m in CONTROLLER_METRICS if m not in ("completed", "cyclic_limit"))


def thread_count(workers: int | None, n: int, scenario: Scenario | None = None) -> int:
    """The threads ``run_threads`` uses for ``n`` tasks: ``workers`` (default: the CPUs
    available), at most ``n``; with ``scenario``, refused (``ResourceLimitError``) when that
    many of its recorded runs at once exceed the memory budget.

    Parameters
    ----------
    workers : int, optional
        Threads asked for, >= 1.
    n : int
        Number of tasks.
    scenario : Scenario, optional
        The run each thread records (its size).

    Returns
    -------
    int
        Threads, >= 1.
    """
    from ..runs.batch import _default_workers
    from ..runs.closed_loop import check_run_memory

    workers = _default_workers() if workers is None else check_integer("workers", workers, low=1)
    threads = max(1, min(workers, n))
    if scenario is not None:
        check_run_memory(
            scenario, concurrent=threads, hint="shorten the duration, or fewer --workers"
        )
    return threads


def run_threads(task: Callable[[int], None], n: int, workers: int | None) -> None:
    """Call ``task(i)`` for i in 0..n-1 on ``workers`` threads (default: the CPUs available;
    1: one after the other, in order); an exception of a task is raised here. The compiled
    engine releases the GIL, so the runs of a comparison fly side by side.

    Parameters
    ----------
    task : callable
        Index -> None; each index's results go to its own slots.
    n : int
        Number of tasks.
    workers : int, optional
        Threads, >= 1.

    Returns
    -------
    None
    """
    threads = thread_count(workers, n)
    if threads == 1:
        for i in range(n):
            task(i)
        return
    with ThreadPoolExecutor(max_workers=threads) as pool:
        for _ in pool.map(task, range(n)):
            pass


def _worst(metric: str) -> float:
    """The value a failed run counts as: -inf where larger is better (the lowest tension)."""
    return -math.inf if metric == "tension_min" else math.inf


def _config(label: str) -> str:
    return "free" if label == FREE else "tethered"


def _sensor_seed(root: int, index: int) -> int:
    return int(np.random.SeedSequence(root, spawn_key=(index, 1)).generate_state(1)[0])


@dataclass(frozen=True, repr=False)
class MonteCarloComparison(SummaryRepr):
    """The result of ``montecarlo_compare``.

    Parameters
    ----------
    scenario_name : str
        The nominal scenario's name.
    runs : int
        Draws N.
    seed : int
        The Monte Carlo's root seed.
    labels : tuple of str
        ``FREE`` then the controllers.
    values : dict of str to dict of str to ndarray
        label -> measure (``CONTROLLER_METRICS``) -> (N,) per draw (NaN where failed).
    ok : dict of str to ndarray
        label -> (N,) bool: the run completed.
    statuses : dict of str to tuple of str
        label -> each draw's status message (or why it could not be set up).
    configuration : dict of str to object
        The nominal scenario and the dispersions as plain data.
    """

    scenario_name: str
    runs: int
    seed: int
    labels: tuple[str, ...]
    values: dict[str, dict[str, np.ndarray]]
    ok: dict[str, np.ndarray]
    statuses: dict[str, tuple[str, ...]]
    configuration: dict[str, Any] = field(default_factory=dict)

    def _summary_rows(self) -> list[tuple[str, str]]:
        return [
            ("scenario", self.scenario_name),
            ("draws", f"{self.runs} (seed {self.seed})"),
            ("failed", ", ".join(f"{lab} {self.failures(lab)}" for lab in self.labels)),
        ]

    def failures(self, label: str) -> int:
        """Draws of ``label`` that failed (in flight or at set-up).

        Parameters
        ----------
        label : str
            ``FREE`` or a controller.

        Returns
        -------
        int
        """
        return int(np.count_nonzero(~self.ok[label]))

    def percentiles(self, label: str) -> dict[str, np.ndarray]:
        """``PERCENTILES`` of every measure of ``label``, failures as the worst value.

        Parameters
        ----------
        label : str
            ``FREE`` or a controller.

        Returns
        -------
        dict of str to ndarray
            measure -> (len(PERCENTILES),); +-inf where a percentile lies among failures.
        """
        ok = self.ok[label]
        return {
            m: tail_percentile(with_failures(self.values[label][m], ok, _worst(m)), PERCENTILES)
            for m in _MEASURES
        }

    def reduction(self, label: str, metric: str) -> np.ndarray:
        """The per-draw paired reduction of ``metric`` by ``label`` against the free run
        (``statistics.paired_reduction``) [%].

        Parameters
        ----------
        label : str
            A controller.
        metric : str
            One of ``REDUCED``.

        Returns
        -------
        ndarray, shape (N,)
        """
        return paired_reduction(
            self.values[FREE][metric], self.values[label][metric], self.ok[FREE], self.ok[label]
        )

    def reduction_percentiles(self, label: str, metric: str) -> tuple[float, float]:
        """The median and 5th percentile (the worst 5 % of draws) of ``reduction`` over the
        draws with a completed free reference (NaN where none has one) [%].

        Parameters
        ----------
        label : str
            A controller.
        metric : str
            One of ``REDUCED``.

        Returns
        -------
        (float, float)
            p50 and p5; -inf where it lies among the controller's failures.
        """
        r = self.reduction(label, metric)
        r = r[~np.isnan(r)]  # a failed free run is no reference
        if not r.size:
            return math.nan, math.nan
        r50, r5 = tail_percentile(r, [50.0, 5.0])
        return float(r50), float(r5)

    def rows(self) -> list[dict[str, Any]]:
        """One row per (label, percentile) in the comparison's columns (``compare``): the
        ``scenario`` names the percentile, ``failures`` the count out of N; the paired
        reductions' median and 5th percentile (the worst 5% of draws) as
        ``reduction_<metric>_p50``, ``_p5`` [%].

        Returns
        -------
        list of dict of str to object
        """
        out = []
        for label in self.labels:
            pct = self.percentiles(label)
            red = {}
            if label != FREE:
                for m in REDUCED:
                    r50, r5 = self.reduction_percentiles(label, m)
                    red[f"reduction_{m}_p50"] = r50
                    red[f"reduction_{m}_p5"] = r5
            status = f"{self.failures(label)}/{self.runs} failed"
            if label != FREE and self.failures(FREE):
                status += f", {self.failures(FREE)}/{self.runs} without a free reference"
            for k, p in enumerate(PERCENTILES):
                row: dict[str, Any] = {
                    "scenario": f"{self.scenario_name} {_config(label)} p{p:g}",
                    "configuration": _config(label),
                    "controller": "paper" if label == FREE else label,
                    "status": status,
                    "failures": self.failures(label),
                    "runs": self.runs,
                    "completed": self.failures(label) == 0,
                    "cyclic_limit": float(self.values[label]["cyclic_limit"][0]),
                }
                row.update({m: float(v[k]) for m, v in pct.items()})
                row.update(red)
                out.append(row)
        return out

    def as_dict(self) -> dict[str, Any]:
        """Per-draw values, statuses and the configuration (JSON-friendly, NaN/inf as null).

        Returns
        -------
        dict of str to object
        """

        def num(v: float) -> float | None:
            return float(v) if math.isfinite(v) else None

        return {
            "scenario": self.scenario_name,
            "runs": self.runs,
            "seed": self.seed,
            "percentiles": list(PERCENTILES),
            "failures": {lab: self.failures(lab) for lab in self.labels},
            "draws": {
                lab: {
                    "ok": self.ok[lab].tolist(),
                    "status": list(self.statuses[lab]),
                    **{m: [num(v) for v in self.values[lab][m]] for m in _MEASURES},
                }
                for lab in self.labels
            },
            "configuration": self.configuration,
        }


#: Memory per (draw, run kind) of a comparison: the measures' arrays, the status, and
#: summary.json's copy (``MonteCarloComparison.as_dict``: Python floats in lists, then the
#: indented JSON text) of about 18 measures; about 1.4 kB, margin kept.
_COMPARED_RUN_BYTES = 2_048


def check_comparison_memory(runs: int, kinds: int) -> int:
    """Estimate the bytes a Monte Carlo comparison of ``runs`` draws and ``kinds`` run kinds
    (the free reference and each controller) holds, its results and its summary.json, and
    refuse it (``ResourceLimitError``) above the memory budget (``tetherheli.resources``),
    before any draw is flown.

    Parameters
    ----------
    runs : int
        Draws N.
    kinds : int
        Run kinds per draw (``FREE`` and the controllers).

    Returns
    -------
    int
        The estimated bytes.

    Raises
    ------
    ResourceLimitError
        The estimate exceeds the budget.
    """
    needed = runs * kinds * _COMPARED_RUN_BYTES
    check_memory(
        f"a Monte Carlo comparison of runs = {runs} draws x {kinds} run kinds",
        needed,
        hint="compare fewer draws (--runs)",
    )
    return needed


def montecarlo_compare(
    base: Scenario,
    config: MonteCarloConfig,
    controllers: tuple[str, ...],
    *,
    runs: int | None = None,
    eq40: bool = False,
    seed: int | None = None,
    workers: int | None = 1,
) -> MonteCarloComparison:
    """Fly the first ``runs`` draws of a Monte Carlo free (paper) and tethered under each of
    ``controllers``, all designed on ``base``'s nominal parameters (module docstring).

    Parameters
    ----------
    base : Scenario
        The nominal scenario (``montecarlo.load_montecarlo``).
    config : MonteCarloConfig
        The dispersions and the root seed.
    controllers : tuple of str
        Controller names (``scenario.core.CONTROLLERS``).
    runs : int, optional
        Draws N (default ``config.runs``).
    eq40 : bool, optional
        Saturate tMR1, tMR2 at eq 40's limit of the nominal parameters (default False).
    seed : int, optional
        The root seed of the draws (default ``config.seed``): draw i is that of
        ``draw_seed(seed, i)``, the same for the same seed.
    workers : int, optional
        Threads flying the draws (default 1, one after the other; None: the CPUs available;
        ``run_threads``). The measures do not depend on it, but for the compute time, which
        is taken with the other runs in flight.

    Returns
    -------
    MonteCarloComparison
        Per-draw measures of every run, failures included.
    """
    n = check_integer("runs", config.runs if runs is None else runs, low=1, high=MAX_RUNS)
    if seed is not None:
        config = replace(config, seed=check_integer("seed", seed, low=0, high=2**63 - 1))
    labels = (FREE, *controllers)
    check_comparison_memory(n, len(labels))
    threads = thread_count(workers, n, base)  # recorded runs in flight at once
    if eq40:
        base = eq40_saturated(base)
    cols = {lab: {m: np.full(n, math.nan) for m in CONTROLLER_METRICS} for lab in labels}
    ok = {lab: np.zeros(n, dtype=bool) for lab in labels}
    statuses: dict[str, list[str]] = {lab: [""] * n for lab in labels}
    noisy = not base.sensors.is_perfect
    for lab in labels:  # compile and warm up each law on the nominal plant (not measured)
        try:
            fly(_flown(base, lab).replace(duration=min(base.duration, 1.0)))
        except TetherheliError:  # the nominal plant cannot be set up: its draws will say why
            pass

    def fly_draw(i: int) -> None:  # draw i's runs: its own slots of cols, ok and statuses
        d = draw(base, config, draw_seed(config.seed, i), i)
        for lab in labels:
            if d.scenario is None:
                statuses[lab][i] = f"set-up: {d.reason}"
                continue
            s = d.scenario.replace(seed=_sensor_seed(config.seed, i)) if noisy else d.scenario
            try:
                result, metrics = fly(_flown(s, lab), design_params=base.params)
            except TetherheliError as exc:  # the dispersed plant cannot be set up
                statuses[lab][i] = f"set-up: {str(exc).splitlines()[0]}"
                continue
            statuses[lab][i] = result.message
            ok[lab][i] = bool(result.ok)
            for m in CONTROLLER_METRICS:
                cols[lab][m][i] = float(metrics[m]) if result.ok else math.nan

    run_threads(fly_draw, n, threads)
    for lab in labels:  # the limit is a setting, not an outcome: kept for failed runs too
        cols[lab]["cyclic_limit"][:] = _cyclic_limit(base)
    return MonteCarloComparison(
        base.name,
        n,
        config.seed,
        labels,
        cols,
        ok,
        {lab: tuple(v) for lab, v in statuses.items()},
        configuration={"scenario": base.to_dict(), "montecarlo": config.to_dict()},
    )


def _cyclic_limit(scenario: Scenario) -> float:
    from .sweep import scenario_cyclic_limit

    lim = scenario_cyclic_limit(scenario)
    return math.nan if lim is None else float(lim)


def _flown(scenario: Scenario, label: str) -> Scenario:
    """The run of ``label``: the free helicopter under the paper's law (no tether at all, so
    none of a lumped study's chain: ``[tether]`` at its defaults), or tethered."""
    if label == FREE:
        return with_controller(free_reference(scenario), "paper")
    return with_controller(scenario.replace(configuration="tethered"), label)


def controller_cyclic_limits(
    scenario: Scenario,
    controllers: tuple[str, ...],
    grid: np.ndarray,
    **search: Any,
) -> dict[str, Any]:
    """The smallest cyclic limit each controller needs on ``scenario``
    (``cyclic_limit.minimum_cyclic_limit``'s criterion, with its ``controller``).

    Parameters
    ----------
    scenario : Scenario
        The scenario (its configuration kept).
    controllers : tuple of str
        Controller names.
    grid : ndarray
        The limits scanned [N m].
    **search
        ``minimum_cyclic_limit``'s keywords (``within``, ``metric``, ``tol``, ``workers``).

    Returns
    -------
    dict of str to LimitSearch
        controller -> its search.
    """
    from .cyclic_limit import minimum_cyclic_limit

    return {
        name: minimum_cyclic_limit(scenario, grid, controller=name, **search)
        for name in controllers
    }
