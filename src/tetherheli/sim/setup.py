"""The set-up of one closed-loop run: model, hover trim, LQI gain and the packed arrays the
compiled engine takes (``layout``: run configuration, controller settings, actuators), the
compiled wind and the sensor-noise table. ``simulate``, ``run_batch``, sweeps and the
Gymnasium environment all start a run here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from ..control.lqi import LQIGain, design_lqi
from ..errors import InfeasibleError
from ..layout import (
    ACT_BREAK,
    ACT_REEL_ACCEL,
    ACT_TAU,
    ACT_U_MAX,
    ACT_U_MIN,
    CFG_ATTACHED,
    CFG_DT,
    CFG_GUST_DT,
    CFG_K_C,
    CFG_MAX_ANGLE,
    CFG_MAX_DEVIATION,
    CFG_MAX_TENSION,
    CFG_N_SUB,
    CFG_SIZE,
    CTRL_DT,
    CTRL_FFWD,
    CTRL_K_I,
    CTRL_K_P,
    CTRL_REEL_ACCEL,
    CTRL_REEL_RATE_LIMIT,
    CTRL_SIZE,
    CTRL_T_REF,
    CTRL_WINCH,
    LANES,
    LAW_SIZE,
    WIND_COLUMNS,
    WIND_CONSTANT,
    WIND_KIND,
    default_actuators,
)
from ..model import TetheredHelicopter, TrimPoint, linearize
from ..names import INPUT, TETHERED_STATE
from ..params import Params
from ..sensors import N_CHANNELS, noise_table
from ..wind import CompiledWind, compile_wind
from .scenario import Scenario

__all__ = [
    "LQI_STATES",
    "EngineSetup",
    "RunSetup",
    "actuator_array",
    "engine_setup",
    "free_trim_input",
    "lane_block",
    "lane_program_into",
    "paper_gain",
    "paper_law",
    "run_setup",
    "sensor_noise",
]

LQI_STATES = TETHERED_STATE[:12]


@lru_cache(maxsize=64)
def paper_gain(
    params: Params, dt: float, Qy: tuple[float, ...], Ru: tuple[float, ...], q9: float = 10.0
) -> LQIGain:
    """K_LQI|F: the LQI gain designed on the linearized tethered equations at TC = 0 (the free
    helicopter) about Table IV's hover (Sec. V-A, eqs 46-53), for sample time dt."""
    model = TetheredHelicopter(params)
    lin = linearize(model, model.trim(0.0, q9)).select(LQI_STATES)
    G, H = lin.discretize(dt)
    return design_lqi(G, H, lin.C, dt, Qy=np.diag(Qy), Ru=np.diag(Ru))


class RunSetup(NamedTuple):
    """The model, hover trim, LQI gain and packed settings of one run (``run_setup``)."""

    model: TetheredHelicopter
    trim: TrimPoint
    gain: LQIGain
    ctrl: np.ndarray  # controller settings (``layout.CTRL_*``)
    cfg: np.ndarray  # run configuration (``layout.CFG_*``)


def run_setup(scenario: Scenario, design_params: Params | None = None) -> RunSetup:
    """Model, trim, LQI gain and packed engine arrays of one run.

    The gain is designed on ``design_params`` (default: the scenario's own parameters; a
    Monte Carlo passes the nominal ones); plant, trim and winch use the scenario's.
    """
    params = scenario.params
    model = TetheredHelicopter(params)
    tethered = scenario.configuration == "tethered"
    T_ref = params.tension_control.T_ref if tethered else 0.0
    trim: TrimPoint = model.trim(T_ref, scenario.q9)
    c = scenario.control
    gain = paper_gain(
        params if design_params is None else design_params,
        c.dt,
        tuple(c.Qy),
        tuple(c.Ru),
        scenario.q9,
    )
    ctrl = np.zeros(CTRL_SIZE)
    ctrl[CTRL_DT] = c.dt
    ctrl[CTRL_FFWD] = float(tethered and c.feedforward)
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
    return RunSetup(model, trim, gain, ctrl, cfg)


def free_trim_input(scenario: Scenario, model: TetheredHelicopter, trim: TrimPoint) -> np.ndarray:
    """u0|F (4,): the free hover's trim input (Table IV) at the scenario's q9, which the paper
    controller uses once the safety device has released the tether (``engine.paper_sample``).
    The free trim's state q4..u6 and outputs equal the tethered trim's (the tension acts along
    the shaft at hover), so only u0 changes; the free configuration's is its own trim input."""
    if scenario.configuration != "tethered":
        return trim.u.copy()
    return model.trim(0.0, scenario.q9).u.copy()


def paper_law(gain: LQIGain, trim: TrimPoint, u0_free: np.ndarray) -> tuple:
    """The paper controller's law (gain, x_ref, y_ref, u0, u0_free) (``layout.LAW_*``)."""
    return (
        np.ascontiguousarray(gain.K),
        np.ascontiguousarray(trim.x[:12]),
        trim.y.copy(),
        trim.u.copy(),
        np.ascontiguousarray(u0_free, dtype=float),
    )


def actuator_array(scenario: Scenario, trim: TrimPoint, ctrl: np.ndarray) -> np.ndarray:
    """The engine's actuator array (``layout.ACT_*``); also sets the winch limits in ``ctrl``.
    Rejects limits the hover input does not fit in (``InfeasibleError``)."""
    a = scenario.actuators
    act = default_actuators()
    act[ACT_U_MIN : ACT_U_MIN + 4] = a.u_min
    act[ACT_U_MAX : ACT_U_MAX + 4] = a.u_max
    act[ACT_TAU] = a.time_constant
    act[ACT_BREAK] = a.breaking_tension
    act[ACT_REEL_ACCEL] = a.reel_acceleration_limit
    ctrl[CTRL_REEL_RATE_LIMIT] = a.reel_rate_limit
    ctrl[CTRL_REEL_ACCEL] = a.reel_acceleration_limit
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


