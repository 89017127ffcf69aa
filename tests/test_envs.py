"""The Gymnasium environment ``TetheredHoverEnv`` (tethered hover in wind, for RL)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from tetherheli import simulate  # noqa: E402
from tetherheli.engine import loop as engine  # noqa: E402
from tetherheli.envs.env import (  # noqa: E402
    ENV_ID,
    OBSERVATION_NAMES,
    TetheredHoverEnv,
    register_envs,
)
from tetherheli.errors import ParameterError  # noqa: E402
from tetherheli.scenario.core import Scenario  # noqa: E402
from tetherheli.wind import Pulse  # noqa: E402


def _rollout(env: TetheredHoverEnv, actions: np.ndarray, seed: int):
    obs, _ = env.reset(seed=seed)
    observations, rewards = [obs], []
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(a)
        observations.append(obs)
        rewards.append(reward)
        if terminated or truncated:
            break
    return np.array(observations), np.array(rewards)


def test_check_env_passes_without_warnings():
    env = TetheredHoverEnv(max_episode_time=2.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    # without a spec, check_env can only say that it cannot try other render modes; nothing
    # about the spaces, seeding, determinism or returned data
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1, messages
    assert "Not able to test alternative render modes" in messages[0]
    assert env.observation_space.shape == (len(OBSERVATION_NAMES),)
    assert env.observation_space.dtype == np.float32
    assert env.action_space.shape == (4,)


def test_check_env_of_registered_env_emits_no_warning():
    register_envs()
    env = gymnasium.make(ENV_ID, max_episode_time=2.0)
    # with a spec, check_env re-makes the env in every render mode, and "human" needs a
    # display: the render modes are checked in test_envs_gym.py
    check_env(env.unwrapped, skip_render_check=True)  # filterwarnings = error
    env.close()


def test_registration_and_make():
    register_envs()
    register_envs()  # idempotent: no "overriding" warning
    assert ENV_ID in gymnasium.registry
    env = gymnasium.make(ENV_ID, wind="pulse", max_episode_time=1.0)
    obs, info = env.reset(seed=3)
    assert env.observation_space.contains(obs)
    assert info["status"] == engine.STATUS_OK
    steps = 0
    truncated = terminated = False
    while not (terminated or truncated):
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        steps += 1
    assert truncated and not terminated and steps == 100
    env.close()


def test_equal_seeds_give_identical_episodes():
    actions = np.random.default_rng(7).uniform(-0.3, 0.3, size=(300, 4)).astype(np.float32)
    for wind in ("pulse", "sine", "turbulence"):
        env_a = TetheredHoverEnv(wind=wind, max_episode_time=3.0)
        env_b = TetheredHoverEnv(wind=wind, max_episode_time=3.0)
        obs_a, rew_a = _rollout(env_a, actions, seed=11)
        obs_b, rew_b = _rollout(env_b, actions, seed=11)
        assert env_a.wind_disturbance == env_b.wind_disturbance
        np.testing.assert_array_equal(obs_a, obs_b)
        np.testing.assert_array_equal(rew_a, rew_b)
        # a different seed draws a different wind
        env_b.reset(seed=12)
        assert env_b.wind_disturbance != env_a.wind_disturbance


def test_zero_residual_without_wind_stays_at_trim():
    env = TetheredHoverEnv(wind="none", max_episode_time=5.0)
    obs, _ = env.reset(seed=0)
    assert np.all(np.abs(obs) < 1e-9)
    truncated = False
    while not truncated:
        obs, reward, terminated, truncated, _ = env.step(np.zeros(4, dtype=np.float32))
        assert not terminated
        assert np.all(np.abs(obs) < 1e-9)
        assert reward <= 0.0 and reward > -1e-15
    assert env.time == pytest.approx(5.0)


def test_zero_residual_equals_simulate():
    pulse = Pulse(start=0.5, duration=1.0, magnitude=20.0, direction=(0.6, 0.8, 0.0))
    scenario = Scenario(duration=2.0, wind=pulse)
    result = simulate(scenario)
    assert result.ok
    env = TetheredHoverEnv(scenario, wind=pulse, max_episode_time=2.0)
    _, info = env.reset(seed=0)
    outputs, states, inputs = [info["outputs"]], [env.state], []
    truncated = False
    while not truncated:
        _, _, terminated, truncated, info = env.step(np.zeros(4, dtype=np.float32))
        assert not terminated
        outputs.append(info["outputs"])
        states.append(env.state)
        inputs.append(info["inputs"])
    np.testing.assert_allclose(np.array(outputs), result.outputs, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.array(states), result.states, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.array(inputs), result.inputs[:-1], rtol=0, atol=1e-12)
    # the pulse moved the helicopter, so the comparison is not trivial
    assert np.abs(result.outputs[:, :2] - result.trim_output[:2]).max() > 0.05


def test_reset_option_overrides_wind():
    pulse = Pulse(start=0.0, duration=1.0, magnitude=10.0, direction=(1.0, 0.0, 0.0))
    env = TetheredHoverEnv(wind="none", max_episode_time=1.0)
    env.reset(seed=0, options={"wind": pulse})
    assert env.wind_disturbance == pulse
    for _ in range(50):
        obs, *_ = env.step(np.zeros(4, dtype=np.float32))
    assert obs[6] > 0.01  # pushed along n1: u1 > 0
    env.reset(seed=0)
    assert env.wind_disturbance != pulse


def test_forced_divergence_terminates_with_penalty():
    env = TetheredHoverEnv(wind="none", residual=False, termination_penalty=50.0)
    env.reset(seed=0)
    action = np.array([0.0, 1.0, 0.0, 0.0], dtype=np.float32)  # full roll torque, open loop
    for _ in range(env.n_max):
        obs, reward, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    assert terminated and not truncated
    assert info["status"] == engine.STATUS_DIVERGED
    assert reward == -50.0
    assert env.observation_space.contains(obs)
    assert info["time"] < 10.0
    with pytest.raises(RuntimeError, match="reset"):
        env.step(action)


def test_residual_action_changes_inputs_by_scale():
    env = TetheredHoverEnv(wind="none", action_scale=(10.0, 1.0, 1.0, 2.0))
    env.reset(seed=0)
    _, _, _, _, info0 = env.step(np.zeros(4, dtype=np.float32))
    env.reset(seed=0)
    _, _, _, _, info1 = env.step(np.array([1.0, -1.0, 0.5, 2.0], dtype=np.float32))  # clipped
    np.testing.assert_allclose(info1["inputs"] - info0["inputs"], [10.0, -1.0, 0.5, 2.0])
    absolute = TetheredHoverEnv(wind="none", residual=False)
    absolute.reset(seed=0)
    _, _, _, _, info = absolute.step(np.zeros(4, dtype=np.float32))
    np.testing.assert_allclose(info["inputs"], absolute.trim.u_total, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"wind": "hurricane"}, "wind"),
        ({"wind": ()}, "wind"),
        ({"residual": 1}, "residual"),
        ({"action_scale": (1.0, 1.0, 0.0, 1.0)}, "action_scale"),
        ({"max_episode_time": -1.0}, "max_episode_time"),
        ({"max_episode_time": 1.005}, "max_episode_time"),
        ({"render_mode": "ansi"}, "render_mode"),
        ({"effort_weight": float("nan")}, "effort_weight"),
    ],
)
def test_invalid_arguments_are_rejected(kwargs, field):
    with pytest.raises(ParameterError) as err:
        TetheredHoverEnv(**kwargs)
    assert err.value.field == field
    assert "\n" not in str(err.value)


def test_messages_name_max_episode_time_not_duration():
    """Issue 43, item 13: the episode's length is the user's ``max_episode_time``; a check
    the scenario makes of it (whole samples, the sample count) names that argument, while a
    table's own ``duration`` key (a turbulence's) keeps its name."""
    from tetherheli.wind import DragModel, GaussMarkovTurbulence, Turbulence

    for value in (1.005, 1e9):
        with pytest.raises(ParameterError) as err:
            TetheredHoverEnv(max_episode_time=value)
        assert err.value.field == "max_episode_time"
        assert "duration" not in str(err.value)
    short = Turbulence(GaussMarkovTurbulence(), DragModel((0.3, 0.3, 0.5)), 1, 1.0, 0.05)
    with pytest.raises(ParameterError) as err:
        TetheredHoverEnv(wind=short, max_episode_time=2.0)
    assert err.value.field == "wind.duration"
    assert "max_episode_time (2 s" in str(err.value)


def test_moving_base_zero_residual_equals_simulate():
    """Issue 43, item 4: the environment flies the scenario's ``[base]`` through the
    engine's sample step and integrator as ``simulate`` does: a heaving deck's episode with
    a zero residual equals ``simulate`` of the same scenario (it was flown as the still
    winch, status 0)."""
    from tetherheli.scenario.core import BaseSettings

    deck = BaseSettings(motion="harmonic", amplitude=(0.0, 0.0, 0.5), frequency=(0.0, 0.0, 0.2))
    scenario = Scenario(duration=2.0, base=deck)
    result = simulate(scenario)
    assert result.ok
    env = TetheredHoverEnv(scenario, wind="none")
    _, info = env.reset(seed=0)
    outputs, states, inputs, truncated = [info["outputs"]], [env.state], [], False
    while not truncated:
        _, _, terminated, truncated, info = env.step(np.zeros(4, dtype=np.float32))
        assert not terminated
        outputs.append(info["outputs"])
        states.append(env.state)
        inputs.append(info["inputs"])
    np.testing.assert_allclose(np.array(states), result.states, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.array(outputs), result.outputs, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.array(inputs), result.inputs[:-1], rtol=0, atol=1e-12)
    # the deck's heave moved the helicopter relative to it: not the still winch's episode
    still = simulate(scenario.replace(base=BaseSettings()))
    assert np.abs(still.states - result.states).max() > 0.1


def _refused_scenarios() -> dict:
    """A scenario per key an environment refuses (``env_checks.SCENARIO_USE``'s "refused"
    fields), each otherwise valid for ``simulate``."""
    from tetherheli.scenario.core import (
        BaseSettings,
        ControlSettings,
        LandingGearSettings,
        TetherSettings,
    )
    from tetherheli.sensing.config import SensorConfig
    from tetherheli.shipped import shipped_scenario

    deck = BaseSettings(motion="harmonic", amplitude=(0.0, 0.0, 0.5), frequency=(0.0, 0.0, 0.2))
    return {
        "control.controller": Scenario(control=ControlSettings(controller="tether_lqi")),
        "control.base_feedforward": Scenario(
            base=deck, control=ControlSettings(base_feedforward=True)
        ),
        "control.reference": Scenario(base=deck, control=ControlSettings(reference="ground")),
        "maneuver.type": shipped_scenario("landing_calm_deck"),
        "landing_gear": Scenario(landing_gear=LandingGearSettings()),
        "trajectory.type": shipped_scenario("paper_waypoints_tethered"),
        "tether.model": Scenario(tether=TetherSettings(model="lumped")),
        "seed": Scenario(seed=3, sensors=SensorConfig(encoder_std=0.01)),
        "metrics_start": Scenario(metrics_start=1.0),
    }


def test_every_scenario_key_is_flown_or_refused():
    """Issue 43, item 4: no key of a scenario is dropped silently. Every field of
    ``Scenario`` has its use in ``SCENARIO_USE``; each refused one is refused in one line
    naming its key (a landing, the deck's feed-forward, a point of N over a moving base, ...);
    the two an argument replaces (``duration``, ``wind``) are flown when it is left out."""
    import dataclasses

    from tetherheli.envs.env import DEFAULT_EPISODE_TIME, SCENARIO_USE

    fields = {f.name for f in dataclasses.fields(Scenario)}
    assert set(SCENARIO_USE) == fields
    assert set(SCENARIO_USE.values()) <= {"flown", "argument", "label", "refused"}
    cases = _refused_scenarios()
    refused_tables = {k for k, use in SCENARIO_USE.items() if use == "refused"}
    assert {key.split(".")[0] for key in cases} == refused_tables
    for key, scenario in cases.items():
        with pytest.raises(ParameterError) as err:
            TetheredHoverEnv(scenario)
        assert err.value.field == f"scenario.{key}", key
        assert "\n" not in str(err.value)
    # an argument left out: the scenario's own duration and wind are flown
    pulse = Pulse(start=0.1, duration=0.2, magnitude=5.0, direction=(1.0, 0.0, 0.0))
    env = TetheredHoverEnv(Scenario(duration=0.5, wind=pulse))
    env.reset(seed=0)
    assert env.max_episode_time == 0.5 and env.n_max == 50
    assert env.wind_disturbance == pulse
    env = TetheredHoverEnv(Scenario(duration=0.5, wind=pulse), wind="none", max_episode_time=0.2)
    env.reset(seed=0)
    assert env.max_episode_time == 0.2 and env.wind_disturbance != pulse
    assert TetheredHoverEnv().max_episode_time == DEFAULT_EPISODE_TIME


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ("wind", "options"),
        ([("wind", None)], "options"),
        (3, "options"),
        ({"wnd": None}, "options['wnd']"),
        ({"wind": "pulse"}, "options['wind']"),
    ],
)
def test_reset_options_are_checked(options, field):
    """Issue 43, item 10: ``reset(options=...)`` takes None or a dict with the documented
    keys; anything else is one ``ParameterError`` line naming ``options`` (it raised
    ``AttributeError``)."""
    env = TetheredHoverEnv(wind="none", max_episode_time=0.1)
    with pytest.raises(ParameterError) as err:
        env.reset(seed=0, options=options)
    assert err.value.field == field
    assert "\n" not in str(err.value)
    obs, _ = env.reset(seed=0, options={})
    assert env.observation_space.contains(obs)


def test_sensors_feed_controller_and_observation():
    """With the scenario's sensors the paper's controller and the observation see
    measurements: a zero residual with the episode's noise table equals ``simulate`` with the
    same table; equal seeds give equal noisy episodes; the reward uses the true position."""
    from tetherheli.runs.packing import sensor_noise
    from tetherheli.sensing.config import SensorConfig

    pulse = Pulse(start=0.5, duration=1.0, magnitude=20.0, direction=(0.6, 0.8, 0.0))
    sensors = SensorConfig(position_source="tether", encoder_std=0.002, altimeter_std=0.05)
    scenario = Scenario(duration=2.0, wind=pulse, sensors=sensors, seed=4)
    result = simulate(scenario)
    # the episodes' noise is seeded by reset (a scenario's seed of noisy sensors is refused)
    scenario = scenario.replace(seed=0)
    env = TetheredHoverEnv(scenario, wind=pulse, max_episode_time=2.0)
    obs0, _ = env.reset(seed=0)
    env._noise = sensor_noise(scenario.replace(seed=4))  # the run's table, as simulate's
    env._observe(env._tension())
    states, truncated = [env.state], False
    while not truncated:
        _, reward, terminated, truncated, info = env.step(np.zeros(4, dtype=np.float32))
        assert not terminated
        e = info["outputs"][:3] - env._y_ref[:3]
        assert reward == pytest.approx(-float(e @ e))
        states.append(env.state)
    np.testing.assert_allclose(np.array(states), result.states, rtol=0, atol=1e-12)
    # the observation is measured: not the true deviation, but close to it
    first, _ = TetheredHoverEnv(scenario, wind=pulse).reset(seed=1)
    again, _ = TetheredHoverEnv(scenario, wind=pulse).reset(seed=1)
    np.testing.assert_array_equal(first, again)
    assert np.any(first[:3] != 0.0) and np.all(np.abs(first[:3]) < 0.5)
    assert not np.array_equal(obs0, first)


def test_actuators_zero_residual_equals_simulate():
    """Saturation, lag and winch limits act in the environment exactly as in simulate."""
    from tetherheli.scenario.core import ActuatorSettings

    inf = math.inf
    pulse = Pulse(start=0.5, duration=1.0, magnitude=20.0, direction=(0.6, 0.8, 0.0))
    act = ActuatorSettings(
        u_min=(-inf, -2.5, -2.5, -inf),
        u_max=(inf, 2.5, 2.5, inf),
        time_constant=0.03,
        reel_rate_limit=0.05,
        reel_acceleration_limit=0.2,
    )
    scenario = Scenario(duration=2.0, wind=pulse, actuators=act)
    result = simulate(scenario)
    assert result.ok and np.abs(result.inputs[:, 1:3]).max() == pytest.approx(2.5)
    env = TetheredHoverEnv(scenario, wind=pulse, max_episode_time=2.0)
    env.reset(seed=0)
    states, inputs, truncated = [env.state], [], False
    while not truncated:
        _, _, terminated, truncated, info = env.step(np.zeros(4, dtype=np.float32))
        assert not terminated
        states.append(env.state)
        inputs.append(info["inputs"])
    np.testing.assert_allclose(np.array(states), result.states, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.array(inputs), result.inputs[:-1], rtol=0, atol=1e-12)
    below = ActuatorSettings(u_max=(100.0, inf, inf, inf))
    with pytest.raises(ParameterError, match="cannot hover"):
        TetheredHoverEnv(Scenario(actuators=below))


def test_reset_leaves_nothing_of_the_previous_episode():
    """``reset`` restarts the environment's arrays in place (``envs.start_episode``, the
    vector environment's too): after episodes with a tether release, winch and actuator lag
    and timed noisy sensors, an episode equals a fresh environment's of the same seed bit
    for bit (observations, rewards, flags, infos)."""
    from tetherheli.scenario.core import ActuatorSettings
    from tetherheli.sensing.config import SensorConfig

    scenario = Scenario().replace(
        sensors=SensorConfig.flown("tether"),
        actuators=ActuatorSettings(breaking_tension=25.1, time_constant=0.02),
    )
    kwargs = {"scenario": scenario, "max_episode_time": 0.4, "max_wind_force": 60.0}
    rng = np.random.default_rng(4)
    actions = rng.uniform(-1.3, 1.3, size=(40, 4)).astype(np.float32)
    used, released = TetheredHoverEnv(**kwargs), 0
    for episode in range(6):
        used.reset(seed=30 + episode)
        for a in actions:
            _, _, terminated, truncated, info = used.step(a)
            if terminated or truncated:
                break
        released += info["tether_release"] is not None
    # the state a reset must clear was in use: the winch, the sensor history
    assert released > 0 and np.any(used._loop[1] != 0.0)
    assert np.any(used._episode_sensors[-1] != 0.0)
    fresh = TetheredHoverEnv(**kwargs)
    pairs = [(used.reset(seed=5), fresh.reset(seed=5))]
    for a in actions:
        pairs.append((used.step(a), fresh.step(a)))
        if pairs[-1][1][2] or pairs[-1][1][3]:
            break
    assert len(pairs) > 10
    for mine, theirs in pairs:
        for x, y in zip(mine[:-1], theirs[:-1], strict=True):
            np.testing.assert_array_equal(x, y)
        assert mine[-1].keys() == theirs[-1].keys()
        for key, value in theirs[-1].items():
            if isinstance(value, np.ndarray):
                np.testing.assert_array_equal(mine[-1][key], value, err_msg=key)
            elif isinstance(value, float) and math.isnan(value):
                assert math.isnan(mine[-1][key]), key
            else:
                assert mine[-1][key] == value, key


def test_a_drawn_wind_without_a_trim_names_its_bound():
    """Found by the environment fuzzer (issue 43): a turbulence drawn with a mean wind no
    hover can trim in (``max_mean_wind = 1e300``) raised the trim's ``N_F_wind`` (after an
    overflow warning); it is one line naming ``max_mean_wind``."""
    env = TetheredHoverEnv(wind="turbulence", max_mean_wind=1e300, max_episode_time=0.05)
    with pytest.raises(ParameterError) as err:
        env.reset(seed=0)
    assert err.value.field == "max_mean_wind"
    assert "\n" not in str(err.value)
