"""The compiled closed-loop engine (Numba): one control sample step for every controller.

One control sample is written once, as phases that every loop shares: ``sample_sense`` (a
lumped chain's ends, the safety device's release check, the sensors), the controller's slot
(the compiled ``paper_law``, or a command from Python), ``sample_apply`` (saturation, lag,
the winch's acceleration limit or drum, the true outputs and the failure checks),
``sample_record`` (the on-line metrics and the recorded row), then ``sample_advance`` (the
integrator to the next sample). ``run_closed_loop`` runs them around the paper's law;
``engine.stepping``'s ``step_sense`` and ``step_command`` run them from Python around any
``Controller`` (``simulate``'s MPC, a user's controller, the adaptive reference, which swaps
only the integrator); the Gymnasium environments and the lanes (``engine.lanes``) run
``paper_sample``.

Inputs are held over a sample (zero-order hold); between samples the plant is integrated by
fixed-step RK4 with ``n_substeps`` steps. Wind discontinuities (pulse and step edges) placed on
integration-step boundaries are handled exactly: an RK4 step over [ta, tb] evaluates the wind
(``wind.evaluate``) at ta as the right limit and at tb as the left limit, i.e. it integrates the
force on the open interval (ta, tb).

A lumped-mass tether (``[tether] model = "lumped"``) rides the same loop
(``engine.lumped_step``): ``chain_ends`` sets its end tensions before the sample and
``lumped_interval`` replaces ``rk4_interval``.

The phases take named records (``layout.Run``: the run's constants; ``layout.LoopState``:
the control phases' state; ``layout.Scratch``; ``layout.Signals`` and the summary: the
recording), built once per run on borrowed views (``_compile.borrowed``); a phase body
compiled once takes the run's read-only view (``read_only_run``, ``control_run``). The
plant is the vehicle slot's (``vehicle_derivative``, ``vehicle_outputs``, on
``cfg[CFG_VEHICLE]``), with the landing gear's contact with the deck when the run's
``layout.Gear`` (``Run.gear``) has points (``model.contact.gear_rhs_sc``). The packed
arrays (``cfg``, ``ctrl``, ``act``, ``held``, the wind program, the summary, the chain) and
the state's slots (``X_*``) are laid out in ``tetherheli.layout``; run statuses are
``tetherheli.status.Status``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._compile import borrowed, compiled, frozen, inline_here, keep_alive, plain
from ..control.paper import paper_control_sc, reel_command
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
    ACT_SIZE,
    ACT_TAU,
    ACT_U_MAX,
    ACT_U_MIN,
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
    CFG_TETHER_EA,
    CFG_VEHICLE,
    CHAIN_NODES,
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
    LAW_GAIN,
    LAW_U0,
    LAW_U0_FREE,
    LAW_X_REF,
    LAW_Y_REF,
    LAW_Z0,
    SC_COS,
    SUMMARY_FIELDS,
    VEHICLE_HELICOPTER,
    WINCH_SIZE,
    WIND_COLUMNS,
    X_LN,
    X_Q4,
    X_Q5,
    X_Q7,
    X_Q8,
    X_Q9,
    X_U1,
    LoopState,
    Run,
    Scratch,
    WindPack,
    default_actuators,
    no_gear,
)
from ..model.contact import gear_rhs_sc
from ..model.kernels import (
    angle_trig,
    angle_trig_from,
    tether_tension,
    tethered_outputs_sc,
    tethered_rhs_sc,
)
from ..sensing.sensors import measure_sampled
from ..status import Status, release_sentence, status_message
from ..tether.winch import drum_step
from ..wind.evaluate import air_force_on_base, base_frame_force
from .lumped_step import (
    COUPLING_CONDENSED,
    _lumped_work,
    chain_ends,
    lumped_interval,
)
from .summary import (
    accumulate,
    finish_summary,
    start_summary,
)

__all__ = [
    "ACT_SIZE",
    "CFG_SIZE",
    "CLOSED_LOOPS",
    "HELD_SIZE",
    "SUMMARY_FIELDS",
    "WIND_COLUMNS",
    "actuate",
    "check_state",
    "closed_loop_for",
    "default_actuators",
    "paper_sample",
    "release_sentence",
    "rk4_interval",
    "run_closed_loop",
    "sense",
    "status_message",
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
def plant_derivative(x, sc, inp, reel_rate, t, side, cfg, vehicle, wind, out):
    """dx/dt (13,) of the vehicle's plant (``vehicle_derivative``) at t under the wind force
    of ``wind`` (``layout.WindPack``; over a moving base with the frame's inertial force:
    ``base_frame_force``); tension 0 when the tether is removed.

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m] (``layout.X_*``).
    sc : numpy.ndarray, shape (10,)
        sin and cos of the angles x[0..4] (``kernels.angle_trig``, ``layout.SC_*``).
    inp : numpy.ndarray, shape (4,)
        The rotor inputs held over the sample [N, N m, N m, N].
    reel_rate : float
        The reel rate dLN/dt [m/s] (ignored when the tether is removed).
    t : float
        The time [s].
    side : int
        The side of a wind discontinuity at t: 1 the right limit, -1 the left limit.
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``), the vehicle among them.
    vehicle : tuple
        (c, gear): the vehicle's model constants (``kernels.model_constants("tethered",
        h)``) and its landing gear (``layout.Gear``; ``layout.no_gear()``: none).
    wind : WindPack
        The wind program, gust table, drag and base motion (``layout.WindPack``).
    out : numpy.ndarray, shape (13,)
        Receives dx/dt.
    """
    c, gear = vehicle
    force = np.empty(3)
    base_frame_force(wind.program, wind.gust, cfg[CFG_GUST_DT], wind.drag, wind.base, t, side,
                     (x[X_U1], x[X_U1 + 1], x[X_U1 + 2]), force)  # fmt: skip
    vehicle_derivative(x, sc, inp, reel_rate, cfg, c, force, out, gear)


# --- the vehicle slot: the plant's derivative and outputs, by ``cfg[CFG_VEHICLE]`` ------------
# The engine flies the vehicle ``cfg[CFG_VEHICLE]`` names (``layout.VEHICLES``). Its
# derivative and its outputs are these two functions' and nothing else of the loop's: a
# second vehicle (the multirotor's ``multirotor_derivative(p, s, cmd, wind, f_p, out)``)
# enters as one more branch of each, its constants in ``c``, with no change to the loop.


@_jit_inline
def vehicle_derivative(x, sc, inp, reel_rate, cfg, c, force, out, gear):
    """dx/dt (13,) of the vehicle ``cfg[CFG_VEHICLE]`` under the air's force ``force`` (3,)
    [N]: the paper's helicopter, the generated tethered model (``kernels.tethered_rhs_sc``),
    with the tether's tension of eq 28 (0 when removed), the reel rate as dLN/dt and, when
    ``gear`` has points, the landing gear's contact with the deck (``contact.gear_rhs_sc``:
    the loads as equivalent inputs and wind force, in scratch; ``inp`` is not modified). A
    vehicle whose kernel the slot does not hold (``layout.VEHICLES_FLOWN``) gets NaN (the
    sample then fails as non-finite).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    sc : numpy.ndarray, shape (10,)
        sin and cos of the angles (``layout.SC_*``).
    inp : numpy.ndarray, shape (4,)
        The vehicle's inputs held over the sample [N, N m, N m, N].
    reel_rate : float
        The reel rate dLN/dt [m/s] (ignored when the tether is removed).
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``): the vehicle, the tether's.
    c : numpy.ndarray
        The vehicle's model constants.
    force : numpy.ndarray, shape (3,)
        The air's force on the vehicle [N] in N.
    out : numpy.ndarray, shape (13,)
        Receives dx/dt.
    gear : Gear
        The landing gear (``layout.Gear``; ``layout.no_gear()``: none).
    """
    if cfg[CFG_VEHICLE] == VEHICLE_HELICOPTER:
        # one inlined copy of the generated right-hand side for both configurations (a
        # removed tether is tension 0: the same arithmetic as a constant 0 would compile to)
        attached = cfg[CFG_ATTACHED] > 0.5
        tension = (
            tether_tension(x[X_Q9], x[X_LN], cfg[CFG_K_C], cfg[CFG_TETHER_EA]) if attached else 0.0
        )
        if gear.points.shape[0] > 0:  # a call (its own copy of the model's right-hand side)
            gear_rhs_sc(x, sc, inp, force, tension, c, gear, out)
        else:
            tethered_rhs_sc(x, sc, inp, force, tension, c, out)
        out[X_LN] = reel_rate if attached else 0.0
    else:  # the multirotor's slot (``layout.VEHICLE_MULTIROTOR``), not flown yet
        for i in range(out.shape[0]):
            out[i] = math.nan


@_jit_inline
def vehicle_outputs(x, sc, cfg, c, y):
    """The outputs y (4,) of the vehicle ``cfg[CFG_VEHICLE]`` at x: HO's position q1, q2,
    q3 [m] and the yaw q6 [rad] (``kernels.tethered_outputs_sc`` for the helicopter; NaN for
    a vehicle the slot does not hold).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The state (``layout.X_*``).
    sc : numpy.ndarray, shape (10,)
        sin and cos of the angles (``layout.SC_*``).
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings: the vehicle.
    c : numpy.ndarray
        The vehicle's model constants.
    y : numpy.ndarray, shape (4,)
        Receives the outputs [m, m, m, rad].
    """
    if cfg[CFG_VEHICLE] == VEHICLE_HELICOPTER:
        tethered_outputs_sc(x, sc, c, y)
    else:
        for i in range(y.shape[0]):
            y[i] = math.nan


#: sin/cos of the step-start angles are chained by angle addition for at most this many
#: RK4 steps, then taken afresh (``angle_trig``; bounds the rounding drift to a few ulp)
TRIG_CHAIN_STEPS = 4


@_jit_inline
def next_step_trig(x, start, sc0, sc, steps_done):
    """sc0 (10,) becomes sin, cos of the angles of x, the start of the next RK4 step: afresh
    (``angle_trig``) every TRIG_CHAIN_STEPS steps, otherwise by angle addition from the
    previous step's start ``start`` whose values sc0 holds (``sc`` is scratch).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The state at the start of the next RK4 step [rad, m, rad/s, m/s, m].
    start : numpy.ndarray, shape (13,)
        The state at the start of the previous step.
    sc0 : numpy.ndarray, shape (10,)
        sin, cos of ``start``'s angles on entry; receives those of x's.
    sc : numpy.ndarray, shape (10,)
        Scratch.
    steps_done : int
        The RK4 steps of the sample taken so far.
    """
    if steps_done % TRIG_CHAIN_STEPS == 0:
        angle_trig(x, sc0)
    else:
        angle_trig_from(x, start, sc0, sc)
        for i in range(10):
            sc0[i] = sc[i]


@_jit
def rk4_interval(x, inp, reel_rate, t0, cfg, c, wind, work, trig_given, gear):
    """Advance x in place over one control sample [t0, t0 + dt] with n_sub RK4 steps.

    ``work`` (RK4_WORK_ROWS, 13) is scratch. sin and cos of the angles come from
    ``angle_trig`` at the sample's start (with ``trig_given`` they are already in work[6, :10],
    ``kernels.angle_trig(x)``) and every TRIG_CHAIN_STEPS steps; everywhere else (the RK4
    stages, the next step's start) by the angle-addition formulas
    (``kernels.angle_trig_from``), which agree with libm to a few units in the last place.
    Without a gust table the wind depends on t only, so the two mid-step stages share it.
    Over a moving ``base`` (``base.compiled``) x is relative to it and the force is
    ``base_frame_force``'s.

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m] at t0; advanced in place to
        t0 + dt.
    inp : numpy.ndarray, shape (4,)
        The rotor inputs held over the sample [N, N m, N m, N].
    reel_rate : float
        The reel rate held over the sample [m/s].
    t0 : float
        The sample's start time [s].
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``): dt, n_sub, the tether's.
    c : numpy.ndarray
        The vehicle's model constants (``kernels.model_constants("tethered", h)``).
    wind : WindPack
        The wind program, gust table, drag and base motion (``layout.WindPack``).
    work : numpy.ndarray, shape (RK4_WORK_ROWS, 13)
        Scratch; work[6, :10] holds sin, cos of x's angles when ``trig_given``.
    trig_given : bool
        Whether work[6, :10] already holds sin, cos of x's angles.
    gear : Gear
        The landing gear (``layout.Gear``; ``layout.no_gear()``: none).
    """
    n_sub = int(cfg[CFG_N_SUB])
    h = cfg[CFG_DT] / n_sub
    # borrowed views (``_compile.borrowed``; the caller holds the arrays): the stages below
    # pick their arrays at run time, with no reference counts
    x, work, gear = borrowed((x, work, gear))
    k1, k2, k3, k4, tmp, force = work[0], work[1], work[2], work[3], work[4], work[5]
    sc0, sc = work[6], work[7]
    program, gust, drag, base = wind.program, wind.gust, wind.drag, wind.base
    n = x.shape[0]
    gdt = cfg[CFG_GUST_DT]
    gusty = gdt > 0.0 and gust.shape[0] > 0
    if not trig_given:
        angle_trig(x, sc0)
    for j in range(n_sub):
        ta = t0 + j * h
        tb = t0 + (j + 1) * h
        tm = ta + 0.5 * h
        # the four stages as one loop: one inlined copy of the wind and the plant (four
        # copies took most of a first run's compilation of this function)
        for stage in range(4):
            if stage == 0:
                xs, scs, ts, side = x, sc0, ta, 1
            else:
                a = h if stage == 3 else 0.5 * h
                kp = work[stage - 1]
                for i in range(n):
                    tmp[i] = x[i] + a * kp[i]
                angle_trig_from(tmp, x, sc0, sc)
                xs, scs = tmp, sc
                ts, side = (tb, -1) if stage == 3 else (tm, 1)
            # without a gust table the wind depends on t only: the third stage keeps the
            # second's (with one, the drag depends on the stage's velocity)
            if stage != 2 or gusty:
                base_frame_force(program, gust, gdt, drag, base, ts, side,
                                 (xs[X_U1], xs[X_U1 + 1], xs[X_U1 + 2]), force)  # fmt: skip
            vehicle_derivative(xs, scs, inp, reel_rate, cfg, c, force, work[stage], gear)
        for i in range(n):
            tmp[i] = x[i]  # the step's start, for the next step's trigonometry
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        if j + 1 < n_sub:
            next_step_trig(x, tmp, sc0, sc, j + 1)


@_jit
def check_state(x, y, y_ref, tension, cfg):
    """Status of a sampled state (``Status``).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The sampled state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    y, y_ref : numpy.ndarray, shape (4,)
        The outputs q1, q2, q3, q6 and their references [m, m, m, rad].
    tension : float
        The tether's tension [N].
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``): attached, the limits ``CFG_MAX_*``.

    Returns
    -------
    int
        The status code (``Status``; ``Status.OK``: none of the checks failed).
    """
    sc = np.empty(10)
    angle_trig(x, sc)
    return check_state_sc(x, sc, y, y_ref, tension, cfg)


@_jit_inline
def check_state_sc(x, sc, y, y_ref, tension, cfg):
    """``check_state`` with sc = sin, cos of x[0..4] given (``kernels.angle_trig``).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The sampled state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    sc : numpy.ndarray, shape (10,)
        sin and cos of x[0..4].
    y, y_ref : numpy.ndarray, shape (4,)
        The outputs q1, q2, q3, q6 and their references [m, m, m, rad].
    tension : float
        The tether's tension [N].
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``): attached, the limits ``CFG_MAX_*``.

    Returns
    -------
    int
        The status code (``Status``).
    """
    finite = True
    for i in range(x.shape[0]):
        finite &= math.isfinite(x[i])
    return state_status(
        finite, cfg[CFG_ATTACHED] > 0.5, (x[X_Q4], x[X_Q5], x[X_Q7], x[X_Q8]), x[X_Q9],
        x[X_LN], (sc[SC_COS + 1], sc[SC_COS + 3], sc[SC_COS + 4]),
        (y[0] - y_ref[0], y[1] - y_ref[1], y[2] - y_ref[2]), y[2], tension,
        (cfg[CFG_MAX_TENSION], cfg[CFG_MAX_ANGLE], cfg[CFG_MAX_DEVIATION]),
    )  # fmt: skip


@_jit_inline
def state_status(finite, attached, angles, q9, length, cosines, deviations, height, tension,
                 limits):  # fmt: skip
    """The status of a sampled state (``Status``), in order of precedence, from its scalars
    (tuples of floats, unpacked at no cost): whether every state is finite, the tether
    attached, the angles, q9 and the natural length LN, the cosines, the outputs' deviations
    from their references, HO's height y3, the tension and the limits (``cfg``'s
    ``CFG_MAX_*``). The one rule of ``check_state_sc`` and the lane engine's checks.

    Parameters
    ----------
    finite : bool
        Whether every state is finite.
    attached : bool
        Whether the tether is attached.
    angles : tuple of float
        (q4, q5, q7, q8): roll, pitch and the tether's angles [rad].
    q9 : float
        The tether's length (HO's distance from the winch) [m].
    length : float
        The tether's natural length LN [m].
    cosines : tuple of float
        (cos q5, cos q7, cos q8).
    deviations : tuple of float
        The deviations of the outputs y1, y2, y3 from their references [m].
    height : float
        HO's height y3 [m].
    tension : float
        The tether's tension [N].
    limits : tuple of float
        (max_tension [N], max_angle [rad], max_deviation [m]): the largest tension, the
        largest |q4|, |q5|, |q7|, |q8| and the largest output deviation allowed
        (cfg[CFG_MAX_TENSION], cfg[CFG_MAX_ANGLE], cfg[CFG_MAX_DEVIATION]).

    Returns
    -------
    int
        The status code (``Status``), the first check failed in order of precedence.
    """
    q4, q5, q7, q8 = angles
    cos_q5, cos_q7, cos_q8 = cosines
    dev1, dev2, dev3 = deviations
    max_tension, max_angle, max_deviation = limits
    if not finite:
        return STATUS_NONFINITE
    # an attached tether's natural (unstretched) length LN <= 0 is no physical tether
    if attached and length <= 0.0:
        return STATUS_TETHER_LENGTH
    # HO below the ground, or the attachment point P touching it (z_P = q9 c7 c8 < 1 cm,
    # which also covers the spherical singularities q9 -> 0 and |q8| -> 90 deg near ground)
    if height < 0.0 or q9 * cos_q7 * cos_q8 < 0.01:
        return STATUS_GROUND
    if q9 <= 0.0 or abs(cos_q5) < 1e-9 or abs(cos_q8) < 1e-9:
        return STATUS_SINGULAR
    if tension > max_tension:
        return STATUS_MAX_TENSION
    a = max_angle
    if abs(q4) > a or abs(q5) > a or abs(q7) > a or abs(q8) > a:
        return STATUS_DIVERGED
    d = max_deviation
    if abs(dev1) > d or abs(dev2) > d or abs(dev3) > d:
        return STATUS_DIVERGED
    return STATUS_OK


@_jit_inline
def copy_into(dst, src):
    """dst[:] = src for 1-d arrays of src's length, as a plain loop: an array assignment's
    broadcasting, shape checks and their error messages are compiled anew at every one in a
    first run, lengthening its compilation.

    Parameters
    ----------
    dst : numpy.ndarray, shape (n,) or longer
        Receives src's values.
    src : numpy.ndarray, shape (n,)
        The values to copy.
    """
    for i in range(src.shape[0]):
        dst[i] = src[i]


# --- the phases of one control sample ----------------------------------------------------------


@_jit_inline
def apply_actuators(inp, held, act, dt, first):
    """Saturate the command, then pass it through the first-order lag (step-invariant at the
    sample rate: u_k = u_{k-1} + (1 - e^{-dt/tau}) (sat(cmd_k) - u_{k-1})); inp becomes the
    applied input and ``held[HELD_INPUTS:]`` keeps it for the next sample.

    Parameters
    ----------
    inp : numpy.ndarray, shape (4,)
        The rotor command [N, N m, N m, N]; receives the applied inputs.
    held : numpy.ndarray, shape (HELD_SIZE,)
        What the actuators hold between samples (``layout.HELD_*``); the inputs are updated.
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``): the input limits and the lag's time constant.
    dt : float
        The sample time [s].
    first : bool
        Whether this is the run's first sample (no lag: the saturated command is applied).
    """
    gain = actuator_lag_gain(act[ACT_TAU], dt)
    for i in range(4):
        v = actuator_value(
            inp[i], held[HELD_INPUTS + i], act[ACT_U_MIN + i], act[ACT_U_MAX + i], gain, first
        )
        held[HELD_INPUTS + i] = v
        inp[i] = v


@_jit_inline
def actuator_lag_gain(tau, dt):
    """The actuators' lag over one sample, 1 - e^{-dt/tau} (1: no lag, tau <= 0).

    Parameters
    ----------
    tau : float
        The actuators' time constant [s] (<= 0: no lag).
    dt : float
        The sample time [s].

    Returns
    -------
    float
        The lag's gain over one sample, in (0, 1].
    """
    return 1.0 if tau <= 0.0 else 1.0 - math.exp(-dt / tau)


@_jit_inline
def actuator_value(command, previous, u_min, u_max, gain, first):
    """One rotor input applied over the sample: the command saturated to [u_min, u_max],
    then lagged from the previous sample's input by ``gain`` (``actuator_lag_gain``; the
    first sample applies the saturated command).

    Parameters
    ----------
    command : float
        The commanded input [N or N m].
    previous : float
        The input applied over the previous sample [N or N m].
    u_min, u_max : float
        The input's limits [N or N m].
    gain : float
        The lag's gain over the sample (``actuator_lag_gain``).
    first : bool
        Whether this is the run's first sample.

    Returns
    -------
    float
        The input applied over the sample [N or N m].
    """
    v = min(max(command, u_min), u_max)
    return v if first else previous + gain * (v - previous)


@_jit_inline
def release_if_broken(tension, t, cfg, ctrl, act, event):
    """The safety device (Sec. IV-C): above act[ACT_BREAK] the tether is released, cfg and the
    paper controller's ctrl switch to the free configuration (no winch, no feed-forward) and
    the event is recorded, event[0] = t [s], event[1] = tension [N] (``event`` (2,) is left
    alone otherwise); returns the tension acting from now on [N].

    Parameters
    ----------
    tension : float
        The tether's tension at P [N].
    t : float
        The sample's time [s].
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``); CFG_ATTACHED cleared on a release.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The paper controller's settings (``layout.CTRL_*``); winch and feed-forward switched
        off on a release.
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``): the breaking tension act[ACT_BREAK] [N].
    event : numpy.ndarray, shape (2,)
        Receives the release's time [s] and tension [N].

    Returns
    -------
    float
        The tension acting from now on [N]: ``tension``, or 0 once released.
    """
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
    attached, else ``tension``, the massless tether's one tension (eq 28) or 0 once released.

    Parameters
    ----------
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``): attached, lumped, the chain's ground tension.
    tension : float
        The tension at P [N] (0 once released).

    Returns
    -------
    float
        The tension at the winch [N].
    """
    if cfg[CFG_LUMPED] > 0.5 and cfg[CFG_ATTACHED] > 0.5:
        return cfg[CFG_TENSION_GROUND]
    return tension


