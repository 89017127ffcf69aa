"""The lane engine's control sample: every phase of a single run's sample
(``engine.loop.paper_sample``: the tether's tension and the release check, the sensors, the
paper's or the tethered LQI with feed-forward and winch law, the actuators, the true outputs,
the failure checks and the on-line metrics) for a block of ``layout.LANES`` runs at once.

Every array is flat (variable, lane), element (i, j) at i * LANES + j, as in
``engine.lanes.rk4_lanes``; each phase is a sequence of loops over the lanes with no call and no
branch on a lane's data (a lane's choices are selects), so the compiler vectorises them. The
formulas are the single run's own: the scalar kernels (``engine.state_status``,
``engine.actuator_value``, ``engine.payout_limited_rate``, ``control.paper.winch_pi``,
``control.paper.reel_command``, ``control.paper.tension_q9_of``, ``summary.larger``,
``summary.smaller``) and the generated lane forms of the outputs and the tether's torque
(``model.codegen``); the LQI's sums run in the single run's order. So each lane performs a
single run's operations in the same order and equals it bit for bit (``tests/test_lanes.py``).

Three parts stay lane by lane: libm's sine and cosine of the angles
(``kernels.angle_trig_lanes``: libm has no vector form equal to its scalar one), and, on the
lane's rows gathered and scattered back, a noisy sensor suite
(``sensing.sensors.measure_sampled``, with its history ring and schedule) and the drum winch
(``engine.drum_winch``); a block without sensors or drum never takes those branches.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._compile import compiled
from ..control.paper import (
    reel_command,
    tension_q9_of,
    winch_pi,
)
from ..layout import (
    ACT_BREAK,
    ACT_DRUM,
    ACT_MAX_LENGTH,
    ACT_MIN_LENGTH,
    ACT_REEL_ACCEL,
    ACT_REEL_RATE,
    ACT_SIZE,
    ACT_TAU,
    ACT_U_MAX,
    ACT_U_MIN,
    CFG_ATTACHED,
    CFG_DT,
    CFG_K_C,
    CFG_MAX_ANGLE,
    CFG_MAX_DEVIATION,
    CFG_MAX_TENSION,
    CFG_METRICS_FROM,
    CFG_TETHER_EA,
    CONTROL_LAW_TETHER_LQI,
    CTRL_ANTI_WINDUP,
    CTRL_DT,
    CTRL_FFWD,
    CTRL_K_I,
    CTRL_K_P,
    CTRL_LAW,
    CTRL_REEL_ACCEL,
    CTRL_REEL_RATE_LIMIT,
    CTRL_T_REF,
    CTRL_TENSION_K_C,
    CTRL_U_MAX,
    CTRL_U_MIN,
    CTRL_WINCH,
    HELD_AT_LIMIT,
    HELD_DRUM_SPEED,
    HELD_INPUTS,
    HELD_LIMIT_TIME,
    HELD_LIMIT_WHICH,
    HELD_REEL_RATE,
    HELD_SIZE,
    LANES,
    SC_COS,
    SUMMARY_N_SAMPLES,
    SUMMARY_PEAK_Q1,
    SUMMARY_PEAK_Q4,
    SUMMARY_PEAK_Q5,
    SUMMARY_SUMSQ_Q1,
    SUMMARY_TENSION_MAX,
    SUMMARY_TENSION_MIN,
    WINCH_INTEGRAL,
    WINCH_PREVIOUS_RATE,
    X_LN,
    X_Q4,
    X_Q5,
    X_Q7,
    X_Q8,
    X_Q9,
    LoopState,
)
from ..model.kernels import (
    angle_trig_lanes,
    tether_tension,
    tethered_outputs_lanes,
    tethered_tether_torque_lanes,
)
from ..sensing.sensors import measure_sampled
from .loop import (
    STATUS_OK,
    actuator_lag_gain,
    actuator_value,
    clamp_reel_rate,
    drum_winch,
    payout_limited_rate,
    state_status,
)
from .summary import larger, smaller

__all__ = ["LaneLaw", "LaneState", "lane_law", "lane_sample", "lane_state"]

_jit_inline = compiled(error_model="numpy", inline="always")


class LaneState(NamedTuple):
    """A block's per-lane state of the control sample, flat (variable, lane): the run's
    ``layout.LoopState`` in lane form (``loop``) with the run's mutable switches and its
    metrics.

    Parameters
    ----------
    cfg, ctrl, act : numpy.ndarray, shape (CFG_SIZE LANES,), (CTRL_SIZE LANES,), (ACT_SIZE LANES,)
        Each lane's ``cfg``, ``ctrl`` and ``act`` (a release clears its CFG_ATTACHED,
        CTRL_WINCH and CTRL_FFWD).
    lag : numpy.ndarray, shape (LANES,)
        The actuators' lag over a sample (``engine.actuator_lag_gain``).
    loop : LoopState
        ``layout.LoopState``'s fields, each flat (variable, lane): z (4 LANES,), winch
        (WINCH_SIZE LANES,), held (HELD_SIZE LANES,), event (2 LANES,), x_meas (13 LANES,),
        sc_meas, sc_true (10 LANES,), y, y_est, inputs, ffwd (4 LANES,); without sensors
        x_meas is the true state x, sc_true is sc_meas and y is y_est (the same arrays).
    tension, measured, rate, status : numpy.ndarray, shape (LANES,)
        The sample's true tension at P [N], measured tension [N], applied reel rate [m/s]
        and status (``Status``, as a float).
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS) LANES,)
        The on-line metrics (``summary.accumulate``'s).
    scratch : numpy.ndarray, shape (8 LANES,)
        Work space.
    """

    cfg: np.ndarray
    ctrl: np.ndarray
    act: np.ndarray
    lag: np.ndarray
    loop: LoopState
    tension: np.ndarray
    measured: np.ndarray
    rate: np.ndarray
    status: np.ndarray
    summary: np.ndarray
    scratch: np.ndarray


class LaneLaw(NamedTuple):
    """A block's control law, flat (variable, lane) (the lane form of ``layout.LAW_*``).

    Parameters
    ----------
    gain_on, gain_off : numpy.ndarray, shape (4 n_cols LANES,)
        The four rotor rows of the gain while the winch runs and once it stops (the tethered
        LQI's rows 0-3 and 5-8; the paper's law has one set, both the same array).
    gain_reel : numpy.ndarray, shape (n_cols LANES,)
        The tethered LQI's reel row (row 4; the paper's law: unused).
    n_cols : int
        The gain's columns (states, then the four integrators).
    x_ref, y_ref, u0_tethered, u0_free : numpy.ndarray
        (13 LANES,), (4 LANES,), (4 LANES,), (4 LANES,).
    """

    gain_on: np.ndarray
    gain_off: np.ndarray
    gain_reel: np.ndarray
    n_cols: int
    x_ref: np.ndarray
    y_ref: np.ndarray
    u0_tethered: np.ndarray
    u0_free: np.ndarray


@_jit_inline
def _flat(rows, out):
    """out (columns LANES,) = rows (LANES, columns) laid out flat (column, lane)."""
    for j in range(rows.shape[0]):
        for i in range(rows.shape[1]):
            out[i * LANES + j] = rows[j, i]
    return out


@_jit_inline
def _gain_rows(gain, first, out):
    """out = rows first .. first + out.size / (n_cols LANES) - 1 of the lanes' gains (LANES,
    rows, n_cols), flat (row, column, lane)."""
    n_cols = gain.shape[2]
    for j in range(gain.shape[0]):
        for r in range(out.shape[0] // (n_cols * LANES)):
            for i in range(n_cols):
                out[(r * n_cols + i) * LANES + j] = gain[j, first + r, i]
    return out


@_jit_inline
def lane_law(gain, x_ref, y_ref, u0, u0_free, tether_law):
    """``LaneLaw`` of a block's stacked law (``layout.LAW_*`` with the lane axis in front:
    gain (LANES, rows, n_cols), x_ref (LANES, 13), ...); ``tether_law``: the block flies the
    tethered LQI (gain rows 0-3, 4, 5-8), else the paper's (rows 0-3).

    Parameters
    ----------
    gain : numpy.ndarray, shape (LANES, rows, n_cols)
        The lanes' gains (``layout.LAW_GAIN``).
    x_ref : numpy.ndarray, shape (LANES, 13)
        The lanes' trim states (``layout.LAW_X_REF``) [rad, m, rad/s, m/s, m].
    y_ref : numpy.ndarray, shape (LANES, 4)
        The lanes' trim outputs [m, m, m, rad].
    u0, u0_free : numpy.ndarray, shape (LANES, 4)
        The lanes' tethered and free trim inputs [N, N m, N m, N].
    tether_law : bool
        Whether the block flies the tethered LQI.

    Returns
    -------
    LaneLaw
        The block's law, flat (variable, lane).
    """
    n_cols = gain.shape[2]
    gain_on = _gain_rows(gain, 0, np.empty(4 * n_cols * LANES))
    if tether_law:
        gain_off = _gain_rows(gain, 5, np.empty(4 * n_cols * LANES))
        gain_reel = _gain_rows(gain, 4, np.empty(n_cols * LANES))
    else:
        gain_off = gain_on
        gain_reel = np.zeros(n_cols * LANES)
    return LaneLaw(
        gain_on, gain_off, gain_reel, n_cols,
        _flat(x_ref, np.empty(13 * LANES)), _flat(y_ref, np.empty(4 * LANES)),
        _flat(u0, np.empty(4 * LANES)), _flat(u0_free, np.empty(4 * LANES)),
    )  # fmt: skip


@_jit_inline
def lane_state(cfg, ctrl, act, z0, x, sensed, n_summary):
    """``LaneState`` at a block's start from its stacked cfg, ctrl, act (LANES, size), the
    integrators' start z0 (LANES, 4) and, flat, the lanes' state x (13 LANES,); ``sensed``:
    some lane has a noise table (else x_meas is x, sc_true sc_meas, y y_est).

    Parameters
    ----------
    cfg : numpy.ndarray, shape (LANES, CFG_SIZE)
        The lanes' settings (``layout.CFG_*``).
    ctrl : numpy.ndarray, shape (LANES, CTRL_SIZE)
        The lanes' controller settings (``layout.CTRL_*``).
    act : numpy.ndarray, shape (LANES, ACT_SIZE)
        The lanes' actuators (``layout.ACT_*``).
    z0 : numpy.ndarray, shape (LANES, 4)
        The lanes' integrators at the start (``layout.LAW_Z0``).
    x : numpy.ndarray, shape (13 LANES,)
        The lanes' true states, flat (variable, lane) [rad, m, rad/s, m/s, m].
    sensed : bool
        Whether some lane has a noise table.
    n_summary : int
        The summary's fields (len(SUMMARY_FIELDS)).

    Returns
    -------
    LaneState
        The block's per-lane state at its start.
    """
    act_flat = _flat(act, np.empty(ACT_SIZE * LANES))
    lag = np.empty(LANES)
    for j in range(LANES):
        lag[j] = actuator_lag_gain(act[j, ACT_TAU], cfg[j, CFG_DT])
    sc_meas = np.empty(10 * LANES)
    y_est = np.empty(4 * LANES)
    return LaneState(
        _flat(cfg, np.empty(cfg.shape[1] * LANES)),
        _flat(ctrl, np.empty(ctrl.shape[1] * LANES)),
        act_flat,
        lag,
        LoopState(
            _flat(z0, np.empty(4 * LANES)),
            np.zeros(2 * LANES),
            np.zeros(HELD_SIZE * LANES),
            np.full(2 * LANES, np.nan),
            x.copy() if sensed else x,
            sc_meas,
            np.empty(10 * LANES) if sensed else sc_meas,
            np.empty(4 * LANES) if sensed else y_est,
            y_est,
            np.empty(4 * LANES),
            np.empty(4 * LANES),
        ),
        np.zeros(LANES),
        np.zeros(LANES),
        np.zeros(LANES),
        np.zeros(LANES),
        np.zeros(n_summary * LANES),
        np.empty(8 * LANES),
    )


@_jit_inline
def _sense(k, x, s):
    """Phase 1 (``engine._sense`` of a massless tether): the tension of eq 28 (0 when
    removed or released), the safety device's release (``engine.release_if_broken``: the
    lane's switches cleared, the event recorded); the measured tension is the true one."""
    cfg, ctrl, act, event = s.cfg, s.ctrl, s.act, s.loop.event
    for j in range(s.tension.shape[0]):
        t = k * cfg[CFG_DT * LANES + j]
        attached = cfg[CFG_ATTACHED * LANES + j] > 0.5
        k_c = cfg[CFG_K_C * LANES + j]
        ea = cfg[CFG_TETHER_EA * LANES + j]
        tension = (
            tether_tension(x[X_Q9 * LANES + j], x[X_LN * LANES + j], k_c, ea) if attached else 0.0
        )
        broken = tension > act[ACT_BREAK * LANES + j]
        cleared = 0.0 if broken else 1.0
        cfg[CFG_ATTACHED * LANES + j] *= cleared
        ctrl[CTRL_WINCH * LANES + j] *= cleared
        ctrl[CTRL_FFWD * LANES + j] *= cleared
        event[j] = t if broken else event[j]
        event[LANES + j] = tension if broken else event[LANES + j]
        tension = 0.0 if broken else tension
        s.tension[j] = tension
        s.measured[j] = tension


