"""Every packed float64 array the compiled code passes around, with its named slots.

Compiled functions take flat arrays rather than objects, so that one compiled function serves
every scenario and Numba's on-disk cache survives between processes. This module is the one
place that says what each slot holds; code elsewhere addresses slots only by these names.
Importing it does not import Numba.
"""

from __future__ import annotations

import math
import os
from typing import NamedTuple

import numpy as np

__all__ = [
    "ACT_SIZE",
    "CFG_SIZE",
    "CTRL_SIZE",
    "LANES",
    "SUMMARY_FIELDS",
    "WIND_COLUMNS",
    "Gear",
    "LaneWind",
    "LoopState",
    "Run",
    "Scratch",
    "Signals",
    "WindPack",
    "default_actuators",
    "empty_chain",
    "no_gear",
]

# --- the lane engine (``engine.lanes.run_lanes``) ---------------------------------------------
#: runs advanced together in one block; the lane arrays are flat, element (variable i, lane j)
#: at i * LANES + j. A constant of the compiled code, chosen by ``benchmarks/bench_lanes.py``
#: (large enough to fill the vector units, small enough that a block's arrays stay in the
#: first-level cache and few lanes idle as padding); ``TETHERHELI_LANES`` overrides it for
#: such measurements (the compile cache keys on it).
DEFAULT_LANES = 16
LANES = int(os.environ.get("TETHERHELI_LANES", DEFAULT_LANES))
if not 1 <= LANES <= 256:
    raise ValueError(f"TETHERHELI_LANES = {LANES}: allowed 1 to 256")

# --- run configuration (``cfg``) ----------------------------------------------------------------
CFG_DT = 0  # control sample time [s]
CFG_N_SUB = 1  # RK4 steps per sample
CFG_K_C = 2  # tether elasticity KC [N/m] (eq 28; the rope's law: CFG_TETHER_EA)
CFG_ATTACHED = 3  # 1: tether attached, 0: removed (free configuration) or released
CFG_MAX_TENSION = 4  # [N]; a run stops when exceeded
CFG_MAX_DEVIATION = 5  # [m]; a run stops as diverged when |y - y_ref| exceeds it
CFG_MAX_ANGLE = 6  # [rad]; |q4|, |q5|, |q7|, |q8| beyond it: diverged
CFG_GUST_DT = 7  # gust-table step [s] (0: no gust table)
CFG_METRICS_FROM = 8  # first control sample k the on-line metrics cover (Scenario.metrics_start)
CFG_LUMPED = 9  # 1: the lumped-mass tether (``chain``) pulls P, 0: eq 28's massless tether
CFG_ARM = 10  # dO-P,3 - dO-HO,3 [m], the arm of the force at P (lumped tether)
CFG_TENSION_TOP = 11  # the lumped chain's tension at P at this sample [N] (set by the engine)
CFG_TENSION_GROUND = 12  # ... and at the winch [N], which the load cell measures
#: the vehicle flown (``VEHICLES``; 0, the default, the paper's helicopter): the engine's
#: vehicle slot (``engine.loop.vehicle_derivative``, ``vehicle_outputs``) dispatches on it
CFG_VEHICLE = 13
#: the massless tether's law (``params.TetherParams``): the rope's axial stiffness EA [N],
#: tension EA (q9 - LN) / LN; 0: the paper's eq 28 with CFG_K_C (``kernels.tether_tension``)
CFG_TETHER_EA = 14
CFG_SIZE = 15

# --- the vehicles the engine's vehicle slot flies (``cfg[CFG_VEHICLE]``), chosen by name ----
#: the vehicles by code: the paper's single-rotor helicopter (the generated tethered model,
#: ``model.kernels``), and a multirotor (code reserved: its kernel,
#: ``multirotor_derivative(p, s, cmd, wind, f_p, out)``, enters at the vehicle slot)
VEHICLES = ("helicopter", "multirotor")
VEHICLE_HELICOPTER = VEHICLES.index("helicopter")
VEHICLE_MULTIROTOR = VEHICLES.index("multirotor")
#: the vehicles whose kernels the engine's vehicle slot holds today
VEHICLES_FLOWN = (VEHICLE_HELICOPTER,)

# --- the plant's state x (13,) and its angles' sin, cos (10,), by name -----------------------
#: the state [q4..q9, u1..u6, LN] (``docs/notation.md``): the attitude angles q4 (roll), q5
#: (pitch), q6 (yaw), the tether's angles q7, q8 and length q9 (HO's distance from the winch)
X_Q4, X_Q5, X_Q6, X_Q7, X_Q8, X_Q9 = range(6)
X_U1 = 6  # (3,) HO's velocity u1..u3 in N [m/s]
X_U4 = 9  # (3,) the body rates u4..u6 [rad/s]
X_LN = 12  # the tether's natural length LN [m]
X_SIZE = 13
#: sin, cos of the angles x[X_Q4..X_Q8] (``model.kernels.angle_trig``): sines first, then
#: cosines, in the angles' order
SC_SIN = 0
SC_COS = 5
SC_SIZE = 10

