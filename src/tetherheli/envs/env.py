"""Gymnasium environment: a tethered helicopter hovering in wind, for reinforcement learning.

``TetheredHoverEnv`` wraps the compiled tethered-coordinate plant of the closed-loop engine
(:func:`tetherheli.engine.loop.rk4_interval`, the same RK4 integration ``simulate`` uses) as a
:class:`gymnasium.Env`. One environment step is one control sample ``dt`` (10 ms by default):
the inputs are held constant over the sample (zero-order hold) and the plant is integrated
with the scenario's RK4 sub-steps. The winch always runs the paper's PI tension loop (eq 56).

Action
    ``Box(-1, 1, (4,), float32)``; the action is clipped to [-1, 1] and multiplied by
    ``action_scale`` (default ``(20 N, 2 N m, 2 N m, 5 N)``) to give a vector in the model's
    input order ``[fMR3, tMR1, tMR2, fTR2]`` (main-rotor collective force, main-rotor torques
    about f1 and f2, tail-rotor force).

    - ``residual=True`` (default): the scaled action is *added* to the command of the paper's
      controller (LQI with integral action + tether-torque feed-forward, eqs 50-55, computed by
      :func:`tetherheli.control.paper.paper_control`). A zero action reproduces ``simulate``.
    - ``residual=False``: the scaled action is the deviation of the rotor inputs from their
      trim values (``trim.u_total``, which includes the trim feed-forward); the LQI is not
      applied. A zero action holds the trim inputs (open loop, unstable in wind).

Observation
    ``Box(-OBS_LIMIT, OBS_LIMIT, (13,), float32)``: deviations from the hover trim, as the
    scenario's sensors read them (the true values with the default, perfect sensors), in the
    order of ``OBSERVATION_NAMES``::

        0-2   q1, q2, q3   position of HO in N (outputs, eqs 43-45) [m]
        3-5   q4, q5, q6   helicopter attitude angles [rad]
        6-8   u1, u2, u3   velocity of HO in N [m/s]
        9-11  u4, u5, u6   angular rates [rad/s]
        12    TC - Tref    tether tension minus its reference [N] (0 - 0 if free)

    Values are clipped to +-``OBS_LIMIT`` and a non-finite value (only possible on the
    terminating step of a blown-up run) is reported as 0.

Reward
    ``-(|q_1..3 - q_ref|^2 + effort_weight |a|^2)`` per step, with the position error [m] after
    the step and the clipped action ``a``; on a terminating step ``-termination_penalty``.

Episode end
    ``terminated`` when :func:`tetherheli.engine.loop.check_state` reports a failure (ground
    contact, non-finite state, coordinate singularity, tension above ``limits.max_tension``,
    deviation or attitude beyond the scenario's limits); ``truncated`` after
    ``max_episode_time`` seconds.

Wind
    Drawn at every ``reset`` from the environment's ``np_random`` (seeded by
    ``reset(seed=...)``): a kind among ``wind`` (``"pulse"``, ``"sine"``, ``"turbulence"``,
    ``"none"``), then its parameters (see :meth:`TetheredHoverEnv.draw_wind`). A fixed
    :class:`~tetherheli.wind.Disturbance` may be passed instead, and
    ``reset(options={"wind": disturbance})`` overrides the wind of one episode.

Rendering
    ``render_mode="rgb_array"``: ``render()`` returns the animation's scene
    (:func:`tetherheli.viz.animation.frame_rgb`, the drawing of ``tetherheli animate``) of the
    episode so far as an (H, W, 3) uint8 array; ``"human"`` shows that frame in a Matplotlib
    window after every reset and step (needs a display: an interactive Matplotlib backend).
    An instance's ``metadata["render_modes"]`` lists "human" only where a window can open,
    so Gymnasium's ``check_env`` passes on a headless machine (clusters, CI).
    ``metadata["render_fps"]`` is 1 / dt, one frame per step. Rendering records the episode
    (one row per step) and redraws the whole scene per frame (a fraction of a second): it is
    for looking at a policy, not for training.

``import tetherheli`` registers ``ENV_ID`` with Gymnasium (:func:`register_envs`, which
imports neither this module nor Numba), so ``gymnasium.make("tetherheli/TetheredHover-v0",
...)`` works after ``import tetherheli``, and
``gymnasium.make("tetherheli:tetherheli/TetheredHover-v0")`` in a fresh process (Gymnasium 1.x
imports the module named before the colon; it no longer loads plugins from entry points,
which older Gymnasium does through the ``gymnasium.envs`` entry point of ``pyproject.toml``).
``gymnasium.make_vec(..., num_envs=N, vectorization_mode="vector_entry_point")``
gives N copies stepped in one compiled call
(:class:`tetherheli.envs.vector.TetheredHoverVectorEnv`). The observation (``observe_into``),
the step's reward and failure check (``finish_step``) and the episode's start
(``start_episode``) are compiled functions that both environments run
(``tetherheli.envs.kernels``, re-exported here). Requires the ``gymnasium`` package
(``pip install "tetherheli[rl]"``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from .._gym_registration import ENV_ID, MAX_EPISODE_STEPS, register_envs
from .._validation import check_bool, check_number, check_vector
from ..engine import loop as engine
from ..errors import InfeasibleError, ParameterError
from ..layout import (
    CFG_GUST_DT,
    CTRL_T_REF,
    LAW_Z0,
    LOOP_EVENT,
    LOOP_INPUTS,
    Run,
    WindPack,
    empty_chain,
    no_gear,
)
from ..model.kernels import tethered_outputs
from ..names import FREE_STATE
from ..runs.packing import actuator_array, read_only, sensor_schedule, sensor_tuple
from ..runs.setup import base_velocity, run_base, run_setup
from ..runs.start import StartPoint, free_trim_input, paper_law, start_point
from ..scenario.core import Scenario
from ..sensing.config import N_CHANNELS
from ..sensing.noise import noise_table
from ..status import Status, status_message
from ..wind import (
    CalibratedGaussMarkovTurbulence,
    CompiledWind,
    Disturbance,
    DragModel,
    GaussMarkovTurbulence,
    NoWind,
    Pulse,
    Sine,
    Turbulence,
    check_gust_grid,
    check_wind_covers,
    compile_wind,
)
from .checks import (
    RENDER_MODES,
    SCENARIO_USE,
    RenderModeError,
    argument_names,
    check_display,
    check_env_memory,
    check_env_scenario,
    check_reset_options,
    display_backend,
)
from .kernels import OBS_LIMIT, finish_step, observe_into, start_episode, tether_tension
from .render import close_window, draw_frame, episode_data, episode_row, show_frame

__all__ = [
    "DEFAULT_EPISODE_TIME",
    "ENV_ID",
    "MAX_EPISODE_STEPS",
    "OBSERVATION_NAMES",
    "OBS_LIMIT",
    "RENDER_MODES",
    "SCENARIO_USE",
    "WIND_KINDS",
    "RenderModeError",
    "TetheredHoverEnv",
    "check_env_memory",
    "finish_step",
    "observe_into",
    "register_envs",
    "start_episode",
    "tether_tension",
]

#: Names of the observation entries (all deviations from trim).
OBSERVATION_NAMES = (*FREE_STATE, "tension")

#: Wind kinds that :meth:`TetheredHoverEnv.draw_wind` can draw.
WIND_KINDS = ("none", "pulse", "sine", "turbulence")

#: Default episode length [s] of :class:`TetheredHoverEnv` (``max_episode_time``).
DEFAULT_EPISODE_TIME = 30.0

#: Wind kinds drawn by default (a scenario without wind, no ``wind`` argument).
DEFAULT_WIND_KINDS = ("pulse", "sine", "turbulence")

#: the chain of the environment's runs (the massless tether): the engine's record takes one
_NO_CHAIN = empty_chain()
_NO_GEAR = no_gear()  # the environments fly no landing gear
_DEFAULT_ACTION_SCALE = (20.0, 2.0, 2.0, 5.0)
_DEFAULT_DRAG = DragModel(cd_area_m2=(0.3, 0.3, 0.5))


class TetheredHoverEnv(gymnasium.Env[np.ndarray, np.ndarray]):
    """Hold a tethered helicopter at its hover trim in wind (see the module docstring).

    Parameters
    ----------
    scenario : Scenario, optional
        Flown as ``simulate`` flies it (``SCENARIO_USE`` says what becomes of each key):
        parameters, configuration (``"tethered"``, or ``"free"`` with the tether removed),
        tether length ``q9``, controller settings (``dt``, RK4 ``substeps``, feed-forward, LQI
        weights), failure limits, the winch and its base (``[base]``: a moving deck through
        the engine's packed base, the controller holding a point of the base). Its
        ``duration`` is the episode length and its wind the episode wind unless
        ``max_episode_time`` or ``wind`` is given. Its actuators (saturation, lag, winch rate
        and acceleration limits, tether release) act on the total command exactly as in
        ``simulate``. Its sensors (``[sensors]``: noise, biases, GPS or tether position
        source) feed both the paper's controller and the observation, with each episode's
        noise drawn from ``np_random``; the reward and the failure checks use the true state.
        What an environment cannot fly is refused (``ParameterError`` naming the key): a
        controller other than the paper's, a ``[maneuver]``, the deck's feed-forward, a point
        of N held over a moving base, the lumped tether, a ``seed`` of noisy sensors (the
        episodes' draws are seeded by ``reset(seed=...)``) and ``metrics_start``.
        Default: ``Scenario(duration=DEFAULT_EPISODE_TIME)``, the paper's tethered
        helicopter with 10 ms samples.
    wind : str, sequence of str or Disturbance, optional
        The episode wind: a kind from ``WIND_KINDS``, several kinds (one drawn uniformly per
        episode), or a fixed built-in disturbance used in every episode. Default: the
        scenario's wind when it has one, else ``DEFAULT_WIND_KINDS`` ("pulse", "sine",
        "turbulence").
    residual : bool, optional
        True (default): the action corrects the paper controller's command. False: the action
        sets the rotor inputs around trim directly.
    action_scale : sequence of 4 floats, optional
        Input per unit action for ``[fMR3, tMR1, tMR2, fTR2]`` [N, N m, N m, N], > 0. Default
        ``(20, 2, 2, 5)``.
    max_episode_time : float, optional
        Episode length before truncation [s], a whole number of samples (default: the
        scenario's ``duration``; 30 s, ``DEFAULT_EPISODE_TIME``, without a scenario).
    max_wind_force : float, optional
        Largest pulse magnitude and sine amplitude drawn [N], >= 0 (default 20, the paper's).
    max_mean_wind : float, optional
        Largest horizontal mean wind of a turbulence draw [m/s], >= 0 (default 3).
    turbulence : GaussMarkovTurbulence, optional
        Gust model of turbulence draws (default ``GaussMarkovTurbulence()``; a calibrated one
        is refused, since the drawn mean wind's speed and direction vary per episode).
    drag : DragModel, optional
        Drag of turbulence draws (default CdA = (0.3, 0.3, 0.5) m^2, an assumption).
    gust_dt : float, optional
        Grid step of the turbulence gust table [s] (default 0.05).
    effort_weight : float, optional
        Weight of ``|a|^2`` in the reward, >= 0 (default 0.01).
    termination_penalty : float, optional
        Reward of a terminating step is ``-termination_penalty`` (default 100).
    render_mode : {None, "rgb_array", "human"}, optional
        None (default): no rendering. "rgb_array": ``render()`` returns the animation's
        scene of the episode so far. "human": that scene in a window after every reset and
        step (needs a display). Anything else raises ``RenderModeError``.

    Attributes
    ----------
    trim : TrimPoint
        The hover trim the observation is measured from.
    wind_disturbance : Disturbance or None
        The current episode's wind (None before the first reset).
    """

    metadata: dict[str, Any] = {  # noqa: RUF012 (gymnasium.Env's; an instance sets its own)
        "render_modes": list(RENDER_MODES),
        "render_fps": 1.0 / Scenario().control.dt,  # the default; an instance sets 1 / dt
    }

    def __init__(
        self,
        scenario: Scenario | None = None,
        *,
        wind: str | Sequence[str] | Disturbance | None = None,
        residual: bool = True,
        action_scale: Sequence[float] = _DEFAULT_ACTION_SCALE,
        max_episode_time: float | None = None,
        max_wind_force: float = 20.0,
        max_mean_wind: float = 3.0,
        turbulence: GaussMarkovTurbulence | None = None,
        drag: DragModel | None = None,
        gust_dt: float = 0.05,
        effort_weight: float = 0.01,
        termination_penalty: float = 100.0,
        render_mode: str | None = None,
    ) -> None:
        if render_mode is not None and render_mode not in RENDER_MODES:
            raise RenderModeError("render_mode", render_mode, f"None or one of {RENDER_MODES}")
        if render_mode == "human":
            check_display()
        self.render_mode = render_mode
        self._frames: list[np.ndarray] = []  # the recorded episode (rendering only)
        self._window: Any = None  # the "human" mode's (figure, image)
        if scenario is None:
            scenario = Scenario(duration=DEFAULT_EPISODE_TIME)
        if not isinstance(scenario, Scenario):
            raise ParameterError("scenario", scenario, "a tetherheli Scenario or None")
        check_env_scenario(scenario)  # what the environment cannot fly, by its key
        renamed: dict[str, str] = {}
        if max_episode_time is None:
            max_episode_time = scenario.duration
        else:
            max_episode_time = check_number(
                "max_episode_time", max_episode_time, low=0.0, low_open=True
            )
            renamed["duration"] = "max_episode_time"
        if wind is None:  # the scenario's wind, else the default draws
            wind = DEFAULT_WIND_KINDS if isinstance(scenario.wind, NoWind) else scenario.wind
        self._kinds, self._fixed_wind = self._parse_wind(wind)
        self._renamed = renamed
        with argument_names(renamed):  # the checks of the episode's length name the argument
            # validates that the episode is a whole number of samples (the episode's wind is
            # checked per episode, ``draw_episode``)
            self.scenario = scenario.replace(duration=max_episode_time, wind=NoWind())
            if self._fixed_wind is not None:  # a gust grid as long as the episode
                check_wind_covers(self._fixed_wind, max_episode_time)
        self.max_episode_time = max_episode_time
        self.residual = check_bool("residual", residual)
        self.action_scale = np.array(
            check_vector("action_scale", action_scale, 4, low=0.0, low_open=True)
        )
        self.max_wind_force = check_number("max_wind_force", max_wind_force, low=0.0)
        self.max_mean_wind = check_number("max_mean_wind", max_mean_wind, low=0.0)
        self.gust_dt = check_number("gust_dt", gust_dt, low=0.0, low_open=True)
        self.effort_weight = check_number("effort_weight", effort_weight, low=0.0)
        self.termination_penalty = check_number("termination_penalty", termination_penalty, low=0.0)
        self.turbulence = GaussMarkovTurbulence() if turbulence is None else turbulence
        if not isinstance(self.turbulence, GaussMarkovTurbulence) or isinstance(
            self.turbulence, CalibratedGaussMarkovTurbulence
        ):
            raise ParameterError(
                "turbulence", turbulence, "an uncalibrated GaussMarkovTurbulence or None"
            )
        self.drag = _DEFAULT_DRAG if drag is None else drag
        if not isinstance(self.drag, DragModel):
            raise ParameterError("drag", drag, "a DragModel or None")

        if "turbulence" in self._kinds:  # the episodes' gust grid, T + gust_dt long
            check_gust_grid("gust_dt", self.scenario.duration + self.gust_dt, self.gust_dt)
        check_env_memory(self.scenario, 1, self.gust_dt)  # before an episode's tables exist
        model, trim, gain, ctrl, cfg = run_setup(self.scenario)
        self._model, self._lqi = model, gain
        # the winch's base as simulate flies it (the paper's still winch without [base])
        self._base = read_only(run_base(self.scenario, model).packed)
        # the engine's read-only inputs as ``simulate`` hands them (``packing.read_only``): one
        # compiled signature of each phase for both
        self._act = read_only(
            actuator_array(self.scenario, trim, ctrl)
        )  # rejects limits below hover need
        self.trim = trim
        self.dt = self.scenario.control.dt
        modes = [m for m in RENDER_MODES if m != "human" or display_backend()[0]]
        self.metadata = {**self.metadata, "render_modes": modes, "render_fps": 1.0 / self.dt}
        self.n_max = self.scenario.n_samples
        self._c = read_only(model.constants)
        self._ctrl_base = ctrl
        self._ctrl = ctrl.copy()
        self._cfg_base = cfg
        self._cfg = cfg.copy()
        self._T_ref = float(ctrl[CTRL_T_REF])
        self._y_ref = read_only(trim.y)
        self._u_trim_total = np.asarray(trim.u_total, dtype=float).copy()

        self.action_space = spaces.Box(-1.0, 1.0, shape=(4,), dtype=np.float32)
        self.observation_space = spaces.Box(
            -OBS_LIMIT, OBS_LIMIT, shape=(len(OBSERVATION_NAMES),), dtype=np.float32
        )

        self.wind_disturbance: Disturbance | None = None
        self._wind: CompiledWind | None = None
        self._x = trim.x.copy()
        self._y = np.empty(4)
        self._sensors = self.scenario.sensors
        self._source = self._sensors.source_code
        self._arm = model.params.helicopter.tether_arm
        self._noise = np.zeros((0, N_CHANNELS))
        # the sensors' sampling schedule of an episode (the scenario's, the same every
        # episode; empty for perfect or untimed sensors)
        self._schedule = sensor_schedule(self._sensors, self.dt, self.n_max)
        # the engine's sensors (noise table, ..., history ring), as simulate builds them; an
        # episode's noise table is its own (``_sensor_args``), the ring restarts with it
        self._episode_sensors = sensor_tuple(self._noise, self._source, self._arm, self._schedule)
        self._x_meas = np.empty(13)
        self._y_meas = np.empty(4)
        self._work = np.empty((engine.RK4_WORK_ROWS, 13))
        # the law of the compiled loop, with u0|F after a tether release (``start.paper_law``)
        # and the integrators' start z0 (set per episode in ``reset``: ``start.start_point``)
        law = paper_law(gain, trim, free_trim_input(self.scenario, model, trim), np.zeros(4))
        self._law = tuple(read_only(a) for a in law)
        # the per-episode arrays of engine.paper_sample (integrators, winch, held actuator
        # state, the tether-release event: time [s], tension [N], NaN: none; scratch), set
        # at each reset by ``start_episode``
        self._loop = engine.new_loop_state(self._x, self._law[LAW_Z0], self._work)
        self._release = self._loop[LOOP_EVENT]
        self._inp = self._loop[LOOP_INPUTS]  # the applied rotor inputs of the last step
        self._k = 0
        self._done = True
        self._status = int(Status.OK)

    # ------------------------------------------------------------------ configuration

    @staticmethod
    def _parse_wind(
        wind: str | Sequence[str] | Disturbance,
    ) -> tuple[tuple[str, ...], Disturbance | None]:
        allowed = f"a kind among {WIND_KINDS}, a sequence of them, or a built-in Disturbance"
        if isinstance(wind, Disturbance):
            if compile_wind(wind) is None:
                raise ParameterError("wind", wind, allowed)
            return (), wind
        if isinstance(wind, str):
            kinds: tuple = (wind,)
        elif isinstance(wind, (list, tuple)):
            kinds = tuple(wind)
        else:  # not a sequence of kinds (a number, a dict, a generator, ...)
            raise ParameterError("wind", wind, allowed)
        if not kinds or not all(isinstance(k, str) and k in WIND_KINDS for k in kinds):
            raise ParameterError("wind", wind, allowed)
        return kinds, None

    @staticmethod
    def _horizontal(rng: np.random.Generator) -> tuple[float, float, float]:
        angle = float(rng.uniform(0.0, 2.0 * math.pi))
        return (math.cos(angle), math.sin(angle), 0.0)

    def draw_wind(self, kind: str, rng: np.random.Generator | None = None) -> Disturbance:
        """Draw one episode's wind of the given kind from ``rng`` (default ``np_random``).

        Parameters
        ----------
        kind : str
            One of ``WIND_KINDS``:

            - ``"none"``: no wind;
            - ``"pulse"``: magnitude U(0, max_wind_force) N, start U(0, T/2), duration
              U(0.5, 2) s (both rounded to the sample grid), random horizontal direction;
            - ``"sine"``: amplitude U(0, max_wind_force) N, frequency U(0.05, 0.5) Hz, start
              U(0, T/2) s on the sample grid, phase chosen so that the force starts from 0,
              random horizontal direction;
            - ``"turbulence"``: a ``Turbulence`` of the ``turbulence`` gust model and ``drag``,
              seeded from ``np_random``, with a horizontal mean wind of random direction and
              speed U(0, max_mean_wind) m/s.

            T is ``max_episode_time``.
        rng : numpy.random.Generator, optional
            The generator to draw from (default the environment's ``np_random``).

        Returns
        -------
        Disturbance
            The episode's wind (a force profile, or turbulence with drag).
        """
        if rng is None:
            rng = self.np_random
        T, dt = self.max_episode_time, self.dt
        if kind == "none":
            return NoWind()
        if kind == "pulse":
            magnitude = float(rng.uniform(0.0, self.max_wind_force))
            start = dt * round(float(rng.uniform(0.0, 0.5 * T)) / dt)
            duration = max(dt, dt * round(float(rng.uniform(0.5, 2.0)) / dt))
            return Pulse(start, duration, magnitude, self._horizontal(rng))
        if kind == "sine":
            amplitude = float(rng.uniform(0.0, self.max_wind_force))
            frequency = float(rng.uniform(0.05, 0.5))
            start = dt * round(float(rng.uniform(0.0, 0.5 * T)) / dt)
            phase = -2.0 * math.pi * frequency * start
            return Sine(amplitude, frequency, start, self._horizontal(rng), phase)
        if kind == "turbulence":
            seed = int(rng.integers(0, 2**63 - 1))
            speed = float(rng.uniform(0.0, self.max_mean_wind))
            mean = tuple(speed * v for v in self._horizontal(rng))
            return Turbulence(
                self.turbulence,
                self.drag,
                seed,
                T + self.gust_dt,
                self.gust_dt,
                N_v_mean_wind=mean,  # type: ignore[arg-type]
            )
        raise ParameterError("kind", kind, f"one of {WIND_KINDS}")

    def draw_episode(
        self, rng: np.random.Generator, wind: Any = None
    ) -> tuple[Disturbance, CompiledWind, StartPoint, np.ndarray]:
        """What ``reset`` draws for an episode, in its order: the wind (``wind`` if given,
        else the fixed wind, else a kind drawn uniformly and ``draw_wind``), the start at
        rest in the trim of its air at t = 0 (``runs.start.start_point``, no draw), then the
        sensor noise table (``sensors.noise_table``; empty with perfect sensors).

        Parameters
        ----------
        rng : numpy.random.Generator
            The generator of the draws (``reset`` passes ``np_random``).
        wind : Disturbance, optional
            A built-in disturbance for this episode instead of a draw (default None: draw).

        Returns
        -------
        wind : Disturbance
            The episode's wind.
        compiled : CompiledWind
            Its compiled form for the engine.
        start : StartPoint
            The start state x and integrators z (``runs.start.start_point``).
        noise : ndarray, shape (n_samples + 1, N_CHANNELS) or (0, N_CHANNELS)
            The episode's sensor noise table (empty with perfect sensors).
        """
        name = "wind" if wind is None else "options['wind']"
        limit = name  # the user's field a start without trim is refused under
        if wind is None:
            if self._fixed_wind is not None:
                wind = self._fixed_wind
            else:
                kind = self._kinds[int(rng.integers(len(self._kinds)))]
                wind = self.draw_wind(kind, rng)
                limit = "max_mean_wind" if kind == "turbulence" else "max_wind_force"
        compiled = compile_wind(wind) if isinstance(wind, Disturbance) else None
        if compiled is None:
            raise ParameterError("options['wind']", wind, "a built-in Disturbance")
        with argument_names(self._renamed):  # a gust grid as long as the episode
            check_wind_covers(wind, self.max_episode_time, name=name)
        try:
            with np.errstate(over="ignore"):  # a force beyond float range: no trim, below
                start = start_point(
                    self._model, self.trim, self._lqi, self._ctrl_base, wind, self.scenario.q9,
                    base_velocity(self.scenario),
                )  # fmt: skip
        except InfeasibleError as exc:  # named by the user's field, not the trim's force
            value = getattr(self, limit) if limit.startswith("max_") else wind
            raise ParameterError(
                limit, value, f"a wind the helicopter can start in at rest (this episode's "
                f"{type(wind).__name__} at t = 0: {exc.allowed})"
            ) from None  # fmt: skip
        if self._sensors.is_perfect:
            noise = np.zeros((0, N_CHANNELS))
        else:  # the episode's sensor noise, from the seeded generator
            noise = noise_table(self._sensors, self.n_max, rng, dt=self.dt)
        return wind, compiled, start, noise

    def action_command(self, action: Any, shape: tuple[int, ...] = (4,)) -> tuple:
        """(clipped action a, rotor command, ``engine.ACTION_*`` mode) of an action of the
        given shape (..., 4): a = clip(action, -1, 1); the command is ``action_scale`` a
        (residual) or ``trim.u_total + action_scale a`` (replace).

        Parameters
        ----------
        action : array_like
            The action(s), of shape ``shape`` exactly, finite (then clipped to [-1, 1]).
        shape : tuple of int, optional
            The shape (..., 4) of the action array (default (4,); the vector environment
            passes (N, 4)).

        Returns
        -------
        a : ndarray, shape ``shape``
            The clipped action.
        command : ndarray, shape ``shape``
            The rotor command [fMR3, tMR1, tMR2, fTR2] in [N, N m, N m, N]: a correction of the
            paper controller's (residual) or the total input (replace).
        mode : int
            ``engine.ACTION_ADD`` (residual) or ``engine.ACTION_REPLACE``.
        """
        allowed = f"finite numbers of shape {shape}"
        try:
            raw = np.asarray(action, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError("action", action, allowed) from None
        # never reshaped: a (2, 2) for 4 inputs or a 12-vector for 3 copies is refused, not
        # flown scrambled; never clipped from inf: the contract is finite
        if raw.shape != tuple(shape):
            raise ParameterError("action", action, f"{allowed}, not {raw.shape}")
        if not np.all(np.isfinite(raw)):
            raise ParameterError("action", action, allowed)
        a = np.clip(raw, -1.0, 1.0)
        if self.residual:
            return a, self.action_scale * a, engine.ACTION_ADD
        return a, self._u_trim_total + self.action_scale * a, engine.ACTION_REPLACE

    # ------------------------------------------------------------------ gymnasium API

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start an episode with a new wind, at rest in the hover trim of its air at t = 0
        (``runs.start.start_point``: a turbulence's mean wind plus its first gust; the
        windless trim for the force profiles).

        Parameters
        ----------
        seed : int, optional
            Reseeds ``np_random`` (which draws the wind).
        options : dict, optional
            ``{"wind": Disturbance}`` uses that (built-in) disturbance for this episode
            instead of a draw; None or ``{}``: the environment's wind. Anything else
            (another type, another key) is a ``ParameterError`` naming ``options``.

        Returns
        -------
        observation : ndarray, shape (13,), float32
            Zero up to the trim's rounding without turbulence; in one, the trim's steady tilt
            (see the module docstring for the order).
        info : dict
            As for :meth:`step`; ``inputs`` (no input applied yet) and ``reel_rate`` are NaN.
        """
        options_wind = check_reset_options(options)
        super().reset(seed=seed)
        wind, compiled, start, noise = self.draw_episode(self.np_random, options_wind)
        self.wind_disturbance = wind
        self._wind = compiled
        self._wind_args = (
            *(read_only(a) for a in (compiled.program, compiled.gust, compiled.drag)),
            self._base,
        )
        self._law = (*self._law[:LAW_Z0], read_only(start.z))
        self._noise = noise
        # at rest in the equilibrium of the episode's air at t = 0 (runs.start.start_point),
        # the loop arrays of engine.paper_sample and the sensor history ring fresh
        start_episode(
            self._x, self._cfg, self._ctrl, self._loop, self._episode_sensors[-1], start.x,
            start.z, self._cfg_base, self._ctrl_base, compiled.gust_dt,
        )  # fmt: skip
        self._k = 0
        self._done = False
        tethered_outputs(self._x, self._c, self._y)
        self._status = int(Status.OK)
        observation = self._observe(self._tension())
        if self.render_mode is not None:
            self._frames = []
            self._record()
        return observation, self._info(Status.OK, math.nan)

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """Advance one control sample.

        Parameters
        ----------
        action : array_like, shape (4,)
            In [-1, 1] (clipped); see the module docstring for its meaning.

        Returns
        -------
        observation : ndarray, shape (13,), float32
            What the sensors read after the step, as deviations from trim (order
            ``OBSERVATION_NAMES``), clipped to +-OBS_LIMIT.
        reward : float
            -(|q_1..3 - q_ref|^2 [m^2] + effort_weight |a|^2), or -termination_penalty
            (``finish_step``).
        terminated : bool
            The state failed ``engine.check_state`` (``info["status"]`` says why).
        truncated : bool
            ``max_episode_time`` reached.
        info : dict
            ``time`` [s]; ``status`` (``Status``) and ``message``; ``outputs``
            (4,) float64 [q1, q2, q3, q6] in [m, m, m, rad]; ``inputs`` (4,) the rotor inputs
            applied over the step; ``reel_rate`` [m/s] applied over the step; ``tension`` [N];
            ``tether_release``: None, or ``{"time", "tension"}`` [s, N] once the safety device
            has released the tether in this episode (``message`` then says so too).
        """
        if self._done:
            raise RuntimeError("the episode has ended (or not started): call reset() first")
        a, command, mode = self.action_command(action)
        x, wind = self._x, self._wind
        assert wind is not None
        t = self._k * self.dt
        # the sample as the compiled loop runs it: release check, sensors, the paper's
        # controller with the action, the scenario's actuators (x itself was checked when
        # the previous step ended)
        wind_pack = WindPack(*self._wind_args)
        run = Run(self._cfg, self._ctrl, self._c, self._act, tuple(self._law), wind_pack,
                  self._sensor_args, _NO_CHAIN, _NO_GEAR)  # fmt: skip
        _, _, rate = engine.paper_sample(run, self._loop, x, self._k, command, mode)
        engine.rk4_interval(x, self._inp, rate, t, self._cfg, self._c, wind_pack, self._work, True,
                            _NO_GEAR)  # fmt: skip
        self._k += 1
        status, reward, tension = finish_step(
            x, a, self._cfg, self._c, self._y, self._y_ref, self.effort_weight,
            self.termination_penalty,
        )  # fmt: skip
        terminated = status != Status.OK
        truncated = not terminated and self._k >= self.n_max
        self._done = terminated or truncated
        observation = self._observe(tension)  # what the sensors read now
        self._status = int(status)
        if self.render_mode is not None:
            self._record()
        return observation, float(reward), terminated, truncated, self._info(status, rate)

    def render(self) -> np.ndarray | None:
        """The scene of the episode so far, as ``tetherheli animate`` draws it
        (:func:`tetherheli.viz.animation.frame_rgb`): helicopter, rotor disc, trail, tether
        coloured by tension, winch and wind-force arrow at the current sample.

        Returns
        -------
        ndarray (H, W, 3) uint8 or None
            The frame with ``render_mode="rgb_array"``; None with "human" (the frame is shown
            in the window) or None (nothing drawn).
        """
        if self.render_mode is None:
            gymnasium.logger.warn("render() called with render_mode=None: nothing to draw")
            return None
        frame = self._draw()
        if self.render_mode == "rgb_array":
            return frame
        self._show(frame)
        return None

    def close(self) -> None:
        """Close the "human" mode's window, if open."""
        if self._window is not None:
            close_window(self._window)
            self._window = None
        super().close()

    # ------------------------------------------------------------------ helpers

    def _record(self) -> None:
        """Append the current sample to the rendered episode: t, q1..q9, wind force on HO
        (``engine.wind_force``, as ``simulate`` records it), tension; shown at once in
        "human" mode."""
        wind = self._wind
        assert wind is not None
        t = self._k * self.dt
        row = episode_row(
            t, self._y, self._x, wind, self._cfg[CFG_GUST_DT], self._tension(), self._base
        )
        self._frames.append(row)
        if self.render_mode == "human":
            self._show(self._draw())

    def episode(self) -> Any:
        """The episode so far as the animation reads a saved run
        (:class:`tetherheli.viz.animation.RunData`, stem "episode"), recorded only with a
        ``render_mode``: per step t, q1..q9, the wind force on HO and the tension.

        Returns
        -------
        RunData
            Time [s], q1..q9 [m, rad], wind force [N] and tension [N] per recorded sample,
            with the trim position, the helicopter and the episode's status.
        """
        if not self._frames:
            raise RuntimeError("no episode recorded: set a render_mode and call reset()")
        return episode_data(
            self._frames, self.scenario, self._y_ref[:3].copy(), self._status,
            float(self._release[0]),
        )  # fmt: skip

    def _draw(self) -> np.ndarray:
        """The animation's frame of the recorded episode at its last sample."""
        return draw_frame(self.episode())

    def _show(self, frame: np.ndarray) -> None:
        """Show a frame in the "human" mode's Matplotlib window (opened on first use)."""
        self._window = show_frame(
            self._window, frame, self.metadata["render_fps"], "tetherheli: " + ENV_ID
        )

    @property
    def _sensor_args(self) -> tuple:
        """The episode's ``runs.packing.sensor_tuple`` (for ``engine.sense`` and ``observe_into``)
        with its current noise table ``_noise``; the schedule and history ring are the
        episode's own."""
        return (self._noise, *self._episode_sensors[1:])

    def _tension(self) -> float:
        return float(tether_tension(self._x, self._cfg))

    def _observe(self, tension: float) -> np.ndarray:
        """The observation at the current sample (``observe_into``)."""
        obs = np.empty(len(OBSERVATION_NAMES), dtype=np.float32)
        observe_into(
            self._x, tension, self._k, self._sensor_args, self._c,
            (self.trim.x, self._y_ref, float(self._T_ref)), self._x_meas, self._y_meas, obs,
        )  # fmt: skip
        return obs

    def _info(self, status: int, rate: float) -> dict[str, Any]:
        t_release, tension_release = (float(v) for v in self._release)
        released = not math.isnan(t_release)
        return {
            "time": self._k * self.dt,
            "status": int(status),
            "message": status_message(status, t_release),
            "tether_release": (
                {"time": t_release, "tension": tension_release} if released else None
            ),
            "outputs": self._y.copy(),
            "inputs": self._inp.copy(),
            "reel_rate": float(rate),
            "tension": self._tension(),
        }

    @property
    def state(self) -> np.ndarray:
        """A copy of the plant state (13,): q4..q9, u1..u6, LN (see ``TetheredHelicopter``)."""
        return self._x.copy()

    @property
    def time(self) -> float:
        """Simulated time since the reset [s]."""
        return self._k * self.dt


register_envs()