@_jit_inline
def _measure(k, x, s, lanes_sensed, sensors, rows):
    """Phase 1's sensors: each lane with a noise table measures its state
    (``sensing.sensors.measure_sampled`` on its rows, gathered and scattered back); the
    others read the true state. ``sensors`` and ``rows`` as ``lanes.run_lanes``'s."""
    noise, noise_rows, source, arm, scratch, schedule, schedule_rows, ring, ring_rows = sensors
    x_row, meas_row = rows
    for j in range(LANES):
        for i in range(13):
            x_row[i] = x[i * LANES + j]
        if lanes_sensed[j]:
            lane_sensors = (
                noise[j, : noise_rows[j]], source[j], arm[j], scratch[j],
                schedule[j, : schedule_rows[j]], ring[j, : ring_rows[j]],
            )  # fmt: skip
            s.measured[j] = measure_sampled(x_row, s.tension[j], k, lane_sensors, meas_row)
        else:
            for i in range(13):
                meas_row[i] = x_row[i]
        for i in range(13):
            s.loop.x_meas[i * LANES + j] = meas_row[i]


@_jit_inline
def _lqi(law, s, q9, use_off, n_cols, two_sets):
    """The LQI's rotor commands (``control.paper.paper_control_sc``'s sums, each row in its
    order): inp = u0 - K (x - x_ref) - K_z z with q9 in place of x[5], over the gain's rows
    for the winch running or stopped (``use_off``) and u0 of the tethered or free trim.
    ``n_cols`` is the gain's column count and ``two_sets`` whether the law has rows for the
    winch stopped (the tethered LQI's), constants at each call site: the sum over the
    columns then unrolls and the loop over the lanes, innermost, vectorises."""
    x, z, cfg, inp = s.loop.x_meas, s.loop.z, s.cfg, s.loop.inputs
    on, off, u0, u0_free, x_ref = law.gain_on, law.gain_off, law.u0_tethered, law.u0_free, law.x_ref
    n_x = n_cols - 4
    for i in range(4):
        row = i * n_cols * LANES
        for j in range(q9.shape[0]):
            stopped = use_off[j] > 0.5
            tethered, free = u0[i * LANES + j], u0_free[i * LANES + j]
            acc = tethered if cfg[CFG_ATTACHED * LANES + j] > 0.5 else free
            for col in range(n_cols):
                if col < n_x:
                    value = q9[j] if col == 5 else x[col * LANES + j]
                    d = value - x_ref[col * LANES + j]
                else:
                    d = z[(col - n_x) * LANES + j]
                e = row + col * LANES + j
                if not two_sets:  # the paper's law (a constant: folded at compile time)
                    g = on[e]
                else:
                    g_on, g_off = on[e], off[e]
                    g = g_off if stopped else g_on
                acc -= g * d
            inp[i * LANES + j] = acc