#: A base motion's packed form (``base.compiled``), one float64 array of BASE_COLUMNS columns.
#: Row 0: counts and the constant parts
BASE_WAVES = 0  # number of sinusoid rows (rows 1 .. BASE_WAVES)
BASE_KNOTS = 1  # number of spline knot rows (after the sinusoids)
BASE_OFFSET = 2  # (3,) b at t = 0 of the linear part [m]
BASE_VELOCITY = 5  # (3,) the constant velocity [m/s]
BASE_MOVING = 8  # 1: the base moves (the engine flies in its frame), 0: the paper's still winch
#: the helicopter's mass m [kg] on which the base frame's inertial force -m b'' acts (set by the
#: run's set-up: ``runs.setup``)
BASE_MASS = 9
#: a sinusoid row: amplitude sin(omega t + phase) on one axis of N
BASE_WAVE_AXIS = 0  # 0, 1, 2: n1, n2, n3
BASE_WAVE_AMPLITUDE = 1  # [m]
BASE_WAVE_OMEGA = 2  # [rad/s]
BASE_WAVE_PHASE = 3  # [rad]
#: a knot row: its time and the cubic's coefficients on [t_k, t_k+1), c0 h^3 + c1 h^2 + c2 h + c3
BASE_KNOT_TIME = 0  # [s]
BASE_CUBIC = 1  # (4, 3) c0..c3 for n1, n2, n3, row-major
BASE_COLUMNS = 13

# --- a run's lumped-mass chain (``chain``, ``engine.loop``): a tuple of arrays; a massless run
# passes ``empty_chain()``'s (zero rows), so the compiled types agree -------------------------
CHAIN_NODES = 0  # (N+1, 3) node positions [m], row 0 the winch (origin), row N the point P
CHAIN_VELOCITIES = 1  # (N+1, 3) node velocities [m/s]
CHAIN_PARAMS = 2  # (LUMPED_SIZE,) ``LumpedTether.packed(g)``
CHAIN_WORK = 3  # ``tether.lumped.ros2_work(N)``
CHAIN_SIZE = 4

# --- the lumped-mass tether's parameters (``lumped``, ``tether.chain.LumpedTether``) -----
LUMPED_MU = 0  # mass per unstretched length [kg/m]
LUMPED_EA = 1  # axial stiffness EA [N]
LUMPED_DAMPING = 2  # a segment's axial dashpot from the damping ratio [N s/m] (any length)
LUMPED_CDN = 3  # 0.5 rho d Cd: normal drag per length per speed^2 [kg/m^2]
LUMPED_CDT = 4  # 0.5 rho pi d Ct: tangential drag per length per speed^2 [kg/m^2]
LUMPED_G = 5  # gravity [m/s^2], along -n3
LUMPED_BA = 6  # internal damping BA [N s]: a segment's dashpot is BA / l0 [N s/m]
#: the ground z = 0 under the free nodes (MoorDyn's seabed): normal stiffness and damping per
#: unit penetration of a node's contact patch d l0 (kbot d [N/m^2], cbot d [N s/m^2]), and the
#: regularised Coulomb friction: coefficient mu_f and the speed below which it is viscous [m/s]
LUMPED_GROUND_K = 7
LUMPED_GROUND_C = 8
LUMPED_FRICTION = 9
LUMPED_FRICTION_SPEED = 10
#: (3,) the base's acceleration b'' [m/s^2] over the step (a moving winch, ``base``): the chain
#: is flown in the base's translating frame, where each free node feels -m b''
LUMPED_BASE_ACC = 11
LUMPED_SIZE = 14
# the ground's default constants (``LumpedTether``, ``[tether] ground_*``)
#: the ground's normal stiffness kbot [Pa/m]: MoorDyn's default seabed (3e6 Pa/m); the
#: default cable (20 g/m, 5 mm) then sinks in by mu g / (kbot d) = 13 um and its contact
#: mode has sqrt(kbot d / mu) = 866 rad/s
GROUND_STIFFNESS_PA_M = 3.0e6
#: the ground's normal damping cbot [Pa s/m]: 2 sqrt(kbot mu / d) rounded, the critically
#: damped contact of the default cable (MoorDyn's 3e5 Pa s/m, sized for heavy mooring
#: lines, would be 43 times critical here)
GROUND_DAMPING_PA_S_M = 7.0e3
#: Coulomb friction coefficient of cable on ground (soil, grass: about 0.5; MoorDyn's
#: default is none)
GROUND_FRICTION = 0.5
#: the friction's regularisation speed v_f [m/s]: viscous below it, mu_f F_n / v_f per
#: m/s (MoorDyn's FricDamp plays the same part)
GROUND_FRICTION_SPEED_M_S = 0.01

