"""When slow and delayed sensors report (``SensorConfig``'s ``<group>_rate``,
``<group>_latency``, ``gps_outage``): the sample schedule of a run (``sample_schedule``), the
samples one group delivers (``group_samples``) and the history ring the compiled measurement
needs for them (``ring_rows``)."""

from __future__ import annotations

import math

import numpy as np

from .._validation import check_integer
from ..errors import ParameterError
from .config import _GRID_TOL, G_GPS, N_GROUPS, SENSOR_GROUPS, SensorConfig, _checked_dt

__all__ = [
    "group_samples",
    "ring_rows",
    "sample_schedule",
]


def sample_schedule(config: SensorConfig, dt: float, n_samples: int) -> np.ndarray:
    """Which sample every sensor group reports at every control sample, shape
    (n_samples + 1, N_GROUPS), int64; (0, N_GROUPS) for untimed sensors (``is_timed``).

    Sensor group g samples at the control samples j = 0, P, 2P, ... (period P, ``group_timing``),
    except GNSS samples with j dt in ``gps_outage`` = [t_start, t_end), which are lost; sample
    j arrives L samples later (latency L). At control sample k the sensor reports its newest
    arrived sample (zero-order hold): the largest valid j <= k - L. Before the first one
    arrives (k < L) it reports sample 0, as a sensor that has been reading the trim since
    before t = 0. The measurement at k is then the true value of sample j plus row j of the
    noise table.

    Parameters
    ----------
    config : SensorConfig
        The sensors (rates, latencies, ``gps_outage``).
    dt : float
        Control sample time [s].
    n_samples : int
        Number of control samples of the run, >= 0.

    Returns
    -------
    numpy.ndarray of int64, shape (n_samples + 1, N_GROUPS) or (0, N_GROUPS)
        Row k, column g: the sample index j group g reports at control sample k; no rows for
        untimed sensors.
    """
    n_samples = check_integer("n_samples", n_samples, low=0)
    if config.is_timed:  # untimed sensors need no dt
        dt = _checked_dt(dt)
    return _sample_schedule(config, dt, n_samples)


def _sample_schedule(config: SensorConfig, dt: float, n_samples: int) -> np.ndarray:
    """``sample_schedule`` of arguments already checked (a run's set-up from its
    ``Scenario``: its sensors, ``control.dt`` and sample count)."""
    if not config.is_timed:
        return np.zeros((0, N_GROUPS), dtype=np.int64)
    period, latency = config._group_timing(dt)
    k = np.arange(n_samples + 1)
    out = np.empty((n_samples + 1, N_GROUPS), dtype=np.int64)
    for g in range(N_GROUPS):
        newest = np.maximum.accumulate(np.where(_valid_samples(config, dt, k, g, period[g]), k, 0))
        out[:, g] = newest[np.maximum(k - latency[g], 0)]
    return out


def _valid_samples(
    config: SensorConfig, dt: float, k: np.ndarray, g: int, period: int
) -> np.ndarray:
    valid = k % period == 0
    if g == G_GPS and config.gps_outage:
        t0, t1 = config.gps_outage
        lo, hi = math.ceil(t0 / dt - _GRID_TOL), math.ceil(t1 / dt - _GRID_TOL)
        valid &= (k < lo) | (k >= hi)
    return valid


def group_samples(
    config: SensorConfig, dt: float, n_samples: int, group: str
) -> tuple[np.ndarray, int]:
    """The samples a sensor group delivers in a run: (sample indices j, latency L in samples);
    sample j reaches the user at j + L (only those with j + L <= n_samples are returned).
    Same rule as ``sample_schedule``.

    Parameters
    ----------
    config : SensorConfig
        The sensors.
    dt : float
        Control sample time [s].
    n_samples : int
        Number of control samples of the run.
    group : str
        One of ``SENSOR_GROUPS``.

    Returns
    -------
    samples : numpy.ndarray of int, shape (m,)
        Control sample indices j at which the group samples (outage samples removed).
    latency : int
        Latency L in control samples.

    Raises
    ------
    ParameterError
        An unknown ``group`` or a rate/latency off the control grid.
    """
    if group not in SENSOR_GROUPS:
        raise ParameterError("group", group, f"one of {SENSOR_GROUPS}")
    g = SENSOR_GROUPS.index(group)
    period, latency = config.group_timing(dt)
    k = np.arange(n_samples + 1 - latency[g])
    return k[_valid_samples(config, dt, k, g, period[g])], int(latency[g])


def ring_rows(schedule: np.ndarray) -> int:
    """Rows of the history ring ``measure_sampled`` needs for ``schedule``: the oldest sample
    ever reported, counted back from the current one, plus one (1 for an empty schedule).

    Parameters
    ----------
    schedule : numpy.ndarray of int, shape (n + 1, N_GROUPS) or (0, N_GROUPS)
        ``sample_schedule``'s output.

    Returns
    -------
    int
        Number of ring rows, >= 1.
    """
    if schedule.shape[0] == 0:
        return 1
    return int((np.arange(schedule.shape[0])[:, None] - schedule).max()) + 1
