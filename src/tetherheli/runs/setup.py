"""The set-up of one closed-loop run: model, hover trim, LQI gain and the packed arrays the
compiled engine takes (``layout``: run configuration, controller settings, actuators), the
compiled wind and the sensor-noise table. ``simulate``, ``run_batch``, sweeps and the
Gymnasium environment all start a run here.

The pieces live beside it, by job: the gain, trims and start in the wind in ``runs.start``,
the actuator and sensor packing in ``runs.packing`` (a block of runs for the lane engine is
``runs.batch.lane_block``); their names the API reference lists under this module are
re-exported here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from ..base.compiled import CompiledBase, compile_base
from ..control.lqi import LQIGain
from ..control.paper import PaperController
from ..control.registry import controller_entry
from ..control.tether_lqi import TetherLQIGain, _tether_lqi_gain
from ..engine import loop as engine
from ..engine import lumped_step, stepping
from ..engine.lanes import lane_program_into
from ..engine.summary import start_summary
from ..errors import DesignError, design_failure
from ..layout import (
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
    CFG_TETHER_EA,
    CFG_VEHICLE,
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
    VEHICLES,
    WIND_COLUMNS,
    Gear,
    Signals,
    WindPack,
    empty_chain,
    no_gear,
)
from ..model import TetheredHelicopter, TrimPoint
from ..model.contact import gear_law_array, gear_record
from ..model.trim import _hover_trim
from ..params import Params
from ..scenario.core import Scenario
from ..scenario.tables import DECK_LOCK_DAMPING, DECK_LOCK_STIFFNESS
from ..tether.lumped_trim import _hover_trim_lumped
from ..wind import CompiledWind, compile_wind
from ..wind.evaluate import air_relative_to_base
from .packing import (
    actuator_array,
    read_only,
    sensor_noise,
    sensor_schedule,
    sensor_tuple,
    winch_into,
)
from .start import (
    LQI_STATES,
    StartPoint,
    chain_start,
    free_trim_input,
    load_cell_trim,
    lumped_tether,
    paper_gain,
    paper_law,
    start_point,
)

__all__ = [
    "LQI_STATES",
    "EngineSetup",
    "RunSetup",
    "StartPoint",
    "actuator_array",
    "chain_start",
    "engine_setup",
    "free_trim_input",
    "lane_program_into",
    "load_cell_trim",
    "lumped_tether",
    "paper_gain",
    "paper_law",
    "python_controlled",
    "run_base",
    "run_setup",
    "sensor_noise",
    "sensor_schedule",
    "sensor_tuple",
    "start_point",
    "winch_into",
]


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
            _hover_trim_lumped(
                params, lumped_tether(scenario), T_ref, scenario.q9, u_min=a.u_min, u_max=a.u_max
            ).trim,
            T_ref,
            model,
        )
    else:
        trim = _hover_trim(params, T_ref, scenario.q9)  # both checked by the scenario
    c = scenario.control
    design = params if design_params is None else design_params
    gain: LQIGain | TetherLQIGain  # the paper's, or the LQI on the tether
    try:
        gain = paper_gain(design, c.dt, tuple(c.Qy), tuple(c.Ru), scenario.q9)
    except DesignError as exc:
        raise design_failure(
            "control.Qy/Ru", f"Qy = {list(c.Qy)}, Ru = {list(c.Ru)}", exc
        ) from None
    lqi_on_tether = controller_entry(c.controller).law == "tether_lqi"
    if lqi_on_tether:  # its plant contains the tether: no feed-forward (eq 55), no PI (eq 56)
        w = c.tether_lqi
        try:
            gain = _tether_lqi_gain(  # T_ref and q9: checked by the scenario
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
    cfg[CFG_TETHER_EA] = params.tether.EA  # the law: 0 eq 28's, > 0 the rope's
    cfg[CFG_ATTACHED] = float(tethered)
    cfg[CFG_MAX_TENSION] = scenario.limits.max_tension
    cfg[CFG_MAX_DEVIATION] = scenario.limits.max_deviation
    cfg[CFG_MAX_ANGLE] = math.radians(scenario.limits.max_angle_deg)
    cfg[CFG_METRICS_FROM] = scenario.metrics_first_sample
    cfg[CFG_LUMPED] = float(lumped)
    cfg[CFG_ARM] = params.helicopter.tether_arm
    cfg[CFG_VEHICLE] = VEHICLES.index("helicopter")  # the engine's vehicle slot, by name
    # the law by name with its gain (``control.paper.check_law``'s pair), both from
    # ``lqi_on_tether``: the engine trusts them
    return RunSetup(model, trim, gain, ctrl, cfg)


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
    base : CompiledBase
        The winch's base in the engine's packed form (``base.compile_base``; default the
        paper's still winch).
    gear : layout.Gear
        The landing gear (``run_gear``; default ``layout.no_gear()``: none).
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
    base: CompiledBase = field(default_factory=lambda: compile_base(None))
    gear: Gear = field(default_factory=no_gear)

    def engine_args(
        self, n_samples: int
    ) -> tuple[Any, Any, Any, Any, Any, Any, Any, Any, Any, Any]:
        """The leading arguments of ``engine.run_closed_loop`` (built-in winds only).

        Parameters
        ----------
        n_samples : int
            Control samples to run.

        Returns
        -------
        tuple
            (x_init (13,), n_samples, cfg, ctrl, model constants, law,
            (program, gust, drag, base),
            act, sensors, chain (a fresh copy: the engine advances it in place)).
        """
        assert self.wind is not None
        return (
            self.start.x.copy(), n_samples, read_only(self.cfg), read_only(self.ctrl),
            *self._engine_inputs(),
        )  # fmt: skip

    def _engine_inputs(self) -> tuple[np.ndarray, tuple, WindPack, np.ndarray, tuple, tuple]:
        # (model constants, law, wind, act, sensors, chain) as every engine entry takes them:
        # what it only reads as ``read_only`` views (one compiled signature), the chain a
        # fresh copy (the engine advances it); a custom disturbance (no compiled wind) an
        # empty wind program, whose force the Python loop adds itself
        if self.wind is None:
            wind = (np.zeros((0, WIND_COLUMNS)), np.zeros((0, 3)), np.zeros(3), self.base.packed)
        else:
            wind = (self.wind.program, self.wind.gust, self.wind.drag, self.base.packed)
        return (
            read_only(self.model.constants),
            tuple(read_only(a) for a in self.law),
            WindPack(*(read_only(a) for a in wind)),
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
            Receives the run's on-line metrics (``summary.start_summary`` first).

        Returns
        -------
        stepping.StepRun
            Fresh copies of everything the run changes (state, cfg, ctrl, chain, loop).
        """
        c, law, wind, act, sensors, chain = self._engine_inputs()
        segments = max(chain[CHAIN_NODES].shape[0] - 1, 1)
        work = np.empty((engine.RK4_WORK_ROWS, 13))
        start_summary(summary)
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
            gear=self.gear,
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
        return PaperController(  # its law checked there (``control.paper.check_law``)
            K, x_ref, y_ref, u0, self.ctrl, self.model.constants,
            free_trim_input=u0_free, z_init=z0,
        )  # fmt: skip

    @property
    def sensors(self) -> tuple:
        """``sensor_tuple`` of this run (``engine.sense``); fresh work arrays per call."""
        return sensor_tuple(self.noise, self.source, self.arm, self.schedule)


