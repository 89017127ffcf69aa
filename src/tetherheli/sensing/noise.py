"""The noise table of a run (``noise_table``: white noise, biases and the flown sensors'
time-correlated errors, drawn up front and discretised exactly at the control step), its
processes (``gauss_markov``, ``random_walk``) and the accelerometer's errors for the state
estimator (``accelerometer_errors``). Channels and fields: ``sensing.config``."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validation import check_integer
from ..errors import ParameterError
from .config import CH_ALTIMETER, CH_GPS, CH_GYRO, N_CHANNELS, SensorConfig, _checked_dt

__all__ = [
    "accelerometer_errors",
    "gauss_markov",
    "noise_table",
    "random_walk",
]


def noise_table(
    config: SensorConfig, n_samples: int, rng: np.random.Generator, *, dt: float | None = None
) -> np.ndarray:
    """Noise plus bias of every channel for a run of ``n_samples`` control samples.

    The draw order is fixed: one ``rng.standard_normal((n_samples + 1, N_CHANNELS))`` call,
    filled row by row (sample 0 channels 0..16, then sample 1, ...), then scaled column-wise
    by ``config.white_std(dt)`` and shifted by ``config.channel_bias()``. Channels with zero
    std consume their draws too, so equal seeds give equal tables, and switching one sensor's
    noise on or off leaves the other channels' noise unchanged (common random numbers).

    Flown sensors (``config.is_white`` False) add their time-correlated errors, discretised
    exactly at the control step ``dt`` from a second block of the same shape drawn next:
    the GNSS and altimeter Gauss-Markov errors (``gauss_markov``, stationary from sample 0)
    and the gyro bias random walk (``random_walk``, 0 at sample 0). A sensor slower than the
    control holds row j of its sample j, so every row is a sample of the continuous process.

    Parameters
    ----------
    config : SensorConfig
        The sensors.
    n_samples : int
        Number of control samples of the run (>= 0); rows are t_k = k dt, k = 0..n_samples.
    rng : numpy.random.Generator
        The run's generator (e.g. from ``SeedSequence.spawn``).
    dt : float or None
        Control sample time [s]; needed when ``config`` has flown sensors or a gyro density.

    Returns
    -------
    ndarray, shape (n_samples + 1, N_CHANNELS)
        Row k is what ``measure`` adds at sample k; units per channel (``CHANNEL_NAMES``).
    """
    if not isinstance(config, SensorConfig):
        raise ParameterError("config", config, "a SensorConfig")
    n_samples = check_integer("n_samples", n_samples, low=0)
    if not isinstance(rng, np.random.Generator):
        raise ParameterError("rng", rng, "a numpy.random.Generator")
    if not config.is_white:
        if dt is None:
            raise ParameterError("dt", dt, "the control sample time [s] (flown sensors are set)")
        dt = _checked_dt(dt)
    return _noise_table(config, n_samples, rng, dt)


def _noise_table(
    config: SensorConfig, n_samples: int, rng: np.random.Generator, dt: float | None
) -> np.ndarray:
    """``noise_table`` of arguments already checked (a run's set-up from its ``Scenario``:
    its sensors, sample count and ``control.dt``)."""
    z = rng.standard_normal((int(n_samples) + 1, N_CHANNELS))
    if config.is_white:
        return np.ascontiguousarray(z * config.channel_std() + config.channel_bias())
    assert dt is not None  # noise_table requires it unless the sensors are white
    table = z * config._white_std(dt) + config.channel_bias()
    w = rng.standard_normal(z.shape)
    gps = slice(CH_GPS, CH_GPS + 3)
    if np.any(np.asarray(config.gps_markov_sigma) > 0.0):
        table[:, gps] += gauss_markov(config.gps_markov_sigma, config.gps_markov_tau, dt, w[:, gps])
    if config.altimeter_markov_sigma > 0.0:
        alt = slice(CH_ALTIMETER, CH_ALTIMETER + 1)
        table[:, alt] += gauss_markov(
            config.altimeter_markov_sigma, config.altimeter_markov_tau, dt, w[:, alt]
        )
    if config.gyro_random_walk > 0.0:
        gyro = slice(CH_GYRO, CH_GYRO + 3)
        table[:, gyro] += random_walk(config.gyro_random_walk, dt, w[:, gyro])
    return np.ascontiguousarray(table)


def gauss_markov(sigma: Any, tau: float, dt: float, w: np.ndarray) -> np.ndarray:
    """A first-order Gauss-Markov process sampled at dt, exactly: e_0 = sigma w_0,
    e_k = phi e_{k-1} + sigma sqrt(1 - phi^2) w_k with phi = exp(-dt / tau).

    It is the sampled solution of de/dt = -e / tau + noise of intensity 2 sigma^2 / tau:
    stationary, variance sigma^2, autocorrelation sigma^2 exp(-|lag| / tau) (Gelb, *Applied
    Optimal Estimation*, Table 3.4-1).

    Parameters
    ----------
    sigma : float or array_like, shape (m,)
        Stationary standard deviation of each column (any unit).
    tau : float
        Correlation time [s], > 0.
    dt : float
        Sample time [s].
    w : numpy.ndarray, shape (n, m)
        Standard normal draws.

    Returns
    -------
    numpy.ndarray, shape (n, m)
        The process at samples 0..n-1, in the unit of ``sigma``.
    """
    from scipy.signal import lfilter

    phi = math.exp(-dt / tau)
    sigma = np.broadcast_to(np.asarray(sigma, dtype=float), (w.shape[1],))
    e = np.empty_like(w)
    e[0] = sigma * w[0]
    if w.shape[0] > 1:
        drive = w[1:] * (sigma * math.sqrt(1.0 - phi * phi))
        e[1:] = lfilter([1.0], [1.0, -phi], drive, axis=0, zi=(phi * e[0])[None, :])[0]
    return e


def random_walk(density: float, dt: float, w: np.ndarray) -> np.ndarray:
    """A random walk sampled at dt: b_0 = 0, b_k = b_{k-1} + density sqrt(dt) w_k, i.e. white
    noise of density ``density`` integrated (a rate random walk for a gyro, rad/s/sqrt(s));
    variance density^2 k dt at sample k.

    Parameters
    ----------
    density : float
        Density of the integrated white noise [unit/sqrt(s)].
    dt : float
        Sample time [s].
    w : numpy.ndarray, shape (n, m)
        Standard normal draws (row 0 is not used: b_0 = 0).

    Returns
    -------
    numpy.ndarray, shape (n, m)
        The walk at samples 0..n-1 [unit of ``density`` times sqrt(s)].
    """
    b = np.cumsum(w * (density * math.sqrt(dt)), axis=0)
    b -= b[0]
    return b


def accelerometer_errors(
    config: SensorConfig, n_samples: int, rng: np.random.Generator, dt: float
) -> np.ndarray:
    """The accelerometer's errors along n1, n2, n3 for the state estimator, shape
    (n_samples + 1, 3) [m/s^2]: white noise of density ``accel_density`` at the control rate
    (sigma = N / sqrt(dt), as ``white_std``), a bias random walk ``accel_random_walk``
    (``random_walk``) and the constant ``accel_bias``. Drawn as one (n + 1, 6) block.

    Parameters
    ----------
    config : SensorConfig
        The sensors (``accel_density``, ``accel_random_walk``, ``accel_bias``).
    n_samples : int
        Number of control samples of the run, >= 0.
    rng : numpy.random.Generator
        The generator the block is drawn from.
    dt : float
        Control sample time [s].

    Returns
    -------
    numpy.ndarray, shape (n_samples + 1, 3)
        Row k: the accelerometer error at sample k [m/s^2].
    """
    n_samples = check_integer("n_samples", n_samples, low=0)
    w = rng.standard_normal((n_samples + 1, 6))
    out = w[:, :3] * (config.accel_density / math.sqrt(dt)) + np.asarray(config.accel_bias)
    if config.accel_random_walk > 0.0:
        out += random_walk(config.accel_random_walk, dt, w[:, 3:])
    return out
