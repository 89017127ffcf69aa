"""Design sweeps: one metric of a scenario against one parameter, e.g. the reference tension
(the trade-off of Sec. IV-C, eq 40), the tether stiffness KC, the attachment offset dO-P,3 or
the sample time dt.

The tension bound of eq 40: the tether moment |dO-P,3 - dO-HO,3| TC must stay below the cyclic
saturation torque tmax_MR1,2, so TC < tmax / |arm|. The paper sizes it as 20% of the hover
lift, tmax = 0.2 fMR3,hover |arm| (``paper_cyclic_limit``).
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write_text, output_directory
from .._version import __version__
from ..analysis import run_metrics
from ..errors import InfeasibleError, ParameterError
from ..names import POSITION
from ..params import Params
from ..sim import Scenario, simulate
from ..sim.batch import run_batch
from ..wind import compile_wind

__all__ = ["METRICS", "SweepResult", "paper_cyclic_limit", "sweep", "tension_bound", "write_sweep"]

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


def paper_cyclic_limit(params: Params) -> float:
    """tmax_MR1,2 implied by the paper (eq 40): 20% of the free hover lift times |arm| [N m]."""
    from ..model import TetheredHelicopter

    lift = float(TetheredHelicopter(params).trim(0.0).u[0])
    return 0.2 * lift * abs(params.helicopter.tether_arm)


def tension_bound(params: Params, cyclic_limit: float) -> float:
    """Eq 40: the largest tension whose moment about HO the cyclic can still balance [N]."""
    if not (math.isfinite(cyclic_limit) and cyclic_limit > 0):
        raise ParameterError("cyclic_limit", cyclic_limit, "a torque > 0 [N m]")
    return cyclic_limit / abs(params.helicopter.tether_arm)


def _with(scenario: Scenario, parameter: str, value: float) -> Scenario:
    if parameter == "q9":
        return scenario.replace(q9=value)
    if parameter == "control.dt":
        return scenario.replace(control=dataclasses.replace(scenario.control, dt=value))
    if parameter == "actuators.cyclic_limit":
        if not (math.isfinite(value) and value > 0):
            raise ParameterError(parameter, value, "a torque > 0 [N m]")
        a = scenario.actuators
        u_min = (a.u_min[0], -value, -value, a.u_min[3])
        u_max = (a.u_max[0], value, value, a.u_max[3])
        return scenario.replace(actuators=dataclasses.replace(a, u_min=u_min, u_max=u_max))
    if parameter in _ACTUATOR_FIELDS:
        field = parameter.partition(".")[2]
        return scenario.replace(actuators=dataclasses.replace(scenario.actuators, **{field: value}))
    return scenario.replace(params=scenario.params.replace({parameter: value}))


@dataclass(frozen=True)
class SweepResult:
    """values (n,), metric (n,) (NaN where the run failed or the point was invalid),
    statuses (n,), completed (n,) (the run completed; a tether release counts as completed),
    and the best value among the completed runs (below the eq-40 bound when sweeping T_ref
    with a bound). An invalid point's status is "invalid: <why>"."""

    parameter: str
    metric_name: str
    values: np.ndarray
    metric: np.ndarray
    statuses: tuple[str, ...]
    bound: float | None
    best_value: float | None
    completed: tuple[bool, ...] = ()

    @property
    def failed(self) -> tuple[int, ...]:
        """Indices of the points whose run failed or that were invalid."""
        return tuple(i for i, ok in enumerate(self.completed) if not ok)

    def as_dict(self) -> dict[str, Any]:
        return {
            "parameter": self.parameter,
            "metric": self.metric_name,
            "values": self.values.tolist(),
            "metric_values": [None if not np.isfinite(m) else float(m) for m in self.metric],
            "statuses": list(self.statuses),
            "completed": list(self.completed),
            "failed": len(self.failed),
            "tension_bound_eq40": self.bound,
            "best_value": self.best_value,
        }


_INVALID = "invalid: "


def _prepare_points(
    scenario: Scenario, parameter: str, values: np.ndarray
) -> tuple[list[Scenario | None], list[str]]:
    """The scenario of every value, or None with the reason when the physics cannot meet it
    (``InfeasibleError``: e.g. a T_ref above what the tether gives); malformed values
    (``ParameterError``) stop the sweep."""
    scenarios: list[Scenario | None] = []
    reasons: list[str] = []
    for v in values:
        try:
            scenarios.append(_with(scenario, parameter, float(v)))
            reasons.append("")
        except InfeasibleError as exc:
            scenarios.append(None)
            reasons.append(_INVALID + str(exc))
    return scenarios, reasons