@_jit_inline
def sense(run, x, k, t, sensed, event, x_meas):
    """Phase 1 of a sample at t = k dt: the tether's tension (0 when removed), the safety
    device's release check (``release_if_broken``; a lumped tether's tension at P, set in
    cfg by ``chain_ends``), then the sensors, whose load cell reads the tension at the winch
    (the lumped chain's ground end; eq 28's one tension otherwise): x_meas (13,) receives
    the measured state (``sensors.measure_sampled``: each sensor at its rate and latency,
    with the noise table's rows, or the true state when ``sensed`` is False). Returns (true
    tension at P, measured tension) [N].

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``); a release changes its cfg and ctrl.
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    k : int
        The control sample's index.
    t : float
        The sample's time k dt [s].
    sensed : bool
        Whether the noise table has rows (``run.sensors[0]``; else the sensors are perfect).
    event : numpy.ndarray, shape (2,)
        Receives a release's time [s] and tension [N].
    x_meas : numpy.ndarray, shape (13,)
        Receives the measured state.

    Returns
    -------
    tuple of float
        (the true tension at P, the load cell's measured tension) [N].
    """
    cfg = run.cfg
    attached = cfg[CFG_ATTACHED] > 0.5
    lumped = cfg[CFG_LUMPED] > 0.5
    if not attached:
        tension = 0.0
    elif lumped:  # the chain's ends at this sample (``chain_ends``)
        tension = cfg[CFG_TENSION_TOP]
    else:
        tension = tether_tension(x[X_Q9], x[X_LN], cfg[CFG_K_C], cfg[CFG_TETHER_EA])
    tension = release_if_broken(tension, t, cfg, run.ctrl, run.act, event)
    load = winch_tension(cfg, tension)  # the load cell at the winch
    if sensed:
        return tension, measure_sampled(x, load, k, run.sensors, x_meas)
    copy_into(x_meas, x)
    return tension, load


