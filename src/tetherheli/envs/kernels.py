"""The compiled pieces that both Gymnasium environments run (``envs.TetheredHoverEnv`` and
each copy of ``vector_env.TetheredHoverVectorEnv``), so that a copy's arithmetic is the single
environment's: the tether tension, the end of a step (reward and failure check), the
observation the sensors give, and the episode's start. No Gymnasium import: they are
compiled functions on the engine's arrays (``layout``).
"""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled, frozen
from ..engine import loop as engine
from ..layout import (
    CFG_ATTACHED,
    CFG_GUST_DT,
    CFG_K_C,
    CFG_TETHER_EA,
    LOOP_EVENT,
    LOOP_HELD,
    LOOP_INPUTS,
    LOOP_WINCH,
    LOOP_X_MEAS,
    LOOP_Z,
)
from ..model.kernels import tether_tension as law_tension
from ..model.kernels import tethered_outputs
from ..sensing.sensors import measure_sampled

__all__ = ["OBS_LIMIT", "finish_step", "observe_into", "start_episode", "tether_tension"]

#: Bound of the observation box; observations are clipped to +-OBS_LIMIT.
OBS_LIMIT = 1.0e4

_jit = compiled(error_model="numpy")


@_jit
def tether_tension(x, cfg):
    """The tether tension of state x [N] (its law: eq 28 or the rope), 0 when the tether is
    removed or released.

    Parameters
    ----------
    x : ndarray, shape (13,)
        State q4..q9, u1..u6, LN (rad, m, m/s, rad/s, m).
    cfg : ndarray, shape (CFG_SIZE,)
        The engine's configuration (``layout.CFG_*``; reads ``CFG_ATTACHED`` and the law,
        ``CFG_K_C`` and ``CFG_TETHER_EA``).

    Returns
    -------
    float
        Tension TC [N], >= 0.
    """
    if cfg[CFG_ATTACHED] <= 0.5:
        return 0.0
    return law_tension(x[5], x[12], cfg[CFG_K_C], cfg[CFG_TETHER_EA])


@_jit
def finish_step(x, a, cfg, c, y, y_ref, effort_weight, penalty):
    """The end of a step at the sampled state x (13,): y (4,) receives the true outputs
    q1, q2, q3, q6 (eqs 43-45); returns (status of ``engine.check_state``, reward, true
    tension [N]). Reward: -(|q_1..3 - q_ref|^2 + effort_weight |a|^2) with the clipped action
    a (4,), or -penalty when the state failed.

    Parameters
    ----------
    x : ndarray, shape (13,)
        The state at the end of the step, [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    a : ndarray, shape (4,)
        The clipped action in [-1, 1] (dimensionless).
    cfg : ndarray, shape (CFG_SIZE,)
        The engine's configuration (``layout.CFG_*``: attachment, K_C, failure limits...).
    c : ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    y : ndarray, shape (4,)
        Scratch; receives the true outputs [q1, q2, q3, q6] in [m, m, m, rad].
    y_ref : ndarray, shape (4,)
        The trim outputs [m, m, m, rad].
    effort_weight : float
        Weight of |a|^2 in the reward, >= 0.
    penalty : float
        The reward of a failed state is -penalty.

    Returns
    -------
    status : int
        ``engine.check_state``'s status (``Status``), ``STATUS_OK`` unless the state failed.
    reward : float
        The step's reward [m^2, with the effort term added].
    tension : float
        The true tether tension [N] (eq 28), 0 when detached.
    """
    tension = tether_tension(x, cfg)
    tethered_outputs(x, frozen(c), y)
    status = engine.check_state(x, y, y_ref, tension, cfg)
    if status != engine.STATUS_OK:
        return status, -penalty, tension
    e0, e1, e2 = y[0] - y_ref[0], y[1] - y_ref[1], y[2] - y_ref[2]
    effort = a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]
    return status, -((e0 * e0 + e1 * e1 + e2 * e2) + effort_weight * effort), tension