# --- the paper controller's settings (``ctrl``, ``control.paper``) ---------------------------
CTRL_DT = 0  # sample time [s]
CTRL_FFWD = 1  # 1: tether-torque feed-forward on (eq 55)
CTRL_WINCH = 2  # 1: winch PI loop runs (eq 56)
CTRL_T_REF = 3  # [N]
CTRL_K_P = 4
CTRL_K_I = 5
CTRL_REEL_RATE_LIMIT = 6  # [m/s] (inf: none)
CTRL_REEL_ACCEL = 7  # |d(reel rate)/dt| the winch allows [m/s^2] (inf: none)
CTRL_ANTI_WINDUP = 8  # 1: the integrators hold while a rotor command is outside its limits
CTRL_U_MIN = 9  # (4,) the rotor inputs' limits the anti-windup compares with (= act's)
CTRL_U_MAX = 13  # (4,)
#: the tethered LQI's tether length from the load cell and the drum encoder, q9 = LN + TC / KC
#: (eq 28), with this design KC [N/m] while taut; 0: q9 from the position source
CTRL_TENSION_K_C = 17
#: the compiled law, by name: ``CONTROL_LAWS.index(name)`` ([control] controller)
CTRL_LAW = 18
CTRL_SIZE = 19
#: the compiled laws ``ctrl[CTRL_LAW]`` names, by code: the paper's LQI with feed-forward and
#: winch PI (gain (4, 16)), and the tethered LQI (gain (9, 17), ``control.tether_lqi``)
CONTROL_LAWS = ("paper", "tether_lqi")
CONTROL_LAW_PAPER = CONTROL_LAWS.index("paper")
CONTROL_LAW_TETHER_LQI = CONTROL_LAWS.index("tether_lqi")
#: the gain's shape each compiled law takes (``layout.LAW_GAIN``), by code
CONTROL_LAW_GAIN_SHAPES = ((4, 16), (9, 17))

# --- the winch PI's state (``winch``, ``control.paper``) ---------------------------------------
WINCH_INTEGRAL = 0  # I_k of eq 56 [N s]
WINCH_PREVIOUS_RATE = 1  # the reel rate commanded at the previous sample [m/s]
WINCH_SIZE = 2

# --- what the actuators hold between samples (``held``, ``engine.loop.actuate``) ---------------
HELD_INPUTS = 0  # (4,) the rotor inputs applied over the last sample (the lag's state)
HELD_REEL_RATE = 4  # the reel rate applied over the last sample [m/s] (the winch starts at rest)
#: the drum winch (``[winch] model = "drum"``, ``tether.winch``; zero for the ideal winch):
HELD_DRUM_SPEED = 5  # the drum's speed w [rad/s], advanced by ``actuate`` to the next sample
HELD_DRUM_SPEED_SAMPLED = 6  # w at the sample's instant, before that update [rad/s]
HELD_MOTOR_TORQUE = 7  # the motor torque averaged over the last sample [N m]
#: the payout limits (``[winch] min_length``, ``max_length``; ``engine.loop.actuate``): the limit
#: the reel is stopped at now (-1 min_length, +1 max_length, 0 none), the first stop's limit
#: (0: none yet) and time [s] (the sample at whose end the length reaches the limit)
HELD_AT_LIMIT = 8
HELD_LIMIT_WHICH = 9
HELD_LIMIT_TIME = 10
HELD_SIZE = 11