@_jit_inline
def _law(law, s, c, tether_law):
    """Phase 2 (``engine.paper_law`` with no action): sin, cos of the measured angles, the
    outputs' estimate, the LQI, the tether-torque feed-forward (eq 55), the integrators
    (eq 50, held by the anti-windup), then the winch's command: the PI of eq 56
    (``winch_pi``) or, with ``tether_law`` (the block flies the tethered LQI), its reel row
    (``reel_command``); 0 while the winch is stopped. The command goes to s.rate."""
    loop = s.loop
    ctrl, x, z, inp, ffwd = s.ctrl, loop.x_meas, loop.z, loop.inputs, loop.ffwd
    y_est, winch = loop.y_est, loop.winch
    n = s.rate.shape[0]  # LANES, at run time: the loops vectorise, not unroll
    q9, use_off, _, integrate = _parts(s.scratch[: 4 * LANES], 4)
    torque = s.scratch[4 * LANES : 6 * LANES]
    reel = s.scratch[6 * LANES : 7 * LANES]
    angle_trig_lanes(x, s.loop.sc_meas)
    tethered_outputs_lanes(x, s.loop.sc_meas, c, y_est)
    for j in range(n):
        winch_on = ctrl[CTRL_WINCH * LANES + j] > 0.5
        tethered = ctrl[CTRL_LAW * LANES + j] == CONTROL_LAW_TETHER_LQI
        use_off[j] = 1.0 if (tethered and not winch_on) else 0.0
        q9_tension = tension_q9_of(
            x[X_Q9 * LANES + j],
            x[X_LN * LANES + j],
            s.measured[j],
            ctrl[CTRL_TENSION_K_C * LANES + j],
        )
        q9[j] = q9_tension if (tethered and winch_on) else x[X_Q9 * LANES + j]
    # the tethered LQI (9, 17) or the paper's law (4, 16) (``control.paper.check_law``): two
    # call sites, each with its shape a constant (``_lqi``)
    if tether_law:
        _lqi(law, s, q9, use_off, 17, True)
    else:
        _lqi(law, s, q9, use_off, 16, False)
    tethered_tether_torque_lanes(x, s.loop.sc_meas, s.measured, c, torque)
    for j in range(n):
        on = ctrl[CTRL_FFWD * LANES + j] > 0.5
        f1 = torque[j] if on else 0.0
        f2 = torque[LANES + j] if on else 0.0
        ffwd[j] = 0.0
        ffwd[LANES + j] = f1
        ffwd[2 * LANES + j] = f2
        ffwd[3 * LANES + j] = 0.0
        inp[LANES + j] = inp[LANES + j] - f1 if on else inp[LANES + j]
        inp[2 * LANES + j] = inp[2 * LANES + j] - f2 if on else inp[2 * LANES + j]
        # the anti-windup's test of the four commands, written out (a loop over them would be
        # the innermost, not the lanes')
        outside = _outside(inp, ctrl, 0, j) | _outside(inp, ctrl, 1, j)
        outside |= _outside(inp, ctrl, 2, j) | _outside(inp, ctrl, 3, j)
        hold = (ctrl[CTRL_ANTI_WINDUP * LANES + j] > 0.5) & outside
        integrate[j] = 0.0 if hold else 1.0
    for i in range(4):
        for j in range(n):
            e = i * LANES + j
            moved = z[e] + ctrl[CTRL_DT * LANES + j] * (law.y_ref[e] - y_est[e])
            z[e] = moved if integrate[j] > 0.5 else z[e]
    if tether_law:  # the reel row, on the integrators just updated (``reel_law_step``)
        n_x = law.n_cols - 4
        for j in range(n):
            reel[j] = 0.0
        for col in range(n_x):
            for j in range(n):
                value = q9[j] if col == 5 else x[col * LANES + j]
                reel[j] -= law.gain_reel[col * LANES + j] * (value - law.x_ref[col * LANES + j])
        for col in range(4):
            for j in range(n):
                reel[j] -= law.gain_reel[(n_x + col) * LANES + j] * z[col * LANES + j]
    for j in range(n):
        winch_on = ctrl[CTRL_WINCH * LANES + j] > 0.5
        tethered = ctrl[CTRL_LAW * LANES + j] == CONTROL_LAW_TETHER_LQI
        previous = winch[WINCH_PREVIOUS_RATE * LANES + j]
        integral = winch[WINCH_INTEGRAL * LANES + j]
        dt = ctrl[CTRL_DT * LANES + j]
        rate_limit = ctrl[CTRL_REEL_RATE_LIMIT * LANES + j]
        accel = ctrl[CTRL_REEL_ACCEL * LANES + j]
        pi_rate, pi_integral = winch_pi(
            integral, previous, s.measured[j], ctrl[CTRL_K_P * LANES + j],
            ctrl[CTRL_K_I * LANES + j], ctrl[CTRL_T_REF * LANES + j], dt, rate_limit, accel,
        )  # fmt: skip
        reel_rate = reel_command(reel[j] if tether_law else 0.0, previous, rate_limit, accel, dt)
        rate = (reel_rate if tethered else pi_rate) if winch_on else 0.0
        winch[WINCH_INTEGRAL * LANES + j] = pi_integral if (winch_on and not tethered) else integral
        winch[WINCH_PREVIOUS_RATE * LANES + j] = rate if winch_on else previous
        s.rate[j] = rate