def sensor_noise(scenario: Scenario) -> np.ndarray:
    """Per-sample sensor noise rows, drawn from the scenario's seed (none when perfect)."""
    if scenario.sensors.is_perfect:
        return np.zeros((0, N_CHANNELS))
    rng = np.random.default_rng(np.random.SeedSequence(scenario.seed))
    return noise_table(scenario.sensors, scenario.n_samples, rng)


@dataclass(frozen=True)
class EngineSetup:
    """Everything one run needs, packed for the compiled engine."""

    model: TetheredHelicopter
    trim: TrimPoint
    gain: LQIGain
    ctrl: np.ndarray
    cfg: np.ndarray
    wind: CompiledWind | None
    act: np.ndarray
    noise: np.ndarray
    source: int
    arm: float
    u0_free: np.ndarray  # u0|F, the trim input after a release (``free_trim_input``)

    def engine_args(self, n_samples: int) -> tuple:
        """The leading arguments of ``engine.run_closed_loop`` (built-in winds only)."""
        assert self.wind is not None
        return (
            self.trim.x.copy(),
            n_samples,
            self.cfg,
            self.ctrl,
            self.model.constants,
            self.law,
            (self.wind.program, self.wind.gust, self.wind.drag),
            self.act,
            self.sensors,
        )

    @property
    def law(self) -> tuple:
        """The paper controller's (gain, x_ref, y_ref, u0, u0_free) (``paper_law``)."""
        return paper_law(self.gain, self.trim, self.u0_free)

    @property
    def sensors(self) -> tuple:
        """(noise table, position-source code, tether arm, scratch) (``engine.sense``)."""
        return (self.noise, self.source, self.arm, np.empty((4, 3)))


def engine_setup(scenario: Scenario, design_params: Params | None = None) -> EngineSetup:
    """Set-up, trim, gain (designed on ``design_params``, default the scenario's), wind,
    actuators and sensor noise of one run."""
    model, trim, gain, ctrl, cfg = run_setup(scenario, design_params)
    wind = compile_wind(scenario.wind)
    if wind is not None:
        cfg[CFG_GUST_DT] = wind.gust_dt
    act = actuator_array(scenario, trim, ctrl)
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
        free_trim_input(scenario, model, trim),
    )


def _stack(arrays: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Arrays (rows, ...) of different row counts stacked along a new lane axis, zero-padded
    to the longest; returns (stacked (B, rows_max, ...), rows in use (B,))."""
    rows = np.array([a.shape[0] for a in arrays], dtype=np.int64)
    stacked = np.zeros((len(arrays), max(1, int(rows.max())), *arrays[0].shape[1:]))
    for j, a in enumerate(arrays):
        stacked[j, : a.shape[0]] = a
    return stacked, rows


def lane_program_into(programs: np.ndarray, j: int, program: np.ndarray) -> None:
    """Lane j of a block's wind programs ``programs`` (rows, WIND_COLUMNS, LANES): the run's
    profile rows ``program`` (k, WIND_COLUMNS), k <= rows, then padding rows of zero force (a
    constant of magnitude 0, which adds +0 to the force)."""
    programs[:, :, j] = 0.0
    programs[:, WIND_KIND, j] = WIND_CONSTANT
    programs[: program.shape[0], :, j] = program


def lane_block(setups: Sequence[EngineSetup], n_samples: Sequence[int]) -> tuple:
    """The leading arguments of ``engine.run_lanes`` for a block of up to ``LANES`` runs,
    lane j packed from ``setups[j]`` as ``EngineSetup.engine_args`` packs a single run
    (built-in winds only; every run must take the same RK4 steps per sample). Lanes beyond
    the runs are padding: copies of the first run with n_samples = -1 (never run). Wind
    programs are padded with rows of zero force and laid out flat (row, column, lane)."""
    if not 0 < len(setups) <= LANES or len(n_samples) != len(setups):
        raise ValueError(f"lane_block: 1 to {LANES} runs, each with its n_samples")
    pad = LANES - len(setups)
    setups = [*setups, *([setups[0]] * pad)]
    counts = np.array([*n_samples, *([-1] * pad)], dtype=np.int64)
    winds = [s.wind for s in setups]
    if any(w is None for w in winds):
        raise ValueError("lane_block: a run's wind is not a built-in disturbance")
    n_rows = max(w.program.shape[0] for w in winds)
    programs = np.empty((n_rows, WIND_COLUMNS, LANES))
    for j, w in enumerate(winds):
        lane_program_into(programs, j, w.program)
    gusts, gust_rows = _stack([np.asarray(w.gust, dtype=float).reshape(-1, 3) for w in winds])
    noise, noise_rows = _stack([s.noise for s in setups])
    laws = [s.law for s in setups]
    return (
        np.stack([s.trim.x for s in setups]),
        counts,
        np.stack([s.cfg for s in setups]),
        np.stack([s.ctrl for s in setups]),
        np.stack([s.model.constants for s in setups]),
        tuple(np.ascontiguousarray(np.stack([law[i] for law in laws])) for i in range(LAW_SIZE)),
        (programs.ravel(), n_rows, gusts, gust_rows, np.stack([w.drag for w in winds])),
        np.stack([s.act for s in setups]),
        (
            noise,
            noise_rows,
            np.array([s.source for s in setups], dtype=np.int64),
            np.array([s.arm for s in setups], dtype=float),
            np.zeros((LANES, 4, 3)),
        ),
    )