# --- the signals a run records (``engine.loop.run_closed_loop``'s ``out``) -------------------
class Signals(NamedTuple):
    """The arrays a run records into, one row per control sample (a named record: the
    compiled code reads them by name).

    Parameters
    ----------
    x : numpy.ndarray, shape (rows, 13)
        The true state.
    u, ffwd : numpy.ndarray, shape (rows, 4)
        The applied rotor inputs (with the feed-forward) and the feed-forward part.
    rate, tension : numpy.ndarray, shape (rows,)
        The applied reel rate [m/s] and the true tension at P [N].
    wind : numpy.ndarray, shape (rows, 3)
        The wind force at the sample [N].
    y, y_est : numpy.ndarray, shape (rows, 4)
        The true outputs and the controller's estimate of them.
    tension_ground : numpy.ndarray, shape (rows,)
        The tension at the winch [N] (the tension, for the massless tether).
    nodes : numpy.ndarray, shape (rows, N + 1, 3) or (0, 0, 3)
        A lumped chain's node positions (none recorded when empty).
    winch : numpy.ndarray, shape (rows, 2) or (1, 2)
        The drum's speed at the sample [rad/s] and mean motor torque after it [N m] (one
        unused row without a drum winch).
    """

    x: np.ndarray
    u: np.ndarray
    ffwd: np.ndarray
    rate: np.ndarray
    tension: np.ndarray
    wind: np.ndarray
    y: np.ndarray
    y_est: np.ndarray
    tension_ground: np.ndarray
    nodes: np.ndarray
    winch: np.ndarray

    @classmethod
    def zeros(cls, rows: int, *, drum: bool = False, nodes: int = 0) -> Signals:
        """Zeroed arrays for ``rows`` samples.

        Parameters
        ----------
        rows : int
            Samples to record (n_samples + 1; 1 for a run that records nothing).
        drum : bool, optional
            Whether the drum winch's signals are recorded.
        nodes : int, optional
            A lumped chain's nodes to record (0: none).

        Returns
        -------
        Signals
            The arrays, float64, C-ordered.
        """
        return cls(
            x=np.zeros((rows, 13)), u=np.zeros((rows, 4)), ffwd=np.zeros((rows, 4)),
            rate=np.zeros(rows), tension=np.zeros(rows), wind=np.zeros((rows, 3)),
            y=np.zeros((rows, 4)), y_est=np.zeros((rows, 4)), tension_ground=np.zeros(rows),
            nodes=np.zeros((rows, nodes, 3) if nodes else (0, 0, 3)),
            winch=np.zeros((rows if drum else 1, 2)),
        )  # fmt: skip

    @classmethod
    def floats_per_row(cls, *, drum: bool = False, nodes: int = 0) -> int:
        """The floats one more sample adds to ``zeros``' arrays (a memory estimate's unit).

        Parameters
        ----------
        drum, nodes
            As for ``zeros``.

        Returns
        -------
        int
        """
        two, one = cls.zeros(2, drum=drum, nodes=nodes), cls.zeros(1, drum=drum, nodes=nodes)
        return sum(a.size for a in two) - sum(a.size for a in one)


# --- one run's loop state (``engine.loop.new_loop_state``): a tuple of arrays -------------------
LOOP_Z = 0  # (4,) the LQI's output-error integral (eq 50)
LOOP_WINCH = 1  # (WINCH_SIZE,) the winch PI's state
LOOP_HELD = 2  # (HELD_SIZE,) what the actuators hold between samples
LOOP_EVENT = 3  # (2,) the tether release: time [s], tension [N]; NaN without one
LOOP_X_MEAS = 4  # (13,) the measured state
LOOP_SC_MEAS = 5  # (10,) sin, cos of the measured angles
LOOP_SC_TRUE = 6  # (10,) sin, cos of the true angles (rk4_interval's first stage reads them)
LOOP_Y = 7  # (4,) the true outputs q1, q2, q3, q6
LOOP_Y_EST = 8  # (4,) the controller's output estimate
LOOP_INPUTS = 9  # (4,) the applied rotor inputs
LOOP_FFWD = 10  # (4,) the feed-forward part of the inputs (eq 55)
LOOP_SIZE = 11


class LoopState(NamedTuple):
    """One run's per-sample state of the control phases (``engine.loop.new_loop_state``), in
    the order of ``LOOP_*``: a named record (fields by name in compiled code, by the
    ``LOOP_*`` index where a tuple is expected).

    Parameters
    ----------
    z : numpy.ndarray, shape (4,)
        The LQI's output-error integral (eq 50).
    winch : numpy.ndarray, shape (WINCH_SIZE,)
        The winch PI's state.
    held : numpy.ndarray, shape (HELD_SIZE,)
        What the actuators hold between samples.
    event : numpy.ndarray, shape (2,)
        The tether release: time [s], tension [N]; NaN without one.
    x_meas : numpy.ndarray, shape (13,)
        The measured state.
    sc_meas, sc_true : numpy.ndarray, shape (10,)
        sin, cos of the measured and of the true angles.
    y, y_est : numpy.ndarray, shape (4,)
        The true outputs q1, q2, q3, q6 and the controller's estimate of them.
    inputs, ffwd : numpy.ndarray, shape (4,)
        The applied rotor inputs and their feed-forward part (eq 55).
    """

    z: np.ndarray
    winch: np.ndarray
    held: np.ndarray
    event: np.ndarray
    x_meas: np.ndarray
    sc_meas: np.ndarray
    sc_true: np.ndarray
    y: np.ndarray
    y_est: np.ndarray
    inputs: np.ndarray
    ffwd: np.ndarray