@_jit
def observe_into(x, tension, k, sensors, c, trim, x_meas, y_meas, obs):
    """The observation (float32 (13,) ``obs``, order ``OBSERVATION_NAMES``) at sample k: what
    the sensors read (``sensors.measure_sampled``: each sensor at its rate and latency, the
    true state and tension when the noise table is empty; ``sensors`` is
    ``runs.packing.sensor_tuple``'s (noise, source code, arm, scratch, schedule, history ring),
    as for ``engine.sense``) as deviations from the trim (x0, y_ref, t_ref); NaN reads 0, values
    are clipped to +-OBS_LIMIT. x_meas (13,), y_meas (4,) are scratch.

    Parameters
    ----------
    x : ndarray, shape (13,)
        The true state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    tension : float
        The true tether tension [N].
    k : int
        The sample index (t = k dt).
    sensors : tuple
        ``runs.packing.sensor_tuple``'s (noise, source code, arm, scratch, schedule, history
        ring).
    c : ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    trim : tuple
        (x0, y_ref, t_ref): the trim state (13,) the angles and rates are measured from, the
        trim outputs (4,) [q1, q2, q3, q6] in [m, m, m, rad] and the reference tension [N].
    x_meas : ndarray, shape (13,)
        Scratch: the measured state.
    y_meas : ndarray, shape (4,)
        Scratch: the measured outputs.
    obs : ndarray, shape (13,), float32
        Receives the observation, filled in place.

    Returns
    -------
    None
    """
    x0, y_ref, t_ref = trim
    if sensors[0].shape[0] == 0:
        for i in range(13):
            x_meas[i] = x[i]
        measured = tension
    else:
        measured = measure_sampled(x, tension, k, sensors, x_meas)
    tethered_outputs(x_meas, frozen(c), y_meas)
    for i in range(13):
        if i < 3:
            v = y_meas[i] - y_ref[i]
        elif i < 6:
            v = x_meas[i - 3] - x0[i - 3]
        elif i < 12:
            v = x_meas[i] - x0[i]
        else:
            v = measured - t_ref
        if math.isnan(v):
            v = 0.0
        obs[i] = min(max(v, -OBS_LIMIT), OBS_LIMIT)


@_jit
def start_episode(x, cfg, ctrl, loop, ring, x_start, z_start, cfg0, ctrl0, gust_dt):
    """Put one environment's arrays at its episode's start, in place (the reset of
    ``TetheredHoverEnv`` and of each copy of the vector environment): at rest in the trim of
    the episode's air at t = 0 (``runs.start.start_point``'s x and z0), the scenario's
    configuration with the wind's gust step, the winch and actuators at rest, no tether
    release, no input applied yet and an empty sensor history.

    Parameters
    ----------
    x : ndarray, shape (13,)
        Receives the state ``x_start``.
    cfg : ndarray, shape (CFG_SIZE,)
        Receives ``cfg0`` with ``CFG_GUST_DT`` = ``gust_dt``.
    ctrl : ndarray, shape (CTRL_SIZE,)
        Receives ``ctrl0``.
    loop : tuple
        ``engine.new_loop_state``'s arrays (order ``layout.LOOP_*``): the integrators receive
        ``z_start``, the measured state ``x_start``, the winch and held actuator states 0,
        the release event and the applied inputs NaN (the rest is scratch, written before
        it is read).
    ring : ndarray, shape (rows, N_CHANNELS)
        The sensor history ring (``runs.packing.sensor_tuple``'s), set to 0.
    x_start : ndarray, shape (13,)
        The start state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    z_start : ndarray, shape (4,)
        The LQI integrators' start z0 [m s, m s, m s, rad s].
    cfg0, ctrl0 : ndarray
        The scenario's engine configuration and controller settings (``run_setup``).
    gust_dt : float
        The episode wind's gust step [s] (``CompiledWind.gust_dt``; 0 without a gust table).

    Returns
    -------
    None
    """
    x[:] = x_start
    cfg[:] = cfg0
    cfg[CFG_GUST_DT] = gust_dt
    ctrl[:] = ctrl0
    loop[LOOP_Z][:] = z_start
    loop[LOOP_WINCH][:] = 0.0
    loop[LOOP_HELD][:] = 0.0
    loop[LOOP_EVENT][:] = np.nan
    loop[LOOP_X_MEAS][:] = x_start
    loop[LOOP_INPUTS][:] = np.nan
    ring[:] = 0.0
