"""A run's actuators and sensors packed for the compiled engine: the actuator array
(``actuator_array``, with the drum winch's settings, ``winch_into``), the sensor-noise table
(``sensor_noise``), the sensors' sample schedule (``sensor_schedule``), the engine's
``sensors`` argument (``sensor_tuple``), and the read-only views the engine is handed
(``read_only``: one compiled signature whichever way an input was built).
"""

from __future__ import annotations

import numpy as np

from ..errors import InfeasibleError, ParameterError
from ..layout import (
    ACT_BREAK,
    ACT_DRUM,
    ACT_DRUM_COULOMB,
    ACT_DRUM_INERTIA,
    ACT_DRUM_RADIUS,
    ACT_DRUM_SPEED_GAIN,
    ACT_DRUM_TENSION_FFWD,
    ACT_DRUM_TORQUE_LIMIT,
    ACT_DRUM_VISCOUS,
    ACT_MAX_LENGTH,
    ACT_MIN_LENGTH,
    ACT_REEL_ACCEL,
    ACT_REEL_RATE,
    ACT_TAU,
    ACT_U_MAX,
    ACT_U_MIN,
    CTRL_REEL_ACCEL,
    CTRL_REEL_RATE_LIMIT,
    CTRL_U_MAX,
    CTRL_U_MIN,
    default_actuators,
)
from ..model import TrimPoint
from ..names import INPUT
from ..scenario.core import Scenario, WinchSettings
from ..sensing.config import N_CHANNELS, N_GROUPS, SensorConfig
from ..sensing.noise import _noise_table
from ..sensing.schedules import _sample_schedule, ring_rows

__all__ = [
    "actuator_array",
    "read_only",
    "sensor_noise",
    "sensor_schedule",
    "sensor_tuple",
    "winch_into",
]


def actuator_array(scenario: Scenario, trim: TrimPoint, ctrl: np.ndarray) -> np.ndarray:
    """The engine's actuator array (``layout.ACT_*``); also sets the winch limits in ``ctrl``.
    Rejects limits the hover input does not fit in (``InfeasibleError``) and payout limits
    ``[winch] min_length``, ``max_length`` the start's natural length is outside of
    (``ParameterError``).

    Parameters
    ----------
    scenario : Scenario
        The run.
    trim : TrimPoint
        The start trim, whose total input must lie inside the limits.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        Controller settings; its winch and input limits are set in place.

    Returns
    -------
    numpy.ndarray, shape (ACT_SIZE,)
        The actuator array.
    """
    a = scenario.actuators
    act = default_actuators()
    act[ACT_U_MIN : ACT_U_MIN + 4] = a.u_min
    act[ACT_U_MAX : ACT_U_MAX + 4] = a.u_max
    act[ACT_TAU] = a.time_constant
    act[ACT_BREAK] = a.breaking_tension
    act[ACT_REEL_ACCEL] = a.reel_acceleration_limit
    act[ACT_REEL_RATE] = a.reel_rate_limit
    winch_into(act, scenario.winch)
    w = scenario.winch
    act[ACT_MIN_LENGTH] = w.min_length
    act[ACT_MAX_LENGTH] = w.max_length
    if scenario.configuration == "tethered":  # the start's natural length within the limits
        L = float(trim.x[12])
        if L < w.min_length:
            raise ParameterError(
                "winch.min_length", w.min_length,
                f"a length at or below the start's natural length L_N = {L:.6g} m",
            )  # fmt: skip
        if L > w.max_length:
            raise ParameterError(
                "winch.max_length", w.max_length,
                f"a length at or above the start's natural length L_N = {L:.6g} m",
            )  # fmt: skip
    ctrl[CTRL_REEL_RATE_LIMIT] = a.reel_rate_limit
    ctrl[CTRL_REEL_ACCEL] = a.reel_acceleration_limit
    ctrl[CTRL_U_MIN : CTRL_U_MIN + 4] = a.u_min  # for the anti-windup (CTRL_ANTI_WINDUP)
    ctrl[CTRL_U_MAX : CTRL_U_MAX + 4] = a.u_max
    need = trim.u_total
    for i, name in enumerate(INPUT):
        if not a.u_min[i] < need[i] < a.u_max[i]:
            raise InfeasibleError(
                "actuators.u_min/u_max",
                f"{name} in [{a.u_min[i]:g}, {a.u_max[i]:g}]",
                f"limits around the hover need {name} = {need[i]:.4g} (the helicopter "
                "cannot hover otherwise)",
            )
    return act


