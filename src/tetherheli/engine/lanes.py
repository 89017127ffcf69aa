"""The lane engine: a block of ``layout.LANES`` runs advanced together (``run_lanes``, behind
``run_batch``, sweeps and the Monte Carlo; ``rk4_lanes`` also behind the vector environment).
Each lane runs the single run's control sample (``engine.loop.paper_sample``), then the block
is integrated at once over flat (variable, lane) arrays, the lanes' loops vectorised; a lane
equals the single run bit for bit."""

from __future__ import annotations

import math

import numpy as np
from numba import types
from numba.extending import intrinsic

from .._compile import (
    borrowed,
    compiled,
    inline_here,
    keep_alive,
    plain,
    restrict_arguments,
)
from ..layout import (
    ACT_DRUM,
    ACT_SIZE,
    CFG_ATTACHED,
    CFG_DT,
    CFG_GUST_DT,
    CFG_K_C,
    CFG_N_SUB,
    CFG_TETHER_EA,
    CFG_VEHICLE,
    CONTROL_LAW_TETHER_LQI,
    CTRL_LAW,
    HELD_SIZE,
    LANES,
    SUMMARY_RELEASE_TENSION,
    SUMMARY_RELEASE_TIME,
    VEHICLE_HELICOPTER,
    WIND_COLUMNS,
    WIND_CONSTANT,
    WIND_DIRECTION,
    WIND_DURATION,
    WIND_FREQUENCY,
    WIND_KIND,
    WIND_MAGNITUDE,
    WIND_PHASE,
    WIND_SINE,
    WIND_START,
    X_LN,
    X_Q9,
    X_U1,
    LaneWind,
)
from ..model.kernels import (
    angle_trig_from_lanes,
    angle_trig_lanes,
    tethered_rhs_lanes,
)
from ..wind.evaluate import gust_velocity, profile_value
from .lane_sample import lane_law, lane_sample, lane_state
from .loop import STATUS_OK, TRIG_CHAIN_STEPS
from .summary import start_summary, winch_limit_into

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")

#: LLVM's ``prefer-vector-width`` of the lane engine's compiled functions [bits]. On a
#: processor with AVX-512 LLVM vectorises with 256-bit registers unless a function asks for
#: wider ones; a block of LANES = 16 doubles fills two 512-bit registers. The width only
#: changes how many lanes one instruction does: each lane's arithmetic stays the same.
LANE_VECTOR_BITS = 512


@intrinsic
def _wide_vectors(typingctx):  # pragma: no cover - compiled
    """In compiled code: mark the function being compiled with LLVM's attribute
    ``"prefer-vector-width"="LANE_VECTOR_BITS"`` (no code). llvmlite's attribute set accepts
    only its listed names, so the string attribute is added to the underlying set."""

    def codegen(context, builder, signature, args):
        attribute = f'"prefer-vector-width"="{LANE_VECTOR_BITS}"'
        set.add(builder.function.attributes, attribute)
        return context.get_dummy_value()

    return types.none(), codegen


# --- the lane engine: a block of LANES runs advanced together ----------------------------------
# Lane arrays are flat, element (variable i, lane j) at i * LANES + j (``layout.LANES``, a
# constant of the compiled code): the loops over j below have no branch and no call, and the
# compiler, knowing every offset, vectorises them.


