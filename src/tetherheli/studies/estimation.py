"""State estimation over a recorded run: the position filter of ``sensing.estimation`` flown
on what a run's sensors read (``estimate_run``), and the consistency of the MPC's Kalman
filter (``kalman_consistency``: NEES and NIS with their chi-square tests). They rebuild the
run's noise table, schedule and filter from its scenario (``runs.setup``,
``runs.mpc_setup``), hence live above the simulation."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..control.mpc import KALMAN_FORCE_COLUMNS, KALMAN_NIS_COLUMN, KALMAN_STATE_COLUMNS
from ..errors import ParameterError, TetherheliError
from ..runs.mpc_setup import mpc_kalman
from ..runs.packing import sensor_noise, sensor_schedule
from ..runs.setup import engine_setup
from ..sensing.config import (
    CH_ALTIMETER,
    CH_ATTITUDE,
    CH_ENCODER_Q7,
    CH_ENCODER_Q8,
    CH_GPS,
    SensorConfig,
)
from ..sensing.estimation import (
    FUSIONS,
    ConsistencyTest,
    EstimateResult,
    Fixes,
    KalmanConsistency,
    normalized_squares,
    position_filter,
    run_filter,
)
from ..sensing.noise import accelerometer_errors
from ..sensing.schedules import group_samples
from ..sensing.sensors import hover_error_std, measured_channels, tether_position_estimate

__all__ = ["estimate_run", "kalman_consistency"]


def estimate_run(result: Any, scenario: Any, fusion: str) -> EstimateResult:
    """The position filter fusing the IMU with ``fusion`` ("gnss", "tether" or "both") over a
    recorded run of ``scenario`` (a ``SimulationResult`` of ``simulate(scenario)``).

    The sensors' readings are replayed from the run's true states and tension with the
    run's own noise table and schedule (``sensing.sensors.measured_channels``: what the controller
    read); the accelerometer's errors come from the scenario's seed's first spawned
    generator. The filter's noise figures are the scenario's ``[sensors]``.

    Parameters
    ----------
    result : SimulationResult
        The recorded run of ``simulate(scenario)``.
    scenario : Scenario
        The run's scenario, with sensors (``[sensors]`` not perfect).
    fusion : str
        One of ``FUSIONS``; "tether" and "both" need the tethered configuration.

    Returns
    -------
    EstimateResult
        The estimate of HO's position [m] with its 1-sigma and the truth.
    """
    if fusion not in FUSIONS:
        raise ParameterError("fusion", fusion, f"one of {FUSIONS}")
    config: SensorConfig = scenario.sensors
    if config.is_perfect:
        raise ParameterError("sensors", scenario.name, "a scenario with sensors ([sensors])")
    if fusion != "gnss" and scenario.configuration != "tethered":
        raise ParameterError("fusion", fusion, "'gnss' for the free configuration")
    dt = scenario.control.dt
    n = result.time.shape[0]
    states = result.states
    arm = scenario.params.helicopter.tether_arm
    noise = sensor_noise(scenario)
    schedule = sensor_schedule(config, dt, scenario.n_samples)
    m = measured_channels(states, result.tension, noise, schedule, arm)
    truth = result.outputs[:, :3]
    # the IMU: HO's velocity change over each sample plus the accelerometer's errors
    accel = np.zeros((n, 3))
    if n > 1:
        accel[:-1] = np.diff(states[:, 6:9], axis=0) / dt
        accel[-1] = accel[-2]
    child = np.random.SeedSequence(scenario.seed).spawn(1)[0]
    accel += accelerometer_errors(config, n - 1, np.random.default_rng(child), dt)

    use_gnss, use_tether = fusion in ("gnss", "both"), fusion in ("tether", "both")
    model = position_filter(config, dt, gnss=use_gnss)
    ns = model.n_states
    fixes = []
    if use_gnss:
        j, lag = group_samples(config, dt, n - 1, "gps")
        H = np.zeros(ns)
        H[0] = 1.0
        if model.gm:
            H[3] = 1.0
        R = np.maximum(np.asarray(config.gps_std) ** 2, 1e-12)
        fixes.append(Fixes(j, m[j + lag, CH_GPS : CH_GPS + 3], lag, H, R))
    if use_tether:
        j, lag = group_samples(config, dt, n - 1, "encoder")
        a = m[j + lag]
        values = tether_position_estimate(
            a[:, CH_ENCODER_Q7],
            a[:, CH_ENCODER_Q8],
            a[:, CH_ALTIMETER],
            a[:, CH_ATTITUDE],
            a[:, CH_ATTITUDE + 1],
            arm,
        )
        std = hover_error_std(config, scenario.q9, arm, float(result.trim_state[0]))
        H = np.zeros(ns)
        H[0] = 1.0
        # horizontal from the encoders' samples; the altitude from the altimeter's own
        # samples, at the time each was taken (an infinite variance leaves an axis alone)
        R = np.array([std[0] ** 2, std[1] ** 2, math.inf])
        fixes.append(Fixes(j, values, lag, H, np.maximum(R, 1e-12)))
        j, lag = group_samples(config, dt, n - 1, "altimeter")
        values = np.zeros((j.size, 3))
        values[:, 2] = m[j + lag, CH_ALTIMETER]
        R = np.array([math.inf, math.inf, std[2] ** 2 + config.altimeter_markov_sigma**2])
        fixes.append(Fixes(j, values, lag, H, np.maximum(R, 1e-12)))
    position, _, position_std = run_filter(model, accel, fixes, result.trim_output[:3])
    return EstimateResult(fusion, result.time.copy(), position, position_std, truth.copy())


def kalman_consistency(
    result: Any, scenario: Any, *, confidence: float = 0.95
) -> KalmanConsistency:
    """NEES and NIS per sample of the MPC's Kalman filter over a recorded run, with their
    chi-square tests.

    The estimate is the one the MPC recorded (``control.mpc.KALMAN_STATE_COLUMNS``,
    ``KALMAN_FORCE_COLUMNS``); the truth is the run's state and its wind force on HO
    (``result.wind``: the force the design model's disturbance stands for); the covariances
    are the steady-state filter's, rebuilt from ``scenario`` (``runs.mpc_setup.mpc_kalman``):
    NEES e' P+^-1 e with the posterior P+ (its [x; d] block), NIS with
    ``DisturbanceKalman.innovation_covariance`` (recorded by the MPC, ``kalman_nis``).

    Correlation: the errors of successive samples are correlated (the filter's error decays
    at the slowest eigenvalue of (I - L C) A), so the mean over n samples is not the mean
    of n independent chi-square variables. The test counts one independent sample per
    ``stride`` = ceil(tau / dt) samples, tau = -dt / ln |lambda_max| (the error's slowest
    time constant), and the band is that of their mean (``ConsistencyTest.band``);
    ``band_independent`` gives the narrower band of n independent samples.

    Parameters
    ----------
    result : SimulationResult
        A run of ``scenario`` with ``[control] controller = "mpc"`` and its Kalman filter.
    scenario : Scenario
        The run's scenario.
    confidence : float, optional
        Probability of the bands.

    Returns
    -------
    KalmanConsistency
        NEES (dimension n + 3), its force part (3) and NIS (p) per sample and their tests.

    Raises
    ------
    TetherheliError
        The run has no recorded Kalman estimate (another controller or observer).
    """
    if KALMAN_NIS_COLUMN not in result.extra:
        raise TetherheliError(
            f"run {scenario.name} has no Kalman estimate ({KALMAN_NIS_COLUMN}); allowed: a "
            'run with [control] controller = "mpc" and its Kalman filter ([control.mpc] '
            'observer = "kalman", or "auto" with sensors)'
        )
    kalman = mpc_kalman(scenario, engine_setup(scenario))
    assert kalman is not None  # the scenario flies the Kalman filter its run recorded
    n = kalman.n_states
    est = np.column_stack(
        [result.extra[c] for c in KALMAN_STATE_COLUMNS[:n] + KALMAN_FORCE_COLUMNS]
    )
    truth = np.column_stack([result.states[:, :n], result.wind])
    err = est - truth
    P = kalman.posterior[: n + 3, : n + 3]
    nees = normalized_squares(err, P)
    force = normalized_squares(err[:, n:], P[n:, n:])
    closed = (np.eye(kalman.A.shape[0]) - kalman.L @ kalman.C) @ kalman.A
    rho = float(np.max(np.abs(np.linalg.eigvals(closed))))
    stride = 1 if rho <= 0.0 else max(1, math.ceil(-1.0 / math.log(min(rho, 1.0 - 1e-12))))
    nis = np.asarray(result.extra[KALMAN_NIS_COLUMN], dtype=float)
    p = kalman.C.shape[0]
    return KalmanConsistency(
        time=result.time.copy(),
        nees=ConsistencyTest(nees, n + 3, stride, confidence),
        nis=ConsistencyTest(nis, p, stride, confidence),
        force_nees=ConsistencyTest(force, 3, stride, confidence),
    )