@_jit_inline
def _outside(inp, ctrl, i, j):
    """Whether lane j's rotor command i lies outside the anti-windup's limits."""
    v = inp[i * LANES + j]
    return (v < ctrl[(CTRL_U_MIN + i) * LANES + j]) | (v > ctrl[(CTRL_U_MAX + i) * LANES + j])


@_jit_inline
def _apply(k, x, s, lanes_drum, rows):
    """Phase 3 (``engine.actuate`` and ``engine.sample_outputs``' checks): the rotor inputs
    saturated and lagged (``actuator_value``), the reel rate's rate and acceleration limits
    (the ideal winch: ``control.paper.reel_command``) or the drum winch on the clamped
    command (``engine.clamp_reel_rate``, ``engine.drum_winch``, per lane on its rows, where
    ``lanes_drum``), the payout limits (``payout_limited_rate``) on the true length; s.rate
    becomes the applied rate."""
    cfg, act, held, inp = s.cfg, s.act, s.loop.held, s.loop.inputs
    n = s.rate.shape[0]
    first = k == 0
    for i in range(4):
        for j in range(n):
            e = (HELD_INPUTS + i) * LANES + j
            v = actuator_value(
                inp[i * LANES + j], held[e], act[(ACT_U_MIN + i) * LANES + j],
                act[(ACT_U_MAX + i) * LANES + j], s.lag[j], first,
            )  # fmt: skip
            held[e] = v
            inp[i * LANES + j] = v
    for j in range(n):
        s.rate[j] = reel_command(
            s.rate[j], held[HELD_REEL_RATE * LANES + j], act[ACT_REEL_RATE * LANES + j],
            act[ACT_REEL_ACCEL * LANES + j], cfg[CFG_DT * LANES + j],
        )  # fmt: skip
    if lanes_drum.any():
        held_row, act_row = rows
        for j in range(LANES):
            if lanes_drum[j]:
                for i in range(HELD_SIZE):
                    held_row[i] = held[i * LANES + j]
                for i in range(ACT_SIZE):
                    act_row[i] = act[i * LANES + j]
                # the command, before the ideal winch's limit: undo it (the drum's own law)
                s.rate[j] = drum_winch(
                    held_row, clamp_reel_rate(s.scratch[7 * LANES + j], act_row), act_row,
                    cfg[CFG_DT * LANES + j],
                    s.tension[j], s.measured[j],
                )  # fmt: skip
                for i in range(HELD_SIZE):
                    held[i * LANES + j] = held_row[i]
    for j in range(n):
        dt = cfg[CFG_DT * LANES + j]
        rate, which = payout_limited_rate(
            s.rate[j], x[X_LN * LANES + j], dt, act[ACT_MIN_LENGTH * LANES + j],
            act[ACT_MAX_LENGTH * LANES + j],
        )  # fmt: skip
        stop = which != 0.0
        drum = act[ACT_DRUM * LANES + j] > 0.5
        speed = held[HELD_DRUM_SPEED * LANES + j]
        held[HELD_DRUM_SPEED * LANES + j] = 0.0 if (stop and drum) else speed
        first_stop = stop and held[HELD_LIMIT_WHICH * LANES + j] == 0.0
        limit_time = held[HELD_LIMIT_TIME * LANES + j]
        held[HELD_LIMIT_TIME * LANES + j] = k * dt + dt if first_stop else limit_time
        limit_which = held[HELD_LIMIT_WHICH * LANES + j]
        held[HELD_LIMIT_WHICH * LANES + j] = which if first_stop else limit_which
        held[HELD_AT_LIMIT * LANES + j] = which
        held[HELD_REEL_RATE * LANES + j] = rate
        s.rate[j] = rate


