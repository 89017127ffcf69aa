"""Metrics of a run: peak and RMS deviation from the run's own trim, tension range, and the
reduction the tether brings (Sec. VI's "up to 30%").

Definitions (used by the report and summary.json):
- deviation of q1, q2, q3: output minus the trim output of the same run [m];
  of q4, q5: Euler angle minus its trim value, reported in degrees;
- peak_abs_dev: max over the samples of |deviation|; rms_dev: sqrt(mean(deviation^2)) over
  the samples; the tension range over the samples. "The samples" are every control sample
  from the scenario's ``metrics_start`` (default 0: the whole run, t = 0 .. duration) on;
- reduction_percent = 100 (free - tethered) / free, positive when the tether helps;
- pareto_front: the designs no other design beats on both a cost and a benefit;
- tether_moment: the tether's moment about HO on f1, f2 at every sample (the C1, C2 of eqs
  33-34 and 55), from the recorded state and tension, against eq 40's worst case |arm| TC.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .engine.summary import summarize
from .layout import SUMMARY_FIELDS
from .names import POSITION
from .params import Params
from .results.result import SimulationResult
from .runs.batch import summary_metrics
from .scenario.core import metrics_first_sample

__all__ = [
    "RunMetrics",
    "TetherMoment",
    "metric_samples",
    "metric_window",
    "pareto_front",
    "reduction_percent",
    "run_metrics",
    "tether_moment",
]


@dataclass(frozen=True)
class RunMetrics:
    """Peak and RMS deviations from trim and the tension range of one run.

    Parameters
    ----------
    peak_abs_dev : dict of str to float
        max |deviation| of "q1", "q2", "q3" [m] and of "q4_deg", "q5_deg" [deg].
    rms_dev : dict of str to float
        RMS deviation of "q1", "q2", "q3" [m].
    tension_min, tension_max : float
        The tension range [N].
    """

    peak_abs_dev: dict[str, float]
    rms_dev: dict[str, float]
    tension_min: float
    tension_max: float

    def as_dict(self) -> dict[str, object]:
        """The metrics as a JSON-friendly record (summary.json).

        Returns
        -------
        dict of str to object
            The four fields, the dictionaries copied.
        """
        return {
            "peak_abs_dev": dict(self.peak_abs_dev),
            "rms_dev": dict(self.rms_dev),
            "tension_min": self.tension_min,
            "tension_max": self.tension_max,
        }


def _first_sample(result: SimulationResult) -> int:
    config = result.configuration
    return metrics_first_sample(config.get("metrics_start", 0.0), config["control"]["dt"])


def metric_samples(result: SimulationResult) -> int:
    """How many recorded samples the metrics cover (0: none, e.g. a run that failed before
    ``metrics_start``).

    Parameters
    ----------
    result : SimulationResult
        A recorded run.

    Returns
    -------
    int
        The number of samples at or after ``metrics_start``.
    """
    return max(0, result.time.size - _first_sample(result))


def metric_window(result: SimulationResult) -> slice:
    """The recorded samples the metrics cover: from ``metrics_start`` on.

    Parameters
    ----------
    result : SimulationResult
        A recorded run.

    Returns
    -------
    slice
        ``slice(k0, None)``, k0 the first sample at or after ``metrics_start``.
    """
    return slice(_first_sample(result), None)


def run_metrics(result: SimulationResult) -> RunMetrics:
    """Metrics of ``result`` over its samples from the recorded ``metrics_start`` on (see the
    module docstring).

    Parameters
    ----------
    result : SimulationResult
        A recorded run with a sample at or after its ``metrics_start``.

    Returns
    -------
    RunMetrics
        Its peak and RMS deviations from trim and its tension range.
    """
    k0 = _first_sample(result)
    if result.time.size <= k0:
        raise ValueError(
            f"result has {result.time.size} samples; allowed: a run with a sample at or after "
            f"metrics_start (sample {k0})"
        )
    # one definition of every metric: the engine's on-line summary (``engine.summary.accumulate``),
    # here over the recorded samples, and its reading (``summary_metrics``), as ``run_batch``,
    # the Monte Carlo and ``simulate``'s summaries have them
    summary = np.empty(len(SUMMARY_FIELDS))
    summarize(
        np.ascontiguousarray(result.states, dtype=float),
        np.ascontiguousarray(result.trim_state, dtype=float),
        np.ascontiguousarray(result.outputs, dtype=float),
        np.ascontiguousarray(result.trim_output, dtype=float),
        np.ascontiguousarray(result.tension, dtype=float),
        k0,
        summary,
    )
    m = summary_metrics(summary)
    peak = {k: m[f"peak_{k}"] for k in POSITION}
    peak["q4_deg"] = m["peak_q4_deg"]
    peak["q5_deg"] = m["peak_q5_deg"]
    rms = {k: m[f"rms_{k}"] for k in POSITION}
    return RunMetrics(peak, rms, m["tension_min"], m["tension_max"])


def reduction_percent(free: float, tethered: float) -> float:
    """100 (free - tethered) / free [%]; NaN-free: raises if free is not positive.

    Parameters
    ----------
    free : float
        The free run's metric, finite and > 0.
    tethered : float
        The tethered run's metric, finite (same unit).

    Returns
    -------
    float
        The reduction [%] (negative when the tether made it worse).
    """
    if not (math.isfinite(free) and free > 0.0 and math.isfinite(tethered)):
        raise ValueError(f"free = {free!r}, tethered = {tethered!r}; allowed: finite, free > 0")
    return 100.0 * (free - tethered) / free


def pareto_front(cost: np.ndarray, benefit: np.ndarray) -> np.ndarray:
    """Which points are Pareto-optimal for "least cost, most benefit": point i is on the front
    unless some point j has cost_j <= cost_i and benefit_j >= benefit_i with one of the two
    strict. Points with a non-finite value are never on the front (and beat no point).

    Parameters
    ----------
    cost, benefit : ndarray, shape (n,)
        Each point's cost (smaller is better) and benefit (larger is better).

    Returns
    -------
    ndarray of bool, shape (n,)
        True for the points on the front (equal points are all kept).
    """
    c = np.asarray(cost, dtype=float)
    b = np.asarray(benefit, dtype=float)
    if c.shape != b.shape or c.ndim != 1:
        raise ValueError(f"cost {c.shape} and benefit {b.shape}; allowed: equal shapes (n,)")
    ok = np.isfinite(c) & np.isfinite(b)
    front = ok.copy()
    for i in np.flatnonzero(ok):
        no_worse = ok & (c <= c[i]) & (b >= b[i])
        better = (c < c[i]) | (b > b[i])
        front[i] = not np.any(no_worse & better)
    return front


@dataclass(frozen=True)
class TetherMoment:
    """The tether's moment about HO over a run (``tether_moment``).

    Parameters
    ----------
    moment : ndarray, shape (n, 2)
        The moment about f1, f2 [N m]: what the cyclic torques tMR1, tMR2 must balance.
    worst_case : ndarray, shape (n,)
        Eq 40's |dO-P,3 - dO-HO,3| TC [N m] (tether perpendicular to the shaft).
    angle_deg : ndarray, shape (n,)
        Angle between the tether and the shaft f3 [deg] (NaN while slack):
        |moment| = worst_case sin(angle).
    """

    moment: np.ndarray
    worst_case: np.ndarray
    angle_deg: np.ndarray

    @property
    def peak(self) -> float:
        """max over the run and both axes of |C1|, |C2| [N m] (compare with the per-axis
        cyclic limit tmax_MR1,2 of eq 40)."""
        return float(np.max(np.abs(self.moment))) if self.moment.size else math.nan

    @property
    def peak_per_axis(self) -> tuple[float, float]:
        """(max |C1|, max |C2|) [N m]."""
        a = np.max(np.abs(self.moment), axis=0)
        return float(a[0]), float(a[1])

    @property
    def peak_angle_deg(self) -> float:
        """The largest tether-to-shaft angle while taut [deg] (NaN if never taut)."""
        taut = self.angle_deg[np.isfinite(self.angle_deg)]
        return float(taut.max()) if taut.size else math.nan

    @property
    def peak_worst_case(self) -> float:
        """max of eq 40's |arm| TC over the run [N m]."""
        return float(self.worst_case.max()) if self.worst_case.size else math.nan