class WindPack(NamedTuple):
    """The wind of one run as the compiled engine takes it (``runs.setup.EngineSetup``): a
    named record, in one shape for every single-run entry (an empty program for a Python
    disturbance, no gust rows without a gust table).

    Parameters
    ----------
    program : numpy.ndarray, shape (rows, WIND_COLUMNS)
        The wind program (``WIND_*``), one row per built-in profile.
    gust : numpy.ndarray, shape (rows, 3)
        The gust table: the air's velocity [m/s] every cfg[CFG_GUST_DT] [s] (no rows: none).
    drag : numpy.ndarray, shape (3,)
        The bluff-body drag 0.5 rho CdA_i per axis of N [kg/m].
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``BASE_*``, ``base.compiled``).
    """

    program: np.ndarray
    gust: np.ndarray
    drag: np.ndarray
    base: np.ndarray


class LaneWind(NamedTuple):
    """The winds of a block of ``LANES`` runs in the lane engine's form
    (``engine.lanes.rk4_lanes``): a named record, flat (variable, lane) where a lane axis is
    last.

    Parameters
    ----------
    programs : numpy.ndarray, shape (R WIND_COLUMNS LANES,)
        The lanes' wind programs (``WIND_*``), flat, R rows each (unused rows inert).
    n_rows : int
        R, the program rows.
    gusts : numpy.ndarray, shape (LANES, G, 3)
        The lanes' gust tables: the air's velocity [m/s].
    gust_rows : numpy.ndarray of int, shape (LANES,)
        The gust rows in use per lane (0: none).
    gust_dt : numpy.ndarray, shape (LANES,)
        The gust tables' step per lane [s] (0: none).
    drag : numpy.ndarray, shape (3 LANES,)
        The bluff-body drag 0.5 rho CdA_i per axis of N and lane [kg/m].
    """

    programs: np.ndarray
    n_rows: int
    gusts: np.ndarray
    gust_rows: np.ndarray
    gust_dt: np.ndarray
    drag: np.ndarray


class Run(NamedTuple):
    """One run's constants as the compiled engine's phases take them (``engine.loop``): a
    named record, built once per run (the compiled loop's own, ``stepping.StepRun``'s).

    Parameters
    ----------
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``CFG_*``), the run's own copy (a release switches it).
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The paper controller's settings (``CTRL_*``), the run's own copy.
    c : numpy.ndarray
        The vehicle's model constants (``kernels.model_constants("tethered", h)``).
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``ACT_*``).
    law : tuple of numpy.ndarray
        The compiled law's arrays (``LAW_*``).
    wind : WindPack
        The wind.
    sensors : tuple
        ``runs.packing.sensor_tuple``'s (noise, source code, arm, scratch, schedule, history
        ring).
    chain : tuple of numpy.ndarray
        The lumped chain (``CHAIN_*``; ``empty_chain()``: the massless tether).
    gear : Gear or tuple
        The landing gear (``Gear``; ``no_gear()``: none); an empty tuple in the records of
        the phases that do not integrate (``engine.loop.control_run``).
    """

    cfg: np.ndarray
    ctrl: np.ndarray
    c: np.ndarray
    act: np.ndarray
    law: tuple
    wind: WindPack
    sensors: tuple
    chain: tuple
    gear: Gear | tuple


class Gear(NamedTuple):
    """The landing gear of one run as the engine's vehicle slot takes it
    (``engine.loop.vehicle_derivative``): its points, contact law and scratch; no points
    (``no_gear()``): no gear, the same types (one compiled signature).

    Parameters
    ----------
    points : numpy.ndarray, shape (n, 3)
        The gear points from HO in F [m] (n = 0: no gear).
    law : numpy.ndarray, shape (GEAR_LAW_SIZE,)
        The contact law (``GEAR_LAW_*``).
    tail : numpy.ndarray, shape (2,)
        TRO from HO in F, its f1 and f3 offsets [m] (``model.contact.tail_lever``).
    work : numpy.ndarray, shape (GEAR_WORK_SIZE,)
        Scratch (``GEAR_WORK_*``); its deck slots hold the level deck through the base.
    penetration : numpy.ndarray, shape (n,)
        Scratch: each point's penetration [m].
    lock : numpy.ndarray, shape (n, LOCK_SIZE)
        The deck lock (``LOCK_*``): which points are held and where (set from Python by a
        landing's ``runs.landing.Touchdown``; all zero: none held).
    """

    points: np.ndarray
    law: np.ndarray
    tail: np.ndarray
    work: np.ndarray
    penetration: np.ndarray
    lock: np.ndarray


