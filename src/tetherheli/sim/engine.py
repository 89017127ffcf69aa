"""The compiled closed-loop engine (Numba): plant, paper controller, winch, wind, integrator.

One call runs a whole scenario without returning to Python: at every control sample t_k the
controller reads the state, computes the inputs (held constant over the sample, zero-order
hold), and the plant is integrated to t_{k+1} by fixed-step RK4 with ``n_substeps`` steps.

Wind discontinuities (pulse and step edges) placed on integration-step boundaries are handled
exactly: an RK4 step over [ta, tb] evaluates the wind at ta as the right limit and at tb as the
left limit, i.e. it integrates the force on the open interval (ta, tb).

Everything a run needs is packed into flat float64 arrays with named indices (``CFG_*``), so
one compiled function serves every scenario and Numba's on-disk cache survives between
processes.
"""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled
from ..control.paper import CTRL_FFWD, CTRL_WINCH, paper_control_sc
from ..model.kernels import (
    angle_trig,
    angle_trig_from,
    tension_from_state,
    tethered_outputs,
    tethered_rhs_sc,
)
from ..sensors import measure

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")

# --- wind program: one row per built-in profile ----------------------------------------------
WIND_PULSE, WIND_SINE, WIND_STEP, WIND_CONSTANT = 0, 1, 2, 3
#: columns: kind, start [s], duration [s], magnitude [N], frequency [Hz], phase [rad], n1, n2, n3
WIND_COLUMNS = 9

# --- scalar configuration, packed in one array ----------------------------------------------
CFG_DT = 0  # control sample time [s]
CFG_N_SUB = 1  # RK4 steps per sample
CFG_K_C = 2  # tether elasticity [N/m]
CFG_ATTACHED = 3  # 1: tether attached, 0: removed (free configuration)
CFG_MAX_TENSION = 4  # [N]; a run stops when exceeded
CFG_MAX_DEVIATION = 5  # [m]; a run stops as diverged when |y - y_ref| exceeds it
CFG_MAX_ANGLE = 6  # [rad]; |q4|, |q5|, |q7|, |q8| beyond it: diverged
CFG_GUST_DT = 7  # gust-table step [s] (0: no gust table)
CFG_SIZE = 8

#: rows of the scratch array of ``rk4_interval``
RK4_WORK_ROWS = 8

# --- run status ------------------------------------------------------------------------------
STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_GROUND = 2
STATUS_MAX_TENSION = 3
STATUS_DIVERGED = 4
STATUS_SINGULAR = 5
STATUS_SETUP = 6  # never returned by the engine: run_batch(record_setup_failures=True)
STATUS_MESSAGES = (
    "completed",
    "the state became non-finite",
    "the helicopter hit the ground (q3 < 0 or the attachment point P at ground level)",
    "the tether tension exceeded the configured maximum",
    "the run diverged (deviation or attitude beyond the configured bounds)",
    "the state reached a coordinate singularity (q9 <= 0 or |q5|, |q8| at 90 deg)",
    "the run could not be set up (no hover trim within the parameters and actuator limits)",
)

# --- summary metrics computed on line --------------------------------------------------------
SUMMARY_FIELDS = (
    "peak_q1", "peak_q2", "peak_q3", "peak_q4", "peak_q5",
    "sumsq_q1", "sumsq_q2", "sumsq_q3", "tension_min", "tension_max", "n_samples",
    "release_time", "release_tension",
)  # fmt: skip
#: summary slots of the tether-release event (``release_if_broken``): the sample time [s] at
#: which the safety device released the tether and the tension [N] that exceeded the breaking
#: tension; both NaN when the tether was not released
SUMMARY_RELEASE_TIME = SUMMARY_FIELDS.index("release_time")
SUMMARY_RELEASE_TENSION = SUMMARY_FIELDS.index("release_tension")
assert SUMMARY_RELEASE_TENSION == SUMMARY_RELEASE_TIME + 1  # one (2,) event slice


def status_message(status: int, release_time: float | None = None) -> str:
    """The message of a run's status; a tether release (at ``release_time`` [s], None or NaN:
    none) is part of it, so a released run is never a plain "completed"."""
    message = STATUS_MESSAGES[int(status)]
    if release_time is None or not math.isfinite(release_time):
        return message
    if status == STATUS_OK:
        return f"{message} (tether released at t = {release_time:g} s)"
    return f"{message} (after the tether was released at t = {release_time:g} s)"


def release_sentence(release_time: float, tension: float, breaking_tension: float) -> str:
    """One line describing a tether release, e.g. "tether released at t = 12.3 s (tension
    61.2034 N > breaking 60 N); continued free"."""
    return (
        f"tether released at t = {release_time:g} s (tension {tension:.6g} N > breaking "
        f"{breaking_tension:g} N); continued free"
    )