def tether_moment(result: SimulationResult, params: Params) -> TetherMoment:
    """The tether's moment about HO at every recorded sample of a tethered-coordinate run,
    from the recorded state and tension through the model's tether-torque function (generated
    from eqs 33-34: C1, C2 of eq 55); ``params`` are the run's parameters (Table II).

    Parameters
    ----------
    result : SimulationResult
        A run recorded in tethered coordinates.
    params : Params
        The run's parameters.

    Returns
    -------
    TetherMoment
        The moment [N m], eq 40's worst case [N m] and the tether's angle to the shaft [deg].
    """
    from .model import kernels  # compiled code: imported when needed

    c = kernels.model_constants("tethered", params.helicopter)
    x = np.ascontiguousarray(result.states, dtype=float)
    tension = np.asarray(result.tension, dtype=float)
    moment = np.empty((x.shape[0], 2))
    for k in range(x.shape[0]):
        kernels.tethered_tether_torque(x[k], float(tension[k]), c, moment[k])
    worst = abs(params.helicopter.tether_arm) * tension
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.hypot(moment[:, 0], moment[:, 1]) / worst
    angle = np.where(tension > 0.0, np.degrees(np.arcsin(np.clip(ratio, 0.0, 1.0))), np.nan)
    return TetherMoment(moment, worst, angle)