@_jit_inline
def _check(x, s, law, c, sensed):
    """Phase 3's end (``engine.sample_outputs``): the true outputs and sin, cos of the true
    angles (the estimate's when the sensors are perfect), then ``state_status``."""
    cfg = s.cfg
    n = s.rate.shape[0]
    if sensed:  # the lanes without sensors get the same values: x_meas is x for them
        angle_trig_lanes(x, s.loop.sc_true)
        tethered_outputs_lanes(x, s.loop.sc_true, c, s.loop.y)
    y, sc, y_ref = s.loop.y, s.loop.sc_true, law.y_ref
    for j in range(n):
        finite = True
        for i in range(13):
            finite &= math.isfinite(x[i * LANES + j])
        s.status[j] = state_status(
            finite, cfg[CFG_ATTACHED * LANES + j] > 0.5,
            (x[X_Q4 * LANES + j], x[X_Q5 * LANES + j], x[X_Q7 * LANES + j],
             x[X_Q8 * LANES + j]),
            x[X_Q9 * LANES + j], x[X_LN * LANES + j],
            (sc[(SC_COS + 1) * LANES + j], sc[(SC_COS + 3) * LANES + j],
             sc[(SC_COS + 4) * LANES + j]),
            (y[j] - y_ref[j], y[LANES + j] - y_ref[LANES + j],
             y[2 * LANES + j] - y_ref[2 * LANES + j]),
            y[2 * LANES + j], s.tension[j],
            (cfg[CFG_MAX_TENSION * LANES + j], cfg[CFG_MAX_ANGLE * LANES + j],
             cfg[CFG_MAX_DEVIATION * LANES + j]),
        )  # fmt: skip


