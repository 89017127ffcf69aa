"""Design sweeps: one metric of a scenario against one parameter, e.g. the reference tension
(the trade-off of Sec. IV-C, eq 40), the tether stiffness KC, the attachment offset dO-P,3 or
the sample time dt.

The tension bound of eq 40: the tether moment |dO-P,3 - dO-HO,3| TC must stay below the cyclic
saturation torque tmax_MR1,2, so TC < tmax / |arm|. The paper sizes it as 20% of the hover
lift, tmax = 0.2 fMR3,hover |arm| (``paper_cyclic_limit``). |arm| TC is a worst case: it is
the moment of a tether perpendicular to the shaft. A sweep of a tethered scenario therefore
also records the moment the tether really exerts (``analysis.tether_moment``) next to it.

The cyclic authority of a sweep is one fact: the limit passed as ``cyclic_limit`` (applied to
every run), else the scenario's own ``[actuators]`` limits on tMR1, tMR2 (applied, as always),
else the paper's 20% rule, which then only sizes the bound: the runs are not saturated
(``SweepResult.limit_applied`` says which).

``minimum_cyclic_limit`` finds the smallest cyclic limit that keeps a metric (the peak
deviation) within a fraction of the unlimited run's, as an interval (``LimitSearch``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analysis import run_metrics, tether_moment
from ..errors import InfeasibleError, ParameterError
from ..names import POSITION
from ..params import Params
from ..progress import Progress
from ..results.result import SummaryRepr
from ..runs import simulate
from ..runs.batch import run_batch
from ..scenario import Scenario
from ..wind import compile_wind

__all__ = [
    "METRICS",
    "SweepResult",
    "paper_cyclic_limit",
    "parameter_label",
    "scenario_cyclic_limit",
    "sweep",
    "tension_bound",
]

#: metric name -> (group, key) of ``RunMetrics``
METRICS = {
    **{f"peak_{q}": ("peak_abs_dev", q) for q in (*POSITION, "q4_deg", "q5_deg")},
    **{f"rms_{q}": ("rms_dev", q) for q in POSITION},
    "tension_max": ("tension_max", None),
}
_ACTUATOR_FIELDS = {
    "actuators.cyclic_limit",  # symmetric limit on tMR1 and tMR2 (eq 40's tmax_MR1,2) [N m]
    "actuators.time_constant",
    "actuators.reel_rate_limit",
    "actuators.reel_acceleration_limit",
    "actuators.breaking_tension",
}
_SCENARIO_FIELDS = {"q9", "control.dt", *_ACTUATOR_FIELDS}
#: axis labels (name [unit]) of the scenario settings a sweep can vary (``ActuatorSettings``)
_SCENARIO_LABELS = {
    "q9": "tether length q9 [m]",
    "control.dt": "controller sample time dt [s]",
    "actuators.cyclic_limit": "cyclic limit tmax_MR1,2 [N m]",
    "actuators.time_constant": "actuator time constant [s]",
    "actuators.reel_rate_limit": "reel-rate limit |dLN/dt| [m/s]",
    "actuators.reel_acceleration_limit": "reel-acceleration limit [m/s^2]",
    "actuators.breaking_tension": "breaking tension [N]",
}


def parameter_label(parameter: str) -> str:
    """An axis label for a swept ``parameter``: its name and unit, from the parameters' own
    documentation (``Params.field_docs``) or the scenario settings'.

    Parameters
    ----------
    parameter : str
        The swept parameter (as ``sweep`` takes it).

    Returns
    -------
    str
        The label, e.g. "name: description [unit]"; the bare name without a unit.
    """
    if parameter in _SCENARIO_LABELS:
        return _SCENARIO_LABELS[parameter]
    doc = Params.field_docs().get(parameter)
    if doc and "]" in doc:
        return f"{parameter}: {doc[: doc.index(']') + 1]}"
    return parameter


def paper_cyclic_limit(params: Params) -> float:
    """tmax_MR1,2 implied by the paper (eq 40): 20% of the free hover lift times |arm| [N m].

    Parameters
    ----------
    params : Params
        The helicopter's parameters.

    Returns
    -------
    float
        The cyclic limit [N m].
    """
    from ..model import TetheredHelicopter

    lift = float(TetheredHelicopter(params).trim(0.0).u[0])
    return 0.2 * lift * abs(params.helicopter.tether_arm)


def scenario_cyclic_limit(scenario: Scenario) -> float | None:
    """The cyclic authority of a scenario's ``[actuators]``: the smallest magnitude among the
    limits of tMR1 and tMR2 (u_min, u_max) [N m]; None when they are unlimited.

    Parameters
    ----------
    scenario : Scenario
        The scenario whose actuator limits are read.

    Returns
    -------
    float or None
        The cyclic authority [N m], or None.
    """
    a = scenario.actuators
    limit = min(abs(a.u_min[1]), abs(a.u_min[2]), abs(a.u_max[1]), abs(a.u_max[2]))
    return float(limit) if math.isfinite(limit) else None


def _check_cyclic_limit(name: str, value: float) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise ParameterError(name, value, "a torque > 0 [N m]")
    return float(value)


def tension_bound(params: Params, cyclic_limit: float) -> float:
    """Eq 40: the largest tension whose moment about HO the cyclic can still balance [N].

    Parameters
    ----------
    params : Params
        The helicopter's parameters (its tether arm [m]).
    cyclic_limit : float
        The cyclic authority tmax_MR1,2 [N m], > 0.

    Returns
    -------
    float
        cyclic_limit / |arm| [N].
    """
    cyclic_limit = _check_cyclic_limit("cyclic_limit", cyclic_limit)
    return cyclic_limit / abs(params.helicopter.tether_arm)


def _with(scenario: Scenario, parameter: str, value: float) -> Scenario:
    if parameter == "q9":
        return scenario.replace(q9=value)
    if parameter == "control.dt":
        return scenario.replace(control=dataclasses.replace(scenario.control, dt=value))
    if parameter == "actuators.cyclic_limit":
        if not (value == math.inf or (math.isfinite(value) and value > 0)):
            raise ParameterError(parameter, value, "a torque > 0 [N m]")
        a = scenario.actuators
        u_min = (a.u_min[0], -value, -value, a.u_min[3])
        u_max = (a.u_max[0], value, value, a.u_max[3])
        return scenario.replace(actuators=dataclasses.replace(a, u_min=u_min, u_max=u_max))
    if parameter in _ACTUATOR_FIELDS:
        field = parameter.partition(".")[2]
        return scenario.replace(actuators=dataclasses.replace(scenario.actuators, **{field: value}))
    if parameter == "tether.EA":  # the law's EA is the scenario's [tether] EA (the rope's)
        return scenario.replace(tether=dataclasses.replace(scenario.tether, EA=value))
    return scenario.replace(params=scenario.params.replace({parameter: value}))


@dataclass(frozen=True, repr=False)
class SweepResult(SummaryRepr):
    """values (n,), metric (n,) (NaN where the run failed or the point was invalid),
    statuses (n,), completed (n,) (the run completed; a tether release counts as completed),
    and the best value among the completed runs.

    ``cyclic_limit`` is the sweep's cyclic authority tmax_MR1,2 [N m] and ``limit_applied``
    whether the runs were saturated at it (False: the paper's 20% rule, used only for the
    bound). ``bound`` is eq 40's tension bound from it (T_ref sweeps), ``best_within_bound``
    the best value at or below the bound. For a tethered scenario ``peak_tether_moment`` (n,)
    is each completed run's largest tether moment about HO on f1 or f2 [N m]
    (``analysis.tether_moment``), ``peak_tether_angle_deg`` (n,) the largest tether-to-shaft
    angle and ``peak_worst_case_moment`` (n,) eq 40's |arm| max TC; NaN otherwise. An invalid
    point's status is "invalid: <why>". ``configuration`` is the swept scenario as plain data
    (``Scenario.to_dict``, as manifests record it), before the swept value is applied.

    Parameters
    ----------
    parameter : str
        The swept parameter.
    metric_name : str
        The metric collected (``METRICS``).
    values : ndarray, shape (n,)
        The swept values, in the parameter's unit.
    metric : ndarray, shape (n,)
        The metric of each point, in its unit (NaN where failed or invalid).
    statuses : tuple of str
        Each point's status message.
    bound : float or None
        Eq 40's tension bound [N] (T_ref sweeps), else None.
    best_value : float or None
        The value with the smallest metric among the completed runs.
    completed : tuple of bool, optional
        Whether each point's run completed.
    cyclic_limit : float or None, optional
        The sweep's cyclic authority [N m].
    limit_applied : bool, optional
        Whether the runs were saturated at ``cyclic_limit``.
    best_within_bound : float or None, optional
        The best value at or below ``bound``.
    peak_tether_moment : ndarray, shape (n,), optional
        Each completed run's largest tether moment about HO [N m].
    peak_tether_angle_deg : ndarray, shape (n,), optional
        The largest tether-to-shaft angle [deg].
    peak_worst_case_moment : ndarray, shape (n,), optional
        Eq 40's |arm| max TC [N m].
    configuration : dict of str to object, optional
        The swept scenario as plain data.
    """

    parameter: str
    metric_name: str
    values: np.ndarray
    metric: np.ndarray
    statuses: tuple[str, ...]
    bound: float | None
    best_value: float | None
    completed: tuple[bool, ...] = ()
    cyclic_limit: float | None = None
    limit_applied: bool = False
    best_within_bound: float | None = None
    peak_tether_moment: np.ndarray | None = None
    peak_tether_angle_deg: np.ndarray | None = None
    peak_worst_case_moment: np.ndarray | None = None
    configuration: dict[str, Any] = field(default_factory=dict)

    @property
    def failed(self) -> tuple[int, ...]:
        """Indices of the points whose run failed or that were invalid."""
        return tuple(i for i, ok in enumerate(self.completed) if not ok)

    def _summary_rows(self) -> list[tuple[str, str]]:
        values = self.values
        span = f"{values.min():g} .. {values.max():g}" if values.size else "none"
        rows = [
            ("parameter", f"{self.parameter}: {values.size} values, {span}"),
            ("metric", self.metric_name),
            ("failed", f"{len(self.failed)} of {values.size}"),
            ("best value", "none" if self.best_value is None else f"{self.best_value:g}"),
        ]
        if self.bound is not None:
            within = self.best_within_bound
            rows.append(("eq 40 bound", f"{self.bound:g} N (best within: "
                         f"{'none' if within is None else f'{within:g}'})"))  # fmt: skip
        return rows

    @property
    def limit_source(self) -> str:
        """Where the cyclic authority comes from, in words."""
        if self.cyclic_limit is None:
            return "none"
        if self.limit_applied:
            return "applied to every run (scenario actuators or cyclic_limit)"
        return "the paper's 20% rule, not applied: the runs are not saturated"

    def as_dict(self) -> dict[str, Any]:
        """The sweep as a JSON-friendly record (summary.json).

        Returns
        -------
        dict of str to object
            The fields with units in their names (NaN written as null).
        """

        def floats(a: np.ndarray | None) -> list[float | None] | None:
            if a is None:
                return None
            return [None if not np.isfinite(m) else float(m) for m in a]

        return {
            "parameter": self.parameter,
            "metric": self.metric_name,
            "values": self.values.tolist(),
            "metric_values": floats(self.metric),
            "statuses": list(self.statuses),
            "completed": list(self.completed),
            "failed": len(self.failed),
            "cyclic_limit_Nm": self.cyclic_limit,
            "cyclic_limit_applied": self.limit_applied,
            "cyclic_limit_source": self.limit_source,
            "tension_bound_eq40": self.bound,
            "best_value": self.best_value,
            "best_value_within_bound": self.best_within_bound,
            "peak_tether_moment_Nm": floats(self.peak_tether_moment),
            "peak_tether_angle_deg": floats(self.peak_tether_angle_deg),
            "eq40_worst_case_moment_Nm": floats(self.peak_worst_case_moment),
            "configuration": self.configuration,
        }


_INVALID = "invalid: "


def _prepare_points(
    scenario: Scenario, parameter: str, values: np.ndarray
) -> tuple[list[Scenario | None], list[str]]:
    """The scenario of every value, or None with the reason when the physics cannot meet it
    (``InfeasibleError``: e.g. a T_ref above what the tether gives); malformed values
    (``ParameterError``) stop the sweep, naming the point."""
    scenarios: list[Scenario | None] = []
    reasons: list[str] = []
    for v in values:
        try:
            scenarios.append(_with(scenario, parameter, float(v)))
            reasons.append("")
        except InfeasibleError as exc:
            scenarios.append(None)
            reasons.append(_INVALID + str(exc))
        except ParameterError as exc:  # named with the point that made it
            raise type(exc)(
                exc.field, exc.value, exc.allowed, source=f"sweep point {parameter} = {v:g}"
            ) from None
    return scenarios, reasons


def _run_batch_feasible(
    scenarios: list[Scenario | None], reasons: list[str], on_done=None, workers: int | None = None
):
    """``run_batch`` over the valid points; a point whose set-up the physics cannot meet
    (no trim, a hover outside the actuator limits) becomes invalid, the others still run."""
    from ..runs.setup import engine_setup

    idx = [i for i, s in enumerate(scenarios) if s is not None]
    try:
        return idx, run_batch([scenarios[i] for i in idx], on_done=on_done, workers=workers)  # type: ignore[misc]
    except InfeasibleError:
        for i in idx:  # rare: find the points that cannot be set up, then run the rest
            try:
                engine_setup(scenarios[i])  # type: ignore[arg-type]
            except InfeasibleError as exc:
                scenarios[i] = None
                reasons[i] = _INVALID + str(exc)
        idx = [i for i, s in enumerate(scenarios) if s is not None]
        return idx, run_batch([scenarios[i] for i in idx], on_done=on_done, workers=workers)  # type: ignore[misc]


def _evaluate(
    scenarios: list[Scenario | None],
    statuses: list[str],
    metric: str,
    bar: Progress | None = None,
    workers: int | None = None,
) -> tuple[np.ndarray, list[bool]]:
    """Run every valid point; the metric (NaN unless completed) and whether each completed.
    ``statuses`` receives each run's message (or "invalid: <why>"); ``bar`` counts runs;
    ``workers``: threads of ``run_batch``."""
    update = bar.update if bar is not None else None
    out = np.full(len(scenarios), np.nan)
    completed = [False] * len(scenarios)
    wind = next((s.wind for s in scenarios if s is not None), None)
    if wind is not None and compile_wind(wind) is not None:
        # built-in winds (the sweep does not change the wind): the compiled batch on all
        # cores (per-run summaries, the numbers of simulate); its metric names are METRICS'
        idx, batch = _run_batch_feasible(scenarios, statuses, update, workers)
        for j, i in enumerate(idx):
            statuses[i] = batch.message(j)
            completed[i] = bool(batch.ok[j])
            if completed[i]:
                out[i] = batch.metrics(j)[metric]
        return out, completed
    group, key = METRICS[metric]
    for i, s in enumerate(scenarios):
        if update is not None:
            update(1)
        if s is None:
            continue
        try:
            r = simulate(s)
        except InfeasibleError as exc:
            statuses[i] = _INVALID + str(exc)
            continue
        statuses[i] = r.message
        completed[i] = r.ok
        if r.ok:
            m = run_metrics(r)
            out[i] = getattr(m, group)[key] if key else getattr(m, group)
    return out, completed


def sweep(
    scenario: Scenario,
    parameter: str,
    values: np.ndarray,
    metric: str = "rms_q1",
    *,
    cyclic_limit: float | None = None,
    moments: bool = True,
    progress: bool = False,
    workers: int | None = None,
) -> SweepResult:
    """Simulate ``scenario`` once per value of ``parameter`` and collect ``metric`` (see
    ``METRICS``).

    ``parameter`` is a "section.field" of Params, "q9", "control.dt", or an actuator setting:
    "actuators.cyclic_limit" (symmetric limit on tMR1, tMR2: eq 40's tmax_MR1,2 [N m]),
    "actuators.time_constant", "actuators.reel_rate_limit",
    "actuators.reel_acceleration_limit", "actuators.breaking_tension". Built-in winds run as
    one compiled batch on all cores (``runs.batch.run_batch``, the numbers of ``simulate``).

    ``cyclic_limit`` [N m], when given, saturates tMR1 and tMR2 of every run at +-cyclic_limit
    (not with ``parameter`` "actuators.cyclic_limit"); without it the scenario's own limits act
    and set the eq-40 bound, or, if it has none, the paper's 20% rule sets the bound alone
    (``SweepResult.limit_applied`` False). With ``moments`` (tethered scenarios) every
    completed point is also simulated with its signals recorded to measure the tether's peak
    moment about HO (``analysis.tether_moment``). ``progress`` shows the runs done on stderr
    (``tetherheli.progress``); ``workers`` is the number of threads (default: all CPUs).

    A value the physics cannot meet (``InfeasibleError``: a T_ref above what the tether gives
    at its length, a hover outside the actuator limits, no trim) is recorded as an invalid
    point, status "invalid: <why>", metric NaN, not completed; the other points still run.
    A malformed value (e.g. a negative cyclic limit) raises ParameterError: no sweep.

    Parameters
    ----------
    scenario : Scenario
        The scenario to sweep.
    parameter : str
        What to sweep (see above).
    values : ndarray, shape (n,)
        The values, finite, in the parameter's unit.
    metric : str, optional
        One of ``METRICS`` (default "rms_q1", [m]).
    cyclic_limit : float, optional
        Saturate tMR1, tMR2 at +-cyclic_limit [N m].
    moments : bool, optional
        Measure the tether's peak moment of each completed point (default True).
    progress : bool, optional
        Show progress on stderr (default False).
    workers : int, optional
        Number of threads (default all CPUs).

    Returns
    -------
    SweepResult
        The metric per value, statuses, the bound and the best value.
    """
    if metric not in METRICS:
        raise ParameterError("metric", metric, f"one of {sorted(METRICS)}")
    allowed = set(Params.field_docs()) | _SCENARIO_FIELDS
    if parameter not in allowed:
        raise ParameterError("parameter", parameter, f"one of {sorted(allowed)}")
    values = np.asarray(values, dtype=float)
    if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values)):
        raise ParameterError("values", values.tolist(), "a non-empty list of finite numbers")
    limit_applied = True
    if cyclic_limit is not None:
        cyclic_limit = _check_cyclic_limit("cyclic_limit", cyclic_limit)
        if parameter == "actuators.cyclic_limit":
            raise ParameterError(
                "cyclic_limit", cyclic_limit, "None when sweeping actuators.cyclic_limit itself"
            )
        scenario = _with(scenario, "actuators.cyclic_limit", cyclic_limit)
    elif parameter != "actuators.cyclic_limit":
        cyclic_limit = scenario_cyclic_limit(scenario)
        if cyclic_limit is None:
            cyclic_limit, limit_applied = paper_cyclic_limit(scenario.params), False
    scenarios, statuses = _prepare_points(scenario, parameter, values)  # validates each
    moments = moments and scenario.configuration == "tethered"
    total = values.size * (2 if moments else 1)
    with Progress("sweep", total, "runs", enabled=progress) as bar:
        out, completed = _evaluate(scenarios, statuses, metric, bar, workers)
        bar.update_to(values.size)  # the invalid points count as done
        peaks = angles = worst = None
        if moments:
            peaks, angles, worst = (np.full(values.size, np.nan) for _ in range(3))
            for i, s in enumerate(scenarios):
                if s is not None and completed[i]:
                    tm = tether_moment(simulate(s), s.params)
                    peaks[i], angles[i], worst[i] = tm.peak, tm.peak_angle_deg, tm.peak_worst_case
                bar.update(1)
    bound = None
    if parameter == "tension_control.T_ref" and cyclic_limit is not None:
        bound = tension_bound(scenario.params, cyclic_limit)
    ok = np.isfinite(out)
    best = float(values[ok][np.argmin(out[ok])]) if np.any(ok) else None
    best_within = None
    if bound is not None:
        inside = ok & (values <= bound)
        best_within = float(values[inside][np.argmin(out[inside])]) if np.any(inside) else None
    return SweepResult(
        parameter,
        metric,
        values,
        out,
        tuple(statuses),
        bound,
        best,
        tuple(completed),
        cyclic_limit=cyclic_limit,
        limit_applied=limit_applied and cyclic_limit is not None,
        best_within_bound=best_within,
        peak_tether_moment=peaks,
        peak_tether_angle_deg=angles,
        peak_worst_case_moment=worst,
        configuration=scenario.to_dict(),
    )