def no_gear() -> Gear:
    """The ``Gear`` of a run without landing gear: no points.

    Returns
    -------
    Gear
        Empty points, penetration and lock, zero law, tail and scratch.
    """
    return Gear(
        np.zeros((0, 3)), np.zeros(GEAR_LAW_SIZE), np.zeros(2), np.zeros(GEAR_WORK_SIZE),
        np.zeros(0), np.zeros((0, LOCK_SIZE)),
    )  # fmt: skip


class Scratch(NamedTuple):
    """One run's scratch arrays in the compiled engine (``engine.loop``).

    Parameters
    ----------
    work : numpy.ndarray, shape (RK4_WORK_ROWS, 13)
        The integrator's scratch (``engine.loop.rk4_interval``).
    cw : tuple
        A lumped chain's scratch (``engine.lumped_step.lumped_work``; unread when massless).
    no_action : numpy.ndarray, shape (4,)
        Zeros: the compiled law's action slot left empty.
    """

    work: np.ndarray
    cw: tuple | np.ndarray
    no_action: np.ndarray


# --- the paper controller's law (``law``, ``engine.loop.paper_sample``): a tuple of arrays ------
#: (4, 16) K_LQI|F (eqs 47-53), columns [q4..u6 (12); z (4)]; or, for the tethered LQI
#: (``control.tether_lqi``), (9, 17) on columns [q4..u6, LN (13); z (4)]: rows 0-4 the
#: tethered law (four rotor inputs, then the reel rate, which replaces the winch PI), rows 5-8
#: the free law flown after a release (its LN column zero)
LAW_GAIN = 0
#: (12,) the trim state q4..u6 (the same for the free and the tethered trim); (13,) with LN
#: for the tethered LQI
LAW_X_REF = 1
LAW_Y_REF = 2  # (4,) the trim outputs q1, q2, q3, q6
LAW_U0 = 3  # (4,) the configuration's trim input u0 (u0|T tethered, u0|F free; eq 54)
LAW_U0_FREE = 4  # (4,) u0|F: used once the tether is released or removed
LAW_Z0 = 5  # (4,) the LQI integrators' state at the start (``runs.start.start_point``)
LAW_SIZE = 6

# --- actuators (``act``) ------------------------------------------------------------------------
ACT_U_MIN = 0  # (4,) lower input limits [N, N m, N m, N]
ACT_U_MAX = 4  # (4,) upper input limits
ACT_TAU = 8  # first-order actuator time constant [s] (0: none)
ACT_BREAK = 9  # tether breaking / release tension [N] (inf: never)
ACT_REEL_ACCEL = 10  # |d(reel rate)/dt| bound of the winch [m/s^2] (inf: none)
#: the drum winch (``scenario.core.WinchSettings``, ``tether.winch.drum_step``)
ACT_DRUM = 11  # 1: the drum winch, 0: the ideal winch (the reel rate applied as commanded)
ACT_DRUM_RADIUS = 12  # r [m]
ACT_DRUM_INERTIA = 13  # J, drum and motor reflected [kg m^2]
ACT_DRUM_TORQUE_LIMIT = 14  # tau_max [N m]
ACT_DRUM_VISCOUS = 15  # b [N m s/rad]
ACT_DRUM_COULOMB = 16  # tau_c [N m]
ACT_DRUM_SPEED_GAIN = 17  # K_w = J omega_w, the speed loop's gain [N m s/rad]
ACT_DRUM_TENSION_FFWD = 18  # 1: the drive adds the load cell's torque r T_meas
#: the payout limits of both winch models [m]: the natural length L_N = x[12] stays within
#: [min, max]; reaching one stops the reel (``engine.loop.actuate``)
ACT_MIN_LENGTH = 19
ACT_MAX_LENGTH = 20
#: |reel rate| bound of the winch [m/s] (``[actuators] reel_rate_limit``; inf: none): the
#: actuator stage clamps every controller's reel-rate command to it, feed-forward included
ACT_REEL_RATE = 21
ACT_SIZE = 22


def empty_chain() -> tuple:
    """The ``chain`` of a run with the massless tether: arrays with zero nodes.

    Returns
    -------
    tuple of numpy.ndarray
        (nodes (0, 3), velocities (0, 3), params (LUMPED_SIZE,), work (0,)), ``CHAIN_*``.
    """
    return (np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(LUMPED_SIZE), np.zeros(0))


#: the shortest natural length the winch reels in to by default [m] (``[winch] min_length``):
#: the lower end of ``params.TETHER_LENGTH_RANGE``, the closest the helicopter is flown to
#: the winch; a positive length, so no natural length reaches zero
WINCH_MIN_LENGTH_M = 0.5