@_jit_inline
def actuate(inp, held, rate, act, dt, first, tensions, length, t, drum):
    """Phase 3: the actuators on a controller's command. Rotor inputs: saturation and lag
    (``apply_actuators``, in place). Reel rate, ideal winch: the acceleration limit relative
    to the rate applied at the previous sample (the paper's PI already keeps within it and
    holds its integral meanwhile: ``control.paper.winch_step``), after the rate limit
    ``[actuators] reel_rate_limit`` (``clamp_reel_rate``: every controller's command, its
    feed-forward included, passes here last). Drum winch (``drum``, True
    when act[ACT_DRUM]; a constant of a specialised caller prunes the other winch's code):
    the command is the drive's speed reference and the drum is advanced over the sample
    (``drum_winch``) under the tension at the winch (the load cell reads the measured
    tension). Then the payout limits (``winch_limits``) on the natural length
    ``length`` = x[X_LN] [m] at the sample's time t [s]. Returns the reel rate applied over
    the sample [m/s].

    Parameters
    ----------
    inp : numpy.ndarray, shape (4,)
        The rotor command [N, N m, N m, N]; receives the applied inputs.
    held : numpy.ndarray, shape (HELD_SIZE,)
        What the actuators hold between samples (``layout.HELD_*``), updated.
    rate : float
        The reel-rate command [m/s].
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``).
    dt : float
        The sample time [s].
    first : bool
        Whether this is the run's first sample.
    tensions : tuple of float
        (the tension at the winch, the load cell's reading) [N].
    length : float
        The natural length LN = x[X_LN] [m].
    t : float
        The sample's time [s].
    drum : bool
        Whether the run has a drum winch (act[ACT_DRUM]).

    Returns
    -------
    float
        The reel rate applied over the sample [m/s].
    """
    tension_ground, measured_tension = tensions
    apply_actuators(inp, held, act, dt, first)
    if drum:
        speed_reference = clamp_reel_rate(rate, act)
        rate = drum_winch(held, speed_reference, act, dt, tension_ground, measured_tension)
    else:
        rate = reel_command(rate, held[HELD_REEL_RATE], act[ACT_REEL_RATE], act[ACT_REEL_ACCEL], dt)
    rate = winch_limits(held, rate, act, dt, length, t)
    held[HELD_REEL_RATE] = rate
    return rate


