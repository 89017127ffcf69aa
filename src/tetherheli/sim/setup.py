"""The set-up of one closed-loop run: model, hover trim, LQI gain and the packed arrays the
compiled engine takes (``layout``: run configuration, controller settings, actuators), the
compiled wind and the sensor-noise table. ``simulate``, ``run_batch``, sweeps and the
Gymnasium environment all start a run here.

A run starts at rest in the equilibrium of the air it meets at t = 0 (``start_point``): in a
turbulence that is the trim in the drag of its mean wind plus the gust drawn for t = 0 (the
gusts start from their stationary distribution), with the LQI's integrators z0 at the values
that make the paper controller command exactly that trim's inputs, as if the loop had been
flying in that air for a long time. Otherwise it is the windless trim with z0 = 0 (the
paper's runs: their force profiles arrive as they come).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from ..control.lqi import LQIGain, design_lqi
from ..control.paper import PaperController, check_law
from ..control.tether_lqi import TetherLQIGain, tether_lqi_gain
from ..errors import DesignError, InfeasibleError, ParameterError, design_failure
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
    CHAIN_NODES,
    CONTROL_LAWS,
    CTRL_ANTI_WINDUP,
    CTRL_DT,
    CTRL_FFWD,
    CTRL_K_I,
    CTRL_K_P,
    CTRL_LAW,
    CTRL_REEL_ACCEL,
    CTRL_REEL_RATE_LIMIT,
    CTRL_SIZE,
    CTRL_T_REF,
    CTRL_TENSION_K_C,
    CTRL_U_MAX,
    CTRL_U_MIN,
    CTRL_WINCH,
    LANES,
    WIND_COLUMNS,
    WIND_CONSTANT,
    WIND_KIND,
    Signals,
    default_actuators,
    empty_chain,
)
from ..model import TetheredHelicopter, TrimPoint, kernels, linearize
from ..names import INPUT, TETHERED_STATE
from ..params import Params
from ..sensing.config import N_CHANNELS, N_GROUPS, SensorConfig
from ..sensing.noise import noise_table
from ..sensing.schedules import ring_rows, sample_schedule
from ..tether.chain import LumpedTether, static_chain
from ..tether.lumped import CHAIN_MAX_SUBSTEPS, COUPLING_OMEGA_H, chain_omega_max, ros2_work
from ..tether.lumped_trim import hover_trim_lumped
from ..wind import CompiledWind, compile_wind, initial_wind_force
from ..wind.profiles import Disturbance
from . import engine, lumped_step, stepping
from .scenario import Scenario, WinchSettings

__all__ = [
    "LQI_STATES",
    "EngineSetup",
    "RunSetup",
    "StartPoint",
    "actuator_array",
    "chain_start",
    "engine_setup",
    "free_trim_input",
    "lane_block",
    "lane_program_into",
    "load_cell_trim",
    "lumped_tether",
    "paper_gain",
    "paper_law",
    "run_setup",
    "sensor_noise",
    "sensor_schedule",
    "sensor_tuple",
    "start_point",
    "winch_into",
]

LQI_STATES = TETHERED_STATE[:12]


@lru_cache(maxsize=64)
def paper_gain(
    params: Params, dt: float, Qy: tuple[float, ...], Ru: tuple[float, ...], q9: float = 10.0
) -> LQIGain:
    """K_LQI|F: the LQI gain designed on the linearized tethered equations at TC = 0 (the free
    helicopter) about Table IV's hover (Sec. V-A, eqs 46-53), for sample time dt.

    Parameters
    ----------
    params : Params
        Parameters of the design model.
    dt : float
        Control sample time [s].
    Qy : tuple of 4 floats
        Diagonal of the output weight on q1, q2, q3, q6 (eq 50).
    Ru : tuple of 4 floats
        Diagonal of the input weight on fMR3, tMR1, tMR2, fTR2 (eq 50).
    q9 : float
        Tether length of the design hover [m].

    Returns
    -------
    LQIGain
        The discrete LQI gain K = [K_x, K_z], shape (4, 16).
    """
    model = TetheredHelicopter(params)
    lin = linearize(model, model.trim(0.0, q9)).select(LQI_STATES)
    G, H = lin.discretize(dt)
    return design_lqi(G, H, lin.C, dt, Qy=np.diag(Qy), Ru=np.diag(Ru))


class RunSetup(NamedTuple):
    """The model, hover trim, LQI gain and packed settings of one run (``run_setup``).

    Attributes
    ----------
    model : TetheredHelicopter
        The plant, on the scenario's parameters.
    trim : TrimPoint
        The windless hover trim at the scenario's q9 and reference tension.
    gain : LQIGain or TetherLQIGain
        The controller's gain.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        Controller settings (``layout.CTRL_*``).
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        Run configuration (``layout.CFG_*``).
    """

    model: TetheredHelicopter
    trim: TrimPoint
    gain: LQIGain | TetherLQIGain
    ctrl: np.ndarray  # controller settings (``layout.CTRL_*``)
    cfg: np.ndarray  # run configuration (``layout.CFG_*``)


def run_setup(scenario: Scenario, design_params: Params | None = None) -> RunSetup:
    """Model, trim, LQI gain and packed engine arrays of one run.

    The gain is designed on ``design_params`` (default: the scenario's own parameters; a
    Monte Carlo passes the nominal ones); plant, trim and winch use the scenario's.

    Parameters
    ----------
    scenario : Scenario
        The run.
    design_params : Params, optional
        Parameters the gain is designed on (default: the scenario's own).

    Returns
    -------
    RunSetup
        Model, trim, gain and the packed ``ctrl`` and ``cfg`` arrays.
    """
    params = scenario.params
    model = TetheredHelicopter(params)
    tethered = scenario.configuration == "tethered"
    T_ref = params.tension_control.T_ref if tethered else 0.0
    lumped = scenario.tether.lumped
    if lumped:  # the hover with the chain hanging below P, T_ref at the winch (eq 56)
        a = scenario.actuators
        trim: TrimPoint = load_cell_trim(
            hover_trim_lumped(
                params, lumped_tether(scenario), T_ref, scenario.q9, u_min=a.u_min, u_max=a.u_max
            ).trim,
            T_ref,
            model,
        )
    else:
        trim = model.trim(T_ref, scenario.q9)
    c = scenario.control
    design = params if design_params is None else design_params
    try:
        gain = paper_gain(design, c.dt, tuple(c.Qy), tuple(c.Ru), scenario.q9)
    except DesignError as exc:
        raise design_failure(
            "control.Qy/Ru", f"Qy = {list(c.Qy)}, Ru = {list(c.Ru)}", exc
        ) from None
    lqi_on_tether = c.controller == "tether_lqi"
    if lqi_on_tether:  # its plant contains the tether: no feed-forward (eq 55), no PI (eq 56)
        w = c.tether_lqi
        try:
            gain = tether_lqi_gain(
                design, design.tension_control.T_ref, scenario.q9, c.dt,
                tuple(w.Qy), w.q_tension, tuple(w.Ru), gain,
            )  # fmt: skip
        except DesignError as exc:
            raise design_failure(
                "control.tether_lqi.Qy/q_tension/Ru",
                f"Qy = {list(w.Qy)}, q_tension = {w.q_tension!r}, Ru = {list(w.Ru)}",
                exc,
            ) from None
    ctrl = np.zeros(CTRL_SIZE)
    ctrl[CTRL_DT] = c.dt
    ctrl[CTRL_LAW] = CONTROL_LAWS.index("tether_lqi" if lqi_on_tether else "paper")
    ctrl[CTRL_FFWD] = float(tethered and c.feedforward and not lqi_on_tether)
    ctrl[CTRL_ANTI_WINDUP] = float(lqi_on_tether and c.tether_lqi.anti_windup)
    if lqi_on_tether and tethered and c.tether_lqi.q9_from_tension:
        # q9 from the load cell (``control.paper.tension_q9``) unless the sensors are perfect
        ctrl[CTRL_TENSION_K_C] = 0.0 if scenario.sensors.is_perfect else design.tether.K_C
    ctrl[CTRL_U_MIN : CTRL_U_MIN + 4] = -math.inf
    ctrl[CTRL_U_MAX : CTRL_U_MAX + 4] = math.inf
    ctrl[CTRL_WINCH] = float(tethered)
    ctrl[CTRL_T_REF] = T_ref
    ctrl[CTRL_K_P] = params.tension_control.K_P
    ctrl[CTRL_K_I] = params.tension_control.K_I
    ctrl[CTRL_REEL_RATE_LIMIT] = math.inf
    ctrl[CTRL_REEL_ACCEL] = math.inf
    cfg = np.zeros(CFG_SIZE)
    cfg[CFG_DT] = c.dt
    cfg[CFG_N_SUB] = c.substeps
    cfg[CFG_K_C] = params.tether.K_C
    cfg[CFG_ATTACHED] = float(tethered)
    cfg[CFG_MAX_TENSION] = scenario.limits.max_tension
    cfg[CFG_MAX_DEVIATION] = scenario.limits.max_deviation
    cfg[CFG_MAX_ANGLE] = math.radians(scenario.limits.max_angle_deg)
    cfg[CFG_METRICS_FROM] = scenario.metrics_first_sample
    cfg[CFG_LUMPED] = float(lumped)
    cfg[CFG_ARM] = params.helicopter.tether_arm
    check_law(ctrl, gain.K)  # the engine's law by name, with its gain (validated once, here)
    return RunSetup(model, trim, gain, ctrl, cfg)


def load_cell_trim(trim: TrimPoint, ground_tension: float, model: TetheredHelicopter) -> TrimPoint:
    """A lumped tether's trim as the paper controller flies it: the feed-forward C_f-fwd
    (eq 55) is built from the load cell's tension, the winch's T_g, not the tension at P of
    ``trim`` (T_g + mu g L0), so u0 = u_total + C_f-fwd(T_g) makes eq 54 command the trim's
    actual inputs u_total at the start (the massless tether's u0|T has T_g = T_P).

    Parameters
    ----------
    trim : TrimPoint
        ``hover_trim_lumped``'s helicopter trim (its feed-forward at the tension at P).
    ground_tension : float
        The tension at the winch [N].
    model : TetheredHelicopter
        The run's model.

    Returns
    -------
    TrimPoint
        The same state, outputs, tension at P and actual inputs; u and feedforward at T_g.
    """
    torque = np.empty(2)
    kernels.tethered_tether_torque(trim.x, float(ground_tension), model.constants, torque)
    ffwd = np.array([0.0, torque[0], torque[1], 0.0])
    return TrimPoint(
        x=trim.x, u=trim.u_total + ffwd, y=trim.y, tension=trim.tension, feedforward=ffwd
    )


def lumped_tether(scenario: Scenario) -> LumpedTether:
    """The ``LumpedTether`` of a scenario's ``[tether]`` table; EA = 0 takes the paper's
    stiffness, EA = K_C LN with the massless trim's natural length LN = q9 - T_ref / K_C
    (eq 28; ``LumpedTether.from_paper_stiffness``).

    Parameters
    ----------
    scenario : Scenario
        The run (any tether model: its ``[tether]`` keys are read).

    Returns
    -------
    LumpedTether
        The chain's parameters (air density ``wind.drag``'s default).
    """
    t = scenario.tether
    params = scenario.params
    kw = dict(
        segments=t.segments,
        mass_per_length_kg_m=t.mass_per_length,
        damping_ratio=t.damping_ratio if t.internal_damping == 0.0 else None,
        internal_damping_Ns=t.internal_damping if t.internal_damping > 0.0 else None,
        diameter_m=t.diameter,
        drag_coefficient=t.drag_coefficient,
        tangential_drag_coefficient=t.tangential_drag_coefficient,
        ground_stiffness_Pa_m=t.ground_stiffness,
        ground_damping_Pa_s_m=t.ground_damping,
        ground_friction=t.ground_friction,
        ground_friction_speed_m_s=t.ground_friction_speed,
    )
    if t.EA > 0.0:
        return LumpedTether(EA_N=t.EA, **kw)
    L_N = params.tether.natural_length(scenario.q9, params.tension_control.T_ref)
    return LumpedTether.from_paper_stiffness(params.tether.K_C, L_N, **kw)


def chain_start(scenario: Scenario, trim: TrimPoint) -> tuple:
    """The run's ``chain`` (``layout.CHAIN_*``): for a lumped tether the static chain hanging
    from P straight down to the winch at rest (``tether.chain.static_chain``, the discrete
    catenary whose winch tension equals hover_trim_lumped's), fresh arrays; otherwise
    ``layout.empty_chain()``.

    Parameters
    ----------
    scenario : Scenario
        The run.
    trim : TrimPoint
        Its trim (x[5] = q9, x[12] = L0).

    Returns
    -------
    tuple of numpy.ndarray
        (nodes (N+1, 3), velocities (N+1, 3), params (LUMPED_SIZE,), ROS2 scratch).
    """
    if not scenario.tether.lumped:
        return empty_chain()
    tether = lumped_tether(scenario)
    g = scenario.params.helicopter.g
    q9, L0 = float(trim.x[5]), float(trim.x[12])
    T_g = scenario.params.tension_control.T_ref  # hover_trim_lumped's tension at the winch
    packed = tether.packed(g)
    # the coupled step's rule (``tether.lumped.coupling_substeps``) at the trim's length: a
    # cable it cannot step within CHAIN_MAX_SUBSTEPS per sample is refused here, instead of
    # being flown for minutes with capped, unstable steps to a failure
    dt = scenario.control.dt
    needed = dt * chain_omega_max(packed, L0, tether.segments) / COUPLING_OMEGA_H
    if needed > CHAIN_MAX_SUBSTEPS:
        ea_max = tether.EA_N * (CHAIN_MAX_SUBSTEPS / needed) ** 2  # omega_max ~ sqrt(EA)
        raise InfeasibleError(
            "tether.EA",
            tether.EA_N,
            f"at most about {ea_max:.3g} N at this mass per length, segments and dt (the "
            f"coupled step would need {needed:.3g} RK4 steps per {dt:g} s sample, above the "
            f"engine's {CHAIN_MAX_SUBSTEPS})",
        )
    nodes = static_chain(np.zeros(3), np.array([0.0, 0.0, q9]), L0, tether, g, ground_tension_N=T_g)
    return (nodes, np.zeros_like(nodes), packed, ros2_work(tether.segments))


def free_trim_input(scenario: Scenario, model: TetheredHelicopter, trim: TrimPoint) -> np.ndarray:
    """u0|F (4,): the free hover's trim input (Table IV) at the scenario's q9, which the paper
    controller uses once the safety device has released the tether (``engine.paper_sample``).
    The free trim's state q4..u6 and outputs equal the tethered trim's (the tension acts along
    the shaft at hover), so only u0 changes; the free configuration's is its own trim input.

    Parameters
    ----------
    scenario : Scenario
        The run.
    model : TetheredHelicopter
        The run's model (``run_setup``).
    trim : TrimPoint
        The run's windless trim (``run_setup``).

    Returns
    -------
    numpy.ndarray, shape (4,)
        u0|F = (fMR3, tMR1, tMR2, fTR2) [N, N m, N m, N].
    """
    if scenario.configuration != "tethered":
        return trim.u.copy()
    return _free_trim_input(model.params, scenario.q9).copy()


@lru_cache(maxsize=256)
def _free_trim_input(params: Params, q9: float) -> np.ndarray:
    """``free_trim_input`` of a tethered run, once per (parameters, q9): a batch's runs share
    it (read-only)."""
    u = TetheredHelicopter(params).trim(0.0, q9).u.copy()
    u.setflags(write=False)
    return u


def paper_law(
    gain: LQIGain | TetherLQIGain, trim: TrimPoint, u0_free: np.ndarray, z0: np.ndarray
) -> tuple:
    """The paper controller's law (gain, x_ref, y_ref, u0, u0_free, z0) (``layout.LAW_*``):
    ``trim`` is the windless trim (its state and outputs are the references), z0 the
    integrators' start (``start_point``). The tethered LQI's law works about the trim's total
    input (no feed-forward) and references LN too.

    Parameters
    ----------
    gain : LQIGain or TetherLQIGain
        The controller's gain, K of shape (4, 16) or (5, 17).
    trim : TrimPoint
        The windless trim.
    u0_free : numpy.ndarray, shape (4,)
        The free hover's trim input (``free_trim_input``).
    z0 : numpy.ndarray, shape (4,)
        The integrators' initial state (``start_point``).

    Returns
    -------
    tuple of 6 numpy.ndarray
        (K, x_ref, y_ref (4,), u0 (4,), u0_free (4,), z0 (4,)), contiguous.
    """
    K = np.ascontiguousarray(gain.K)
    return (
        K,
        np.ascontiguousarray(trim.x[: K.shape[1] - 4]),
        trim.y.copy(),
        trim.u_total.copy() if isinstance(gain, TetherLQIGain) else trim.u.copy(),
        np.ascontiguousarray(u0_free, dtype=float),
        np.array(z0, dtype=float),
    )


class StartPoint(NamedTuple):
    """Where a run starts (``start_point``): the trim in the steady wind and the LQI's
    integrator state z0 [m s, m s, m s, rad s] that holds it.

    Attributes
    ----------
    trim : TrimPoint
        The trim in the wind at t = 0 (its ``x`` is the initial state).
    z : numpy.ndarray, shape (4,)
        The integrators' initial state z0 [m s, m s, m s, rad s].
    """

    trim: TrimPoint
    z: np.ndarray  # (4,)

    @property
    def x(self) -> np.ndarray:
        """The initial state (13,)."""
        return self.trim.x


#: the largest condition number of the LQI's integrator block K_z accepted by ``start_point``
MAX_KZ_CONDITION = 1e10


def start_point(
    model: TetheredHelicopter,
    trim: TrimPoint,
    gain: LQIGain,
    ctrl: np.ndarray,
    wind: Disturbance,
    q9: float,
) -> StartPoint:
    """The equilibrium a run starts from in the air of ``wind`` at t = 0: the drag F of the
    turbulence's mean wind plus its gust at t = 0 (``wind.initial_wind_force``).

    The trim in F (``hover_trim(..., N_F_wind=F)``) keeps the windless
    trim's outputs, which stay the controller's references. The paper law (eq 54),
    u = u0 - K_x (x - x_ref) - K_z z - C_f-fwd, gives that trim's rotor inputs when
    K_z z0 = u0 - K_x (x_w - x_ref) - u_cmd, with u_cmd the trim's u0|T (feed-forward on) or
    its total input (off). K_z, the gain's 4 x 4 integrator block, must be invertible
    (condition number below ``MAX_KZ_CONDITION``). Without turbulence: ``trim`` and z0 = 0.

    Parameters
    ----------
    model : TetheredHelicopter
        As returned by ``run_setup``.
    trim : TrimPoint
        The windless trim (``run_setup``).
    gain : LQIGain or TetherLQIGain
        As returned by ``run_setup``.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        As returned by ``run_setup``.
    wind : Disturbance
        The run's disturbance.
    q9 : float
        The tether length of the windless trim [m].

    Returns
    -------
    StartPoint
        The trim in the wind at t = 0 and z0.

    Raises
    ------
    InfeasibleError
        No trim in that wind (naming ``N_F_wind``).
        Or K_z is singular (naming ``control.Qy/Ru``).
    """
    force = initial_wind_force(wind)
    if not np.any(force):
        return StartPoint(trim, np.zeros(4))
    windy = model.trim(trim.tension, q9, N_F_wind=force)
    K = np.asarray(gain.K)
    n_x = K.shape[1] - 4  # 12, or 13 for the tethered LQI (whose rows 0-3 are its rotor law)
    K_x, K_z = K[:4, :n_x], K[:4, n_x:]
    cond = np.linalg.cond(K_z)
    if not cond < MAX_KZ_CONDITION:
        raise InfeasibleError(
            "control.Qy/Ru",
            f"an LQI gain whose integrator block K_z has condition number {cond:.3g}",
            f"weights giving an invertible K_z (condition < {MAX_KZ_CONDITION:g}), so that an "
            "integrator state holds the trim in the wind at t = 0",
        )
    u_law = trim.u_total if isinstance(gain, TetherLQIGain) else trim.u

    def integrators(windy: TrimPoint) -> np.ndarray:
        u_cmd = windy.u if ctrl[CTRL_FFWD] > 0.5 else windy.u_total
        rhs = u_law - K_x @ (windy.x[:n_x] - trim.x[:n_x]) - u_cmd
        return np.linalg.solve(K_z, rhs)

    z0 = integrators(windy)
    if isinstance(gain, TetherLQIGain) and ctrl[CTRL_WINCH] > 0.5:
        windy, z0 = _reel_at_rest(model, trim, K, force, q9, windy, z0, integrators)
    return StartPoint(windy, z0)


def _reel_at_rest(model, trim, K, force, q9, windy, z0, integrators):
    """The tethered LQI's start in wind: its fifth row (the reel rate) must command zero too.
    The windy trims of any tension keep the outputs (``hover_trim``), so the tension is the
    free unknown: the secant method on the reel command r(T) = -K_5 [x_w(T) - x_ref; z0(T)]
    (near-linear in T), from the windless trim's tension; returns (windy trim, z0)."""

    def reel(w: TrimPoint, z: np.ndarray) -> float:
        return float(-K[4, :13] @ (w.x[:13] - trim.x[:13]) - K[4, 13:] @ z)

    T_prev, r_prev = trim.tension, reel(windy, z0)
    T = 1.02 * T_prev
    for _ in range(12):
        windy = model.trim(T, q9, N_F_wind=force)
        z0 = integrators(windy)
        r = reel(windy, z0)
        if abs(r) < 1e-12 or r == r_prev:
            break
        T, T_prev, r_prev = T - r * (T - T_prev) / (r - r_prev), T, r
        if not T > 0.0:
            raise InfeasibleError(
                "control.tether_lqi", "a start in the wind", "weights whose reel row holds "
                "the winch at rest at a positive tension"
            )  # fmt: skip
    return windy, z0


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
        ``sensing.noise.noise_table`` of the run, units per channel.
    """
    if scenario.sensors.is_perfect:
        return np.zeros((0, N_CHANNELS))
    rng = np.random.default_rng(np.random.SeedSequence(scenario.seed))
    return noise_table(scenario.sensors, scenario.n_samples, rng, dt=scenario.control.dt)


def sensor_schedule(config: SensorConfig, dt: float, n_samples: int) -> np.ndarray:
    """``sensing.schedules.sample_schedule`` of a run, empty, (0, N_GROUPS), for perfect sensors (no
    measurement).

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
    return sample_schedule(config, dt, n_samples)


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
    ``run_closed_loop`` has one compiled signature (issue 24)."""
    view = np.ascontiguousarray(a, dtype=np.float64).view()
    view.setflags(write=False)
    return view


@dataclass(frozen=True)
class EngineSetup:
    """Everything one run needs, packed for the compiled engine.

    Parameters
    ----------
    model, trim, gain, ctrl, cfg
        As ``RunSetup``'s.
    wind : CompiledWind or None
        The engine form of the wind (None: a custom disturbance).
    act : numpy.ndarray, shape (ACT_SIZE,)
        Actuator array (``actuator_array``).
    noise : numpy.ndarray, shape (n_samples + 1, N_CHANNELS) or (0, N_CHANNELS)
        Sensor noise table (``sensor_noise``).
    source : int
        Position-source code (``sensors.SOURCE_*``).
    arm : float
        dO-P,3 - dO-HO,3 [m].
    schedule : numpy.ndarray of int64, shape (n_samples + 1, N_GROUPS) or (0, N_GROUPS)
        Sensor sample schedule (``sensor_schedule``).
    u0_free : numpy.ndarray, shape (4,)
        u0|F, the trim input after a release (``free_trim_input``).
    start : StartPoint
        The start in the wind (``start_point``; a lumped tether starts from the windless
        hanging chain).
    chain : tuple of numpy.ndarray
        The lumped chain at the start (``chain_start``; ``layout.empty_chain()``: massless).
    """

    model: TetheredHelicopter
    trim: TrimPoint
    gain: LQIGain | TetherLQIGain
    ctrl: np.ndarray
    cfg: np.ndarray
    wind: CompiledWind | None
    act: np.ndarray
    noise: np.ndarray
    source: int
    arm: float
    schedule: np.ndarray
    u0_free: np.ndarray  # u0|F, the trim input after a release (``free_trim_input``)
    start: StartPoint
    chain: tuple = field(default_factory=empty_chain)

    def engine_args(self, n_samples: int) -> tuple:
        """The leading arguments of ``engine.run_closed_loop`` (built-in winds only).

        Parameters
        ----------
        n_samples : int
            Control samples to run.

        Returns
        -------
        tuple
            (x_init (13,), n_samples, cfg, ctrl, model constants, law, (program, gust, drag),
            act, sensors, chain (a fresh copy: the engine advances it in place)).
        """
        assert self.wind is not None
        return (
            self.start.x.copy(), n_samples, read_only(self.cfg), read_only(self.ctrl),
            *self._engine_inputs(),
        )  # fmt: skip

    def _engine_inputs(self) -> tuple:
        # (model constants, law, wind, act, sensors, chain) as every engine entry takes them:
        # what it only reads as ``read_only`` views (one compiled signature), the chain a
        # fresh copy (the engine advances it); a custom disturbance (no compiled wind) an
        # empty wind program, whose force the Python loop adds itself
        if self.wind is None:
            wind = (np.zeros((0, WIND_COLUMNS)), np.zeros((0, 3)), np.zeros(3))
        else:
            wind = (self.wind.program, self.wind.gust, self.wind.drag)
        return (
            read_only(self.model.constants),
            tuple(read_only(a) for a in self.law),
            tuple(read_only(a) for a in wind),
            read_only(self.act),
            self.sensors,
            tuple(a.copy() for a in self.chain),
        )

    def step_run(self, out: Signals, summary: np.ndarray) -> stepping.StepRun:
        """The run's arrays for the sample step driven from Python (``stepping.StepRun``: a
        ``Controller`` other than the compiled laws, or the adaptive reference), recording
        into ``out`` and accumulating its metrics into ``summary``. A custom disturbance (no
        compiled wind) gets an empty wind program: the Python loop adds its force itself.

        Parameters
        ----------
        out : Signals
            The recorded signals, n_samples + 1 rows each.
        summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
            Receives the run's on-line metrics (``engine.start_summary`` first).

        Returns
        -------
        stepping.StepRun
            Fresh copies of everything the run changes (state, cfg, ctrl, chain, loop).
        """
        c, law, wind, act, sensors, chain = self._engine_inputs()
        segments = max(chain[CHAIN_NODES].shape[0] - 1, 1)
        work = np.empty((engine.RK4_WORK_ROWS, 13))
        engine.start_summary(summary)
        x = self.start.x.copy()
        return stepping.StepRun(
            x=x,
            cfg=self.cfg.copy(),
            ctrl=self.ctrl.copy(),
            c=c,
            law=law,
            wind=wind,
            act=act,
            sensors=sensors,
            chain=chain,
            cw=lumped_step.lumped_work(segments),
            work=work,
            loop=engine.new_loop_state(x, read_only(self.start.z), work),
            summary=summary,
            out=out,
        )

    @property
    def law(self) -> tuple:
        """The paper controller's (gain, x_ref, y_ref, u0, u0_free, z0) (``paper_law``); z0 is
        the integrators' initial state (``start_point``)."""
        return paper_law(self.gain, self.trim, self.u0_free, self.start.z)

    def paper_controller(self) -> PaperController:
        """The paper's controller as a Python ``Controller``, on the same law and start.

        Returns
        -------
        PaperController
            A controller the Python loop (``simulate``) can fly.
        """
        K, x_ref, y_ref, u0, u0_free, z0 = self.law
        return PaperController(
            K, x_ref, y_ref, u0, self.ctrl, self.model.constants,
            free_trim_input=u0_free, z_init=z0,
        )  # fmt: skip

    @property
    def sensors(self) -> tuple:
        """``sensor_tuple`` of this run (``engine.sense``); fresh work arrays per call."""
        return sensor_tuple(self.noise, self.source, self.arm, self.schedule)


def engine_setup(scenario: Scenario, design_params: Params | None = None) -> EngineSetup:
    """Set-up, trim, gain (designed on ``design_params``, default the scenario's), wind,
    actuators and sensor noise of one run.

    Parameters
    ----------
    scenario : Scenario
        The run.
    design_params : Params, optional
        Parameters the gain is designed on (default: the scenario's own).

    Returns
    -------
    EngineSetup
        The packed run.
    """
    model, trim, gain, ctrl, cfg = run_setup(scenario, design_params)
    wind = compile_wind(scenario.wind)
    if wind is not None:
        cfg[CFG_GUST_DT] = wind.gust_dt
    if scenario.tether.lumped:  # the windless hanging chain, even in a gust (its drag then
        start = StartPoint(trim, np.zeros(4))  # acts from t = 0 as a disturbance)
    else:
        start = start_point(model, trim, gain, ctrl, scenario.wind, scenario.q9)
    act = actuator_array(scenario, start.trim, ctrl)
    return EngineSetup(
        model,
        trim,
        gain,
        ctrl,
        cfg,
        wind,
        act,
        sensor_noise(scenario),
        scenario.sensors.source_code,
        model.params.helicopter.tether_arm,
        sensor_schedule(scenario.sensors, scenario.control.dt, scenario.n_samples),
        free_trim_input(scenario, model, trim),
        start,
        chain_start(scenario, trim),
    )


def _stack(arrays: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Arrays (rows, ...) of different row counts stacked along a new lane axis, zero-padded
    to the longest (their dtype kept); returns (stacked (B, rows_max, ...), rows in use (B,))."""
    rows = np.array([a.shape[0] for a in arrays], dtype=np.int64)
    shape = (len(arrays), max(1, int(rows.max())), *arrays[0].shape[1:])
    stacked = np.zeros(shape, dtype=arrays[0].dtype)
    for j, a in enumerate(arrays):
        stacked[j, : a.shape[0]] = a
    return stacked, rows


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


def lane_block(setups: Sequence[EngineSetup], n_samples: Sequence[int]) -> tuple:
    """The leading arguments of ``lanes.run_lanes`` for a block of up to ``LANES`` runs:
    lane j holds ``setups[j].engine_args(n_samples[j])``, the single run's own packing, with
    a lane axis in front (built-in winds only; every run must take the same RK4 steps per
    sample). Lanes beyond the runs are padding: copies of the first run with n_samples = -1
    (never run). Wind programs are padded with rows of zero force and laid out flat (row,
    column, lane); tables of other lengths are zero-padded with their rows in use.

    Parameters
    ----------
    setups : sequence of EngineSetup
        1 to ``LANES`` runs with built-in winds.
    n_samples : sequence of int
        Control samples of each run.

    Returns
    -------
    tuple
        The arguments of ``lanes.run_lanes`` before its outputs, each with a leading lane
        axis of length ``LANES``.
    """
    if not 0 < len(setups) <= LANES or len(n_samples) != len(setups):
        raise ValueError(f"lane_block: 1 to {LANES} runs, each with its n_samples")
    pad = LANES - len(setups)
    runs = [s.engine_args(n) for s, n in zip(setups, n_samples, strict=True)]
    runs += [runs[0]] * pad
    counts = np.array([*n_samples, *([-1] * pad)], dtype=np.int64)
    if any(s.chain[0].shape[0] > 0 for s in setups):
        raise ValueError("lane_block: lumped tethers run alone (engine.run_closed_loop)")
    x_init, _, cfg, ctrl, c, law, wind, act, sensors, _ = zip(*runs, strict=True)
    program, gust, drag = zip(*wind, strict=True)
    n_rows = max(p.shape[0] for p in program)
    programs = np.empty((n_rows, WIND_COLUMNS, LANES))
    for j, p in enumerate(program):
        lane_program_into(programs, j, p)
    noise, source, arm, scratch, schedule, ring = zip(*sensors, strict=True)
    return (
        np.stack(x_init),
        counts,
        np.stack(cfg),
        np.stack(ctrl),
        np.stack(c),
        tuple(np.ascontiguousarray(np.stack(part)) for part in zip(*law, strict=True)),
        (programs.ravel(), n_rows, *_stack(list(gust)), np.stack(drag)),
        np.stack(act),
        (
            *_stack(list(noise)),
            np.array(source, dtype=np.int64),
            np.array(arm, dtype=float),
            np.stack(scratch),
            *_stack(list(schedule)),
            *_stack(list(ring)),
        ),
    )
