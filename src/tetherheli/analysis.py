"""Metrics of a run: peak and RMS deviation from the run's own trim, tension range, and the
reduction the tether brings (Sec. VI's "up to 30%").

Definitions (used by the report and summary.json):
- deviation of q1, q2, q3: output minus the trim output of the same run [m];
  of q4, q5: Euler angle minus its trim value, reported in degrees;
- peak_abs_dev: max over the samples of |deviation|; rms_dev: sqrt(mean(deviation^2)) over
  the samples; the tension range over the samples. "The samples" are every control sample
  from the scenario's ``metrics_start`` (default 0: the whole run, t = 0 .. duration) on;
- reduction_percent = 100 (free - tethered) / free, positive when the tether helps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .names import POSITION
from .sim.result import SimulationResult
from .sim.scenario import metrics_first_sample

__all__ = ["RunMetrics", "metric_samples", "reduction_percent", "run_metrics"]


@dataclass(frozen=True)
class RunMetrics:
    """Peak and RMS deviations from trim and the tension range of one run."""

    peak_abs_dev: dict[str, float]
    rms_dev: dict[str, float]
    tension_min: float
    tension_max: float

    def as_dict(self) -> dict[str, object]:
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
    ``metrics_start``)."""
    return max(0, result.time.size - _first_sample(result))


def run_metrics(result: SimulationResult) -> RunMetrics:
    """Metrics of ``result`` over its samples from the recorded ``metrics_start`` on (see the
    module docstring)."""
    k0 = _first_sample(result)
    if result.time.size <= k0:
        raise ValueError(
            f"result has {result.time.size} samples; allowed: a run with a sample at or after "
            f"metrics_start (sample {k0})"
        )
    dev = {k: v[k0:] for k, v in result.deviations().items()}
    peak = {k: float(np.max(np.abs(dev[k]))) for k in POSITION}
    peak["q4_deg"] = math.degrees(float(np.max(np.abs(dev["q4"]))))
    peak["q5_deg"] = math.degrees(float(np.max(np.abs(dev["q5"]))))
    rms = {k: float(np.sqrt(np.mean(dev[k] ** 2))) for k in POSITION}
    tension = result.tension[k0:]
    return RunMetrics(peak, rms, float(tension.min()), float(tension.max()))


def reduction_percent(free: float, tethered: float) -> float:
    """100 (free - tethered) / free [%]; NaN-free: raises if free is not positive."""
    if not (math.isfinite(free) and free > 0.0 and math.isfinite(tethered)):
        raise ValueError(f"free = {free!r}, tethered = {tethered!r}; allowed: finite, free > 0")
    return 100.0 * (free - tethered) / free