def default_actuators() -> np.ndarray:
    """Ideal actuators: no limits, no lag, an unbreakable tether.

    Returns
    -------
    numpy.ndarray, shape (ACT_SIZE,)
        The actuator array (``ACT_*``): input bounds at -inf/+inf, breaking tension,
        reel acceleration and the longest payout infinite, the shortest
        ``WINCH_MIN_LENGTH_M``, all else 0.
    """
    act = np.zeros(ACT_SIZE)
    act[ACT_U_MIN : ACT_U_MIN + 4] = -math.inf
    act[ACT_U_MAX : ACT_U_MAX + 4] = math.inf
    act[ACT_BREAK] = math.inf
    act[ACT_REEL_ACCEL] = math.inf
    act[ACT_REEL_RATE] = math.inf
    act[ACT_MIN_LENGTH] = WINCH_MIN_LENGTH_M
    act[ACT_MAX_LENGTH] = math.inf
    return act


# --- wind program (``program``): one row per built-in profile --------------------------------
WIND_PULSE, WIND_SINE, WIND_STEP, WIND_CONSTANT = 0, 1, 2, 3
#: columns: kind, start [s], duration [s], magnitude [N], frequency [Hz], phase [rad], n1, n2, n3
WIND_KIND, WIND_START, WIND_DURATION, WIND_MAGNITUDE, WIND_FREQUENCY, WIND_PHASE = range(6)
WIND_DIRECTION = 6  # (3,) unit direction in N
WIND_COLUMNS = 9

# --- on-line metrics of a run (``summary``) -----------------------------------------------------
SUMMARY_FIELDS = (
    "peak_q1", "peak_q2", "peak_q3", "peak_q4", "peak_q5",
    "sumsq_q1", "sumsq_q2", "sumsq_q3", "tension_min", "tension_max", "n_samples",
    "release_time", "release_tension", "winch_limit_time", "winch_limit",
)  # fmt: skip
SUMMARY_PEAK_Q1 = SUMMARY_FIELDS.index("peak_q1")  # (3,) max |q1..q3 - trim| [m]
SUMMARY_PEAK_Q4 = SUMMARY_FIELDS.index("peak_q4")  # max |q4 - trim| [rad]
SUMMARY_PEAK_Q5 = SUMMARY_FIELDS.index("peak_q5")  # max |q5 - trim| [rad]
SUMMARY_SUMSQ_Q1 = SUMMARY_FIELDS.index("sumsq_q1")  # (3,) sum of (q1..q3 - trim)^2 [m^2]
SUMMARY_TENSION_MIN = SUMMARY_FIELDS.index("tension_min")  # [N]
SUMMARY_TENSION_MAX = SUMMARY_FIELDS.index("tension_max")  # [N]
SUMMARY_N_SAMPLES = SUMMARY_FIELDS.index("n_samples")  # samples accumulated
#: the tether-release event: the sample time [s] at which the safety device released the
#: tether and the tension [N] that exceeded the breaking tension; both NaN without a release
SUMMARY_RELEASE_TIME = SUMMARY_FIELDS.index("release_time")
SUMMARY_RELEASE_TENSION = SUMMARY_FIELDS.index("release_tension")
assert SUMMARY_FIELDS[SUMMARY_PEAK_Q1 : SUMMARY_PEAK_Q1 + 3] == ("peak_q1", "peak_q2", "peak_q3")
assert SUMMARY_FIELDS[SUMMARY_SUMSQ_Q1 : SUMMARY_SUMSQ_Q1 + 3] == (
    "sumsq_q1",
    "sumsq_q2",
    "sumsq_q3",
)
assert SUMMARY_RELEASE_TENSION == SUMMARY_RELEASE_TIME + 1  # one (2,) event slice
#: the first stop of the reel at a payout limit (``HELD_LIMIT_*``): the time [s] the length
#: reached it and which (-1 ``[winch] min_length``, +1 ``max_length``); both NaN without one
SUMMARY_WINCH_LIMIT_TIME = SUMMARY_FIELDS.index("winch_limit_time")
SUMMARY_WINCH_LIMIT = SUMMARY_FIELDS.index("winch_limit")