@_jit_inline
def _wind_program_force(program, t, side, out):
    """Add the built-in profiles' force at time t; side = +1 right limit, -1 left limit."""
    for r in range(program.shape[0]):
        kind = program[r, 0]
        start = program[r, 1]
        if kind == WIND_CONSTANT:
            active = True
            value = program[r, 3]
        elif kind == WIND_PULSE:
            end = start + program[r, 2]
            if side > 0:
                active = start <= t < end
            else:
                active = start < t <= end
            value = program[r, 3]
        elif kind == WIND_STEP:
            active = start <= t if side > 0 else start < t
            value = program[r, 3]
        else:  # WIND_SINE, absolute time (Sec. VI: 20 sin(2 pi 0.1 t) from t = 30 s)
            active = start <= t if side > 0 else start < t
            value = program[r, 3] * math.sin(2.0 * math.pi * program[r, 4] * t + program[r, 5])
        if active:
            out[0] += value * program[r, 6]
            out[1] += value * program[r, 7]
            out[2] += value * program[r, 8]


@_jit_inline
def wind_force(program, gust, gust_dt, drag, t, side, v1, v2, v3, out):
    """Wind force on HO in N [N]: the profiles plus the drag of the gust velocity relative to
    HO, 0.5 rho CdA |v_rel| v_rel per axis (drag[i] = 0.5 rho CdA_i)."""
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    _wind_program_force(program, t, side, out)
    if gust_dt > 0.0 and gust.shape[0] > 0:
        s = t / gust_dt
        i = int(s) if s > 0.0 else 0  # floor for s >= 0
        if s <= 0.0:
            w = 0.0
        elif i >= gust.shape[0] - 1:
            i, w = gust.shape[0] - 1, 0.0
        else:
            w = s - i
        for a in range(3):
            g = gust[i, a] if w == 0.0 else gust[i, a] * (1.0 - w) + gust[i + 1, a] * w
            rel = g - (v1 if a == 0 else (v2 if a == 1 else v3))
            out[a] += drag[a] * abs(rel) * rel


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
    """Status of a sampled state (``STATUS_*``)."""
    sc = np.empty(10)
    angle_trig(x, sc)
    return check_state_sc(x, sc, y, y_ref, tension, cfg)


@_jit_inline
def check_state_sc(x, sc, y, y_ref, tension, cfg):
    """``check_state`` with sc = sin, cos of x[0..4] given (``kernels.angle_trig``)."""
    for i in range(x.shape[0]):
        if not math.isfinite(x[i]):
            return STATUS_NONFINITE
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
def _accumulate(summary, x, x_ref, y, y_ref, tension):
    for a in range(3):
        dev = y[a] - y_ref[a]
        if abs(dev) > summary[a]:
            summary[a] = abs(dev)
        summary[5 + a] += dev * dev
    if abs(x[0] - x_ref[0]) > summary[3]:
        summary[3] = abs(x[0] - x_ref[0])
    if abs(x[1] - x_ref[1]) > summary[4]:
        summary[4] = abs(x[1] - x_ref[1])
    if tension < summary[8]:
        summary[8] = tension
    if tension > summary[9]:
        summary[9] = tension
    summary[10] += 1.0


# --- actuators, packed in one array -----------------------------------------------------------
ACT_U_MIN = 0  # (4,) lower input limits [N, N m, N m, N]
ACT_U_MAX = 4  # (4,) upper input limits
ACT_TAU = 8  # first-order actuator time constant [s] (0: none)
ACT_BREAK = 9  # tether breaking / release tension [N] (inf: never)
ACT_REEL_ACCEL = 10  # |d(reel rate)/dt| bound of the winch [m/s^2] (inf: none)
ACT_SIZE = 11


def default_actuators() -> np.ndarray:
    """Ideal actuators: no limits, no lag, an unbreakable tether."""
    act = np.zeros(ACT_SIZE)
    act[ACT_U_MIN : ACT_U_MIN + 4] = -np.inf
    act[ACT_U_MAX : ACT_U_MAX + 4] = np.inf
    act[ACT_BREAK] = np.inf
    act[ACT_REEL_ACCEL] = np.inf
    return act


@_jit
def apply_actuators(inp, applied, act, dt, first):
    """Saturate the command, then pass it through the first-order lag (step-invariant at the
    sample rate: u_k = u_{k-1} + (1 - e^{-dt/tau}) (sat(cmd_k) - u_{k-1})); inp becomes the
    applied input and ``applied`` (4,) keeps it for the next sample."""
    tau = act[ACT_TAU]
    gain = 1.0 if (first or tau <= 0.0) else 1.0 - math.exp(-dt / tau)
    for i in range(4):
        v = min(max(inp[i], act[ACT_U_MIN + i]), act[ACT_U_MAX + i])
        v = applied[i] + gain * (v - applied[i]) if not first else v
        applied[i] = v
        inp[i] = v


