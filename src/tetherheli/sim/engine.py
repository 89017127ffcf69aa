"""The compiled closed-loop engine (Numba): plant, paper controller, winch, wind, integrator.

One control sample is written once, as phases that every loop shares (``sample_step``):
``sense`` (the safety device's release check, then the sensors), the controller, ``actuate``
(saturation, lag, the winch's acceleration limit or drum), ``check_state_sc`` (failure checks of
the sampled state); then the integrator advances the plant to the next sample. The compiled loop
``run_closed_loop`` and the Gymnasium environment run ``paper_sample`` (the phases around the
paper's controller) with fixed-step RK4 (``rk4_interval``); ``simulate``'s Python loop runs
the same phases around any ``Controller`` with RK4 or the adaptive reference.

Inputs are held over a sample (zero-order hold); between samples the plant is integrated by
fixed-step RK4 with ``n_substeps`` steps. Wind discontinuities (pulse and step edges) placed on
integration-step boundaries are handled exactly: an RK4 step over [ta, tb] evaluates the wind
at ta as the right limit and at tb as the left limit, i.e. it integrates the force on the open
interval (ta, tb).

A lumped-mass tether (``[tether] model = "lumped"``) rides the same loop: ``chain_ends`` sets
its end tensions before the sample and ``lumped_interval`` replaces ``rk4_interval``.

The packed arrays (``cfg``, ``ctrl``, ``act``, ``held``, the wind program, the summary, the
chain) are laid out in ``tetherheli.layout``; run statuses are ``tetherheli.status.Status``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._compile import borrowed, compiled, keep_alive, plain
from ..control.paper import limit_rate_change_jit, paper_control_sc
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
    ACT_SIZE,
    ACT_TAU,
    ACT_U_MAX,
    ACT_U_MIN,
    CFG_ARM,
    CFG_ATTACHED,
    CFG_DT,
    CFG_GUST_DT,
    CFG_K_C,
    CFG_LUMPED,
    CFG_MAX_ANGLE,
    CFG_MAX_DEVIATION,
    CFG_MAX_TENSION,
    CFG_METRICS_FROM,
    CFG_N_SUB,
    CFG_SIZE,
    CFG_TENSION_GROUND,
    CFG_TENSION_TOP,
    CHAIN_NODES,
    CHAIN_PARAMS,
    CHAIN_VELOCITIES,
    CHAIN_WORK,
    CTRL_FFWD,
    CTRL_WINCH,
    HELD_AT_LIMIT,
    HELD_DRUM_SPEED,
    HELD_DRUM_SPEED_SAMPLED,
    HELD_INPUTS,
    HELD_LIMIT_TIME,
    HELD_LIMIT_WHICH,
    HELD_MOTOR_TORQUE,
    HELD_REEL_RATE,
    HELD_SIZE,
    LANES,
    LAW_X_REF,
    LAW_Y_REF,
    LAW_Z0,
    LUMPED_MU,
    SUMMARY_FIELDS,
    SUMMARY_N_SAMPLES,
    SUMMARY_PEAK_Q1,
    SUMMARY_PEAK_Q4,
    SUMMARY_PEAK_Q5,
    SUMMARY_RELEASE_TENSION,
    SUMMARY_RELEASE_TIME,
    SUMMARY_SUMSQ_Q1,
    SUMMARY_TENSION_MAX,
    SUMMARY_TENSION_MIN,
    SUMMARY_WINCH_LIMIT,
    SUMMARY_WINCH_LIMIT_TIME,
    WINCH_SIZE,
    WIND_COLUMNS,
    WIND_CONSTANT,
    WIND_DIRECTION,
    WIND_DURATION,
    WIND_FREQUENCY,
    WIND_KIND,
    WIND_MAGNITUDE,
    WIND_PHASE,
    WIND_PULSE,
    WIND_SINE,
    WIND_START,
    LoopState,
    Signals,
    default_actuators,
)
from ..model.kernels import (
    angle_trig,
    angle_trig_from,
    angle_trig_from_lanes,
    sin_branchless,
    tension_from_state,
    tethered_outputs,
    tethered_outputs_sc,
    tethered_rhs_lanes,
    tethered_rhs_sc,
)
from ..sensing.sensors import measure_sampled
from ..status import Status, release_sentence, status_message
from ..tether.lumped import chain_forces, chain_interval, coupling_substeps
from ..tether.winch import drum_step

__all__ = [
    "ACT_SIZE",
    "CFG_SIZE",
    "HELD_SIZE",
    "SUMMARY_FIELDS",
    "WIND_COLUMNS",
    "StepRun",
    "actuate",
    "check_state",
    "default_actuators",
    "paper_sample",
    "release_sentence",
    "rk4_interval",
    "run_closed_loop",
    "sense",
    "status_message",
    "step_advance",
    "step_command",
    "step_finish",
    "step_sense",
    "summarize",
]

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")

#: rows of the scratch array of ``rk4_interval``
RK4_WORK_ROWS = 8

# the statuses as the integers the compiled code returns (``Status`` says what they mean)
STATUS_OK = int(Status.OK)
STATUS_NONFINITE = int(Status.NONFINITE)
STATUS_GROUND = int(Status.GROUND)
STATUS_MAX_TENSION = int(Status.MAX_TENSION)
STATUS_DIVERGED = int(Status.DIVERGED)
STATUS_SINGULAR = int(Status.SINGULAR)
STATUS_SETUP = int(Status.SETUP)
STATUS_TETHER_LENGTH = int(Status.TETHER_LENGTH)
STATUS_MESSAGES = tuple(status.message for status in Status)

#: no command override (``paper_sample``'s ``action_mode``): the paper's controller alone
ACTION_NONE = 0
#: the action is added to the paper controller's rotor inputs (a residual policy)
ACTION_ADD = 1
#: the action replaces the rotor inputs (the winch stays under the paper's PI)
ACTION_REPLACE = 2


@_jit_inline
def profile_value(kind, start, duration, magnitude, frequency, phase, t, side, any_sine):
    """The force magnitude [N] of one built-in wind profile (a program row's columns) at t,
    zero while the profile is off; side = +1 right limit, -1 left limit. Branch-free (selects
    and ``sin_branchless``), so the lane engine evaluates it for a block of runs in one
    vectorised pass; every loop uses it, so lanes and single runs agree bit for bit.
    ``any_sine`` False skips the sine where no profile evaluated together is one."""
    end = start + duration
    right = side > 0
    started = (start <= t) if right else (start < t)
    before_end = (t < end) if right else (t <= end)
    # pulse: [start, end); step and sine: from start (absolute time, Sec. VI); constant: always
    active = kind == WIND_CONSTANT or (started and (kind != WIND_PULSE or before_end))
    wave = sin_branchless(2.0 * math.pi * frequency * t + phase) if any_sine else 1.0
    value = magnitude * (wave if kind == WIND_SINE else 1.0)
    return value if active else 0.0


@_jit_inline
def _wind_program_force(program, t, side, out):
    """Add the built-in profiles' force at time t; side = +1 right limit, -1 left limit."""
    for r in range(program.shape[0]):
        row = program[r]
        value = profile_value(
            row[WIND_KIND], row[WIND_START], row[WIND_DURATION], row[WIND_MAGNITUDE],
            row[WIND_FREQUENCY], row[WIND_PHASE], t, side, row[WIND_KIND] == WIND_SINE,
        )  # fmt: skip
        out[0] += value * row[WIND_DIRECTION]
        out[1] += value * row[WIND_DIRECTION + 1]
        out[2] += value * row[WIND_DIRECTION + 2]


@_jit_inline
def gust_velocity(gust, gust_dt, t):
    """The gust table's air velocity at t [m/s], linear between its rows and held after the
    last one (``gust`` (m, 3) on a grid of step gust_dt [s]; zeros without a table)."""
    if gust_dt <= 0.0 or gust.shape[0] == 0:
        return 0.0, 0.0, 0.0
    s = t / gust_dt
    i = int(s) if s > 0.0 else 0  # floor for s >= 0
    if s <= 0.0:
        w = 0.0
    elif i >= gust.shape[0] - 1:
        i, w = gust.shape[0] - 1, 0.0
    else:
        w = s - i
    if w == 0.0:
        return gust[i, 0], gust[i, 1], gust[i, 2]
    return (
        gust[i, 0] * (1.0 - w) + gust[i + 1, 0] * w,
        gust[i, 1] * (1.0 - w) + gust[i + 1, 1] * w,
        gust[i, 2] * (1.0 - w) + gust[i + 1, 2] * w,
    )


@_jit_inline
def wind_force(program, gust, gust_dt, drag, t, side, v1, v2, v3, out):
    """Wind force on HO in N [N]: the profiles plus the bluff-body drag of the air velocity
    relative to HO, F_i = 0.5 rho CdA_i |v_rel| v_rel,i with |v_rel| the norm of the whole
    relative velocity (drag[i] = 0.5 rho CdA_i; ``wind.drag.DragModel``)."""
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    _wind_program_force(program, t, side, out)
    if gust_dt > 0.0 and gust.shape[0] > 0:
        g1, g2, g3 = gust_velocity(gust, gust_dt, t)
        r1, r2, r3 = g1 - v1, g2 - v2, g3 - v3
        speed = math.sqrt(r1 * r1 + r2 * r2 + r3 * r3)
        out[0] += drag[0] * speed * r1
        out[1] += drag[1] * speed * r2
        out[2] += drag[2] * speed * r3


@_jit_inline
def plant_derivative(x, sc, inp, reel_rate, t, side, cfg, c, program, gust, drag, wind, out):
    """dx/dt (13,) of the tethered-coordinate plant; tension 0 when the tether is removed.
    sc (10,): sin and cos of x[0..4] (``kernels.angle_trig``); wind (3,) receives the force."""
    wind_force(program, gust, cfg[CFG_GUST_DT], drag, t, side, x[6], x[7], x[8], wind)
    _plant_in_wind(x, sc, inp, reel_rate, cfg, c, wind, out)


@_jit_inline
def _plant_in_wind(x, sc, inp, reel_rate, cfg, c, wind, out):
    if cfg[CFG_ATTACHED] > 0.5:
        tension = tension_from_state(x[5], x[12], cfg[CFG_K_C])
        tethered_rhs_sc(x, sc, inp, wind, tension, c, out)
        out[12] = reel_rate
    else:
        tethered_rhs_sc(x, sc, inp, wind, 0.0, c, out)
        out[12] = 0.0


#: sin/cos of the step-start angles are chained by angle addition for at most this many
#: RK4 steps, then taken from libm again (bounds the rounding drift to a few ulp)
TRIG_CHAIN_STEPS = 4


@_jit_inline
def next_step_trig(x, start, sc0, sc, steps_done):
    """sc0 (10,) becomes sin, cos of the angles of x, the start of the next RK4 step: from libm
    every TRIG_CHAIN_STEPS steps, otherwise by angle addition from the previous step's start
    ``start`` whose values sc0 holds (``sc`` is scratch)."""
    if steps_done % TRIG_CHAIN_STEPS == 0:
        angle_trig(x, sc0)
    else:
        angle_trig_from(x, start, sc0, sc)
        for i in range(10):
            sc0[i] = sc[i]


@_jit
def rk4_interval(x, inp, reel_rate, t0, cfg, c, program, gust, drag, work, trig_given):
    """Advance x in place over one control sample [t0, t0 + dt] with n_sub RK4 steps.

    ``work`` (RK4_WORK_ROWS, 13) is scratch. sin and cos of the angles come from libm at the
    sample's start (with ``trig_given`` they are already in work[6, :10],
    ``kernels.angle_trig(x)``) and every TRIG_CHAIN_STEPS steps; everywhere else (the RK4
    stages, the next step's start) by the angle-addition formulas
    (``kernels.angle_trig_from``), which agree with libm to a few units in the last place.
    Without a gust table the wind depends on t only, so the two mid-step stages share it.
    """
    n_sub = int(cfg[CFG_N_SUB])
    h = cfg[CFG_DT] / n_sub
    k1, k2, k3, k4, tmp, wind = work[0], work[1], work[2], work[3], work[4], work[5]
    sc0, sc = work[6], work[7]
    n = x.shape[0]
    gdt = cfg[CFG_GUST_DT]
    gusty = gdt > 0.0 and gust.shape[0] > 0
    if not trig_given:
        angle_trig(x, sc0)
    for j in range(n_sub):
        ta = t0 + j * h
        tb = t0 + (j + 1) * h
        tm = ta + 0.5 * h
        wind_force(program, gust, gdt, drag, ta, 1, x[6], x[7], x[8], wind)
        _plant_in_wind(x, sc0, inp, reel_rate, cfg, c, wind, k1)
        for i in range(n):
            tmp[i] = x[i] + 0.5 * h * k1[i]
        angle_trig_from(tmp, x, sc0, sc)
        wind_force(program, gust, gdt, drag, tm, 1, tmp[6], tmp[7], tmp[8], wind)
        _plant_in_wind(tmp, sc, inp, reel_rate, cfg, c, wind, k2)
        for i in range(n):
            tmp[i] = x[i] + 0.5 * h * k2[i]
        angle_trig_from(tmp, x, sc0, sc)
        if gusty:  # the drag depends on the stage's velocity
            wind_force(program, gust, gdt, drag, tm, 1, tmp[6], tmp[7], tmp[8], wind)
        _plant_in_wind(tmp, sc, inp, reel_rate, cfg, c, wind, k3)
        for i in range(n):
            tmp[i] = x[i] + h * k3[i]
        angle_trig_from(tmp, x, sc0, sc)
        wind_force(program, gust, gdt, drag, tb, -1, tmp[6], tmp[7], tmp[8], wind)
        _plant_in_wind(tmp, sc, inp, reel_rate, cfg, c, wind, k4)
        for i in range(n):
            tmp[i] = x[i]  # the step's start, for the next step's trigonometry
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        if j + 1 < n_sub:
            next_step_trig(x, tmp, sc0, sc, j + 1)


@_jit
def check_state(x, y, y_ref, tension, cfg):
    """Status of a sampled state (``Status``)."""
    sc = np.empty(10)
    angle_trig(x, sc)
    return check_state_sc(x, sc, y, y_ref, tension, cfg)


@_jit_inline
def check_state_sc(x, sc, y, y_ref, tension, cfg):
    """``check_state`` with sc = sin, cos of x[0..4] given (``kernels.angle_trig``)."""
    for i in range(x.shape[0]):
        if not math.isfinite(x[i]):
            return STATUS_NONFINITE
    # an attached tether's natural (unstretched) length LN = x[12] <= 0 is no physical tether
    if cfg[CFG_ATTACHED] > 0.5 and x[12] <= 0.0:
        return STATUS_TETHER_LENGTH
    # HO below the ground, or the attachment point P touching it (z_P = q9 c7 c8 < 1 cm,
    # which also covers the spherical singularities q9 -> 0 and |q8| -> 90 deg near ground)
    if y[2] < 0.0 or x[5] * sc[8] * sc[9] < 0.01:
        return STATUS_GROUND
    if x[5] <= 0.0 or abs(sc[6]) < 1e-9 or abs(sc[9]) < 1e-9:
        return STATUS_SINGULAR
    if tension > cfg[CFG_MAX_TENSION]:
        return STATUS_MAX_TENSION
    a = cfg[CFG_MAX_ANGLE]
    if abs(x[0]) > a or abs(x[1]) > a or abs(x[3]) > a or abs(x[4]) > a:
        return STATUS_DIVERGED
    d = cfg[CFG_MAX_DEVIATION]
    if abs(y[0] - y_ref[0]) > d or abs(y[1] - y_ref[1]) > d or abs(y[2] - y_ref[2]) > d:
        return STATUS_DIVERGED
    return STATUS_OK


@_jit
def start_summary(summary):
    """Empty on-line metrics (``layout.SUMMARY_FIELDS``): no sample, no release."""
    summary[:] = 0.0
    summary[SUMMARY_TENSION_MIN] = np.inf
    summary[SUMMARY_TENSION_MAX] = -np.inf
    summary[SUMMARY_RELEASE_TIME] = np.nan
    summary[SUMMARY_RELEASE_TENSION] = np.nan
    summary[SUMMARY_WINCH_LIMIT_TIME] = np.nan
    summary[SUMMARY_WINCH_LIMIT] = np.nan


@_jit_inline
def winch_limit_into(held, summary):
    """The first stop of the reel at a payout limit (``held``'s ``HELD_LIMIT_*``, set by
    ``actuate``) into the summary's ``winch_limit_time`` [s] and ``winch_limit`` (-1
    min_length, +1 max_length); both NaN when no limit was reached."""
    if held[HELD_LIMIT_WHICH] != 0.0:
        summary[SUMMARY_WINCH_LIMIT_TIME] = held[HELD_LIMIT_TIME]
        summary[SUMMARY_WINCH_LIMIT] = held[HELD_LIMIT_WHICH]
    else:
        summary[SUMMARY_WINCH_LIMIT_TIME] = np.nan
        summary[SUMMARY_WINCH_LIMIT] = np.nan


@_jit_inline
def accumulate(summary, x, x_ref, y, y_ref, tension):
    """One sample into the on-line metrics (``layout.SUMMARY_FIELDS``; their definitions:
    ``analysis``): peaks of |y - y_ref| (q1..q3) and |x - x_ref| (q4, q5), sums of squares of
    the position deviations, the tension range, the sample count."""
    for a in range(3):
        dev = y[a] - y_ref[a]
        if abs(dev) > summary[SUMMARY_PEAK_Q1 + a]:
            summary[SUMMARY_PEAK_Q1 + a] = abs(dev)
        summary[SUMMARY_SUMSQ_Q1 + a] += dev * dev
    if abs(x[0] - x_ref[0]) > summary[SUMMARY_PEAK_Q4]:
        summary[SUMMARY_PEAK_Q4] = abs(x[0] - x_ref[0])
    if abs(x[1] - x_ref[1]) > summary[SUMMARY_PEAK_Q5]:
        summary[SUMMARY_PEAK_Q5] = abs(x[1] - x_ref[1])
    if tension < summary[SUMMARY_TENSION_MIN]:
        summary[SUMMARY_TENSION_MIN] = tension
    if tension > summary[SUMMARY_TENSION_MAX]:
        summary[SUMMARY_TENSION_MAX] = tension
    summary[SUMMARY_N_SAMPLES] += 1.0


@_jit
def summarize(x, x_ref, y, y_ref, tension, first, summary):
    """The on-line metrics (``accumulate``) of recorded samples first, first + 1, ... of x
    (n, 13), y (n, 4) and tension (n,) into ``summary`` (``start_summary`` first): a recorded
    or loaded run measured as the engine measures it while it flies."""
    start_summary(summary)
    for k in range(first, x.shape[0]):
        accumulate(summary, x[k], x_ref, y[k], y_ref, tension[k])


# --- the phases of one control sample ----------------------------------------------------------


@_jit_inline
def apply_actuators(inp, held, act, dt, first):
    """Saturate the command, then pass it through the first-order lag (step-invariant at the
    sample rate: u_k = u_{k-1} + (1 - e^{-dt/tau}) (sat(cmd_k) - u_{k-1})); inp becomes the
    applied input and ``held[HELD_INPUTS:]`` keeps it for the next sample."""
    tau = act[ACT_TAU]
    gain = 1.0 if (first or tau <= 0.0) else 1.0 - math.exp(-dt / tau)
    for i in range(4):
        v = min(max(inp[i], act[ACT_U_MIN + i]), act[ACT_U_MAX + i])
        v = held[HELD_INPUTS + i] + gain * (v - held[HELD_INPUTS + i]) if not first else v
        held[HELD_INPUTS + i] = v
        inp[i] = v


@_jit_inline
def release_if_broken(tension, t, cfg, ctrl, act, event):
    """The safety device (Sec. IV-C): above act[ACT_BREAK] the tether is released, cfg and the
    paper controller's ctrl switch to the free configuration (no winch, no feed-forward) and
    the event is recorded, event[0] = t [s], event[1] = tension [N] (``event`` (2,) is left
    alone otherwise); returns the tension acting from now on [N]."""
    if tension > act[ACT_BREAK]:
        cfg[CFG_ATTACHED] = 0.0
        ctrl[CTRL_WINCH] = 0.0
        ctrl[CTRL_FFWD] = 0.0
        event[0] = t
        event[1] = tension
        return 0.0
    return tension


@_jit_inline
def winch_tension(cfg, tension):
    """The tension at the winch [N]: a lumped chain's ground end (set by ``chain_ends``) while
    attached, else ``tension``, the massless tether's one tension (eq 28) or 0 once released."""
    if cfg[CFG_LUMPED] > 0.5 and cfg[CFG_ATTACHED] > 0.5:
        return cfg[CFG_TENSION_GROUND]
    return tension


@_jit_inline
def sense(x, k, t, cfg, ctrl, act, sensors, event, x_meas):
    """Phase 1 of a sample at t = k dt: the tether's tension (0 when removed), the safety
    device's release check (``release_if_broken``; a lumped tether's tension at P, set in
    cfg by ``chain_ends``), then the sensors, whose load cell reads the tension at the winch
    (the lumped chain's ground end; eq 28's one tension otherwise): x_meas (13,) receives
    the measured state (``sensors.measure_sampled``: each sensor at its rate and latency,
    with the noise table's rows, or the true state when the table is empty); ``sensors`` is
    ``sim.setup.sensor_tuple``'s (noise, source code, arm, scratch, schedule, history ring).
    Returns (true tension at P, measured tension) [N]."""
    return _sense(x, k, t, cfg, ctrl, act, sensors, sensors[0].shape[0] > 0, event, x_meas)


@_jit_inline
def _sense(x, k, t, cfg, ctrl, act, sensors, sensed, event, x_meas):
    # ``sense`` with ``sensed`` (the noise table has rows) given by the caller
    attached = cfg[CFG_ATTACHED] > 0.5
    lumped = cfg[CFG_LUMPED] > 0.5
    if not attached:
        tension = 0.0
    elif lumped:  # the chain's ends at this sample (``chain_ends``)
        tension = cfg[CFG_TENSION_TOP]
    else:
        tension = tension_from_state(x[5], x[12], cfg[CFG_K_C])
    tension = release_if_broken(tension, t, cfg, ctrl, act, event)
    load = winch_tension(cfg, tension)  # the load cell at the winch
    if sensed:
        return tension, measure_sampled(x, load, k, sensors, x_meas)
    x_meas[:] = x
    return tension, load


@_jit_inline
def actuate(inp, held, rate, act, dt, first, tension_ground, measured_tension, length, t):
    """Phase 3: the actuators on a controller's command. Rotor inputs: saturation and lag
    (``apply_actuators``, in place). Reel rate, ideal winch: the acceleration limit relative
    to the rate applied at the previous sample (the paper's PI already keeps within it and
    holds its integral meanwhile: ``control.paper.winch_step``). Drum winch (act[ACT_DRUM]):
    the command is the drive's speed reference and the drum is advanced over the sample
    (``drum_winch``) under the tension at the winch, tension_ground [N] (the load cell reads
    measured_tension [N]). Then the payout limits (``winch_limits``) on the natural length
    ``length`` = x[12] [m] at the sample's time t [s]. Returns the reel rate applied over
    the sample [m/s]."""
    apply_actuators(inp, held, act, dt, first)
    if act[ACT_DRUM] > 0.5:
        rate = drum_winch(held, rate, act, dt, tension_ground, measured_tension)
    else:
        rate = limit_rate_change_jit(rate, held[HELD_REEL_RATE], act[ACT_REEL_ACCEL], dt)
    rate = winch_limits(held, rate, act, dt, length, t)
    held[HELD_REEL_RATE] = rate
    return rate


@_jit_inline
def winch_limits(held, rate, act, dt, length, t):
    """The payout limits ``[winch] min_length``, ``max_length`` (act[ACT_MIN_LENGTH],
    act[ACT_MAX_LENGTH]) on a reel rate [m/s] held over the sample [t, t + dt] from the
    natural length ``length`` [m]: a rate that would carry the length past a limit is cut to
    the one that reaches it at t + dt exactly (0 while the length sits at it), the length
    then holds there: a brake stops the reel (the drum winch's drum too: its speed is set to
    zero, the brake taking the tether's pull; a command back inside releases it). The first
    stop is recorded in ``held`` (``HELD_LIMIT_WHICH`` -1 min_length, +1 max_length, and
    ``HELD_LIMIT_TIME`` = t + dt [s], when the length reaches the limit); a run that reaches
    a limit is not failed by it. Returns the rate applied [m/s]."""
    which = 0.0
    end = length + rate * dt
    if end > act[ACT_MAX_LENGTH]:
        which = 1.0
        rate = (act[ACT_MAX_LENGTH] - length) / dt
    elif end < act[ACT_MIN_LENGTH]:
        which = -1.0
        rate = (act[ACT_MIN_LENGTH] - length) / dt
    if which != 0.0:
        if act[ACT_DRUM] > 0.5:
            held[HELD_DRUM_SPEED] = 0.0  # braked
        if held[HELD_LIMIT_WHICH] == 0.0:
            held[HELD_LIMIT_WHICH] = which
            held[HELD_LIMIT_TIME] = t + dt
    held[HELD_AT_LIMIT] = which
    return rate


@_jit_inline
def drum_winch(held, rate_cmd, act, dt, tension_ground, measured_tension):
    """The drum winch over one sample (``model.winch``): speed reference rate_cmd / r, the
    drive's feed-forward r T_meas (when act[ACT_DRUM_TENSION_FFWD]), the tether's pull r T_g
    with T_g = tension_ground held over the sample; the drum's speed in ``held`` is advanced by
    the exact piecewise solution (``model.winch.drum_step``) and ``held`` keeps the mean motor
    torque (hauling in). Returns the mean reel rate over the sample, r int w dt / dt [m/s], so
    that L_N advances exactly by the length paid out."""
    r = act[ACT_DRUM_RADIUS]
    ffwd = r * measured_tension if act[ACT_DRUM_TENSION_FFWD] > 0.5 else 0.0
    w0 = held[HELD_DRUM_SPEED]
    w1, speed_integral, torque_integral = drum_step(
        w0, rate_cmd / r, r * tension_ground, ffwd, dt, act[ACT_DRUM_INERTIA],
        act[ACT_DRUM_SPEED_GAIN], act[ACT_DRUM_TORQUE_LIMIT], act[ACT_DRUM_VISCOUS],
        act[ACT_DRUM_COULOMB],
    )  # fmt: skip
    held[HELD_DRUM_SPEED_SAMPLED] = w0
    held[HELD_DRUM_SPEED] = w1
    held[HELD_MOTOR_TORQUE] = torque_integral / dt
    return r * speed_integral / dt


@_jit_inline
def paper_sample(x, k, cfg, ctrl, act, sensors, c, law, loop, action, action_mode):
    """One control sample of the paper's scheme at t = k dt (Fig. 5): ``sense``, the LQI with
    feed-forward and the winch PI (``paper_law``), an optional ``action`` on the rotor inputs
    (``ACTION_*``), ``actuate``, and the failure checks of the sampled state
    (``sample_outputs``). ``law`` is (gain, x_ref, y_ref, u0, u0_free, z0) (``layout.LAW_*``):
    once the tether is released (or in the free configuration) the LQI works about the free
    trim's input u0_free; z0 is the integrators' start; ``loop`` the per-run arrays in the
    order of ``layout.LOOP_*`` (z, winch, held, event, x_meas, sc_meas, sc_true, y, y_est,
    inp, ffwd), updated in place: inp then holds the applied inputs, y the true outputs,
    sc_true sin and cos of the true angles. Returns (status, true tension [N], applied reel
    rate [m/s])."""
    gain, x_ref, y_ref, u0_tethered, u0_free, _z0 = law
    z, winch, held, event, x_meas, sc_meas, sc_true, y, y_est, inp, ffwd = loop
    return _paper_sample(
        x, k, cfg, ctrl, act, sensors, sensors[0].shape[0] > 0, c, gain, x_ref, y_ref,
        u0_tethered, u0_free, z, winch, held, event, x_meas, sc_meas, sc_true, y, y_est, inp,
        ffwd, action, action_mode,
    )  # fmt: skip


@_jit_inline
def _paper_sample(
    x, k, cfg, ctrl, act, sensors, sensed, c, gain, x_ref, y_ref, u0_tethered, u0_free, z,
    winch, held, event, x_meas, sc_meas, sc_true, y, y_est, inp, ffwd, action, action_mode,
):  # fmt: skip
    # ``paper_sample`` on the members of its tuples, unpacked by the caller. The compiled loop
    # unpacks them once per run: every array taken out of a tuple is a reference count
    # raised and dropped by an atomic instruction (issue 24; measured within noise, ~4 %)
    tension, measured = _sense(x, k, k * cfg[CFG_DT], cfg, ctrl, act, sensors, sensed, event,
                               x_meas)  # fmt: skip
    rate = paper_law(x_meas, sc_meas, measured, cfg, ctrl, c, gain, x_ref, y_ref, u0_tethered,
                     u0_free, z, winch, y_est, inp, ffwd, action, action_mode)  # fmt: skip
    status, rate = sample_apply(x, k, cfg, act, c, held, inp, rate, tension, measured, sensed,
                                y, y_est, sc_true, sc_meas, y_ref)  # fmt: skip
    return status, tension, rate


# --- the phases of one sample, shared by every loop (issue 24: one sample step) -------------
# A sample at t = k dt is: ``sample_sense`` (a lumped chain's ends, the release check, the
# sensors); the controller (the compiled ``paper_law``, or a command from Python:
# ``step_command``); ``sample_apply`` (actuators, true outputs, failure checks);
# ``sample_record`` (the on-line metrics and the recorded signals); then the integrator
# (``sample_advance``: RK4 or the lumped chain's coupled step; the adaptive reference swaps
# only this phase). ``run_closed_loop`` runs them around the paper's law; ``step_sense``,
# ``step_command`` and ``step_advance`` run them from Python around any ``Controller``.


@_jit_inline
def sample_sense(x, k, cfg, ctrl, act, sensors, sensed, event, x_meas, lumped, gust, chain, cw):
    """Phase 1 at t = k dt: a lumped chain's end tensions (``chain_ends``, while attached),
    then ``sense``. Returns (true tension at P, measured tension) [N]."""
    t = k * cfg[CFG_DT]
    if lumped and cfg[CFG_ATTACHED] > 0.5:
        chain_ends(x, t, cfg, gust, chain, cw)
    return _sense(x, k, t, cfg, ctrl, act, sensors, sensed, event, x_meas)


@_jit_inline
def paper_law(
    x_meas, sc_meas, measured, cfg, ctrl, c, gain, x_ref, y_ref, u0_tethered, u0_free, z,
    winch, y_est, inp, ffwd, action, action_mode,
):  # fmt: skip
    """Phase 2, the compiled controller: the paper's LQI with feed-forward and winch PI, or
    the tethered LQI (``control.paper.paper_control_sc``) on the measured state x_meas, about
    u0_tethered while the tether is attached and u0_free after (sc_meas receives sin, cos of
    x_meas's angles, y_est its outputs, inp the rotor command, ffwd the feed-forward), then an
    optional ``action`` added to or replacing the rotor command (``ACTION_*``). Returns the
    reel-rate command [m/s]."""
    u0 = u0_tethered if cfg[CFG_ATTACHED] > 0.5 else u0_free
    angle_trig(x_meas, sc_meas)
    rate = paper_control_sc(
        x_meas, sc_meas, measured, z, winch, ctrl, c, gain, x_ref, y_ref, u0, y_est, inp, ffwd
    )
    if action_mode == ACTION_ADD:
        for i in range(4):
            inp[i] += action[i]
    elif action_mode == ACTION_REPLACE:
        for i in range(4):
            inp[i] = action[i]
    return rate


@_jit_inline
def sample_outputs(x, c, sensed, y, y_est, sc_true, sc_meas, y_ref, tension, cfg):
    """The true outputs y and sin, cos of the true angles sc_true (copies of the estimate's
    when the sensors are perfect, x_meas = x), then the failure checks (``check_state_sc``);
    returns the status."""
    if sensed:
        tethered_outputs(x, c, y)
        angle_trig(x, sc_true)
    else:
        y[:] = y_est
        sc_true[:] = sc_meas
    return check_state_sc(x, sc_true, y, y_ref, tension, cfg)


@_jit_inline
def sample_apply(
    x, k, cfg, act, c, held, inp, rate, tension, measured, sensed, y, y_est, sc_true, sc_meas,
    y_ref,
):  # fmt: skip
    """Phase 3: ``actuate`` on the controller's command (inp, the reel rate ``rate``), then
    ``sample_outputs``. Returns (status, applied reel rate [m/s])."""
    dt = cfg[CFG_DT]
    rate = actuate(
        inp, held, rate, act, dt, k == 0, winch_tension(cfg, tension), measured, x[12], k * dt
    )
    return sample_outputs(x, c, sensed, y, y_est, sc_true, sc_meas, y_ref, tension, cfg), rate


@_jit_inline
def sample_record(
    k, cfg, act, summary, x, x_ref, y, y_ref, tension, rate, inp, ffwd, y_est, held, record,
    out, program, gust, drag, scratch, nodes,
):  # fmt: skip
    """Phase 4: the on-line metrics of the samples k >= cfg[CFG_METRICS_FROM] into
    ``summary`` (``accumulate``), and with ``record`` the sample's row of ``out``
    (``layout.Signals``); ``scratch`` (>= 3,) receives the wind force."""
    if k >= cfg[CFG_METRICS_FROM]:  # the metrics' window (Scenario.metrics_start)
        accumulate(summary, x, x_ref, y, y_ref, tension)
    if not record:
        return
    wind_force(program, gust, cfg[CFG_GUST_DT], drag, k * cfg[CFG_DT], 1, x[6], x[7], x[8],
               scratch)  # fmt: skip
    out.x[k] = x
    out.u[k] = inp
    out.ffwd[k] = ffwd
    out.rate[k] = rate
    out.tension[k] = tension
    out.wind[k] = scratch[:3]
    out.y[k] = y
    out.y_est[k] = y_est
    out.tension_ground[k] = winch_tension(cfg, tension)
    if out.nodes.shape[0] > 0:
        out.nodes[k] = nodes
    if act[ACT_DRUM] > 0.5:  # the drum's speed at t_k, its mean torque after t_k
        out.winch[k, 0] = held[HELD_DRUM_SPEED_SAMPLED]
        out.winch[k, 1] = held[HELD_MOTOR_TORQUE]


@_jit_inline
def sample_advance(x, inp, rate, k, cfg, c, program, gust, drag, work, chain, cw, lumped):
    """Phase 5, the fixed-step integrator over [k dt, (k + 1) dt]: a lumped chain's coupled
    step while attached (``lumped_interval``), else ``rk4_interval`` (sin, cos of x's angles
    already in work[6], ``sample_outputs``'s sc_true)."""
    t = k * cfg[CFG_DT]
    if lumped and cfg[CFG_ATTACHED] > 0.5:
        lumped_interval(x, inp, rate, t, cfg, c, program, gust, drag, work, chain, cw,
                        plain(COUPLING_CONDENSED))  # fmt: skip
    else:
        rk4_interval(x, inp, rate, t, cfg, c, program, gust, drag, work, plain(True))


@_jit_inline
def finish_summary(summary, event, held):
    """The run's release event and first payout limit into its summary."""
    summary[SUMMARY_RELEASE_TIME] = event[0]
    summary[SUMMARY_RELEASE_TENSION] = event[1]
    winch_limit_into(held, summary)


def new_loop_state(x_init: np.ndarray, z_init: np.ndarray, work: np.ndarray) -> tuple:
    """The per-run arrays of ``paper_sample`` (from Python; the compiled loop builds its own):
    integrators (starting at z_init, ``law[LAW_Z0]``), winch, held actuator state, release event
    (NaN: none), scratch."""
    return _loop_state(x_init, z_init, work)


@_jit_inline
def _loop_state(x_init, z_init, work):
    return LoopState(
        z_init.copy(),  # z: the LQI's output-error integral (eq 50), from sim.setup.start_point
        np.zeros(WINCH_SIZE),  # winch: layout.WINCH_* (the PI's integral, its last command)
        np.zeros(HELD_SIZE),  # held: layout.HELD_* (the winch starts at rest)
        np.full(2, np.nan),  # event: release time [s], tension [N]
        x_init.copy(),  # x_meas
        np.empty(10),  # sc_meas
        work[6, :10],  # sc_true: shared with rk4_interval's first stage
        np.empty(4),  # y
        np.empty(4),  # y_est
        np.empty(4),  # inputs
        np.empty(4),  # ffwd
    )


@_jit
def run_closed_loop(
    x_init,
    n_samples,
    cfg_in,
    ctrl_in,
    c,
    law,
    wind,
    act,
    sensors,
    chain,
    record,
    out,
    summary,
):
    """Run the closed loop for n_samples control samples; returns (status, samples done).

    Each sample is the phases above around ``paper_law``: ``sample_sense``, ``paper_law``,
    ``sample_apply``, ``sample_record``, ``sample_advance``; with a lumped tether (``chain``,
    ``layout.CHAIN_*``, nodes present) the chain's ends are set before the sample and
    ``lumped_interval`` advances helicopter and chain (``layout.empty_chain()``: the massless
    tether of eq 28). ``law`` is (gain, x_ref, y_ref, u0, u0_free, z0) (``layout.LAW_*``),
    ``wind`` (program, gust table, drag), ``sensors`` (``sim.setup.sensor_tuple``). With
    ``record`` the arrays of ``out`` (``layout.Signals``: x, u, ffwd, rate, tension, wind, y,
    y_est, tension_ground, nodes, winch), n_samples + 1 rows each, receive the sampled
    signals: true state, applied inputs (with feed-forward), feed-forward, reel rate, true
    tension (at P),
    wind force, true outputs, the controller's output estimate, the tension at the winch
    (equal to the tension for the massless tether), when its first axis is not empty the
    chain's node positions (n_samples + 1, N + 1, 3), and the drum winch's speed at the sample
    [rad/s] and mean motor torque over the sample after it [N m] (drum winch only; the ideal
    winch leaves it alone, one row is enough). ``summary`` (len(SUMMARY_FIELDS),) always
    receives the on-line metrics of the samples k >= cfg[CFG_METRICS_FROM], the release event
    in its ``release_*`` slots (NaN without one).
    """
    # The loop works on borrowed views (``_compile.borrowed``: no atomic reference counts):
    # of the arguments, which the caller holds, and of the run's own arrays, held below
    # (``keep_alive``) until the loop is done.
    own_cfg, own_ctrl, own_x = cfg_in.copy(), ctrl_in.copy(), x_init.copy()
    own_work = np.empty((RK4_WORK_ROWS, 13))
    own_loop = _loop_state(x_init, law[LAW_Z0], own_work)
    own_no_action = np.zeros(4)
    own_cw = _lumped_work(max(chain[CHAIN_NODES].shape[0] - 1, 1))
    cfg, ctrl, x, work, no_action = borrowed((own_cfg, own_ctrl, own_x, own_work, own_no_action))
    c, act, summary, sensors, chain, out, cw = borrowed(
        (c, act, summary, sensors, chain, out, own_cw)
    )
    program, gust, drag = borrowed(wind)
    # the tuples' arrays taken out once, before the loop (see ``_paper_sample``)
    gain, x_ref, y_ref, u0_tethered, u0_free, _z0 = borrowed(law)
    z, winch, held, event, x_meas, sc_meas, sc_true, y, y_est, inp, ffwd = borrowed(own_loop)
    sensed = sensors[0].shape[0] > 0
    start_summary(summary)
    status, done = STATUS_OK, n_samples + 1
    nodes = chain[CHAIN_NODES]
    lumped = nodes.shape[0] > 0
    for k in range(n_samples + 1):
        tension, measured = sample_sense(
            x, k, cfg, ctrl, act, sensors, sensed, event, x_meas, lumped, gust, chain, cw
        )
        rate = paper_law(
            x_meas, sc_meas, measured, cfg, ctrl, c, gain, x_ref, y_ref, u0_tethered, u0_free,
            z, winch, y_est, inp, ffwd, no_action, ACTION_NONE,
        )  # fmt: skip
        sample_status, rate = sample_apply(
            x, k, cfg, act, c, held, inp, rate, tension, measured, sensed, y, y_est, sc_true,
            sc_meas, y_ref,
        )  # fmt: skip
        if sample_status != STATUS_OK:
            status, done = sample_status, k
            break
        sample_record(
            k, cfg, act, summary, x, x_ref, y, y_ref, tension, rate, inp, ffwd, y_est, held,
            record, out, program, gust, drag, work[5], nodes,
        )  # fmt: skip
        if k == n_samples:
            break
        sample_advance(x, inp, rate, k, cfg, c, program, gust, drag, work, chain, cw, lumped)
    finish_summary(summary, event, held)
    keep_alive((own_cfg, own_ctrl, own_x, own_work, own_loop, own_no_action, own_cw))
    return status, done


# --- the same sample driven from Python, around any ``Controller`` ------------------------
# ``simulate``'s Python path (the MPC, a user's ``Controller``, the adaptive reference)
# holds a ``StepRun`` (``sim.setup.EngineSetup.step_run``) and calls, per sample,
# ``step_sense``, then the controller, then ``step_command``, then ``step_advance`` (or its
# own integrator): the phases above, compiled once, with the controller's slot in Python.


class StepRun(NamedTuple):
    """One run's arrays for the sample step driven from Python (``step_sense``,
    ``step_command``, ``step_advance``, ``step_finish``), built by
    ``sim.setup.EngineSetup.step_run``; a named record, so each step function has one
    compiled signature and reads its fields by name."""

    x: np.ndarray  #: (13,) the true state, advanced in place
    cfg: np.ndarray  #: ``layout.CFG_*``, a run's own copy (the release switches it)
    ctrl: np.ndarray  #: ``layout.CTRL_*``, a run's own copy
    c: np.ndarray  #: the model constants
    law: tuple  #: ``layout.LAW_*`` (x_ref and y_ref are the metrics' references)
    wind: tuple  #: (program, gust table, drag); an empty program for a Python disturbance
    act: np.ndarray  #: ``layout.ACT_*``
    sensors: tuple  #: ``sim.setup.sensor_tuple``
    chain: tuple  #: ``layout.CHAIN_*`` (``layout.empty_chain()``: massless)
    cw: tuple  #: the chain's scratch (``lumped_work``)
    work: np.ndarray  #: (RK4_WORK_ROWS, 13) the integrator's scratch
    loop: LoopState  #: the control phases' state (``new_loop_state``)
    summary: np.ndarray  #: (len(SUMMARY_FIELDS),) the on-line metrics (``start_summary``)
    out: Signals  #: the recorded signals


@_jit
def step_sense(run, k):
    """``sample_sense`` of sample k of a ``StepRun``: the measured state lands in
    ``run.loop.x_meas``; returns (true tension at P, measured tension) [N]."""
    return sample_sense(
        run.x, k, run.cfg, run.ctrl, run.act, run.sensors, run.sensors[0].shape[0] > 0,
        run.loop.event, run.loop.x_meas, run.chain[CHAIN_NODES].shape[0] > 0, run.wind[1],
        run.chain, run.cw,
    )  # fmt: skip


@_jit
def step_command(run, k, command, reel_rate, feedforward, tension, measured):
    """The controller's slot filled from Python, then ``sample_apply`` and ``sample_record``
    (always recording into ``run.out``) of sample k of a ``StepRun``. ``command`` (4,) are
    the rotor inputs, ``reel_rate`` the reel-rate command [m/s] (0 once the tether is
    released), ``feedforward`` (4,) the part of ``command`` that is feed-forward (recorded);
    ``tension``, ``measured`` are ``step_sense``'s. A non-finite command is not actuated and
    fails the sample (``Status.NONFINITE``). Returns (status, applied reel rate [m/s])."""
    loop = run.loop
    held, x_meas, sc_meas, sc_true, y, y_est = (
        loop.held,
        loop.x_meas,
        loop.sc_meas,
        loop.sc_true,
        loop.y,
        loop.y_est,
    )
    inp, ffwd = loop.inputs, loop.ffwd
    x, cfg, c = run.x, run.cfg, run.c
    program, gust, drag = run.wind
    sensed = run.sensors[0].shape[0] > 0
    if cfg[CFG_ATTACHED] <= 0.5:
        reel_rate = 0.0
    finite = math.isfinite(reel_rate)
    for i in range(4):
        inp[i] = command[i]
        ffwd[i] = feedforward[i]
        finite = finite and math.isfinite(command[i])
    angle_trig(x_meas, sc_meas)
    tethered_outputs_sc(x_meas, sc_meas, c, y_est)
    if finite:
        status, rate = sample_apply(
            x, k, cfg, run.act, c, held, inp, reel_rate, tension, measured, sensed, y, y_est,
            sc_true, sc_meas, run.law[LAW_Y_REF],
        )  # fmt: skip
    else:
        rate = reel_rate
        status = sample_outputs(x, c, sensed, y, y_est, sc_true, sc_meas, run.law[LAW_Y_REF],
                                tension, cfg)  # fmt: skip
        if status == STATUS_OK:
            status = STATUS_NONFINITE
    if status == STATUS_OK:
        sample_record(
            k, cfg, run.act, run.summary, x, run.law[LAW_X_REF], y, run.law[LAW_Y_REF],
            tension, rate, inp, ffwd, y_est, held, True, run.out, program, gust, drag,
            run.work[5], run.chain[CHAIN_NODES],
        )  # fmt: skip
    return status, rate


@_jit
def step_advance(run, k, rate):
    """``sample_advance`` of a ``StepRun`` from sample k to k + 1 with the applied reel rate
    ``rate`` (``step_command``'s) and the applied inputs it left in ``run.loop``."""
    program, gust, drag = run.wind
    sample_advance(run.x, run.loop.inputs, rate, k, run.cfg, run.c, program, gust, drag,
                   run.work, run.chain, run.cw, run.chain[CHAIN_NODES].shape[0] > 0)  # fmt: skip


@_jit
def step_finish(run):
    """``finish_summary`` of a ``StepRun``: the release event and the first payout limit."""
    finish_summary(run.summary, run.loop.event, run.loop.held)


# --- the lumped-mass tether (issue 13; ``model.tether_lumped``) --------------------------------
# A lumped run carries its chain (``layout.CHAIN_*``: node positions and velocities, the
# packed tether, the ROS2 scratch) next to the helicopter's state x; x[12] is the chain's
# unstretched length L0 (the winch pays out by re-discretising it uniformly, as ``ros2_step``
# does), q7..q9 only locate P, and eq 28's tension is replaced by the chain's force at P.
# The wind on the nodes is the gust table's air (the helicopter's drag uses the same);
# force-only wind profiles act on the helicopter alone.

#: coupling of the helicopter's RK4 step and the chain's ROS2 step (``lumped_interval``)
COUPLING_STAGGERED = 0
COUPLING_CONDENSED = 1


def lumped_work(segments: int) -> tuple:
    """The scratch of ``chain_ends`` and ``lumped_interval`` for a chain of ``segments``
    segments (allocate once per run).

    Parameters
    ----------
    segments : int
        Number of segments N.

    Returns
    -------
    tuple of numpy.ndarray
        Node forces, segment tensions, the segment Jacobian blocks (K, C, D), the air at the
        nodes, the force at P, the stage loads and P's motion, the condensed K and C,
        the top interior node's velocity and acceleration.
    """
    return _lumped_work(segments)


@_jit
def _lumped_work(n):
    return (
        np.empty((n + 1, 3)),  # 0 F: node forces
        np.empty(n),  # 1 T: segment tensions
        np.empty((n, 3, 3)),  # 2 K
        np.empty((n, 3, 3)),  # 3 C
        np.empty((n, 3, 3)),  # 4 D
        np.zeros((n + 1, 3)),  # 5 air at the nodes
        np.zeros(3),  # 6 force on P at the step's start
        np.empty(4),  # 7 the stage's equivalent rotor inputs
        np.empty(3),  # 8 the stage's equivalent wind force
        np.empty(6),  # 9 P's position and velocity at a stage
        np.empty(3),  # 10 the stage's force on P
        np.empty(3),  # 11 the stage's wind force on HO
        np.empty(6),  # 12 P's position and velocity at the step's start
        np.zeros(9),  # 13 stiffness seen from P (3 x 3, row-major)
        np.zeros(9),  # 14 damping seen from P
        np.zeros(3),  # 15 the top interior node's velocity at the step's start
        np.zeros(3),  # 16 the top interior node's acceleration at the step's start
    )


@_jit_inline
def p_motion(x, sc, arm, out):
    """out (6,) = the position of P from the winch NO [m] and its velocity [m/s] in N:
    P = q9 c3 (eqs 43-45; c3 = [s8, -s7 c8, c7 c8]) and v_P = v_HO + w x (arm f3) with
    v_HO = (u1, u2, u3) in N and w = (u4, u5, u6) in F: w x arm f3 = arm (u5 f1 - u4 f2).
    sc (10,) the sin, cos of x[0..4] (f1, f2 from Table I's columns)."""
    s4, s5, s6, s7, s8 = sc[0], sc[1], sc[2], sc[3], sc[4]
    c4, c5, c6, c7, c8 = sc[5], sc[6], sc[7], sc[8], sc[9]
    q9 = x[5]
    out[0] = q9 * s8
    out[1] = -q9 * s7 * c8
    out[2] = q9 * c7 * c8
    a4 = -arm * x[9]
    a5 = arm * x[10]
    out[3] = x[6] + a5 * (c5 * c6) + a4 * (-c5 * s6)
    out[4] = x[7] + a5 * (s5 * c6 * s4 + s6 * c4) + a4 * (c6 * c4 - s5 * s6 * s4)
    out[5] = x[8] + a5 * (s6 * s4 - c6 * s5 * c4) + a4 * (s5 * s6 * c4 + c6 * s4)


@_jit_inline
def lumped_loads(sc, inp, wind, force_P, arm, inp_out, wind_out):
    """``tether_lumped.force_at_P_as_loads`` with the sin, cos sc (10,) of the stage given:
    a force F [N, in N] at P = HO + arm f3 enters the generated equations as wind + F and the
    rotor torques tMR1 - arm F.f2, tMR2 + arm F.f1 (f1, f2 from Table I's columns)."""
    s4, s5, s6 = sc[0], sc[1], sc[2]
    c4, c5, c6 = sc[5], sc[6], sc[7]
    f1 = (
        force_P[0] * (c5 * c6)
        + force_P[1] * (s5 * c6 * s4 + s6 * c4)
        + force_P[2] * (s6 * s4 - c6 * s5 * c4)
    )
    f2 = (
        force_P[0] * (-c5 * s6)
        + force_P[1] * (c6 * c4 - s5 * s6 * s4)
        + force_P[2] * (s5 * s6 * c4 + c6 * s4)
    )
    for j in range(3):
        wind_out[j] = wind[j] + force_P[j]
    inp_out[0] = inp[0]
    inp_out[1] = inp[1] - arm * f2
    inp_out[2] = inp[2] + arm * f1
    inp_out[3] = inp[3]


@_jit_inline
def _node_air(gust, gust_dt, t, air):
    """The gust table's air velocity at t [m/s] on every node (uniform field)."""
    g1, g2, g3 = gust_velocity(gust, gust_dt, t)
    for i in range(air.shape[0]):
        air[i, 0] = g1
        air[i, 1] = g2
        air[i, 2] = g3


@_jit
def chain_ends(x, t, cfg, gust, chain, cw):
    """The chain's top node put on P (``p_motion``), its forces at t in the gust table's air
    (``tether_lumped.chain_forces``, with the Jacobian blocks), and the ends' tensions into
    cfg: CFG_TENSION_TOP = |force on P|, CFG_TENSION_GROUND = |force on the winch| (each end
    force includes half an end segment's weight and drag, so the two differ by the cable's
    weight in a still hang). cw = ``lumped_work(N)``; cw[6] receives the force on P [N]."""
    nodes, vel, p = chain[CHAIN_NODES], chain[CHAIN_VELOCITIES], chain[CHAIN_PARAMS]
    F, T, K, C, D, air, force_P = cw[0], cw[1], cw[2], cw[3], cw[4], cw[5], cw[6]
    pm = cw[9]
    sc = np.empty(10)
    angle_trig(x, sc)
    p_motion(x, sc, cfg[CFG_ARM], pm)
    n = nodes.shape[0] - 1
    for j in range(3):
        nodes[n, j] = pm[j]
        vel[n, j] = pm[3 + j]
    _node_air(gust, cfg[CFG_GUST_DT], t, air)
    chain_forces(nodes, vel, air, x[12], p, F, T, K, C, D, plain(True))
    for j in range(3):
        force_P[j] = F[n, j]
    cfg[CFG_TENSION_TOP] = math.sqrt(F[n, 0] ** 2 + F[n, 1] ** 2 + F[n, 2] ** 2)
    cfg[CFG_TENSION_GROUND] = math.sqrt(F[0, 0] ** 2 + F[0, 1] ** 2 + F[0, 2] ** 2)


@_jit_inline
def _lumped_stage(xs, sc, inp, reel_rate, t, tau, side, cfg, c, program, gust, drag, cw, out):
    """dx/dt (13,) of the helicopter at a stage state xs (sin, cos sc) at t, tau [s] into
    the step, pulled at P by the chain: the step-start force cw[6] minus (condensed coupling)
    the top segment's stiffness cw[13] times its stretch since the step's start (P's motion
    less the top interior node's, moving on from its start velocity cw[15] at its start
    acceleration cw[16]) and its damping cw[14]
    times P's change of velocity (cw[12]: P at the step's start)."""
    force_P, inp2, wind2, pm, fp, wind = cw[6], cw[7], cw[8], cw[9], cw[10], cw[11]
    pm0, kc, cc, v_top, a_top = cw[12], cw[13], cw[14], cw[15], cw[16]
    wind_force(program, gust, cfg[CFG_GUST_DT], drag, t, side, xs[6], xs[7], xs[8], wind)
    p_motion(xs, sc, cfg[CFG_ARM], pm)
    for a in range(3):
        fp[a] = force_P[a]
        for b in range(3):
            stretch = pm[b] - pm0[b] - (v_top[b] + 0.5 * a_top[b] * tau) * tau
            fp[a] -= kc[3 * a + b] * stretch + cc[3 * a + b] * (pm[3 + b] - pm0[3 + b])
    lumped_loads(sc, inp, wind, fp, cfg[CFG_ARM], inp2, wind2)
    tethered_rhs_sc(xs, sc, inp2, wind2, 0.0, c, out)
    out[12] = reel_rate


@_jit
def lumped_interval(x, inp, reel_rate, t0, cfg, c, program, gust, drag, work, chain, cw,
                    coupling):  # fmt: skip
    """Advance the helicopter x and its lumped chain over one control sample [t0, t0 + dt]:
    per substep h = dt / n_sub (n_sub the scenario's substeps, or more by the coupled step's
    rule ``tether_lumped.coupling_substeps``: h omega_max <= 2.5), ``chain_ends`` (the force
    on P at the step's start), one RK4 step of the helicopter under that force, then the
    chain's step
    (``tether_lumped.chain_interval``: ROS2 sub-steps of the chain's step-size rule, issue 23)
    with its top driven to P's new position and velocity and L0 = x[12] held at the step's
    start value.

    ``coupling`` COUPLING_STAGGERED holds the force on P over the RK4 step;
    COUPLING_CONDENSED corrects it within the stages by the top segment's stiffness and
    damping seen from P (its Jacobian blocks at the step's start, the interior nodes held),
    F_P = F_P0 - K_top (r_P - r_P0 - v_(N-1) tau - a_(N-1) tau^2 / 2) - (C_top + D_top / 4)
    (v_P - v_P0), tau the time into the step and v_(N-1), a_(N-1) = F_(N-1) / m the top
    interior node's velocity and acceleration at its start (issue 23: the acceleration term
    halved the 20 kN cable's energy drift at 4 substeps, 0.84 % to 0.46 %): the force
    follows P's motion relative to the chain inside the step, and the helicopter's RK4 sees
    the top segment's stiffness (stable while h sqrt(EA / (l0 m)) stays within RK4's bound:
    0.2 for 20 kN, N = 10, h = 5 ms). Why: against SciPy's Radau on the joint helicopter +
    chain ODE (rtol 1e-9; 2 s open loop, 10 N on HO, dt = 10 ms, 2 substeps) the staggered
    step, first order in the force's change, is 5.3-5.8e-4 m off on P's position, the
    condensed one 4.8-5.3e-5 m, for EA = 375 N (N = 10, 20) and 20 kN (N = 10) alike; the
    nodes' 5.5-6.0e-4 m is ROS2's own error (``tests/test_engine_lumped.py``,
    ``benchmarks/bench_engine_lumped.py --coupling``). The full Schur complement of the
    chain's implicit step was not needed. The engine runs COUPLING_CONDENSED.

    Parameters
    ----------
    x : ndarray, shape (13,)
        The helicopter's state, x[12] the unstretched length L0 [m]; advanced in place.
    inp, reel_rate, t0, cfg, c, program, gust, drag, work
        As ``rk4_interval``'s.
    chain : tuple
        ``layout.CHAIN_*``: the chain, advanced in place.
    cw : tuple
        ``lumped_work(N)``.
    coupling : int
        COUPLING_STAGGERED or COUPLING_CONDENSED.

    Returns
    -------
    None
    """
    nodes, vel, p, rwork = (
        chain[CHAIN_NODES],
        chain[CHAIN_VELOCITIES],
        chain[CHAIN_PARAMS],
        chain[CHAIN_WORK],
    )
    F, K, C, D, air = cw[0], cw[2], cw[3], cw[4], cw[5]
    pm, pm0, kc, cc = cw[9], cw[12], cw[13], cw[14]
    n = nodes.shape[0] - 1
    n_sub = coupling_substeps(p, x[12], n, cfg[CFG_DT], int(cfg[CFG_N_SUB]))
    h = cfg[CFG_DT] / n_sub
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    sc0, sc = work[6, :10], work[7, :10]
    rate = reel_rate if cfg[CFG_ATTACHED] > 0.5 else 0.0
    for j in range(n_sub):
        ta = t0 + j * h
        tb = t0 + (j + 1) * h
        tm = ta + 0.5 * h
        L0 = x[12]
        chain_ends(x, ta, cfg, gust, chain, cw)  # also puts nodes[n] on P(x)
        v_top, a_top = cw[15], cw[16]
        m_node = p[LUMPED_MU] * L0 / n
        for a in range(3):
            pm0[a] = nodes[n, a]
            pm0[3 + a] = vel[n, a]
            v_top[a] = vel[n - 1, a]
            a_top[a] = F[n - 1, a] / m_node
            for b in range(3):
                if coupling == COUPLING_CONDENSED:
                    kc[3 * a + b] = K[n - 1, a, b]
                    cc[3 * a + b] = C[n - 1, a, b] + 0.25 * D[n - 1, a, b]
                else:
                    kc[3 * a + b] = 0.0
                    cc[3 * a + b] = 0.0
        angle_trig(x, sc0)
        _lumped_stage(x, sc0, inp, rate, ta, 0.0, 1, cfg, c, program, gust, drag, cw, k1)
        for i in range(13):
            tmp[i] = x[i] + 0.5 * h * k1[i]
        angle_trig_from(tmp, x, sc0, sc)
        _lumped_stage(tmp, sc, inp, rate, tm, 0.5 * h, 1, cfg, c, program, gust, drag, cw, k2)
        for i in range(13):
            tmp[i] = x[i] + 0.5 * h * k2[i]
        angle_trig_from(tmp, x, sc0, sc)
        _lumped_stage(tmp, sc, inp, rate, tm, 0.5 * h, 1, cfg, c, program, gust, drag, cw, k3)
        for i in range(13):
            tmp[i] = x[i] + h * k3[i]
        angle_trig_from(tmp, x, sc0, sc)
        _lumped_stage(tmp, sc, inp, rate, tb, h, -1, cfg, c, program, gust, drag, cw, k4)
        for i in range(13):
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        angle_trig(x, sc0)
        p_motion(x, sc0, cfg[CFG_ARM], pm)
        chain_interval(nodes, vel, air, L0, p, h, pm[:3], pm[3:], rwork)


# --- the lane engine: a block of LANES runs advanced together ----------------------------------
# Lane arrays are flat, element (variable i, lane j) at i * LANES + j (``layout.LANES``, a
# constant of the compiled code): the loops over j below have no branch and no call, and the
# compiler, knowing every offset, vectorises them.


@_jit_inline
def _lanes_program_force(programs, n_rows, t, side, out):
    """out (3 LANES,) = the profiles' force of every lane at its time t (LANES,): the lanes'
    programs are flat (row, column, lane), element at (r WIND_COLUMNS + column) LANES + j,
    padded with zero rows (``setup.lane_block``); the sum runs over rows in the order of
    ``_wind_program_force``."""
    for i in range(out.shape[0]):
        out[i] = 0.0
    n_lanes = t.shape[0]  # = LANES, read at run time: the loop stays a loop and vectorises
    for r in range(n_rows):
        base = r * WIND_COLUMNS * LANES
        any_sine = False  # loop-invariant below: the compiler makes a loop with, one without
        for j in range(n_lanes):
            any_sine |= programs[base + WIND_KIND * LANES + j] == WIND_SINE
        for j in range(n_lanes):
            value = profile_value(
                programs[base + WIND_KIND * LANES + j],
                programs[base + WIND_START * LANES + j],
                programs[base + WIND_DURATION * LANES + j],
                programs[base + WIND_MAGNITUDE * LANES + j],
                programs[base + WIND_FREQUENCY * LANES + j],
                programs[base + WIND_PHASE * LANES + j],
                t[j],
                side,
                any_sine,
            )
            for a in range(3):
                out[a * LANES + j] += value * programs[base + (WIND_DIRECTION + a) * LANES + j]


@_jit_inline
def _lanes_stage(xs, sc, inp, rate, attached, k_c, c, program_force, gust_air, drag, force, out):
    """out (13 LANES,) = dx/dt of every lane at the stage state xs: the wind force of
    ``wind_force`` (profiles plus bluff-body drag), the tension (eq 28: zero when slack or
    released), eqs 10-12, 29-35 (``tethered_rhs_lanes``) and dLN/dt = RC (eq 37). ``force``
    (4 LANES,) receives the wind force and the tension."""
    for j in range(rate.shape[0]):  # LANES, read at run time (see ``_lanes_axpy``)
        r1 = gust_air[j] - xs[6 * LANES + j]
        r2 = gust_air[LANES + j] - xs[7 * LANES + j]
        r3 = gust_air[2 * LANES + j] - xs[8 * LANES + j]
        speed = math.sqrt(r1 * r1 + r2 * r2 + r3 * r3)
        force[j] = program_force[j] + drag[j] * speed * r1
        force[LANES + j] = program_force[LANES + j] + drag[LANES + j] * speed * r2
        force[2 * LANES + j] = program_force[2 * LANES + j] + drag[2 * LANES + j] * speed * r3
        stretch = xs[5 * LANES + j] - xs[12 * LANES + j]
        tied = attached[j] > 0.5
        force[3 * LANES + j] = k_c[j] * stretch if (tied and stretch > 0.0) else 0.0
        out[12 * LANES + j] = rate[j] if tied else 0.0
    tethered_rhs_lanes(xs, sc, inp, force, force[3 * LANES :], c, out)


@_jit_inline
def _lanes_axpy(out, x, a, h, k):
    """out = x + (a h_j) k over (13, lane) (an RK4 stage's state). The lane loops of the lane
    engine take their trip count LANES from an array's length at run time: with a constant
    count the compiler unrolls a short loop into scalar code instead of vectorising it."""
    n_lanes = h.shape[0]
    for i in range(13):
        for j in range(n_lanes):
            out[i * LANES + j] = x[i * LANES + j] + a * h[j] * k[i * LANES + j]


@_jit_inline
def lane_work():
    """The scratch arrays of ``rk4_lanes`` (k1..k4, stage state, its sin/cos, wind force and
    tension, profile forces, gust air, stage times), for the lane engine and the vector env."""
    return (
        np.empty(13 * LANES),  # k1
        np.empty(13 * LANES),  # k2
        np.empty(13 * LANES),  # k3
        np.empty(13 * LANES),  # k4
        np.empty(13 * LANES),  # the stage state
        np.empty(10 * LANES),  # its sin and cos
        np.empty(4 * LANES),  # the wind force and tension of a stage
        np.empty(9 * LANES),  # the profiles' force at the step's start, middle, end
        np.empty(9 * LANES),  # the gust air velocity at the same times
        np.empty(3 * LANES),  # the three times
    )


@_jit_inline
def _thirds(a):
    """The three equal consecutive parts of a (views)."""
    n = a.shape[0] // 3
    return a[:n], a[n : 2 * n], a[2 * n :]


@_jit
def rk4_lanes(x, sc0, inp, rate, t0, h, n_sub, attached, k_c, c, wind, work):
    """``rk4_interval`` for a block of LANES runs: advance every lane j of x (13 LANES,) over
    its control sample [t0_j, t0_j + n_sub h_j] by n_sub RK4 steps of h_j.

    Flat (variable, lane) arrays: sc0 (10 LANES,) sin, cos of the angles of x on entry
    (overwritten), inp (4 LANES,) the held rotor inputs, c (n_c LANES,) the model constants;
    rate, t0, h, attached (1/0), k_c (LANES,). wind = (programs (R WIND_COLUMNS LANES,), R,
    gusts (LANES, G, 3), gust rows in use (LANES,), gust_dt (LANES,), drag (3 LANES,));
    work = ``lane_work()``. The gust tables are read per lane; everything else runs in
    branch-free passes over the lanes. Each lane performs the operations of ``rk4_interval``
    in the same order, so it equals a single run bit for bit.
    """
    programs, n_rows, gusts, gust_rows, gust_dt, drag = wind
    k1, k2, k3, k4, tmp, sc, force, program_force, gust_air, times = work
    pf_a, pf_m, pf_b = _thirds(program_force)
    ga_a, ga_m, ga_b = _thirds(gust_air)
    ta, tm, tb = _thirds(times)
    n_lanes = h.shape[0]
    for step in range(n_sub):
        for j in range(n_lanes):
            ta[j] = t0[j] + step * h[j]
            tb[j] = t0[j] + (step + 1) * h[j]
            tm[j] = ta[j] + 0.5 * h[j]
        _lanes_program_force(programs, n_rows, ta, 1, pf_a)
        _lanes_program_force(programs, n_rows, tm, 1, pf_m)
        _lanes_program_force(programs, n_rows, tb, -1, pf_b)
        for j in range(LANES):
            gust = gusts[j, : gust_rows[j]]
            for t, air in ((ta[j], ga_a), (tm[j], ga_m), (tb[j], ga_b)):
                air[j], air[LANES + j], air[2 * LANES + j] = gust_velocity(gust, gust_dt[j], t)
        _lanes_stage(x, sc0, inp, rate, attached, k_c, c, pf_a, ga_a, drag, force, k1)
        _lanes_axpy(tmp, x, 0.5, h, k1)
        angle_trig_from_lanes(tmp, x, sc0, sc)
        _lanes_stage(tmp, sc, inp, rate, attached, k_c, c, pf_m, ga_m, drag, force, k2)
        _lanes_axpy(tmp, x, 0.5, h, k2)
        angle_trig_from_lanes(tmp, x, sc0, sc)
        _lanes_stage(tmp, sc, inp, rate, attached, k_c, c, pf_m, ga_m, drag, force, k3)
        _lanes_axpy(tmp, x, 1.0, h, k3)
        angle_trig_from_lanes(tmp, x, sc0, sc)
        _lanes_stage(tmp, sc, inp, rate, attached, k_c, c, pf_b, ga_b, drag, force, k4)
        for i in range(x.shape[0]):
            tmp[i] = x[i]  # the step's start, for the next step's trigonometry
        for i in range(13):
            for j in range(n_lanes):
                e = i * LANES + j
                x[e] += h[j] / 6.0 * (k1[e] + 2.0 * k2[e] + 2.0 * k3[e] + k4[e])
        if step + 1 < n_sub:
            if (step + 1) % TRIG_CHAIN_STEPS == 0:
                for i in range(5):
                    for j in range(LANES):
                        a = x[i * LANES + j]
                        sc0[i * LANES + j] = math.sin(a)
                        sc0[(5 + i) * LANES + j] = math.cos(a)
            else:
                angle_trig_from_lanes(x, tmp, sc0, sc)
                for i in range(sc0.shape[0]):
                    sc0[i] = sc[i]


@_jit_inline
def set_lane(lane_in, j, x_j, sc_j, inp_j, rate_j, t0_j, attached_j):
    """Lane j of ``rk4_lanes``'s inputs lane_in = (x, sc0, inp, rate, t0, attached) from one
    run's state x_j (13,), sin/cos of its angles sc_j (10,), held inputs inp_j (4,), reel
    rate, sample start [s] and tether state."""
    x, sc0, inp, rate, t0, attached = lane_in
    for i in range(13):
        x[i * LANES + j] = x_j[i]
    for i in range(10):
        sc0[i * LANES + j] = sc_j[i]
    for i in range(4):
        inp[i * LANES + j] = inp_j[i]
    rate[j] = rate_j
    t0[j] = t0_j
    attached[j] = attached_j


@_jit_inline
def park_lane(lane_in, j, x_park, sc_park, u_park):
    """Lane j of ``rk4_lanes``'s inputs set to a hover (x_park, its sin/cos sc_park, trim
    inputs u_park) with no tether: a lane that runs nothing keeps finite, cheap arithmetic and
    its result is not used."""
    set_lane(lane_in, j, x_park, sc_park, u_park, 0.0, 0.0, 0.0)


@_jit
def run_lanes(
    x_init, n_samples, cfg_in, ctrl_in, c, law, wind, act, sensors, summary, status, done
):
    """Run a block of LANES closed loops together (unrecorded); lane j for n_samples[j]
    samples, none where n_samples[j] < 0 (padding).

    The arguments of ``run_closed_loop`` with a leading lane axis of length LANES, packed by
    ``setup.lane_block``: x_init (LANES, 13), cfg_in, ctrl_in, c (LANES, n_c), law (each part
    of ``layout.LAW_*`` with the lane axis in front), act, sensors = (noise (LANES, N,
    N_CHANNELS), noise rows in use (LANES,), source codes, arms, scratch (LANES, 4, 3),
    schedules (LANES, S, N_GROUPS) int, their rows in use, history rings (LANES, H,
    N_CHANNELS), their rows in use) (``sim.setup.sensor_tuple`` per lane);
    wind = (programs flat (R WIND_COLUMNS LANES,), R, gusts (LANES, G, 3), gust rows in use,
    drag (LANES, 3)).
    summary (LANES, len(SUMMARY_FIELDS)), status and done (LANES,) receive each lane's on-line
    metrics, status and samples done, as ``run_closed_loop`` returns them for a single run.
    Lanes may differ in every number but the RK4 steps per sample (cfg[:, CFG_N_SUB]).

    Each sample runs ``paper_sample`` per lane (sensors, controller, actuators, checks: the
    very function of a single run), then ``rk4_lanes`` advances all lanes at once. Massless
    tethers only: runs with a lumped tether go through ``run_closed_loop`` (``run_batch``).
    A lane that fails or completes is frozen with its result and parked at its initial state
    while the others go on.
    """
    cfg = cfg_in.copy()
    ctrl = ctrl_in.copy()
    gain, x_ref, y_ref, u0, u0_free, z0 = law
    programs, n_rows, gusts, gust_rows, drag = wind
    noise, noise_rows, source, arm, sensor_scratch, schedule, schedule_rows, ring, ring_rows = (
        sensors
    )
    n_sub = int(cfg[0, CFG_N_SUB])
    for j in range(LANES):
        if int(cfg[j, CFG_N_SUB]) != n_sub:
            raise ValueError("run_lanes: every lane must take the same RK4 steps per sample")
    x = np.empty(13 * LANES)  # the lanes' states, flat (variable, lane)
    c_lanes = np.empty(c.shape[1] * LANES)
    drag_lanes = np.empty(3 * LANES)
    for j in range(LANES):
        for i in range(13):
            x[i * LANES + j] = x_init[j, i]
        for i in range(c.shape[1]):
            c_lanes[i * LANES + j] = c[j, i]
        for i in range(3):
            drag_lanes[i * LANES + j] = drag[j, i]
    gust_dt = np.empty(LANES)
    lane_wind = (programs, n_rows, gusts, gust_rows, gust_dt, drag_lanes)
    work = lane_work()
    sc0 = np.empty(10 * LANES)
    held_inp = np.empty(4 * LANES)
    rate = np.zeros(LANES)
    t0 = np.zeros(LANES)
    h = np.empty(LANES)
    attached = np.empty(LANES)
    k_c = np.empty(LANES)
    sc_init = np.empty((LANES, 10))
    x_lane = x_init.copy()  # each lane's state for its control phases
    # the per-lane loop state, in the order of layout.LOOP_*
    z = z0.copy()
    winch = np.zeros((LANES, WINCH_SIZE))
    held = np.zeros((LANES, HELD_SIZE))
    event = np.full((LANES, 2), np.nan)
    x_meas = x_init.copy()
    sc_meas = np.empty((LANES, 10))
    sc_true = np.empty((LANES, 10))
    y = np.empty((LANES, 4))
    y_est = np.empty((LANES, 4))
    inp = np.empty((LANES, 4))
    ffwd = np.empty((LANES, 4))
    no_action = np.zeros(4)
    active = np.zeros(LANES, np.bool_)
    # borrowed views (``_compile.borrowed``) of the run's arrays, held to the end by
    # ``keep_alive``, and of the arguments: the lane loop slices rows of them per lane and
    # sample, which would otherwise each be an atomic reference count
    own = (cfg, ctrl, x, c_lanes, drag_lanes, gust_dt, work, sc0, held_inp, rate, t0, h,
           attached, k_c, sc_init, x_lane, z, winch, held, event, x_meas, sc_meas, sc_true, y,
           y_est, inp, ffwd, no_action, active)  # fmt: skip
    (cfg, ctrl, x, c_lanes, drag_lanes, gust_dt, work, sc0, held_inp, rate, t0, h, attached, k_c,
     sc_init, x_lane, z, winch, held, event, x_meas, sc_meas, sc_true, y, y_est, inp, ffwd,
     no_action, active) = borrowed(own)  # fmt: skip
    x_init, c, act, summary, status, done = borrowed((x_init, c, act, summary, status, done))
    gain, x_ref, y_ref, u0, u0_free, z0 = borrowed((gain, x_ref, y_ref, u0, u0_free, z0))
    programs, n_rows, gusts, gust_rows = borrowed((programs, n_rows, gusts, gust_rows))
    noise, noise_rows, source, arm, sensor_scratch, schedule, schedule_rows, ring, ring_rows = (
        borrowed(sensors)
    )
    lane_wind = (programs, n_rows, gusts, gust_rows, gust_dt, drag_lanes)
    n_active = 0
    for j in range(LANES):
        start_summary(summary[j])
        status[j] = STATUS_OK
        done[j] = max(n_samples[j] + 1, 0)
        angle_trig(x_init[j], sc_init[j])
        h[j] = cfg[j, CFG_DT] / n_sub
        k_c[j] = cfg[j, CFG_K_C]
        gust_dt[j] = cfg[j, CFG_GUST_DT]
        if n_samples[j] >= 0:
            active[j] = True
            n_active += 1
    k = plain(0)  # an int64 from the start (a literal 0 would compile callees twice)
    while n_active > 0:
        for j in range(LANES):
            if active[j]:
                xj = x_lane[j]
                for i in range(13):
                    xj[i] = x[i * LANES + j]
                loop = (
                    z[j], winch[j], held[j], event[j], x_meas[j], sc_meas[j], sc_true[j],
                    y[j], y_est[j], inp[j], ffwd[j],
                )  # fmt: skip
                lane_sensors = (
                    noise[j, : noise_rows[j]], source[j], arm[j], sensor_scratch[j],
                    schedule[j, : schedule_rows[j]], ring[j, : ring_rows[j]],
                )  # fmt: skip
                lane_law = (gain[j], x_ref[j], y_ref[j], u0[j], u0_free[j], z0[j])
                sample_status, tension, rate_j = paper_sample(
                    xj, k, cfg[j], ctrl[j], act[j], lane_sensors, c[j], lane_law, loop,
                    no_action, ACTION_NONE,
                )  # fmt: skip
                if sample_status != STATUS_OK:
                    status[j], done[j] = sample_status, k
                    active[j] = False
                    n_active -= 1
                else:
                    if k >= cfg[j, CFG_METRICS_FROM]:  # the metrics' window
                        accumulate(summary[j], xj, x_ref[j], y[j], y_ref[j], tension)
                    if k == n_samples[j]:
                        active[j] = False
                        n_active -= 1
                    else:
                        lane_in = (x, sc0, held_inp, rate, t0, attached)
                        set_lane(lane_in, j, xj, sc_true[j], inp[j], rate_j, k * cfg[j, CFG_DT],
                                 cfg[j, CFG_ATTACHED])  # fmt: skip
                        continue
            # a finished or padding lane is parked at its initial state (finite arithmetic)
            park_lane((x, sc0, held_inp, rate, t0, attached), j, x_init[j], sc_init[j], u0[j])
        if n_active == 0:
            break
        rk4_lanes(x, sc0, held_inp, rate, t0, h, n_sub, attached, k_c, c_lanes, lane_wind, work)
        k += 1
    for j in range(LANES):
        summary[j, SUMMARY_RELEASE_TIME] = event[j, 0]
        summary[j, SUMMARY_RELEASE_TENSION] = event[j, 1]
        winch_limit_into(held[j], summary[j])
    keep_alive(own)
