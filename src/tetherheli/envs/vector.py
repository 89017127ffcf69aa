"""Vectorised Gymnasium environment: N copies of ``TetheredHoverEnv`` stepped in one compiled call.

``TetheredHoverVectorEnv`` is a :class:`gymnasium.vector.VectorEnv` whose copy i behaves as a
:class:`tetherheli.envs.env.TetheredHoverEnv` of the same arguments: same spaces, observation,
reward, termination, truncation and info, the same draws (the wind, then the sensor noise)
from the copy's own generator at each reset. One ``step`` is one compiled call
(``vector_step``): per copy, the environment's control sample (``engine.paper_sample`` with
the action added to or replacing the paper controller's command); then the plant of all
copies advanced over the sample by the lane engine (``lane_engine.rk4_lanes``) in blocks of
``layout.LANES`` copies (N rounded up to whole blocks, the extra lanes parked at the trim);
then per copy the reward, the failure checks (``env_kernels.finish_step``) and the
observation (``env_kernels.observe_into``); a copy's episode starts as the single
environment's does (``env_kernels.start_episode``). Each copy's arithmetic is that of the
single environment, so copy i equals a ``TetheredHoverEnv`` reset with the same seed bit for
bit (``tests/test_vector_env.py``).

Seeds
    ``reset(seed=s)`` seeds copy i with ``s + i`` (as ``gymnasium.vector.SyncVectorEnv``
    does); a list gives each copy its seed; ``None`` keeps each copy's generator (fresh
    entropy on the first reset).

Autoreset
    Gymnasium's next-step mode (``metadata["autoreset_mode"] = AutoresetMode.NEXT_STEP``): the
    step after a copy's episode ended ignores its action, resets it (a new draw from its
    generator) and returns its first observation with reward 0 and both flags False.

Info
    Each key of the single environment's info as an array over the copies (``time``,
    ``status``, ``outputs`` (N, 4), ``inputs`` (N, 4), ``reel_rate``, ``tension``; ``message``
    and ``tether_release`` as object arrays), each with its ``_key`` mask (all True), as
    ``SyncVectorEnv`` gathers them. ``tether_release`` holds None or the single environment's
    dict per copy (``SyncVectorEnv`` itself fails to gather it once one copy has a dict and
    another None).

Every copy takes the same scenario, so the copies share the lane engine's constants (model,
gains, sample time) and the sensors' sampling schedule (``packing.sensor_schedule``, a function
of the scenario alone); a copy's episode draws (wind, sensor noise), its start at rest in the
trim of its wind at t = 0 (state and LQI integrators, ``start.start_point``) and its sensor
history ring are its own. Noisy sensors keep a noise table per copy, (n_samples + 1) x 17
doubles.

``reset(options={"wind": disturbance})`` uses that built-in disturbance in every copy for the
episode that starts.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from .._compile import compiled, frozen, plain
from .._validation import check_integer, is_integer
from ..engine import lanes as lane_engine
from ..engine import loop as engine
from ..engine.lanes import lane_program_into
from ..errors import ParameterError
from ..layout import (
    BASE_MOVING,
    CFG_ATTACHED,
    CFG_DT,
    CFG_K_C,
    CFG_N_SUB,
    CFG_TETHER_EA,
    GEAR_LAW_SIZE,
    GEAR_WORK_SIZE,
    HELD_SIZE,
    LANES,
    LAW_U0,
    LAW_Y_REF,
    LOCK_SIZE,
    LUMPED_SIZE,
    WINCH_SIZE,
    WIND_COLUMNS,
    Gear,
    LaneWind,
    LoopState,
    Run,
    WindPack,
)
from ..model.kernels import angle_trig, tethered_outputs
from ..runs.packing import sensor_tuple
from ..sensing.config import N_CHANNELS
from ..status import Status, status_message
from .checks import RenderModeError, check_env_memory, check_reset_options
from .env import OBSERVATION_NAMES, TetheredHoverEnv
from .kernels import finish_step, observe_into, start_episode, tether_tension

__all__ = ["TetheredHoverVectorEnv", "vector_restart", "vector_step"]

_jit = compiled(error_model="numpy")


@_jit
def vector_step(reset, a, command, mode, copies, shared, lanes, wind, out):
    """One step of every copy (the arrays are laid out by ``TetheredHoverVectorEnv``).

    reset (N,) bool: copies that start an episode (their state is set to their episode's
    start, ``start.start_point``'s x and integrators z0, with a fresh sensor history ring;
    their action is ignored); the others run ``engine.paper_sample`` with their row of
    ``command`` (``mode`` an ``engine.ACTION_*``), then the lane engine advances them over the
    sample, then ``env_kernels.finish_step`` with their clipped action row of ``a``. Every
    copy's observation is written by ``env_kernels.observe_into``. ``copies`` holds the
    per-copy state (rows: copies, padded to whole blocks), ``shared`` what all copies share,
    ``lanes`` the lane engine's block arrays, ``wind`` the copies' winds in lane form;
    ``out`` = (obs, reward, status, tension, rate, y) receives the step's results. Over a
    moving base (``moving``) each copy is advanced by ``engine.rk4_interval``, the single
    environment's (and ``simulate``'s) integrator, with its own wind rows and the packed
    base (the lane engine flies a still base only).

    Parameters
    ----------
    reset : numpy.ndarray, shape (N,), bool
        The copies that start an episode (their action ignored).
    a : numpy.ndarray, shape (N, 4)
        The clipped actions (``TetheredHoverEnv.action_command``), for the reward.
    command : numpy.ndarray, shape (N, 4)
        The rotor commands [fMR3, tMR1, tMR2, fTR2] [N, N m, N m, N] the actions make.
    mode : int
        How ``command`` acts on the paper controller's: ``engine.ACTION_*``.
    copies : tuple of numpy.ndarray
        The per-copy arrays (rows: copies, padded to whole blocks): x, k, cfg, ctrl, the loop
        state in ``layout.LOOP_*`` order, the sensor noise, its rows and history ring, the
        episode start's x and z0 (``TetheredHoverVectorEnv``'s ``_copies``).
    shared : tuple
        What all copies share: the trim state, ``cfg`` (``layout.CFG_*``), ``ctrl``
        (``layout.CTRL_*``), ``act``, the model constants, the law's arrays, the sensors' set-up,
        T_ref [N], the reward's weights and scratch arrays (``_shared``).
    lanes : tuple of numpy.ndarray
        The lane engine's block arrays (``lane_engine.rk4_lanes``'s state, inputs, reel rates,
        times, step, attachment, KC [N/m], constants, the parked trig and work).
    wind : tuple
        The copies' winds in lane form: the blocks' profile programs (``layout.WIND_*``) and
        their row count, each copy's gust table [m/s], its rows and step [s], the blocks' drag
        [kg/m], each copy's program, rows and drag, the packed base (``layout.BASE_*``), the
        moving-base flag and the RK4 work array (``_lane_wind``).
    out : tuple of numpy.ndarray
        Receives the results per copy: (obs (N, n_obs) float32, reward (N,), status (N,) int,
        tension (N,) [N], rate (N,) reel rate [m/s], y (N, 4) outputs [m, m, m, rad]).
    """
    (x, k, cfg, ctrl, z, winch, held, event, x_meas, sc_meas, sc_true, y_loop, y_est, inp,
     ffwd, noise, noise_rows, ring, _, _) = copies  # fmt: skip
    (x_trim, cfg0, _, act, c, law, source, arm, scratch, schedule, t_ref, weight, penalty,
     x_scr, y_scr) = shared  # fmt: skip
    x_l, sc_l, inp_l, rate_l, t0_l, h_l, attached_l, k_c_l, c_l, sc_park, work = lanes
    programs, n_rows, gusts, gust_rows, gust_dt, drag = wind[:6]
    copy_programs, program_rows, copy_drag, base, moving, rk4_work = wind[6:]
    obs, reward, status, tension, rate, y = out
    y_ref, u0 = law[LAW_Y_REF], law[LAW_U0]
    n = reset.shape[0]
    # the engine's record takes a chain: the massless tether's (never read by the sample)
    no_chain = (np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(LUMPED_SIZE), np.zeros(0))
    # and a landing gear: none (``layout.no_gear()``'s)
    no_gear = Gear(np.zeros((0, 3)), np.zeros(GEAR_LAW_SIZE), np.zeros(2),
                   np.zeros(GEAR_WORK_SIZE), np.zeros(0), np.zeros((0, LOCK_SIZE)))  # fmt: skip
    for i in range(n):
        if reset[i]:
            restart_copy(i, copies, shared, wind, out)
        else:
            sensors = (noise[i, : noise_rows[i]], source, arm, scratch, schedule, ring[i])
            loop = LoopState(
                z[i], winch[i], held[i], event[i], x_meas[i], sc_meas[i], sc_true[i],
                y_loop[i], y_est[i], inp[i], ffwd[i],
            )  # fmt: skip
            copy_wind = WindPack(
                frozen(copy_programs[i, : program_rows[i]]), frozen(gusts[i, : gust_rows[i]]),
                frozen(copy_drag[i]), base,
            )  # fmt: skip
            run = Run(cfg[i], ctrl[i], c, act, law, copy_wind, sensors, no_chain, no_gear)
            _, _, rate[i] = engine.paper_sample(run, loop, x[i], k[i], command[i], mode)
    n_sub = int(cfg0[CFG_N_SUB])
    if moving:  # copy by copy, as TetheredHoverEnv.step (sin, cos of x in work[6])
        for i in range(n):
            if not reset[i]:
                for v in range(10):
                    rk4_work[6, v] = sc_true[i, v]
                # the engine's own argument types (read-only wind, a plain flag): one
                # compiled rk4_interval for both (tests/test_signatures.py)
                copy_wind = WindPack(
                    frozen(copy_programs[i, : program_rows[i]]),
                    frozen(gusts[i, : gust_rows[i]]), frozen(copy_drag[i]), base,
                )  # fmt: skip
                engine.rk4_interval(x[i], inp[i], rate[i], k[i] * cfg[i, CFG_DT], cfg[i], c,
                                    copy_wind, rk4_work, plain(True), no_gear)  # fmt: skip
    else:  # the lane engine, LANES copies at a time
        for b in range(x_l.shape[0]):
            xb, scb, inpb = x_l[b], sc_l[b], inp_l[b]
            busy = False
            for j in range(LANES):
                i = b * LANES + j
                lane_in = (xb, scb, inpb, rate_l, t0_l, attached_l)
                if i < n and not reset[i]:
                    busy = True
                    lane_engine.set_lane(lane_in, j, x[i], sc_true[i], inp[i], rate[i],
                                         k[i] * cfg[i, CFG_DT], cfg[i, CFG_ATTACHED])  # fmt: skip
                else:  # parked at the trim (finite arithmetic, result unused)
                    lane_engine.park_lane(lane_in, j, x_trim, sc_park, u0)
            if not busy:
                continue
            lo, hi = b * LANES, (b + 1) * LANES
            lane_wind = LaneWind(
                programs[b],
                n_rows,
                gusts[lo:hi],
                gust_rows[lo:hi],
                gust_dt[lo:hi],
                drag[b],
            )
            lane_engine.rk4_lanes(
                (xb, scb, inpb, rate_l, t0_l, attached_l), h_l, n_sub, k_c_l, c_l, lane_wind, work
            )
            for j in range(LANES):
                i = b * LANES + j
                if i < n and not reset[i]:
                    for v in range(13):
                        x[i, v] = xb[v * LANES + j]
    for i in range(n):
        if reset[i]:
            observe_start(i, copies, shared, out)
        else:
            k[i] += 1
            status[i], reward[i], tension[i] = finish_step(
                x[i], a[i], cfg[i], c, y[i], y_ref, weight, penalty
            )
            sensors = (noise[i, : noise_rows[i]], source, arm, scratch, schedule, ring[i])
            observe_into(
                x[i], tension[i], k[i], sensors, c, (x_trim, y_ref, t_ref), x_scr, y_scr, obs[i]
            )


@_jit
def restart_copy(i, copies, shared, wind, out):
    """Copy i at its episode's start (``env_kernels.start_episode``, as
    ``TetheredHoverEnv.reset``): its start state x and integrators z0 (``start.start_point``),
    a fresh loop state and sensor history ring, no reward yet.

    Parameters
    ----------
    i : int
        The copy's index.
    copies : tuple of numpy.ndarray
        The per-copy arrays (rows: copies, padded to whole blocks): x, k, cfg, ctrl, the loop
        state in ``layout.LOOP_*`` order, the sensor noise, its rows and history ring, the
        episode start's x and z0 (``TetheredHoverVectorEnv``'s ``_copies``).
    shared : tuple
        What all copies share: the trim state, ``cfg`` (``layout.CFG_*``), ``ctrl``
        (``layout.CTRL_*``), ``act``, the model constants, the law's arrays, the sensors' set-up,
        T_ref [N], the reward's weights and scratch arrays (``_shared``).
    wind : tuple
        The copies' winds in lane form: the blocks' profile programs (``layout.WIND_*``) and
        their row count, each copy's gust table [m/s], its rows and step [s], the blocks' drag
        [kg/m], each copy's program, rows and drag, the packed base (``layout.BASE_*``), the
        moving-base flag and the RK4 work array (``_lane_wind``).
    out : tuple of numpy.ndarray
        The results per copy (obs (N, n_obs) float32, reward (N,), status (N,) int, tension
        (N,) [N], rate (N,) reel rate [m/s], y (N, 4) outputs [m, m, m, rad]); the copy's
        reward, status and rate are reset.
    """
    (x, k, cfg, ctrl, z, winch, held, event, x_meas, sc_meas, sc_true, y_loop, y_est, inp,
     ffwd, _, _, ring, x_start, z_start) = copies  # fmt: skip
    _, reward, status, _, rate, _ = out
    loop = LoopState(
        z[i], winch[i], held[i], event[i], x_meas[i], sc_meas[i], sc_true[i], y_loop[i],
        y_est[i], inp[i], ffwd[i],
    )  # fmt: skip
    start_episode(
        x[i], cfg[i], ctrl[i], loop, ring[i], x_start[i], z_start[i], shared[1], shared[2],
        wind[4][i],
    )  # fmt: skip
    k[i] = 0
    rate[i] = np.nan
    reward[i] = 0.0
    status[i] = engine.STATUS_OK


@_jit
def observe_start(i, copies, shared, out):
    """Tension, outputs and first observation of copy i just restarted.

    Parameters
    ----------
    i : int
        The copy's index.
    copies : tuple of numpy.ndarray
        The per-copy arrays (rows: copies, padded to whole blocks): x, k, cfg, ctrl, the loop
        state in ``layout.LOOP_*`` order, the sensor noise, its rows and history ring, the
        episode start's x and z0 (``TetheredHoverVectorEnv``'s ``_copies``).
    shared : tuple
        What all copies share: the trim state, ``cfg`` (``layout.CFG_*``), ``ctrl``
        (``layout.CTRL_*``), ``act``, the model constants, the law's arrays, the sensors' set-up,
        T_ref [N], the reward's weights and scratch arrays (``_shared``).
    out : tuple of numpy.ndarray
        The results per copy (obs (N, n_obs) float32, reward (N,), status (N,) int, tension
        (N,) [N], rate (N,) reel rate [m/s], y (N, 4) outputs [m, m, m, rad]); receives the
        copy's tension, outputs and observation.
    """
    x, k, cfg, noise, noise_rows, ring = (
        copies[0],
        copies[1],
        copies[2],
        copies[15],
        copies[16],
        copies[17],
    )
    x_trim, c, law, source, arm, scratch, schedule, t_ref, x_scr, y_scr = (
        shared[0], shared[4], shared[5], shared[6], shared[7], shared[8], shared[9],
        shared[10], shared[13], shared[14],
    )  # fmt: skip
    obs, _, _, tension, _, y = out
    tension[i] = tether_tension(x[i], cfg[i])
    tethered_outputs(x[i], frozen(c), y[i])
    sensors = (noise[i, : noise_rows[i]], source, arm, scratch, schedule, ring[i])
    observe_into(
        x[i],
        tension[i],
        k[i],
        sensors,
        c,
        (x_trim, law[LAW_Y_REF], t_ref),
        x_scr,
        y_scr,
        obs[i],
    )


@_jit
def vector_restart(mask, copies, shared, wind, out):
    """Restart the copies of ``mask`` (N,) bool, leaving the others as they are, and write
    their first observation (the same-step autoreset of Stable-Baselines3's ``VecEnv``).

    Parameters
    ----------
    mask : numpy.ndarray, shape (N,), bool
        The copies to restart.
    copies : tuple of numpy.ndarray
        The per-copy arrays (rows: copies, padded to whole blocks): x, k, cfg, ctrl, the loop
        state in ``layout.LOOP_*`` order, the sensor noise, its rows and history ring, the
        episode start's x and z0 (``TetheredHoverVectorEnv``'s ``_copies``).
    shared : tuple
        What all copies share: the trim state, ``cfg`` (``layout.CFG_*``), ``ctrl``
        (``layout.CTRL_*``), ``act``, the model constants, the law's arrays, the sensors' set-up,
        T_ref [N], the reward's weights and scratch arrays (``_shared``).
    wind : tuple
        The copies' winds in lane form: the blocks' profile programs (``layout.WIND_*``) and
        their row count, each copy's gust table [m/s], its rows and step [s], the blocks' drag
        [kg/m], each copy's program, rows and drag, the packed base (``layout.BASE_*``), the
        moving-base flag and the RK4 work array (``_lane_wind``).
    out : tuple of numpy.ndarray
        Receives the results per copy: (obs (N, n_obs) float32, reward (N,), status (N,) int,
        tension (N,) [N], rate (N,) reel rate [m/s], y (N, 4) outputs [m, m, m, rad]).
    """
    for i in range(mask.shape[0]):
        if mask[i]:
            restart_copy(i, copies, shared, wind, out)
            observe_start(i, copies, shared, out)


class TetheredHoverVectorEnv(VectorEnv):
    """``num_envs`` copies of :class:`~tetherheli.envs.env.TetheredHoverEnv` stepped together
    (see the module docstring).

    Parameters
    ----------
    num_envs : int
        Number of copies, >= 1.
    scenario, **kwargs
        As for :class:`~tetherheli.envs.env.TetheredHoverEnv` (validated by it): every copy has
        the same configuration and draws its own episodes. ``render_mode`` must be None (the
        copies are not drawn; ``RenderModeError`` otherwise).
    max_episode_steps : int, optional
        Truncate a copy's episode after this many steps if that comes before its
        ``max_episode_time`` (what Gymnasium's ``TimeLimit`` does to the single environment;
        ``gymnasium.make_vec`` passes the registration's ``MAX_EPISODE_STEPS``).

    Attributes
    ----------
    env : TetheredHoverEnv
        The configuration the copies share (spaces, trim, set-up, episode draws); not stepped.
    wind_disturbances : list of Disturbance or None
        Each copy's current episode wind.
    """

    metadata: dict[str, Any] = {  # noqa: RUF012 (an instance variable of gymnasium's VectorEnv)
        "render_modes": [],
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }

    def __init__(
        self,
        num_envs: int = 1,
        scenario: Any = None,
        *,
        max_episode_steps: int | None = None,
        **kwargs: Any,
    ) -> None:
        self.num_envs = n = check_integer("num_envs", num_envs, low=1)
        render_mode = kwargs.pop("render_mode", None)
        if render_mode is not None:
            raise RenderModeError("render_mode", render_mode, "None (the copies are not drawn)")
        self.env = env = TetheredHoverEnv(scenario, **kwargs)
        check_env_memory(env.scenario, n, env.gust_dt)  # all copies, before any is allocated
        self.render_mode = None
        self._step_limit = env.n_max
        if max_episode_steps is not None:
            limit = check_integer("max_episode_steps", max_episode_steps, low=1)
            self._step_limit = min(env.n_max, limit)
        self.single_observation_space = env.observation_space
        self.single_action_space = env.action_space
        self.observation_space = batch_space(env.observation_space, n)
        self.action_space = batch_space(env.action_space, n)
        n_blocks = -(-n // LANES)
        n_pad = n_blocks * LANES
        cfg0, ctrl0, x_trim = env._cfg_base, env._ctrl_base, np.ascontiguousarray(env.trim.x)
        noise_rows = 0 if env.scenario.sensors.is_perfect else env.n_max + 1

        def rows(width: int, fill: float = 0.0) -> np.ndarray:
            return np.full((n_pad, width), fill)

        self._x = np.tile(x_trim, (n_pad, 1))
        self._k = np.zeros(n_pad, dtype=np.int64)
        self._cfg = np.tile(cfg0, (n_pad, 1))
        self._ctrl = np.tile(ctrl0, (n_pad, 1))
        self._event = rows(2, np.nan)
        self._inp = rows(4, np.nan)
        self._noise = np.zeros((n_pad, noise_rows, N_CHANNELS))
        self._noise_rows = np.zeros(n_pad, dtype=np.int64)
        # each copy's sensor history ring (``packing.sensor_tuple``'s size for the scenario's
        # schedule, which all copies share) and episode start (``start.start_point``)
        ring = sensor_tuple(env._noise, env._source, env._arm, env._schedule)[-1]
        self._ring = np.zeros((n_pad, *ring.shape))
        self._x_start = np.tile(x_trim, (n_pad, 1))
        self._z_start = np.zeros((n_pad, 4))
        # per copy, in the order of layout.LOOP_* where paper_sample takes them
        self._copies = (
            self._x, self._k, self._cfg, self._ctrl,
            rows(4), rows(WINCH_SIZE), rows(HELD_SIZE), self._event, self._x.copy(),
            rows(10), rows(10), rows(4), rows(4), self._inp, rows(4),
            self._noise, self._noise_rows, self._ring, self._x_start, self._z_start,
        )  # fmt: skip
        self._shared = (
            x_trim, cfg0, ctrl0, env._act, env._c, env._law, env._source, env._arm,
            np.zeros((4, 3)), env._schedule, env._T_ref, env.effort_weight, env.termination_penalty,
            np.empty(13), np.empty(4),
        )  # fmt: skip
        n_sub = int(cfg0[CFG_N_SUB])
        sc_park = np.empty(10)
        angle_trig(x_trim, sc_park)
        self._lanes = (
            np.empty((n_blocks, 13 * LANES)),
            np.empty((n_blocks, 10 * LANES)),
            np.empty((n_blocks, 4 * LANES)),
            np.zeros(LANES),
            np.zeros(LANES),
            np.full(LANES, cfg0[CFG_DT] / n_sub),
            np.zeros(LANES),
            np.repeat([cfg0[CFG_K_C], cfg0[CFG_TETHER_EA]], LANES),  # the law (``rk4_lanes``)
            np.repeat(env._c, LANES),  # (constant, lane) flat
            sc_park,
            lane_engine.lane_work(),
        )
        # the winds in lane form; profile rows and gust rows grow as episodes need them; the
        # same programs and drag per copy for the copy-by-copy integration over a moving base
        self._programs = np.empty((n_blocks, 0, WIND_COLUMNS, LANES))
        self._copy_programs = np.zeros((n_pad, 0, WIND_COLUMNS))
        self._program_rows = np.zeros(n_pad, dtype=np.int64)
        self._copy_drag = np.zeros((n_pad, 3))
        self._moving = bool(env._base[0, BASE_MOVING] > 0.5)
        self._rk4_work = np.empty((engine.RK4_WORK_ROWS, 13))
        self._gusts = np.zeros((n_pad, 0, 3))
        self._gust_rows = np.zeros(n_pad, dtype=np.int64)
        self._gust_dt = np.zeros(n_pad)
        self._drag = np.zeros((n_blocks, 3 * LANES))
        self._obs = np.zeros((n, len(OBSERVATION_NAMES)), dtype=np.float32)
        self._reward = np.zeros(n)
        self._status = np.zeros(n, dtype=np.int64)
        self._tension = np.zeros(n)
        self._rate = np.full(n, np.nan)
        self._y = np.zeros((n, 4))
        self._out = (self._obs, self._reward, self._status, self._tension, self._rate, self._y)
        self._rngs: list[np.random.Generator | None] = [None] * n
        self._autoreset = np.zeros(n, dtype=bool)
        self._started = False
        # the infos of copies without news (copied at every step)
        self._ok_messages = np.full(n, status_message(Status.OK, math.nan), dtype=object)
        self._no_release = np.full(n, None, dtype=object)
        self._mask = np.ones(n, dtype=bool)
        self._wind: tuple | None = None
        self.wind_disturbances: list[Any] = [None] * n

    # ------------------------------------------------------------------ episodes

    def _start_episode(self, i: int, wind: Any) -> None:
        """Copy i's draws for a new episode (``TetheredHoverEnv.draw_episode``), packed."""
        rng = self._rngs[i]
        if rng is None:  # as gymnasium.Env.np_random: fresh entropy
            rng, _ = seeding.np_random()
            self._rngs[i] = rng
        wind, compiled_wind, start, noise = self.env.draw_episode(rng, wind)
        self.wind_disturbances[i] = wind
        self._x_start[i] = start.x
        self._z_start[i] = start.z
        self._wind = None  # repack (the arrays may grow)
        self._noise[i, : noise.shape[0]] = noise
        self._noise_rows[i] = noise.shape[0]
        b, j = divmod(i, LANES)
        program = compiled_wind.program
        if program.shape[0] > self._programs.shape[1]:  # more profile rows: grow every lane
            old = self._programs
            self._programs = np.empty((old.shape[0], program.shape[0], WIND_COLUMNS, LANES))
            for bb in range(old.shape[0]):
                for jj in range(LANES):
                    lane_program_into(self._programs[bb], jj, old[bb, :, :, jj])
        lane_program_into(self._programs[b], j, program)
        if program.shape[0] > self._copy_programs.shape[1]:
            grown_programs = np.zeros(
                (self._copy_programs.shape[0], program.shape[0], WIND_COLUMNS)
            )
            grown_programs[:, : self._copy_programs.shape[1]] = self._copy_programs
            self._copy_programs = grown_programs
        self._copy_programs[i, : program.shape[0]] = program
        self._program_rows[i] = program.shape[0]
        self._copy_drag[i] = compiled_wind.drag
        gust = np.asarray(compiled_wind.gust, dtype=float).reshape(-1, 3)
        if gust.shape[0] > self._gusts.shape[1]:
            grown = np.zeros((self._gusts.shape[0], gust.shape[0], 3))
            grown[:, : self._gusts.shape[1]] = self._gusts
            self._gusts = grown
        self._gusts[i, : gust.shape[0]] = gust
        self._gust_rows[i] = gust.shape[0]
        self._gust_dt[i] = compiled_wind.gust_dt
        self._drag[b, j::LANES] = compiled_wind.drag

    def _lane_wind(self) -> tuple:
        """The winds as ``vector_step`` takes them (programs flat per block)."""
        programs = self._programs
        return (
            programs.reshape(programs.shape[0], programs[0].size),
            programs.shape[1],
            self._gusts,
            self._gust_rows,
            self._gust_dt,
            self._drag,
            self._copy_programs,
            self._program_rows,
            self._copy_drag,
            self.env._base,
            self._moving,
            self._rk4_work,
        )

    def _run(self, restart: np.ndarray, a: np.ndarray, command: np.ndarray, mode: int) -> None:
        if self._wind is None:
            self._wind = self._lane_wind()
        vector_step(
            restart, a, command, mode, self._copies, self._shared, self._lanes, self._wind,
            self._out,
        )  # fmt: skip

    def restart(self, mask: np.ndarray) -> np.ndarray:
        """Start a new episode now in the copies of ``mask`` (num_envs,) bool (a new draw from
        each one's generator), leaving the other copies untouched.

        This is the same-step autoreset that Stable-Baselines3's ``VecEnv`` expects
        (``tetherheli.envs.sb3``); Gymnasium's own next-step autoreset needs no call.

        Parameters
        ----------
        mask : array_like of bool, shape (num_envs,)
            The copies to restart.

        Returns
        -------
        observations : ndarray, shape (num_envs, 13), float32
            Every copy's current observation: the restarted copies' first one.
        """
        if not self._started:
            raise RuntimeError("call reset() before restart()")
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != (self.num_envs,):
            raise ParameterError("mask", mask.shape, f"a bool array of shape ({self.num_envs},)")
        for i in np.flatnonzero(mask):
            self._start_episode(int(i), None)
        if self._wind is None:
            self._wind = self._lane_wind()
        vector_restart(mask, self._copies, self._shared, self._wind, self._out)
        self._autoreset = self._autoreset & ~mask
        return self._obs.copy()

    def _infos(self) -> dict[str, Any]:
        """The single environment's info keys as arrays over the copies, with masks."""
        n = self.num_envs
        event = self._event[:n]
        released = ~np.isnan(event[:, 0])
        status = self._status.copy()
        message = self._ok_messages.copy()
        release = self._no_release.copy()
        for i in np.flatnonzero(released | (status != engine.STATUS_OK)):
            t_release = float(event[i, 0])
            message[i] = status_message(int(status[i]), t_release)
            if released[i]:
                release[i] = {"time": t_release, "tension": float(event[i, 1])}
        info: dict[str, Any] = {
            "time": self._k[:n] * self.env.dt,
            "status": status,
            "message": message,
            "tether_release": release,
            "outputs": self._y.copy(),
            "inputs": self._inp[:n].copy(),
            "reel_rate": self._rate.copy(),
            "tension": self._tension.copy(),
        }
        for key in list(info):
            info[f"_{key}"] = self._mask.copy()
        return info

    # ------------------------------------------------------------------ gymnasium API

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start an episode in every copy.

        Parameters
        ----------
        seed : int, list of int or None, optional
            An int s seeds copy i with s + i; a list gives one seed (or None) per copy; None
            keeps each copy's generator.
        options : dict, optional
            ``{"wind": Disturbance}``: that built-in disturbance in every copy this episode;
            None or ``{}``: each copy's draw. Anything else is a ``ParameterError`` naming
            ``options``.

        Returns
        -------
        observations : ndarray, shape (num_envs, 13), float32
            Each copy's first observation.
        infos : dict
            As for :meth:`step`.
        """
        n = self.num_envs
        wind = check_reset_options(options)  # before any copy's generator is reseeded
        allowed = f"an int >= 0, None, or a list of {n} ints >= 0 or None"
        if seed is None:
            seeds: list[int | None] = [None] * n
        elif is_integer(seed) and seed >= 0:
            seeds = [int(seed) + i for i in range(n)]
        elif (
            isinstance(seed, (list, tuple))
            and len(seed) == n
            and all(s is None or (is_integer(s) and s >= 0) for s in seed)
        ):
            seeds = [None if s is None else int(s) for s in seed]
        else:
            raise ParameterError("seed", seed, allowed)
        for i, s in enumerate(seeds):
            if s is not None:
                self._rngs[i], _ = seeding.np_random(s)
        for i in range(n):
            self._start_episode(i, wind)
        zeros = np.zeros((n, 4))
        self._run(np.ones(n, dtype=bool), zeros, zeros, engine.ACTION_NONE)
        self._autoreset[:] = False
        self._started = True
        return self._obs.copy(), self._infos()

    def step(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Advance every copy one control sample (copies whose episode ended at the previous
        step are reset instead; see the module docstring).

        Parameters
        ----------
        actions : array_like, shape (num_envs, 4)
            In [-1, 1] (clipped), as for ``TetheredHoverEnv.step``.

        Returns
        -------
        observations : ndarray, shape (num_envs, 13), float32
            Each copy's observation (order ``envs.OBSERVATION_NAMES``).
        rewards : ndarray, shape (num_envs,)
            Each copy's reward (as ``TetheredHoverEnv.step``'s).
        terminated : ndarray, shape (num_envs,), bool
            Copies whose state failed ``engine.check_state``.
        truncated : ndarray, shape (num_envs,), bool
            Copies that reached their step limit.
        infos : dict
            The keys of ``TetheredHoverEnv.step``'s info as arrays over the copies, each with
            its ``_key`` mask.
        """
        if not self._started:
            raise RuntimeError("call reset() before step()")
        n = self.num_envs
        a, command, mode = self.env.action_command(actions, (n, 4))
        restart = self._autoreset
        if restart.any():
            for i in np.flatnonzero(restart):
                self._start_episode(int(i), None)
        self._run(restart, np.ascontiguousarray(a), np.ascontiguousarray(command), mode)
        terminated = (self._status != engine.STATUS_OK) & ~restart
        truncated = ~terminated & ~restart & (self._k[:n] >= self._step_limit)
        self._autoreset = terminated | truncated
        return self._obs.copy(), self._reward.copy(), terminated, truncated, self._infos()

    @property
    def states(self) -> np.ndarray:
        """A copy of every copy's plant state (num_envs, 13) (``TetheredHoverEnv.state``)."""
        return self._x[: self.num_envs].copy()