@_jit
def limit_reel_acceleration(rate, previous_rate, act, dt):
    """The commanded reel rate with its change since the last sample bounded by
    act[ACT_REEL_ACCEL] dt (the winch motor's acceleration limit)."""
    step = act[ACT_REEL_ACCEL] * dt
    return min(max(rate, previous_rate - step), previous_rate + step)


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
def actuate(inp, applied, rate, previous_rate, act, dt, first, winch_integral, integral_before):
    """The actuators on the paper controller's command: saturation and lag of inp (in place,
    ``apply_actuators``) and the winch's acceleration limit on the reel rate, the PI's
    integrator held at ``integral_before`` while the limit binds (conditional integration,
    no windup). Returns the applied reel rate [m/s]."""
    apply_actuators(inp, applied, act, dt, first)
    limited = limit_reel_acceleration(rate, previous_rate, act, dt)
    if limited != rate:
        winch_integral[0] = integral_before
    return limited


@_jit
def run_closed_loop(
    x_init,
    n_samples,
    cfg_in,
    ctrl_in,
    c,
    gain,
    x_ref,
    y_ref,
    u0,
    program,
    gust,
    drag,
    act,
    noise,
    source_code,
    arm,
    record,
    out_x,
    out_u,
    out_ffwd,
    out_rate,
    out_tension,
    out_wind,
    out_y,
    out_y_est,
    summary,
):
    """Run the closed loop for n_samples control samples; returns (status, samples done).

    The controller sees measurements (``sensors.measure`` with the sample's row of ``noise``
    when ``noise`` has rows, else the true state); its command goes through the actuators
    (``act``); a tension above act[ACT_BREAK] releases the tether (the run continues free;
    the release's time and tension go to the summary's ``release_*`` slots, else NaN).
    With ``record`` the out_* arrays (n_samples + 1 rows) receive the sampled signals: true
    state, applied inputs (with feed-forward), feed-forward, reel rate, true tension, wind
    force, true outputs, and the controller's output estimate. ``summary``
    (len(SUMMARY_FIELDS),) always receives the on-line metrics.
    """
    cfg = cfg_in.copy()
    ctrl = ctrl_in.copy()
    x = x_init.copy()
    x_meas = x_init.copy()
    z = np.zeros(4)
    winch_integral = np.zeros(1)
    y = np.empty(4)
    y_est = np.empty(4)
    inp = np.empty(4)
    applied = np.empty(4)
    ffwd = np.empty(4)
    wind = np.empty(3)
    work = np.empty((RK4_WORK_ROWS, 13))
    sc_meas = np.empty(10)
    sc_true = work[6, :10]  # sin, cos of the true angles: the checks and the first RK4 step
    previous_rate = 0.0  # the winch starts at rest
    summary[:] = 0.0
    summary[8] = np.inf
    summary[9] = -np.inf
    summary[SUMMARY_RELEASE_TIME] = np.nan
    summary[SUMMARY_RELEASE_TENSION] = np.nan
    release = summary[SUMMARY_RELEASE_TIME : SUMMARY_RELEASE_TIME + 2]
    dt = cfg[CFG_DT]
    sensed = noise.shape[0] > 0
    for k in range(n_samples + 1):
        t = k * dt
        attached = cfg[CFG_ATTACHED] > 0.5
        tension = tension_from_state(x[5], x[12], cfg[CFG_K_C]) if attached else 0.0
        tension = release_if_broken(tension, t, cfg, ctrl, act, release)
        if sensed:
            measured_tension = measure(x, tension, noise[k], source_code, arm, x_meas)
        else:
            x_meas[:] = x
            measured_tension = tension
        angle_trig(x_meas, sc_meas)
        integral_before = winch_integral[0]
        rate = paper_control_sc(
            x_meas,
            sc_meas,
            measured_tension,
            z,
            winch_integral,
            ctrl,
            c,
            gain,
            x_ref,
            y_ref,
            u0,
            y_est,
            inp,
            ffwd,
        )
        rate = actuate(
            inp, applied, rate, previous_rate, act, dt, k == 0, winch_integral, integral_before
        )
        previous_rate = rate
        if sensed:
            tethered_outputs(x, c, y)
            angle_trig(x, sc_true)
        else:
            y[:] = y_est
            sc_true[:] = sc_meas
        status = check_state_sc(x, sc_true, y, y_ref, tension, cfg)
        if status != STATUS_OK:
            return status, k
        _accumulate(summary, x, x_ref, y, y_ref, tension)
        if record:
            wind_force(program, gust, cfg[CFG_GUST_DT], drag, t, 1, x[6], x[7], x[8], wind)
            out_x[k] = x
            out_u[k] = inp
            out_ffwd[k] = ffwd
            out_rate[k] = rate
            out_tension[k] = tension
            out_wind[k] = wind
            out_y[k] = y
            out_y_est[k] = y_est
        if k == n_samples:
            break
        rk4_interval(x, inp, rate, t, cfg, c, program, gust, drag, work, True)
    return STATUS_OK, n_samples + 1
