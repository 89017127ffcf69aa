"""Metrics of a run: peak and RMS deviation from the run's own trim, tension range, and the
reduction the tether brings (Sec. VI's "up to 30%").

Definitions (used by the report and summary.json):
- deviation of q1, q2, q3: output minus the trim output of the same run [m];
  of q4, q5: Euler angle minus its trim value, reported in degrees;
- peak_abs_dev: max over all samples of |deviation|; rms_dev: sqrt(mean(deviation^2)) over all
  samples of the whole run (t = 0 .. duration, every control sample);
- reduction_percent = 100 (free - tethered) / free, positive when the tether helps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .names import POSITION
from .sim.result import SimulationResult

__all__ = ["RunMetrics", "reduction_percent", "run_metrics"]


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


def run_metrics(result: SimulationResult) -> RunMetrics:
    """Metrics of ``result`` over the whole run (see the module docstring)."""
    if result.time.size == 0:
        raise ValueError("result has no samples; allowed: a run with at least one sample")
    dev = result.deviations()
    peak = {k: float(np.max(np.abs(dev[k]))) for k in POSITION}
    peak["q4_deg"] = math.degrees(float(np.max(np.abs(dev["q4"]))))
    peak["q5_deg"] = math.degrees(float(np.max(np.abs(dev["q5"]))))
    rms = {k: float(np.sqrt(np.mean(dev[k] ** 2))) for k in POSITION}
    return RunMetrics(peak, rms, float(result.tension.min()), float(result.tension.max()))


def reduction_percent(free: float, tethered: float) -> float:
    """100 (free - tethered) / free [%]; NaN-free: raises if free is not positive."""
    if not (math.isfinite(free) and free > 0.0 and math.isfinite(tethered)):
        raise ValueError(f"free = {free!r}, tethered = {tethered!r}; allowed: finite, free > 0")
    return 100.0 * (free - tethered) / free