@_jit_inline
def _lanes_program_force(programs, n_rows, t, side, out):
    """out (3 LANES,) = the profiles' force of every lane at its time t (LANES,): the lanes'
    programs are flat (row, column, lane), element at (r WIND_COLUMNS + column) LANES + j,
    padded with zero rows (``batch.lane_block``); the sum runs over rows in the order of
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


@_jit
def _lanes_stage(xs, sc, inp, rate, attached, k_c, c, air, force, out):
    """out (13 LANES,) = dx/dt of every lane at the stage state xs: the wind force of
    ``wind_force`` (profiles plus bluff-body drag; air = (the profiles' force, the gust air
    velocity, the drag), flat (variable, lane)), the tension (eq 28: zero when slack or
    released), eqs 10-12, 29-35 (``tethered_rhs_lanes``) and dLN/dt = RC (eq 37). ``force``
    (4 LANES,) receives the wind force and the tension."""
    # typed and lowered once for the four stages, inlined by LLVM (``inline_here``): Numba's
    # inlining of the four (``tethered_rhs_lanes`` in each) took 15 s of the first compile
    _wide_vectors()
    inline_here()
    restrict_arguments()  # separate arrays (``rk4_lanes``'s scratch and inputs)
    program_force, gust_air, drag = air
    for j in range(rate.shape[0]):  # LANES, read at run time (see ``_lanes_axpy``)
        r1 = gust_air[j] - xs[X_U1 * LANES + j]
        r2 = gust_air[LANES + j] - xs[(X_U1 + 1) * LANES + j]
        r3 = gust_air[2 * LANES + j] - xs[(X_U1 + 2) * LANES + j]
        speed = math.sqrt(r1 * r1 + r2 * r2 + r3 * r3)
        force[j] = program_force[j] + drag[j] * speed * r1
        force[LANES + j] = program_force[LANES + j] + drag[LANES + j] * speed * r2
        force[2 * LANES + j] = program_force[2 * LANES + j] + drag[2 * LANES + j] * speed * r3
        stretch = xs[X_Q9 * LANES + j] - xs[X_LN * LANES + j]
        tied = attached[j] > 0.5
        ea = k_c[LANES + j]  # the rope's EA (0: eq 28's KC; ``kernels.tether_tension``)
        stiffness = ea / xs[X_LN * LANES + j] if ea > 0.0 else k_c[j]
        force[3 * LANES + j] = stiffness * stretch if (tied and stretch > 0.0) else 0.0
        out[X_LN * LANES + j] = rate[j] if tied else 0.0
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
    tension, profile forces, gust air, stage times), for the lane engine and the vector env.

    Returns
    -------
    tuple of numpy.ndarray
        The ten scratch arrays, flat (variable, lane).
    """
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
def rk4_lanes(lane_in, h, n_sub, k_c, c, wind, work):
    """``rk4_interval`` for a block of LANES runs: advance every lane j of x (13 LANES,) over
    its control sample [t0_j, t0_j + n_sub h_j] by n_sub RK4 steps of h_j; lane_in = (x, sc0,
    inp, rate, t0, attached) (``set_lane``).

    Flat (variable, lane) arrays: sc0 (10 LANES,) sin, cos of the angles of x on entry
    (overwritten), inp (4 LANES,) the held rotor inputs, c (n_c LANES,) the model constants;
    rate, t0, h, attached (1/0), k_c (LANES,). wind (``layout.LaneWind``) = (programs
    (R WIND_COLUMNS LANES,), R, gusts (LANES, G, 3), gust rows in use (LANES,), gust_dt
    (LANES,), drag (3 LANES,)); work = ``lane_work()``. The gust tables are read per lane;
    everything else runs in branch-free passes over the lanes. Each lane performs the
    operations of ``rk4_interval`` in the same order, so it equals a single run bit for bit.

    Every array argument must be a separate array (``restrict_arguments``: LLVM vectorises
    the lanes' loops without run-time overlap checks).

    Parameters
    ----------
    lane_in : tuple of numpy.ndarray
        (x, sc0, inp, rate, t0, attached): the lanes' states (13 LANES,) [q4..q9, u1..u6, LN]
        in [rad, m, rad/s, m/s, m], advanced in place; sin, cos of x's angles on entry
        (10 LANES,), overwritten; the held rotor inputs (4 LANES,) [N, N m, N m, N]; the held
        reel rates (LANES,) [m/s]; the samples' start times (LANES,) [s]; 1 where the lane's
        tether is attached, 0 where removed or released (LANES,).
    h : numpy.ndarray, shape (LANES,)
        The RK4 step of each lane [s].
    n_sub : int
        The RK4 steps per sample.
    k_c : numpy.ndarray, shape (2 LANES,)
        The tether's law per lane: eq 28's KC [N/m], then the rope's EA [N] (0: the paper's).
    c : numpy.ndarray, shape (n_c LANES,)
        The lanes' model constants, flat.
    wind : LaneWind
        The lanes' winds (``layout.LaneWind``: programs (R WIND_COLUMNS LANES,), R, gusts
        (LANES, G, 3) [m/s], gust rows in use (LANES,), gust_dt (LANES,) [s], drag
        (3 LANES,) [kg/m]).
    work : tuple of numpy.ndarray
        ``lane_work()``'s scratch.
    """
    _wide_vectors()
    restrict_arguments()
    x, sc0, inp, rate, t0, attached = lane_in
    programs, n_rows, gusts, gust_rows, gust_dt, drag = wind
    k1, k2, k3, k4, tmp, sc, force, program_force, gust_air, times = work
    pf_a, pf_m, pf_b = _thirds(program_force)
    ga_a, ga_m, ga_b = _thirds(gust_air)
    ta, tm, tb = _thirds(times)
    n_lanes = h.shape[0]
    gusty = False  # a lane with a gust table; without, gust_velocity's air is zero
    for j in range(LANES):
        gusty |= gust_dt[j] > 0.0 and gust_rows[j] > 0
    if not gusty:
        for i in range(gust_air.shape[0]):
            gust_air[i] = 0.0
    for step in range(n_sub):
        for j in range(n_lanes):
            ta[j] = t0[j] + step * h[j]
            tb[j] = t0[j] + (step + 1) * h[j]
            tm[j] = ta[j] + 0.5 * h[j]
        _lanes_program_force(programs, n_rows, ta, 1, pf_a)
        _lanes_program_force(programs, n_rows, tm, 1, pf_m)
        _lanes_program_force(programs, n_rows, tb, -1, pf_b)
        for j in range(LANES if gusty else 0):
            gust = gusts[j, : gust_rows[j]]
            for t, air in ((ta[j], ga_a), (tm[j], ga_m), (tb[j], ga_b)):
                air[j], air[LANES + j], air[2 * LANES + j] = gust_velocity(gust, gust_dt[j], t)
        _lanes_stage(x, sc0, inp, rate, attached, k_c, c, (pf_a, ga_a, drag), force, k1)
        _lanes_axpy(tmp, x, 0.5, h, k1)
        angle_trig_from_lanes(tmp, x, sc0, sc)
        _lanes_stage(tmp, sc, inp, rate, attached, k_c, c, (pf_m, ga_m, drag), force, k2)
        _lanes_axpy(tmp, x, 0.5, h, k2)
        angle_trig_from_lanes(tmp, x, sc0, sc)
        _lanes_stage(tmp, sc, inp, rate, attached, k_c, c, (pf_m, ga_m, drag), force, k3)
        _lanes_axpy(tmp, x, 1.0, h, k3)
        angle_trig_from_lanes(tmp, x, sc0, sc)
        _lanes_stage(tmp, sc, inp, rate, attached, k_c, c, (pf_b, ga_b, drag), force, k4)
        for i in range(x.shape[0]):
            tmp[i] = x[i]  # the step's start, for the next step's trigonometry
        for i in range(13):
            for j in range(n_lanes):
                e = i * LANES + j
                x[e] += h[j] / 6.0 * (k1[e] + 2.0 * k2[e] + 2.0 * k3[e] + k4[e])
        if step + 1 < n_sub:
            if (step + 1) % TRIG_CHAIN_STEPS == 0:
                angle_trig_lanes(x, sc0)
            else:
                angle_trig_from_lanes(x, tmp, sc0, sc)
                for i in range(sc0.shape[0]):
                    sc0[i] = sc[i]