def _run_batch_feasible(scenarios: list[Scenario | None], reasons: list[str]):
    """``run_batch`` over the valid points; a point whose set-up the physics cannot meet
    (no trim, a hover outside the actuator limits) becomes invalid, the others still run."""
    from ..sim.setup import engine_setup

    idx = [i for i, s in enumerate(scenarios) if s is not None]
    try:
        return idx, run_batch([scenarios[i] for i in idx])  # type: ignore[misc]
    except InfeasibleError:
        for i in idx:  # rare: find the points that cannot be set up, then run the rest
            try:
                engine_setup(scenarios[i])  # type: ignore[arg-type]
            except InfeasibleError as exc:
                scenarios[i] = None
                reasons[i] = _INVALID + str(exc)
        idx = [i for i, s in enumerate(scenarios) if s is not None]
        return idx, run_batch([scenarios[i] for i in idx])  # type: ignore[misc]


def sweep(
    scenario: Scenario,
    parameter: str,
    values: np.ndarray,
    metric: str = "rms_q1",
    *,
    cyclic_limit: float | None = None,
) -> SweepResult:
    """Simulate ``scenario`` once per value of ``parameter`` and collect ``metric`` (see
    ``METRICS``).

    ``parameter`` is a "section.field" of Params, "q9", "control.dt", or an actuator setting:
    "actuators.cyclic_limit" (symmetric limit on tMR1, tMR2: eq 40's tmax_MR1,2 [N m]),
    "actuators.time_constant", "actuators.reel_rate_limit",
    "actuators.reel_acceleration_limit", "actuators.breaking_tension". Built-in winds run as
    one compiled batch on all cores (``sim.batch.run_batch``, the numbers of ``simulate``).

    A value the physics cannot meet (``InfeasibleError``: a T_ref above what the tether gives
    at its length, a hover outside the actuator limits, no trim) is recorded as an invalid
    point, status "invalid: <why>", metric NaN, not completed; the other points still run.
    A malformed value (e.g. a negative cyclic limit) raises ParameterError: no sweep.
    """
    if metric not in METRICS:
        raise ParameterError("metric", metric, f"one of {sorted(METRICS)}")
    allowed = set(Params.field_docs()) | _SCENARIO_FIELDS
    if parameter not in allowed:
        raise ParameterError("parameter", parameter, f"one of {sorted(allowed)}")
    values = np.asarray(values, dtype=float)
    if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values)):
        raise ParameterError("values", values.tolist(), "a non-empty list of finite numbers")
    scenarios, statuses = _prepare_points(scenario, parameter, values)  # validates each
    out = np.full(values.size, np.nan)
    completed = [False] * values.size
    if compile_wind(scenario.wind) is not None:
        # built-in winds (the sweep does not change the wind): the compiled batch on all
        # cores (per-run summaries, the numbers of simulate); its metric names are METRICS'
        idx, batch = _run_batch_feasible(scenarios, statuses)
        for j, i in enumerate(idx):
            statuses[i] = batch.message(j)
            completed[i] = bool(batch.ok[j])
            if completed[i]:
                out[i] = batch.metrics(j)[metric]
    else:
        group, key = METRICS[metric]
        for i, s in enumerate(scenarios):
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
    bound = None
    if parameter == "tension_control.T_ref":
        limit = cyclic_limit if cyclic_limit is not None else paper_cyclic_limit(scenario.params)
        bound = tension_bound(scenario.params, limit)
    ok = np.isfinite(out) & (values <= bound if bound is not None else True)
    best = float(values[ok][np.argmin(out[ok])]) if np.any(ok) else None
    return SweepResult(
        parameter, metric, values, out, tuple(statuses), bound, best, tuple(completed)
    )


def write_sweep(
    result: SweepResult,
    out_dir: str | Path,
    *,
    command: str,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
) -> None:
    """Table (CSV), plot (PNG) and summary.json of a sweep, written whole or not at all
    (``_io.output_directory``: the user's files in ``out_dir`` are kept, never replaced)."""
    from ..viz.plots import figure_sweep, save_figure

    fig = figure_sweep(result)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")  # quotes a status holding a comma
    writer.writerow(["value", "metric", "status"])
    for v, m, s in zip(
        result.values.tolist(), result.metric.tolist(), result.statuses, strict=True
    ):
        writer.writerow([repr(v), repr(m), s])
    with output_directory(out_dir, writer="sweep", inputs=inputs, force=force) as tmp:
        save_figure(fig, tmp / "sweep.png")
        atomic_write_text(tmp / "sweep.csv", buf.getvalue())
        info = {**result.as_dict(), "tetherheli_version": __version__, "command": command}
        atomic_write_text(tmp / "summary.json", json.dumps(info, indent=2) + "\n")