def python_controlled(scenario: Scenario) -> bool:
    """Whether ``scenario``'s controller is a Python ``Controller`` that ``simulate``'s loop
    flies around the engine's sample step, not a compiled law: the MPC, a tethered landing
    (``runs.landing``), a ``[reference]`` beyond hover (``runs.flight``), a point of N held
    over a moving base, the deck's heave fed forward (``control.deck``). The one rule
    ``simulate`` and ``run_batch`` route runs by.

    Parameters
    ----------
    scenario : Scenario
        The run.

    Returns
    -------
    bool
    """
    return (
        not controller_entry(scenario.control.controller).compiled
        or scenario.maneuver.landing
        or scenario.trajectory.moving
        or scenario.control.base_feedforward
        or (scenario.reference == "ground" and not scenario.base_motion.fixed)
    )


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
        start = start_point(
            model, trim, gain, ctrl, scenario.wind, scenario.q9, base_velocity(scenario)
        )
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
        run_base(scenario, model),
        run_gear(scenario, model),
    )


def run_gear(scenario: Scenario, model: TetheredHelicopter) -> Gear:
    """The landing gear of a run as the engine takes it (``layout.Gear``, over the level
    deck through the base: ``model.contact.gear_record``); ``layout.no_gear()`` without a
    ``[landing_gear]`` table.

    Parameters
    ----------
    scenario : Scenario
        The run.
    model : TetheredHelicopter
        Its model (the tail lever).

    Returns
    -------
    layout.Gear
        The run's own record (its scratch is written by the engine).
    """
    g = scenario.landing_gear
    if g is None:
        return no_gear()
    law = gear_law_array(g.stiffness, g.damping, g.friction, g.slip_speed)
    return gear_record(np.array(g.points, dtype=float), law, model.params.helicopter,
                       DECK_LOCK_STIFFNESS, DECK_LOCK_DAMPING)  # fmt: skip


def run_base(scenario: Scenario, model: TetheredHelicopter) -> CompiledBase:
    """The winch's base of a run in the engine's packed form (``base.compile_base``), with
    the helicopter's mass for the frame's inertial force: what ``simulate`` and the
    Gymnasium environments fly (the paper's still winch without a ``[base]`` table).

    Parameters
    ----------
    scenario : Scenario
        The run (its ``base_motion``).
    model : TetheredHelicopter
        The plant (``run_setup``'s), on the scenario's parameters.

    Returns
    -------
    CompiledBase
    """
    return compile_base(scenario.base_motion, model.params.helicopter.m)


def base_velocity(scenario: Scenario) -> np.ndarray:
    """The base's velocity b'(0) in N at the run's start [m/s] (zero for the paper's still
    winch): HO starts at rest relative to the base, so at this velocity in N, and the start's
    trim balances the air relative to it (``start.start_point``): the still air's velocity
    relative to the base negated, from the one rule the engine flies
    (``wind.evaluate.air_relative_to_base`` on the packed base).

    Parameters
    ----------
    scenario : Scenario
        The run (its ``base_motion``).

    Returns
    -------
    numpy.ndarray, shape (3,)
    """
    motion = scenario.base_motion
    if motion.fixed:
        return np.zeros(3)
    return -np.array(air_relative_to_base(compile_base(motion).packed, 0.0, 0.0, 0.0, 0.0))