@_jit_inline
def set_lane(lane_in, j, x_j, sc_j, inp_j, rate_j, t0_j, attached_j):
    """Lane j of ``rk4_lanes``'s inputs lane_in = (x, sc0, inp, rate, t0, attached) from one
    run's state x_j (13,), sin/cos of its angles sc_j (10,), held inputs inp_j (4,), reel
    rate, sample start [s] and tether state.

    Parameters
    ----------
    lane_in : tuple of numpy.ndarray
        ``rk4_lanes``'s (x, sc0, inp, rate, t0, attached), flat (variable, lane).
    j : int
        The lane.
    x_j : numpy.ndarray, shape (13,)
        The run's state [rad, m, rad/s, m/s, m].
    sc_j : numpy.ndarray, shape (10,)
        sin, cos of its angles.
    inp_j : numpy.ndarray, shape (4,)
        The held rotor inputs [N, N m, N m, N].
    rate_j : float
        The held reel rate [m/s].
    t0_j : float
        The sample's start [s].
    attached_j : float
        1: the tether is attached, 0: not.
    """
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
    its result is not used.

    Parameters
    ----------
    lane_in : tuple of numpy.ndarray
        ``rk4_lanes``'s (x, sc0, inp, rate, t0, attached), flat (variable, lane).
    j : int
        The lane.
    x_park : numpy.ndarray, shape (13,)
        The hover state [rad, m, rad/s, m/s, m].
    sc_park : numpy.ndarray, shape (10,)
        sin, cos of its angles.
    u_park : numpy.ndarray, shape (4,)
        The trim inputs [N, N m, N m, N].
    """
    set_lane(lane_in, j, x_park, sc_park, u_park, 0.0, 0.0, 0.0)


@compiled(error_model="numpy", nogil=True)
def run_lanes(x_init, n_samples, cfg_in, ctrl_in, c, law, wind, act, sensors, results):
    """Run a block of LANES closed loops together (unrecorded); lane j for n_samples[j]
    samples, none where n_samples[j] < 0 (padding).

    The arguments of ``run_closed_loop`` with a leading lane axis of length LANES, packed by
    ``batch.lane_block``: x_init (LANES, 13), cfg_in, ctrl_in, c (LANES, n_c), law (each part
    of ``layout.LAW_*`` with the lane axis in front), act, sensors = (noise (LANES, N,
    N_CHANNELS), noise rows in use (LANES,), source codes, arms, scratch (LANES, 4, 3),
    schedules (LANES, S, N_GROUPS) int, their rows in use, history rings (LANES, H,
    N_CHANNELS), their rows in use) (``runs.packing.sensor_tuple`` per lane);
    wind = (programs flat (R WIND_COLUMNS LANES,), R, gusts (LANES, G, 3), gust rows in use,
    drag (LANES, 3)).
    results = (summary (LANES, len(SUMMARY_FIELDS)), status, done (LANES,)) receive each lane's
    on-line metrics, status and samples done, as ``run_closed_loop`` returns them for a single
    run. Lanes may differ in every number but the RK4 steps per sample (cfg[:, CFG_N_SUB]) and
    the law (ctrl[:, CTRL_LAW]); they fly the helicopter (cfg[:, CFG_VEHICLE]).

    Each sample is ``lane_sample.lane_sample`` (sensors, controller, actuators, checks and
    metrics of every lane at once, each lane the single run's operations), then
    ``rk4_lanes`` advances all lanes at once. Massless tethers only: runs with a lumped
    tether go through ``run_closed_loop`` (``run_batch``). A lane that fails or completes
    keeps its result and flies on parked at its initial state (finite, cheap arithmetic)
    while the others go on.

    Parameters
    ----------
    x_init : numpy.ndarray, shape (LANES, 13)
        The lanes' initial states [rad, m, rad/s, m/s, m].
    n_samples : numpy.ndarray of int, shape (LANES,)
        Each lane's control samples (< 0: a padding lane).
    cfg_in : numpy.ndarray, shape (LANES, CFG_SIZE)
        The lanes' settings (``layout.CFG_*``).
    ctrl_in : numpy.ndarray, shape (LANES, CTRL_SIZE)
        The lanes' controller settings (``layout.CTRL_*``).
    c : numpy.ndarray, shape (LANES, n_c)
        The lanes' model constants.
    law : tuple of numpy.ndarray
        ``layout.LAW_*``, each with the lane axis in front.
    wind : tuple
        (programs flat (R WIND_COLUMNS LANES,), R, gusts (LANES, G, 3) [m/s], gust rows in
        use, drag (LANES, 3) [kg/m]).
    act : numpy.ndarray, shape (LANES, ACT_SIZE)
        The lanes' actuators (``layout.ACT_*``).
    sensors : tuple
        The lanes' sensors, ``runs.packing.sensor_tuple`` per lane with a lane axis.
    results : tuple of numpy.ndarray
        (summary (LANES, len(SUMMARY_FIELDS)), status (LANES,), done (LANES,)): receive each
        lane's on-line metrics (``layout.SUMMARY_*``), status code (``Status``) and samples
        done.
    """
    _wide_vectors()
    summary, status, done = results
    gain, x_ref, y_ref, u0, u0_free, z0 = law
    programs, n_rows, gusts, gust_rows, drag = wind
    n_sub = int(cfg_in[0, CFG_N_SUB])
    tether_law = ctrl_in[0, CTRL_LAW] == CONTROL_LAW_TETHER_LQI
    for j in range(LANES):
        if int(cfg_in[j, CFG_N_SUB]) != n_sub:
            raise ValueError("run_lanes: every lane must take the same RK4 steps per sample")
        if (ctrl_in[j, CTRL_LAW] == CONTROL_LAW_TETHER_LQI) != tether_law:
            raise ValueError("run_lanes: every lane must fly the same law")
        if cfg_in[j, CFG_VEHICLE] != VEHICLE_HELICOPTER:
            raise ValueError("run_lanes: the lane engine flies the helicopter only")
    if gain.shape[2] != (17 if tether_law else 16):  # the laws' shapes (``check_law``)
        raise ValueError("run_lanes: a gain of another law's shape")
    noise_rows = sensors[1]
    lanes_sensed = noise_rows > 0
    lanes_drum = act[:, ACT_DRUM] > 0.5
    x = np.empty(13 * LANES)  # the lanes' states, flat (variable, lane)
    for j in range(LANES):
        for i in range(13):
            x[i * LANES + j] = x_init[j, i]
    c_lanes = np.empty(c.shape[1] * LANES)
    drag_lanes = np.empty(3 * LANES)
    for j in range(LANES):
        for i in range(c.shape[1]):
            c_lanes[i * LANES + j] = c[j, i]
        for i in range(3):
            drag_lanes[i * LANES + j] = drag[j, i]
    state = lane_state(cfg_in, ctrl_in, act, z0, x, lanes_sensed.any(), summary.shape[1])
    lane_law_ = lane_law(gain, x_ref, y_ref, u0, u0_free, tether_law)
    rows = (np.empty(13), np.empty(13), np.empty(HELD_SIZE), np.empty(ACT_SIZE))
    gust_dt = np.empty(LANES)
    work = lane_work()
    rate = np.zeros(LANES)
    t0 = np.zeros(LANES)
    h = np.empty(LANES)
    attached = np.empty(LANES)
    k_c = np.empty(2 * LANES)
    sc_init = np.empty(10 * LANES)
    angle_trig_lanes(x, sc_init)
    active = np.zeros(LANES, np.bool_)
    for j in range(LANES):
        start_summary(summary[j])
        status[j] = STATUS_OK
        done[j] = max(n_samples[j] + 1, 0)
        h[j] = cfg_in[j, CFG_DT] / n_sub
        k_c[j] = cfg_in[j, CFG_K_C]
        k_c[LANES + j] = cfg_in[j, CFG_TETHER_EA]
        gust_dt[j] = cfg_in[j, CFG_GUST_DT]
        active[j] = n_samples[j] >= 0
    for f in range(summary.shape[1]):
        for j in range(LANES):
            state.summary[f * LANES + j] = summary[j, f]
    # borrowed views (``_compile.borrowed``) of the run's arrays, held to the end by
    # ``keep_alive``: the loop's phases take views of them per sample, which would otherwise
    # each be an atomic reference count
    own = (x, c_lanes, drag_lanes, state, lane_law_, rows, gust_dt, work, rate, t0, h, attached,
           k_c, sc_init, active)  # fmt: skip
    (x, c_lanes, drag_lanes, state, lane_law_, rows, gust_dt, work, rate, t0, h, attached, k_c,
     sc_init, active) = borrowed(own)  # fmt: skip
    x_init, n_samples, act, summary, status, done = borrowed(
        (x_init, n_samples, act, summary, status, done)
    )
    programs, n_rows, gusts, gust_rows = borrowed((programs, n_rows, gusts, gust_rows))
    sensors, lanes_sensed, lanes_drum = borrowed((sensors, lanes_sensed, lanes_drum))
    lane_wind = LaneWind(programs, n_rows, gusts, gust_rows, gust_dt, drag_lanes)
    cfg = state.cfg
    n_active = 0
    for j in range(LANES):
        n_active += 1 if active[j] else 0
    k = plain(0)  # an int64 from the start (a literal 0 would compile callees twice)
    while n_active > 0:
        lane_sample(k, x, state, lane_law_, c_lanes, active, (lanes_sensed, sensors),
                    lanes_drum, rows, tether_law)  # fmt: skip
        for j in range(LANES):
            if not active[j]:
                continue
            sample_status = int(state.status[j])
            if sample_status != STATUS_OK or k == n_samples[j]:
                if sample_status != STATUS_OK:
                    status[j], done[j] = sample_status, k
                active[j] = False
                n_active -= 1
                _finish_lane(j, state, summary)
        if n_active == 0:
            break
        # the RK4's inputs: a running lane's own, a finished or padding lane parked at its
        # initial state with no tether (its result is kept; the arithmetic stays finite)
        for j in range(LANES):
            running = active[j]
            rate[j] = state.rate[j] if running else 0.0
            t0[j] = k * cfg[CFG_DT * LANES + j] if running else 0.0
            attached[j] = cfg[CFG_ATTACHED * LANES + j] if running else 0.0
        if n_active < LANES:  # some lane parked
            for i in range(13):
                for j in range(LANES):
                    e = i * LANES + j
                    x[e] = x[e] if active[j] else x_init[j, i]
            for i in range(10):
                for j in range(LANES):
                    e = i * LANES + j
                    state.loop.sc_true[e] = state.loop.sc_true[e] if active[j] else sc_init[e]
            for i in range(4):
                for j in range(LANES):
                    e = i * LANES + j
                    state.loop.inputs[e] = state.loop.inputs[e] if active[j] else u0[j, i]
        loop = state.loop
        rk4_lanes((x, loop.sc_true, loop.inputs, rate, t0, attached), h, n_sub, k_c, c_lanes,
                  lane_wind, work)  # fmt: skip
        k += 1
    keep_alive(own)


@_jit_inline
def _finish_lane(j, state, summary):
    """Lane j's result into its row of summary (LANES, len(SUMMARY_FIELDS)): its on-line
    metrics, release event and first payout limit (``summary.finish_summary``'s)."""
    for f in range(summary.shape[1]):
        summary[j, f] = state.summary[f * LANES + j]
    summary[j, SUMMARY_RELEASE_TIME] = state.loop.event[j]
    summary[j, SUMMARY_RELEASE_TENSION] = state.loop.event[LANES + j]
    held = state.scratch[:HELD_SIZE]  # the lane's held row (``winch_limit_into`` reads it)
    for i in range(HELD_SIZE):
        held[i] = state.loop.held[i * LANES + j]
    winch_limit_into(held, summary[j])


# --- a block of runs packed for the lanes (``run_lanes``'s leading arguments) --------------


def lane_program_into(programs: np.ndarray, j: int, program: np.ndarray) -> None:
    """Lane j of a block's wind programs ``programs`` (rows, WIND_COLUMNS, LANES): the run's
    profile rows ``program`` (k, WIND_COLUMNS), k <= rows, then padding rows of zero force (a
    constant of magnitude 0, which adds +0 to the force).

    Parameters
    ----------
    programs : numpy.ndarray, shape (rows, WIND_COLUMNS, LANES)
        The block's wind programs; lane ``j`` is overwritten.
    j : int
        Lane index, 0 <= j < LANES.
    program : numpy.ndarray, shape (k, WIND_COLUMNS)
        The run's profile rows (``CompiledWind.program``), k <= rows.
    """
    programs[:, :, j] = 0.0
    programs[:, WIND_KIND, j] = WIND_CONSTANT
    programs[: program.shape[0], :, j] = program