@_jit_inline
def _accumulate(k, x, s, law, active):
    """Phase 4's metrics (``summary.accumulate``) of the lanes still running whose sample
    passed its checks, from sample cfg[CFG_METRICS_FROM] on."""
    summary, y, y_ref, x_ref, cfg = s.summary, s.loop.y, law.y_ref, law.x_ref, s.cfg
    n = s.rate.shape[0]
    for j in range(n):
        # a lane outside the metrics adds values that leave them as they are (0 to the peaks
        # and sums, which are >= 0; +-inf to the tension's range): the stores are
        # unconditional and the loop vectorises
        on = active[j] & (s.status[j] == STATUS_OK) & (k >= cfg[CFG_METRICS_FROM * LANES + j])
        # q1, q2, q3 written out: a loop over them would be the innermost, not the lanes'
        _position_metrics(summary, y, y_ref, on, 0, j)
        _position_metrics(summary, y, y_ref, on, 1, j)
        _position_metrics(summary, y, y_ref, on, 2, j)
        e = SUMMARY_PEAK_Q4 * LANES + j
        summary[e] = larger(summary[e], abs(x[j] - x_ref[j]) if on else 0.0)
        e = SUMMARY_PEAK_Q5 * LANES + j
        summary[e] = larger(summary[e], abs(x[LANES + j] - x_ref[LANES + j]) if on else 0.0)
        e = SUMMARY_TENSION_MIN * LANES + j
        summary[e] = smaller(summary[e], s.tension[j] if on else math.inf)
        e = SUMMARY_TENSION_MAX * LANES + j
        summary[e] = larger(summary[e], s.tension[j] if on else -math.inf)
        e = SUMMARY_N_SAMPLES * LANES + j
        summary[e] = summary[e] + (1.0 if on else 0.0)