@_jit_inline
def clamp_reel_rate(rate, act):
    """A reel-rate command [m/s] clamped to ``[actuators] reel_rate_limit``
    (act[ACT_REEL_RATE]): the actuator stage's rate limit, for both winch models (the drum's
    speed reference).

    Parameters
    ----------
    rate : float
        The reel-rate command [m/s].
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``): the rate limit act[ACT_REEL_RATE] [m/s].

    Returns
    -------
    float
        The clamped reel rate [m/s].
    """
    limit = act[ACT_REEL_RATE]
    return min(max(rate, -limit), limit)


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
    a limit is not failed by it. Returns the rate applied [m/s].

    Parameters
    ----------
    held : numpy.ndarray, shape (HELD_SIZE,)
        What the actuators hold between samples (``layout.HELD_*``): the limit's slots, and the
        drum's speed, updated.
    rate : float
        The reel rate [m/s].
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``): the payout limits [m], the winch model.
    dt : float
        The sample time [s].
    length : float
        The natural length LN at t [m].
    t : float
        The sample's time [s].

    Returns
    -------
    float
        The reel rate applied [m/s].
    """
    rate, which = payout_limited_rate(rate, length, dt, act[ACT_MIN_LENGTH], act[ACT_MAX_LENGTH])
    if which != 0.0:
        if act[ACT_DRUM] > 0.5:
            held[HELD_DRUM_SPEED] = 0.0  # braked
        if held[HELD_LIMIT_WHICH] == 0.0:
            held[HELD_LIMIT_WHICH] = which
            held[HELD_LIMIT_TIME] = t + dt
    held[HELD_AT_LIMIT] = which
    return rate


@_jit_inline
def payout_limited_rate(rate, length, dt, min_length, max_length):
    """(rate, which): a reel rate [m/s] held over dt [s] from the natural length ``length``
    [m] cut to the one that reaches ``max_length`` or ``min_length`` at the sample's end
    exactly (``winch_limits``); which = +1 at max_length, -1 at min_length, else 0.

    Parameters
    ----------
    rate : float
        The reel rate [m/s].
    length : float
        The natural length at the sample's start [m].
    dt : float
        The sample time [s].
    min_length, max_length : float
        The payout limits [m].

    Returns
    -------
    rate : float
        The reel rate applied [m/s].
    which : float
        +1 at max_length, -1 at min_length, 0 within the limits.
    """
    end = length + rate * dt
    if end > max_length:
        return (max_length - length) / dt, 1.0
    if end < min_length:
        return (min_length - length) / dt, -1.0
    return rate, 0.0


@_jit_inline
def drum_winch(held, rate_cmd, act, dt, tension_ground, measured_tension):
    """The drum winch over one sample (``model.winch``): speed reference rate_cmd / r, the
    drive's feed-forward r T_meas (when act[ACT_DRUM_TENSION_FFWD]), the tether's pull r T_g
    with T_g = tension_ground held over the sample; the drum's speed in ``held`` is advanced by
    the exact piecewise solution (``model.winch.drum_step``) and ``held`` keeps the mean motor
    torque (hauling in). Returns the mean reel rate over the sample, r int w dt / dt [m/s], so
    that L_N advances exactly by the length paid out. The drum's step is a call
    (``_drum_step``), not inlined: only a drum winch takes it, and one compiled copy shortens
    a first run's compilation.

    Parameters
    ----------
    held : numpy.ndarray, shape (HELD_SIZE,)
        What the actuators hold between samples (``layout.HELD_*``): the drum's speed [rad/s]
        and mean motor torque [N m], updated.
    rate_cmd : float
        The reel-rate command, the drive's speed reference times r [m/s].
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``): the drum's ``ACT_DRUM_*``.
    dt : float
        The sample time [s].
    tension_ground : float
        The tension at the winch [N], held over the sample.
    measured_tension : float
        The load cell's reading [N] (the drive's feed-forward).

    Returns
    -------
    float
        The mean reel rate over the sample [m/s].
    """
    r = act[ACT_DRUM_RADIUS]
    ffwd = r * measured_tension if act[ACT_DRUM_TENSION_FFWD] > 0.5 else 0.0
    w0 = held[HELD_DRUM_SPEED]
    w1, speed_integral, torque_integral = _drum_step(
        w0, rate_cmd / r, r * tension_ground, ffwd, dt, act[ACT_DRUM_INERTIA],
        act[ACT_DRUM_SPEED_GAIN], act[ACT_DRUM_TORQUE_LIMIT], act[ACT_DRUM_VISCOUS],
        act[ACT_DRUM_COULOMB],
    )  # fmt: skip
    held[HELD_DRUM_SPEED_SAMPLED] = w0
    held[HELD_DRUM_SPEED] = w1
    held[HELD_MOTOR_TORQUE] = torque_integral / dt
    return r * speed_integral / dt


@_jit_inline
def paper_sample(run, loop, x, k, action, action_mode):
    """One control sample of the paper's scheme at t = k dt (Fig. 5): ``sense``, the LQI with
    feed-forward and the winch PI (``paper_law``), an optional ``action`` on the rotor inputs
    (``ACTION_*``), ``actuate``, and the failure checks of the sampled state
    (``sample_outputs``). Once the tether is released (or in the free configuration) the
    LQI works about the free trim's input (``layout.LAW_U0_FREE``); ``loop`` (``LoopState``)
    is updated in place: its inputs then hold the applied inputs, y the true outputs,
    sc_true sin and cos of the true angles. Returns (status, true tension [N], applied reel
    rate [m/s]).

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``).
    loop : LoopState
        The per-run arrays (``layout.LoopState``, ``new_loop_state``), updated.
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    k : int
        The control sample's index.
    action : numpy.ndarray, shape (4,)
        An action on the rotor inputs [N, N m, N m, N] (read unless ``ACTION_NONE``).
    action_mode : int
        ``ACTION_NONE``, ``ACTION_ADD`` or ``ACTION_REPLACE``.

    Returns
    -------
    status : int
        The sample's status code (``Status``).
    tension : float
        The true tension at P [N].
    rate : float
        The applied reel rate [m/s].
    """
    sensed = run.sensors[0].shape[0] > 0
    tension, measured = sense(run, x, k, k * run.cfg[CFG_DT], sensed, loop.event, loop.x_meas)
    rate = paper_law(run, loop, measured, action, action_mode)
    status, rate = sample_apply(run, loop, x, k, rate, tension, measured, sensed,
                                run.act[ACT_DRUM] > 0.5)  # fmt: skip
    return status, tension, rate


@_jit_inline
def read_only_run(run):
    """``run`` (``layout.Run``) with the arrays the phases only read (c, act, law, wind)
    typed read-only (``_compile.frozen``) and no sensors (read by ``sense`` alone, which is
    inlined): every caller of a phase compiled once then selects the same signature.

    Parameters
    ----------
    run : Run
        The run's record.

    Returns
    -------
    Run
        The same arrays, borrowed.
    """
    return Run(run.cfg, run.ctrl, frozen(run.c), frozen(run.act), frozen(run.law),
               frozen(run.wind), (), run.chain, run.gear)  # fmt: skip


@_jit_inline
def control_run(run):
    """``read_only_run`` without the wind and the chain (empty tuples): the record of the
    phases that neither read (the controller, the actuators and checks), so that their
    compiled bodies take (and compile) fewer arrays.

    Parameters
    ----------
    run : Run
        The run's record.

    Returns
    -------
    Run
        The same arrays, borrowed, the wind, sensors and chain left out.
    """
    return Run(run.cfg, run.ctrl, frozen(run.c), frozen(run.act), frozen(run.law), (), (), (),
               ())  # fmt: skip


@_jit
def _drum_step(w0, w_cmd, tension_torque, ffwd, dt, inertia, gain, torque_limit, viscous,
               coulomb):  # fmt: skip
    # ``drum_winch``'s ``model.winch.drum_step``, compiled apart (scalars only: one signature)
    return drum_step(w0, w_cmd, tension_torque, ffwd, dt, inertia, gain, torque_limit, viscous,
                     coulomb)  # fmt: skip


# --- the phases of one sample, shared by every loop: one sample step ------------------------
# A sample at t = k dt is: ``sample_sense`` (a lumped chain's ends, the release check, the
# sensors); the controller (the compiled ``paper_law``, or a command from Python:
# ``step_command``); ``sample_apply`` (actuators, true outputs, failure checks);
# ``sample_record`` (the on-line metrics and the recorded signals); then the integrator
# (``sample_advance``: RK4 or the lumped chain's coupled step; the adaptive reference swaps
# only this phase). ``run_closed_loop`` runs them around the paper's law; ``step_sense`` and
# ``step_command`` run them from Python around any ``Controller``.


@_jit_inline
def sample_sense(run, loop, scratch, x, k, sensed, lumped):
    """Phase 1 at t = k dt: a lumped chain's end tensions (``chain_ends``, while attached),
    then ``sense``. Returns (true tension at P, measured tension) [N].

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``); the chain's tensions are set in its cfg.
    loop : LoopState
        The control phases' state: the release event and the measured state are written.
    scratch : Scratch
        The run's scratch (``layout.Scratch``): the chain's.
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    k : int
        The control sample's index.
    sensed : bool
        Whether the noise table has rows (else the sensors are perfect).
    lumped : bool
        Whether the tether is a lumped chain.

    Returns
    -------
    tuple of float
        (the true tension at P, the measured tension) [N].
    """
    cfg = run.cfg
    t = k * cfg[CFG_DT]
    if lumped and cfg[CFG_ATTACHED] > 0.5:
        chain_ends(x, t, cfg, run.wind.gust, run.wind.base, run.chain, scratch.cw)
    return sense(run, x, k, t, sensed, loop.event, loop.x_meas)


@_jit_inline
def paper_law(run, loop, measured, action, action_mode):
    """Phase 2, the compiled controller: the law ``run.ctrl[CTRL_LAW]`` names
    (``layout.CONTROL_LAWS``: the paper's LQI with feed-forward and winch PI, or the
    tethered LQI; ``control.paper.paper_control_sc``) on the measured state
    ``loop.x_meas``, about the tethered trim input while the tether is attached and the
    free one after (``loop.sc_meas`` receives sin, cos of its angles, ``y_est`` its
    outputs, ``inputs`` the rotor command, ``ffwd`` the feed-forward), then an optional
    ``action`` added to or replacing the rotor command (``ACTION_*``). Returns the
    reel-rate command [m/s].

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``).
    loop : LoopState
        The control phases' state, updated.
    measured : float
        The load cell's tension [N].
    action : numpy.ndarray, shape (4,)
        An action on the rotor command [N, N m, N m, N].
    action_mode : int
        ``ACTION_NONE``, ``ACTION_ADD`` or ``ACTION_REPLACE``.

    Returns
    -------
    float
        The reel-rate command [m/s].
    """
    return _paper_law(control_run(run), loop, measured, action, plain(action_mode))


@_jit
def _paper_law(run, loop, measured, action, action_mode):
    # ``paper_law``'s body, typed once for every caller (its read-only arrays frozen, its
    # constants plain: one signature) and inlined by LLVM (``inline_here``)
    inline_here()
    law = run.law
    u0 = law[LAW_U0] if run.cfg[CFG_ATTACHED] > 0.5 else law[LAW_U0_FREE]
    angle_trig(loop.x_meas, loop.sc_meas)
    rate = paper_control_sc(
        loop.x_meas, loop.sc_meas, measured, (loop.z, loop.winch), run.ctrl, run.c,
        (law[LAW_GAIN], law[LAW_X_REF], law[LAW_Y_REF], u0), (loop.y_est, loop.inputs, loop.ffwd),
    )  # fmt: skip
    inp = loop.inputs
    if action_mode == ACTION_ADD:
        for i in range(4):
            inp[i] += action[i]
    elif action_mode == ACTION_REPLACE:
        for i in range(4):
            inp[i] = action[i]
    return rate


@_jit_inline
def sample_outputs(run, loop, x, sensed, tension):
    """The true outputs ``loop.y`` (``vehicle_outputs``) and sin, cos of the true angles
    ``loop.sc_true`` (copies of the estimate's when the sensors are perfect, x_meas = x),
    then the failure checks (``check_state_sc``); returns the status.

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``).
    loop : LoopState
        The control phases' state: y and sc_true are written.
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    sensed : bool
        Whether the sensors are not perfect (x_meas differs from x).
    tension : float
        The true tension at P [N].

    Returns
    -------
    int
        The status code (``Status``).
    """
    y, sc_true = loop.y, loop.sc_true
    if sensed:
        angle_trig(x, sc_true)
        vehicle_outputs(x, sc_true, run.cfg, frozen(run.c), y)
    else:
        copy_into(y, loop.y_est)
        copy_into(sc_true, loop.sc_meas)
    return check_state_sc(x, sc_true, y, frozen(run.law[LAW_Y_REF]), tension, run.cfg)


@_jit_inline
def sample_apply(run, loop, x, k, rate, tension, measured, sensed, drum):
    """Phase 3: ``actuate`` on the controller's command (``loop.inputs``, the reel rate
    ``rate``), then ``sample_outputs``. ``drum``: the run has a drum winch (act[ACT_DRUM]);
    where it is a constant of the caller (the specialised loops) the other winch is not
    compiled. Returns (status, applied reel rate [m/s]).

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``).
    loop : LoopState
        The control phases' state: the held actuator state and the inputs are updated.
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    k : int
        The control sample's index.
    rate : float
        The reel-rate command [m/s].
    tension : float
        The true tension at P [N].
    measured : float
        The load cell's tension [N].
    sensed : bool
        Whether the sensors are not perfect.
    drum : bool
        Whether the run has a drum winch.

    Returns
    -------
    status : int
        The status code (``Status``).
    rate : float
        The applied reel rate [m/s].
    """
    if drum:
        return _sample_apply_drum(control_run(run), loop, x, k, rate, tension, measured,
                                  plain(sensed))  # fmt: skip
    return _sample_apply_ideal(control_run(run), loop, x, k, rate, tension, measured,
                               plain(sensed))  # fmt: skip


def _specialised_apply(drum: bool):
    """``sample_apply``'s body for an ideal winch (``drum`` False) or a drum winch: a closure
    whose ``drum`` is a constant of the compiled code, so the ideal winch's body compiles no
    drum (``_drum_step``: about 1.5 s of a first ``tetherheli paper``)."""

    def sample_apply_body(run, loop, x, k, rate, tension, measured, sensed):
        # typed once for every caller (its read-only arrays frozen, its constants plain: one
        # signature) and inlined by LLVM (``inline_here``)
        inline_here()
        cfg = run.cfg
        dt = cfg[CFG_DT]
        rate = actuate(
            loop.inputs, loop.held, rate, run.act, dt, k == 0,
            (winch_tension(cfg, tension), measured), x[X_LN], k * dt, drum,
        )  # fmt: skip
        status = sample_outputs(run, loop, x, sensed, tension)
        return status, rate

    return sample_apply_body


_sample_apply_ideal = _jit(_specialised_apply(False))
_sample_apply_drum = _jit(_specialised_apply(True))


@_jit_inline
def sample_record(run, loop, summary, out, x, k, tension, rate, record, force):
    """Phase 4: the on-line metrics of the samples k >= cfg[CFG_METRICS_FROM] into
    ``summary`` (``accumulate``), and with ``record`` the sample's row of ``out``
    (``layout.Signals``); ``force`` (>= 3,) receives the wind force.

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``).
    loop : LoopState
        The control phases' state (outputs, inputs, held actuator state).
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        The on-line metrics (``layout.SUMMARY_*``), updated.
    out : Signals
        The recorded signals (``layout.Signals``).
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    k : int
        The control sample's index.
    tension : float
        The true tension at P [N].
    rate : float
        The applied reel rate [m/s].
    record : bool
        Whether to record the sample's row of ``out``.
    force : numpy.ndarray, shape (>= 3,)
        Receives the wind force [N].

    Returns
    -------
    None
        Nothing: ``summary`` and ``out`` are written in place.
    """
    return _sample_record(read_only_run(run), loop, summary, out, x, k, tension, rate,
                          plain(record), force)  # fmt: skip


@_jit
def _sample_record(run, loop, summary, out, x, k, tension, rate, record, force):
    # ``sample_record``'s body, typed once for every caller (its read-only arrays frozen, its
    # constants plain: one signature) and inlined by LLVM (``inline_here``)
    inline_here()
    if k >= run.cfg[CFG_METRICS_FROM]:  # the metrics' window (Scenario.metrics_start)
        accumulate(summary, x, run.law[LAW_X_REF], loop.y, run.law[LAW_Y_REF], tension)
    if record:
        record_row(run, loop, out, x, k, tension, rate, force)


@_jit
def record_row(run, loop, out, x, k, tension, rate, force):
    """``sample_record``'s row of ``out``: a call, not inlined (once per sample, and
    a first run compiles it apart).

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``): cfg, act, the wind and the chain's nodes.
    loop : LoopState
        The control phases' state: outputs, inputs, feed-forward, held actuator state.
    out : Signals
        The recorded signals (``layout.Signals``); row k is written.
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m].
    k : int
        The control sample's index, the row of ``out``.
    tension : float
        The true tension at P [N].
    rate : float
        The applied reel rate [m/s].
    force : numpy.ndarray, shape (>= 3,)
        Receives the wind force [N].
    """
    cfg, wind, held = run.cfg, run.wind, loop.held
    air_force_on_base(wind.program, wind.gust, cfg[CFG_GUST_DT], wind.drag, wind.base,
                      k * cfg[CFG_DT], 1, (x[X_U1], x[X_U1 + 1], x[X_U1 + 2]), force)  # fmt: skip
    copy_into(out.x[k], x)
    copy_into(out.u[k], loop.inputs)
    copy_into(out.ffwd[k], loop.ffwd)
    out.rate[k] = rate
    out.tension[k] = tension
    copy_into(out.wind[k], force[:3])
    copy_into(out.y[k], loop.y)
    copy_into(out.y_est[k], loop.y_est)
    out.tension_ground[k] = winch_tension(cfg, tension)
    if out.nodes.shape[0] > 0:
        nodes = run.chain[CHAIN_NODES]
        row = out.nodes[k]
        for i in range(nodes.shape[0]):
            copy_into(row[i], nodes[i])
    if run.act[ACT_DRUM] > 0.5:  # the drum's speed at t_k, its mean torque after t_k
        out.winch[k, 0] = held[HELD_DRUM_SPEED_SAMPLED]
        out.winch[k, 1] = held[HELD_MOTOR_TORQUE]


@_jit_inline
def sample_advance(run, scratch, x, inp, rate, k, lumped):
    """Phase 5, the fixed-step integrator over [k dt, (k + 1) dt]: a lumped chain's coupled
    step while attached (``lumped_interval``), else ``rk4_interval`` (sin, cos of x's angles
    already in scratch.work[6], ``sample_outputs``'s sc_true).

    Parameters
    ----------
    run : Run
        The run's record (``layout.Run``); the chain is advanced in place.
    scratch : Scratch
        The run's scratch (``layout.Scratch``): the integrator's and the chain's.
    x : numpy.ndarray, shape (13,)
        The true state (``layout.X_*``) [rad, m, rad/s, m/s, m], advanced in place.
    inp : numpy.ndarray, shape (4,)
        The applied rotor inputs [N, N m, N m, N].
    rate : float
        The applied reel rate [m/s].
    k : int
        The control sample's index.
    lumped : bool
        Whether the tether is a lumped chain.
    """
    cfg = run.cfg
    t = k * cfg[CFG_DT]
    if lumped and cfg[CFG_ATTACHED] > 0.5:
        lumped_interval(x, inp, rate, t, cfg, run.c, run.wind, run.chain,
                        (scratch.work, scratch.cw), plain(COUPLING_CONDENSED))  # fmt: skip
    else:
        rk4_interval(x, inp, rate, t, cfg, run.c, run.wind, scratch.work, plain(True), run.gear)


def new_loop_state(x_init: np.ndarray, z_init: np.ndarray, work: np.ndarray) -> LoopState:
    """The per-run arrays of ``paper_sample`` (from Python; the compiled loop builds its own):
    integrators (starting at z_init, ``law[LAW_Z0]``), winch, held actuator state, release event
    (NaN: none), scratch.

    Parameters
    ----------
    x_init : numpy.ndarray, shape (13,)
        The initial state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    z_init : numpy.ndarray, shape (4,)
        The LQI integrators' start (``law[LAW_Z0]``).
    work : numpy.ndarray, shape (RK4_WORK_ROWS, 13)
        The integrator's scratch (sc_true shares work[6, :10]).

    Returns
    -------
    LoopState
        The per-run arrays (``layout.LOOP_*``).
    """
    return _loop_state(x_init, z_init, work)


@_jit_inline
def _loop_state(x_init, z_init, work):
    return LoopState(
        z_init.copy(),  # z: the LQI's output-error integral (eq 50), from runs.start.start_point
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


def is_lumped(chain: tuple) -> bool:
    """Whether ``chain`` (``layout.CHAIN_*``) is a lumped tether's: it has nodes (the massless
    tether's, ``layout.empty_chain()``, has none); chooses the loop (``closed_loop_for``).

    Parameters
    ----------
    chain : tuple of numpy.ndarray
        The run's chain (``layout.CHAIN_*``).

    Returns
    -------
    bool
        Whether the chain has nodes.
    """
    return chain[CHAIN_NODES].shape[0] > 0


def run_closed_loop(
    x_init, n_samples, cfg_in, ctrl_in, c, law, wind, act, sensors, chain, record, out, summary,
    gear=None,
):  # fmt: skip
    """Run the closed loop for n_samples control samples; returns (status, samples done).

    Each sample is the phases above around ``paper_law``: ``sample_sense``, ``paper_law``,
    ``sample_apply``, ``sample_record``, ``sample_advance``; with a lumped tether (``chain``,
    ``layout.CHAIN_*``, nodes present) the chain's ends are set before the sample and
    ``lumped_interval`` advances helicopter and chain (``layout.empty_chain()``: the massless
    tether of eq 28). ``law`` is (gain, x_ref, y_ref, u0, u0_free, z0) (``layout.LAW_*``),
    ``wind`` (program, gust table, drag, base), ``sensors`` (``runs.packing.sensor_tuple``). With
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

    The one loop, ``_specialised_loop``'s, is compiled per tether kind, sensing and winch
    (``CLOSED_LOOPS``, chosen by ``closed_loop_for``): a massless run does not compile the
    lumped chain's step (about 20 s of a first run's compilation), a run with perfect
    sensors not the sensors, an ideal winch not the drum.

    Parameters
    ----------
    x_init : numpy.ndarray, shape (13,)
        The initial state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    n_samples : int
        The control samples to run (n_samples + 1 sampled instants).
    cfg_in : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``; copied).
    ctrl_in : numpy.ndarray, shape (CTRL_SIZE,)
        The paper controller's settings (``layout.CTRL_*``; copied).
    c : numpy.ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    law : tuple of numpy.ndarray
        The controller's arrays (``layout.LAW_*``).
    wind : tuple of numpy.ndarray
        (program, gust table, drag, base), as for ``plant_derivative``.
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``).
    sensors : tuple
        ``runs.packing.sensor_tuple``'s.
    chain : tuple of numpy.ndarray
        The lumped chain (``layout.CHAIN_*``; ``layout.empty_chain()``: massless), advanced.
    record : bool
        Whether to record the signals into ``out``.
    out : Signals
        The recorded signals (``layout.Signals``).
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        Receives the on-line metrics (``layout.SUMMARY_*``).
    gear : Gear, optional
        The landing gear (``layout.Gear``; default none, ``layout.no_gear()``).

    Returns
    -------
    status : int
        The run's status code (``Status``).
    done : int
        The samples done (n_samples + 1 for a complete run, else the failed sample's index).
    """
    loop = closed_loop_for(chain, sensors, act)
    gear = no_gear() if gear is None else gear
    run = Run(cfg_in, ctrl_in, c, act, tuple(law), WindPack(*wind), sensors, chain, gear)
    return loop(x_init, n_samples, run, record, out, summary)


def closed_loop_for(chain: tuple, sensors: tuple, act: np.ndarray) -> Any:
    """The compiled loop of ``run_closed_loop`` for a run's tether (``chain``: lumped or
    massless), ``sensors`` (a noise table with rows: sensed, else perfect) and winch (``act``,
    ``layout.ACT_*``: drum or ideal), one of ``CLOSED_LOOPS``; it releases the GIL.

    Parameters
    ----------
    chain : tuple of numpy.ndarray
        The run's chain (``layout.CHAIN_*``).
    sensors : tuple
        ``runs.packing.sensor_tuple``'s.
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``).

    Returns
    -------
    callable
        The compiled loop, called as ``run_closed_loop``.
    """
    return CLOSED_LOOPS[is_lumped(chain), sensors[0].shape[0] > 0, bool(act[ACT_DRUM] > 0.5)]


def _specialised_loop(lumped: bool, sensed: bool, drum: bool):
    """``run_closed_loop``'s loop for a massless tether (or none, ``lumped`` False) or a
    lumped one, with perfect sensors (``sensed`` False) or a noise table, with the ideal
    winch (``drum`` False) or the drum winch: a closure whose ``lumped``, ``sensed`` and
    ``drum`` are constants of the compiled code, so that the compiler drops the branches a
    run never takes (Numba's cache keys a closure on its variables' values
    too). Not an inlined function called with a constant: Numba copies an
    inlined function's IR block by block, each block with every variable of the function, so
    inlining the whole loop cost about a quarter of a first run's compilation."""

    def closed_loop(x_init, n_samples, run_in, record, out, summary):
        # The loop works on borrowed views (``_compile.borrowed``: no atomic reference counts):
        # of the arguments, which the caller holds, and of the run's own arrays, held below
        # (``keep_alive``) until the loop is done.
        own_cfg, own_ctrl, own_x = run_in.cfg.copy(), run_in.ctrl.copy(), x_init.copy()
        own_work = np.empty((RK4_WORK_ROWS, 13))
        own_loop = _loop_state(x_init, run_in.law[LAW_Z0], own_work)
        own_no_action = np.zeros(4)
        if lumped:
            own_cw = _lumped_work(max(run_in.chain[CHAIN_NODES].shape[0] - 1, 1))
        else:  # never read: a massless loop's chain branches are pruned
            own_cw = np.empty(0)
        cfg, ctrl, x, work, no_action = borrowed(
            (own_cfg, own_ctrl, own_x, own_work, own_no_action)
        )
        c, act, law, wind, sensors, chain, gear = borrowed(
            (run_in.c, run_in.act, run_in.law, run_in.wind, run_in.sensors, run_in.chain,
             run_in.gear)
        )  # fmt: skip
        summary, out, cw, loop = borrowed((summary, out, own_cw, own_loop))
        # the run's records: built once, their fields read by name in the phases
        run = Run(cfg, ctrl, c, act, law, wind, sensors, chain, gear)
        scratch = Scratch(work, cw, no_action)
        start_summary(summary)
        status, done = STATUS_OK, n_samples + 1
        for k in range(n_samples + 1):
            tension, measured = sample_sense(run, loop, scratch, x, k, sensed, lumped)
            rate = paper_law(run, loop, measured, no_action, ACTION_NONE)
            sample_status, rate = sample_apply(
                run, loop, x, k, rate, tension, measured, sensed, drum
            )
            if sample_status != STATUS_OK:
                status, done = sample_status, k
                break
            sample_record(run, loop, summary, out, x, k, tension, rate, record, work[5])
            if k == n_samples:
                break
            sample_advance(run, scratch, x, loop.inputs, rate, k, lumped)
        finish_summary(summary, loop.event, loop.held)
        keep_alive((own_cfg, own_ctrl, own_x, own_work, own_loop, own_no_action, own_cw))
        return status, done

    return closed_loop


#: ``_specialised_loop`` by (lumped, sensed, drum): the loop of a massless (or no) tether or
#: a lumped one (``chain``'s nodes present), with perfect sensors or a noise table, with the
#: ideal or the drum winch; each compiles at its first run and releases the GIL
#: (``runs.batch`` runs them on threads)
CLOSED_LOOPS = {
    (lumped, sensed, drum): compiled(error_model="numpy", nogil=True)(
        _specialised_loop(lumped, sensed, drum)
    )
    for lumped in (False, True)
    for sensed in (False, True)
    for drum in (False, True)
}