# --- landing-gear contact (``model.contact.gear_contact``) -------------------------------------
#: the contact law, per gear point
GEAR_LAW_STIFFNESS = 0  # normal stiffness [N/m]
GEAR_LAW_DAMPING = 1  # normal damping [N s/m]
GEAR_LAW_FRICTION = 2  # Coulomb coefficient [-]
GEAR_LAW_SLIP_SPEED = 3  # slip speed below which friction is viscous [m/s]
GEAR_LAW_SIZE = 4
#: a rigid body's pose and motion
BODY_POSITION = 0  # (3,) HO from NO in N [m]
BODY_VELOCITY = 3  # (3,) HO's velocity in N [m/s]
BODY_R_NF = 6  # (9,) N_R_F row-major: element (i, j) at 6 + 3 i + j, column j = f_j in N
BODY_OMEGA_F = 15  # (3,) F's angular velocity in N, F components [rad/s]
BODY_SIZE = 18
#: a deck plane
DECK_POINT = 0  # (3,) a point of the plane in N [m]
DECK_NORMAL = 3  # (3,) its unit normal, out of the deck
DECK_VELOCITY = 6  # (3,) that point's velocity in N [m/s]
DECK_OMEGA = 9  # (3,) the deck's angular velocity in N [rad/s]
DECK_SIZE = 12
#: the loads the gear puts on the helicopter
LOADS_FORCE_N = 0  # (3,) the total force in N [N]
LOADS_MOMENT_F = 3  # (3,) its moment about HO, F components [N m]
LOADS_SIZE = 6
#: the gear's scratch in the engine (``Gear.work``): the loads, the inputs and wind force they
#: become (``kernels.wrench_loads_sc``), the body, the deck (level, through the base: set once)
#: and HO's position (``tethered_outputs_sc``)
GEAR_WORK_LOADS = 0  # (LOADS_SIZE,)
GEAR_WORK_INPUTS = 6  # (4,) [N, N m, N m, N]
GEAR_WORK_WIND = 10  # (3,) [N]
GEAR_WORK_BODY = 13  # (BODY_SIZE,)
GEAR_WORK_DECK = 31  # (DECK_SIZE,)
GEAR_WORK_OUTPUTS = 43  # (4,) HO from the base [m], q6 [rad]
GEAR_WORK_LOCK_STIFFNESS = 47  # the deck lock's anchor stiffness per held point [N/m]
GEAR_WORK_LOCK_DAMPING = 48  # ... and damping [N s/m]
GEAR_WORK_SIZE = 49
#: a gear point's deck lock (``Gear.lock``, a row per point): held (1) or not (0), and the
#: anchor, where the point was captured, from the base in N [m]
LOCK_HELD = 0
LOCK_ANCHOR = 1  # (3,)
LOCK_SIZE = 4

# --- the multirotor's parameters (``mr``, ``model.multirotor.Multirotor.packed``) -------------
#: a header of named slots, then one row of MR_ROTOR_COLUMNS per rotor from MR_HEADER on
MR_MASS = 0  # m [kg]
MR_G = 1  # gravity [m/s^2], along -n3
MR_INERTIA = 2  # (3, 3) J about the centre of mass in body axes, row-major [kg m^2]
MR_INERTIA_INV = 11  # (3, 3) its inverse, row-major [1/(kg m^2)]
MR_TETHER_POINT = 20  # (3,) the tether's attachment P from the centre of mass, body axes [m]
MR_DRAG = 23  # (3,) parasitic drag c_Dx, c_Dy, c_Dz [N/(m/s)^2]
MR_K_ETA = 26  # thrust coefficient: a rotor's thrust k_eta w^2 [N/(rad/s)^2]
MR_K_M = 27  # yaw-moment coefficient: a rotor's moment k_m w^2 [N m/(rad/s)^2]
MR_K_D = 28  # rotor drag (H force) in the rotor plane [N/(rad m/s^2)]
MR_K_Z = 29  # induced inflow, along the rotor axis [N/(rad m/s^2)]
MR_K_H = 30  # translational lift [N/(m/s)^2]
MR_K_FLAP = 31  # flapping moment [N m/(rad m/s^2)]
MR_TAU_M = 32  # the motors' first-order time constant [s]
MR_SPEED_MIN = 33  # rotor speed limits: a command is clipped to [min, max] [rad/s]
MR_SPEED_MAX = 34
MR_AERO = 35  # 1: the drag terms (MR_DRAG .. MR_K_FLAP) act, 0: thrust and yaw moment only
MR_ROTORS = 36  # the number of rotors n
MR_HEADER = 37
MR_ROTOR_POSITION = 0  # (3,) in a rotor's row: its hub from the centre of mass, body axes [m]
MR_ROTOR_DIRECTION = 3  # in a rotor's row: +1 or -1, the sign of its yaw moment
MR_ROTOR_COLUMNS = 4

# --- the multirotor's state (``model.multirotor_kernels.multirotor_derivative``) ---------------
#: RotorPy's state vector without its wind slot: position and velocity in N, the attitude
#: quaternion (x, y, z, w) of body axes B in N, body rates in B, then the n rotor speeds
MRS_X = 0  # (3,) [m]
MRS_V = 3  # (3,) [m/s]
MRS_Q = 6  # (4,) [-]
MRS_W = 10  # (3,) [rad/s]
MRS_ROTORS = 13  # (n,) [rad/s]