@_jit_inline
def _position_metrics(summary, y, y_ref, on, a, j):
    """``_accumulate``'s peak and sum of squares of output a of lane j."""
    dev = y[a * LANES + j] - y_ref[a * LANES + j]
    e = (SUMMARY_PEAK_Q1 + a) * LANES + j
    summary[e] = larger(summary[e], abs(dev) if on else 0.0)
    e = (SUMMARY_SUMSQ_Q1 + a) * LANES + j
    summary[e] = summary[e] + (dev * dev if on else 0.0)


@_jit_inline
def lane_sample(k, x, s, law, c, active, sensing, lanes_drum, rows, tether_law):
    """One control sample at t = k dt of every lane of a block (``engine.paper_sample``,
    then ``summary.accumulate`` for the lanes in ``active``): x (13 LANES,) the lanes' true
    states, s its ``LaneState``, law its ``LaneLaw``, c (n_c LANES,) the model constants;
    ``sensing`` = (lanes_sensed (LANES,), which lanes have a noise table, and ``sensors`` as
    ``lanes.run_lanes``'s); ``lanes_drum`` (LANES,) which lanes have a drum winch; rows = (x
    row, measured row, held row, act row), scratch for the per-lane parts. s.status, s.rate,
    s.loop.inputs, s.loop.sc_true then hold each lane's status, reel rate, applied inputs and
    sin, cos of its true angles.

    Parameters
    ----------
    k : int
        The control sample's index.
    x : numpy.ndarray, shape (13 LANES,)
        The lanes' true states, flat (variable, lane) [rad, m, rad/s, m/s, m].
    s : LaneState
        The block's per-lane state, updated.
    law : LaneLaw
        The block's law.
    c : numpy.ndarray, shape (n_c LANES,)
        The lanes' model constants, flat.
    active : numpy.ndarray of bool, shape (LANES,)
        The lanes still running (their metrics accumulate).
    sensing : tuple
        (lanes_sensed, sensors): the lanes with a noise table (bool (LANES,)) and the lanes'
        sensors, as ``lanes.run_lanes``'s.
    lanes_drum : numpy.ndarray of bool, shape (LANES,)
        The lanes with a drum winch.
    rows : tuple of numpy.ndarray
        (x row, measured row, held row, act row): scratch for the per-lane parts.
    tether_law : bool
        Whether the block flies the tethered LQI.
    """
    lanes_sensed, sensors = sensing
    _sense(k, x, s)
    sensed = lanes_sensed.any()
    if sensed:
        _measure(k, x, s, lanes_sensed, sensors, (rows[0], rows[1]))
    _law(law, s, c, tether_law)
    for j in range(s.rate.shape[0]):
        s.scratch[7 * LANES + j] = s.rate[j]  # the controller's command (the drum's input)
    _apply(k, x, s, lanes_drum, (rows[2], rows[3]))
    _check(x, s, law, c, sensed)
    _accumulate(k, x, s, law, active)


@_jit_inline
def _parts(a, m):
    """The first four of m equal consecutive parts of a (views)."""
    n = a.shape[0] // m
    return a[:n], a[n : 2 * n], a[2 * n : 3 * n], a[3 * n : 4 * n]
