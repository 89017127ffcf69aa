"""The vectorised environment ``TetheredHoverVectorEnv`` (issue 15, item 3): copy i is a
``TetheredHoverEnv`` seeded with seed + i, bit for bit, with Gymnasium's next-step autoreset
(against single environments stepped as ``SyncVectorEnv`` steps them, and against
``gymnasium.vector.SyncVectorEnv`` itself); spaces batched as Gymnasium batches them;
registration through ``make_vec``. Gymnasium has no ``check_env`` for vector environments."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.vector import AutoresetMode, SyncVectorEnv  # noqa: E402
from gymnasium.vector.utils import batch_space  # noqa: E402

from tetherheli.envs.env import ENV_ID, TetheredHoverEnv, register_envs  # noqa: E402
from tetherheli.envs.vector import TetheredHoverVectorEnv  # noqa: E402
from tetherheli.errors import ParameterError  # noqa: E402
from tetherheli.layout import LANES  # noqa: E402
from tetherheli.scenario.core import ActuatorSettings, Scenario  # noqa: E402
from tetherheli.sensing.config import SensorConfig  # noqa: E402
from tetherheli.status import Status  # noqa: E402

# info keys whose arrays must agree exactly (NaN where the single environment has NaN)
NUMERIC_INFO = ("time", "status", "outputs", "inputs", "reel_rate", "tension")


class _SingleEnvs:
    """The reference: n single environments stepped in turn with Gymnasium's next-step
    autoreset, as ``SyncVectorEnv.step`` does, with the infos kept per copy (SyncVectorEnv
    cannot gather ``tether_release`` once one copy has a dict and another None)."""

    def __init__(self, n: int, **kwargs):
        self.envs = [TetheredHoverEnv(**kwargs) for _ in range(n)]
        self.ended = np.zeros(n, dtype=bool)

    def reset(self, seed: int):
        out = [env.reset(seed=seed + i) for i, env in enumerate(self.envs)]
        self.ended[:] = False
        return np.array([o for o, _ in out]), [info for _, info in out]

    def step(self, actions):
        rows = []
        for i, (env, a) in enumerate(zip(self.envs, actions, strict=True)):
            if self.ended[i]:
                obs, info = env.reset()
                rows.append((obs, 0.0, False, False, info))
            else:
                rows.append(env.step(a))
        obs, reward, terminated, truncated, infos = (list(c) for c in zip(*rows, strict=True))
        self.ended = np.logical_or(terminated, truncated)
        return np.array(obs), np.array(reward), np.array(terminated), np.array(truncated), infos


def _assert_infos_equal(info_v: dict, infos: list, msg: str) -> None:
    for key in NUMERIC_INFO:
        np.testing.assert_array_equal(
            info_v[key], np.array([info[key] for info in infos]), err_msg=f"{msg} {key}"
        )
        assert info_v[f"_{key}"].all()
    assert list(info_v["message"]) == [info["message"] for info in infos], msg
    assert list(info_v["tether_release"]) == [info["tether_release"] for info in infos], msg


def _compare(n: int, steps: int, actions, seed: int, **kwargs) -> dict:
    """Step the vector env and n single envs side by side from the same seed (copy i: seed +
    i); assert equal observations, rewards, flags and infos at every step; return counts of
    terminations, truncations, restarts and copies with a released tether."""
    vec = TetheredHoverVectorEnv(n, **kwargs)
    ref = _SingleEnvs(n, **kwargs)
    seen = {"terminated": 0, "truncated": 0, "released": 0, "restarts": 0}
    obs_v, info_v = vec.reset(seed=seed)
    obs_s, infos = ref.reset(seed)
    np.testing.assert_array_equal(obs_v, obs_s)
    _assert_infos_equal(info_v, infos, "reset")
    for step in range(steps):
        a = actions(step)
        obs_v, rew_v, term_v, trunc_v, info_v = vec.step(a)
        obs_s, rew_s, term_s, trunc_s, infos = ref.step(a)
        msg = f"step {step}"
        np.testing.assert_array_equal(obs_v, obs_s, err_msg=msg)
        np.testing.assert_array_equal(rew_v, rew_s, err_msg=msg)
        np.testing.assert_array_equal(term_v, term_s, err_msg=msg)
        np.testing.assert_array_equal(trunc_v, trunc_s, err_msg=msg)
        _assert_infos_equal(info_v, infos, msg)
        seen["terminated"] += int(term_v.sum())
        seen["truncated"] += int(trunc_v.sum())
        seen["released"] += sum(r is not None for r in info_v["tether_release"])
        seen["restarts"] += int(np.sum(info_v["time"] == 0.0))
        assert vec.observation_space.contains(obs_v)
    vec.close()
    return seen


def test_zero_actions_copies_equal_single_envs_across_autoreset():
    """Zero actions (the paper's controller alone, pulse, sine and turbulence winds): copy i
    equals TetheredHoverEnv reset with seed 7 + i bit for bit, over two blocks of lanes (one
    partly padding) and two autoresets per copy."""
    n = LANES + 3
    seen = _compare(
        n, 2 * 25 + 5, lambda step: np.zeros((n, 4), dtype=np.float32), 7, max_episode_time=0.25
    )
    assert seen["truncated"] == 2 * n and seen["restarts"] == 2 * n
    assert seen["terminated"] == 0


def test_actions_sensors_release_and_failures_match_single_envs():
    """Random residual actions (some clipped), noisy tether-sourced sensors, actuator lag, a
    breaking tension just above the trim's (releases) and a 3 cm deviation limit (failures):
    every copy still equals its single environment, through terminations and autoresets."""
    scenario = Scenario().replace(
        sensors=SensorConfig.typical_tether(),
        actuators=ActuatorSettings(breaking_tension=25.1, time_constant=0.02),
    )
    scenario = scenario.replace(limits=dataclasses.replace(scenario.limits, max_deviation=0.03))
    n = 6
    rng = np.random.default_rng(3)
    actions = rng.uniform(-1.3, 1.3, size=(90, n, 4)).astype(np.float32)
    seen = _compare(
        n, 90, lambda step: actions[step], 21, scenario=scenario, max_episode_time=0.4,
        wind=("pulse", "sine"), max_wind_force=60.0,
    )  # fmt: skip
    assert seen["terminated"] > 0 and seen["restarts"] > 0
    assert seen["released"] > 0


def test_replacing_actions_match_single_envs():
    """Random actions replacing the controller's rotor inputs (``residual=False``) in
    turbulence."""
    n = 3
    rng = np.random.default_rng(5)
    actions = rng.uniform(-0.3, 0.3, size=(40, n, 4)).astype(np.float32)
    _compare(
        n, 40, lambda step: actions[step], 2, wind="turbulence", residual=False,
        max_episode_time=0.3,
    )  # fmt: skip


def test_flown_timed_sensors_match_single_envs():
    """Sensors as flown (``SensorConfig.flown``: datasheet presets at their own rates and
    latencies, position from the tether; ``sensing.sensors.measure_sampled`` with each copy's
    history ring) in turbulence, pulse and sine winds: every copy equals its single environment,
    observations included, through an autoreset (a fresh ring per episode)."""
    scenario = Scenario().replace(sensors=SensorConfig.flown("tether"))
    n = 5
    vec = TetheredHoverVectorEnv(n, scenario=scenario, max_episode_time=0.3)
    assert vec.env._schedule.shape[0] > 0  # timed sensors: the schedule is in use
    vec.close()
    rng = np.random.default_rng(11)
    actions = rng.uniform(-0.5, 0.5, size=(70, n, 4)).astype(np.float32)
    seen = _compare(
        n, 70, lambda step: actions[step], 13, scenario=scenario, max_episode_time=0.3,
        wind=("pulse", "sine", "turbulence"),
    )  # fmt: skip
    assert seen["restarts"] >= n


def test_turbulence_episodes_start_in_the_wind_like_single_envs():
    """Turbulence episodes start at rest in the trim of their air at t = 0
    (``start.start_point``: own state and LQI integrators per copy and episode), as the
    single environment's reset does; the copies then equal their single environments."""
    n = 3
    vec = TetheredHoverVectorEnv(n, wind="turbulence", max_episode_time=0.2)
    vec.reset(seed=4)
    for i in range(n):
        env = TetheredHoverEnv(wind="turbulence", max_episode_time=0.2)
        env.reset(seed=4 + i)
        np.testing.assert_array_equal(vec.states[i], env.state)
        np.testing.assert_array_equal(vec._z_start[i], env._law[-1])
        assert np.any(env.state != env.trim.x) and np.any(env._law[-1] != 0.0)
    vec.close()
    _compare(n, 45, lambda step: np.zeros((n, 4)), 4, wind="turbulence", max_episode_time=0.2)


def test_equals_gymnasium_sync_vector_env():
    """Gymnasium's own reference: ``SyncVectorEnv`` of the single environment (seeds s + i,
    next-step autoreset) gives the same batches, infos included, through an autoreset."""
    n, kwargs = 4, {"max_episode_time": 0.1, "wind": ("pulse", "sine")}
    vec = TetheredHoverVectorEnv(n, **kwargs)
    sync = SyncVectorEnv(
        [lambda: TetheredHoverEnv(**kwargs) for _ in range(n)],
        autoreset_mode=AutoresetMode.NEXT_STEP,
    )
    rng = np.random.default_rng(0)
    pairs = [(vec.reset(seed=9), sync.reset(seed=9))]
    for _ in range(25):
        a = rng.uniform(-1.0, 1.0, size=(n, 4)).astype(np.float32)
        pairs.append((vec.step(a), sync.step(a)))
    for mine, theirs in pairs:
        for x, y in zip(mine[:-1], theirs[:-1], strict=True):
            np.testing.assert_array_equal(x, y)
            assert x.dtype == y.dtype
        assert set(mine[-1]) == set(theirs[-1])
        for key, value in theirs[-1].items():
            assert mine[-1][key].dtype == value.dtype, key
            if value.dtype != object:
                np.testing.assert_array_equal(mine[-1][key], value, err_msg=key)
            else:
                assert list(mine[-1][key]) == list(value), key
    assert any(m[0][3].any() for m in pairs[1:])  # a truncation, then its autoreset
    sync.close()


def test_spaces_are_batched_single_spaces():
    env = TetheredHoverEnv(max_episode_time=0.1)
    vec = TetheredHoverVectorEnv(5, max_episode_time=0.1)
    assert vec.single_observation_space == env.observation_space
    assert vec.single_action_space == env.action_space
    assert vec.observation_space == batch_space(env.observation_space, 5)
    assert vec.action_space == batch_space(env.action_space, 5)
    assert vec.observation_space.shape == (5, 13) and vec.action_space.shape == (5, 4)
    assert vec.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    obs, info = vec.reset(seed=0)
    assert obs.shape == (5, 13) and obs.dtype == np.float32
    assert vec.observation_space.contains(obs)
    obs, reward, terminated, truncated, info = vec.step(vec.action_space.sample())
    assert reward.shape == terminated.shape == truncated.shape == (5,)
    assert reward.dtype == np.float64 and terminated.dtype == np.bool_
    assert info["outputs"].shape == (5, 4) and (info["status"] == Status.OK).all()


def test_seeds_reproduce_and_list_seeds_match_int_seed():
    vec = TetheredHoverVectorEnv(3, max_episode_time=0.1)
    vec.reset(seed=4)
    winds = list(vec.wind_disturbances)
    vec.reset(seed=[4, 5, 6])
    assert vec.wind_disturbances == winds
    vec.reset(seed=[5, None, None])  # copy 0 now draws seed 5's wind, as copy 1 did
    assert vec.wind_disturbances[0] == winds[1]
    vec.reset()  # the generators go on: new winds
    assert vec.wind_disturbances[0] != winds[1]


def test_make_vec_uses_the_vector_entry_point():
    register_envs()
    vec = gymnasium.make_vec(
        ENV_ID, num_envs=4, vectorization_mode="vector_entry_point", max_episode_time=0.1
    )
    assert isinstance(vec.unwrapped, TetheredHoverVectorEnv)
    assert vec.num_envs == 4
    obs, _ = vec.reset(seed=1)
    assert obs.shape == (4, 13)
    vec.close()


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: TetheredHoverVectorEnv(0), "num_envs"),
        (lambda: TetheredHoverVectorEnv(2, max_episode_time=-1.0), "max_episode_time"),
        (lambda: TetheredHoverVectorEnv(2).reset(seed=[1]), "seed"),
    ],
)
def test_bad_arguments_are_rejected(call, field):
    with pytest.raises(ParameterError, match=field):
        call()