def winch_into(act: np.ndarray, winch: WinchSettings) -> None:
    """Write the drum winch's settings into the actuator array (``layout.ACT_DRUM*``; left
    zero, the ideal winch, for ``model = "ideal"``).

    Parameters
    ----------
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuator array, changed in place.
    winch : WinchSettings
        The scenario's ``[winch]`` table.
    """
    if winch.model != "drum":
        return
    act[ACT_DRUM] = 1.0
    act[ACT_DRUM_RADIUS] = winch.drum_radius
    act[ACT_DRUM_INERTIA] = winch.drum_inertia
    act[ACT_DRUM_TORQUE_LIMIT] = winch.torque_limit
    act[ACT_DRUM_VISCOUS] = winch.viscous_friction
    act[ACT_DRUM_COULOMB] = winch.coulomb_friction
    act[ACT_DRUM_SPEED_GAIN] = winch.drum_inertia * winch.speed_loop_bandwidth
    act[ACT_DRUM_TENSION_FFWD] = 1.0 if winch.tension_feedforward else 0.0


def sensor_noise(scenario: Scenario) -> np.ndarray:
    """Per-sample sensor noise rows, drawn from the scenario's seed (none when perfect).

    Parameters
    ----------
    scenario : Scenario
        The run.

    Returns
    -------
    numpy.ndarray, shape (n_samples + 1, N_CHANNELS) or (0, N_CHANNELS)
        ``sensing.noise.noise_table`` of the run, units per channel (its arguments the
        scenario's, checked when it was built).
    """
    if scenario.sensors.is_perfect:
        return np.zeros((0, N_CHANNELS))
    rng = np.random.default_rng(np.random.SeedSequence(scenario.seed))
    return _noise_table(scenario.sensors, scenario.n_samples, rng, scenario.control.dt)


def sensor_schedule(config: SensorConfig, dt: float, n_samples: int) -> np.ndarray:
    """``sensing.schedules.sample_schedule`` of a run, empty, (0, N_GROUPS), for perfect sensors (no
    measurement); its arguments trusted (a scenario's, checked when it was built).

    Parameters
    ----------
    config : SensorConfig
        The run's sensors.
    dt : float
        Control sample time [s].
    n_samples : int
        Number of control samples of the run.

    Returns
    -------
    numpy.ndarray of int64, shape (n_samples + 1, N_GROUPS) or (0, N_GROUPS)
        The schedule.
    """
    if config.is_perfect:
        return np.zeros((0, N_GROUPS), dtype=np.int64)
    return _sample_schedule(config, dt, n_samples)


def sensor_tuple(noise: np.ndarray, source: int, arm: float, schedule: np.ndarray) -> tuple:
    """The ``sensors`` argument of the engine's ``sense`` (``sensing.sensors.measure_sampled``),
    for every loop (compiled, Python, Gymnasium): (noise table, position-source code, tether
    arm, a (4, 3) scratch, schedule, a fresh history ring of
    ``sensing.schedules.ring_rows(schedule) + 1`` rows).

    Parameters
    ----------
    noise : numpy.ndarray, shape (n + 1, N_CHANNELS) or (0, N_CHANNELS)
        The noise table (``sensor_noise``).
    source : int
        Position-source code (``sensors.SOURCE_*``).
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).
    schedule : numpy.ndarray of int64, shape (n + 1, N_GROUPS) or (0, N_GROUPS)
        The sample schedule (``sensor_schedule``).

    Returns
    -------
    tuple
        (noise, source, arm, scratch (4, 3), schedule, ring (rows, N_CHANNELS)).
    """
    ring = np.zeros((ring_rows(schedule) + 1, N_CHANNELS))
    return (noise, source, arm, np.empty((4, 3)), schedule, ring)


def read_only(a: np.ndarray) -> np.ndarray:
    """A read-only, C-ordered float64 view of an input the engine only reads (a copy only where
    the layout or dtype differs): whichever way a law, a wind or a model was built (a cached,
    frozen gain or a fresh one), ``engine_args`` hands the engine the same types, so that
    ``run_closed_loop`` has one compiled signature (a second one would compile the whole loop
    again).

    Parameters
    ----------
    a : numpy.ndarray
        The input array.

    Returns
    -------
    numpy.ndarray
        A read-only, C-ordered float64 view of ``a`` (or of its copy).
    """
    view = np.ascontiguousarray(a, dtype=np.float64).view()
    view.setflags(write=False)
    return view