def test_moving_base_copies_equal_single_envs():
    """Issue 43, item 4: over a heaving deck each copy is advanced by the single
    environment's integrator (``engine.rk4_interval`` with the packed base; the lane engine
    flies a still base only): copy i equals ``TetheredHoverEnv`` bit for bit, with random
    actions, pulse and turbulence winds and an autoreset."""
    from tetherheli.scenario.core import BaseSettings

    deck = BaseSettings(motion="harmonic", amplitude=(0.0, 0.0, 0.5), frequency=(0.0, 0.0, 0.2))
    rng = np.random.default_rng(3)
    seen = _compare(
        3, 40, lambda _: rng.uniform(-1.0, 1.0, (3, 4)), 5,
        scenario=Scenario(duration=1.0, base=deck), wind=("pulse", "turbulence"),
        max_episode_time=0.3,
    )  # fmt: skip
    assert seen["truncated"] == 3 and seen["restarts"] >= 3


@pytest.mark.parametrize(
    ("options", "field"),
    [("wind", "options"), (["wind"], "options"), ({"gust": 1}, "options['gust']")],
)
def test_reset_options_are_checked(options, field):
    """Issue 43, item 10: the vector environment's ``reset(options=...)`` is checked as the
    single one's (it raised ``AttributeError``), before any copy is reseeded."""
    vec = TetheredHoverVectorEnv(2, wind="none", max_episode_time=0.1)
    with pytest.raises(ParameterError) as err:
        vec.reset(seed=0, options=options)
    assert err.value.field == field
    with pytest.raises(ParameterError, match="seed"):
        vec.reset(seed=[0, -1])


def test_step_before_reset_and_bad_actions_raise():
    vec = TetheredHoverVectorEnv(2, max_episode_time=0.1)
    with pytest.raises(RuntimeError, match="reset"):
        vec.step(np.zeros((2, 4)))
    vec.reset(seed=0)
    with pytest.raises(ParameterError, match="action"):
        vec.step(np.full((2, 4), np.nan))
    with pytest.raises(ValueError):
        vec.step(np.zeros((3, 4)))
