"""The Gymnasium environment's reward and episode-end rules, computed by hand (issue 10, item 6).

Only the public API is used (``reset``, ``step``, ``state``, ``trim``, ``info``), so these
tests hold for any implementation of the closed-loop step. The position of HO is computed
here from the state by eqs 43-45 (SPEC.md's s5 fix: p_HO = q9 c3 - (dO-P,3 - dO-HO,3) f3) with
the centre of mass of eq 3 and Table II, not by the package's output function.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("gymnasium")

from tetherheli.engine import loop as engine
from tetherheli.envs.env import TetheredHoverEnv
from tetherheli.params import Params
from tetherheli.scenario.core import Limits, Scenario
from tetherheli.sensing.config import SensorConfig
from tetherheli.wind import Pulse

PULSE = Pulse(start=0.2, duration=1.0, magnitude=20.0, direction=(0.6, 0.8, 0.0))


def _arm(params: Params) -> float:
    """dO-P,3 - dO-HO,3 with dO-HO,3 from eq 3 (Table II)."""
    h = params.helicopter
    d_HO = (h.m_F * h.d_O_FO3 + h.m_MR * h.d_O_MRO3) / (h.m_F + h.m_MR)
    return h.d_O_P3 - d_HO


def _position(x: np.ndarray, arm: float) -> np.ndarray:
    """Eqs 43-45: HO in N from q4, q5 (attitude) and q7, q8, q9 (tether)."""
    q4, q5, _q6, q7, q8, q9 = x[:6]
    c3 = np.array([math.sin(q8), -math.sin(q7) * math.cos(q8), math.cos(q7) * math.cos(q8)])
    f3 = np.array([math.sin(q5), -math.sin(q4) * math.cos(q5), math.cos(q4) * math.cos(q5)])
    return q9 * c3 - arm * f3


def _episode(env: TetheredHoverEnv, actions: np.ndarray, seed: int = 0):
    """Rewards, states after each step, flags and infos of one episode."""
    env.reset(seed=seed)
    out = []
    for a in actions:
        obs, reward, terminated, truncated, info = env.step(a)
        out.append((obs, reward, terminated, truncated, info, env.state))
        if terminated or truncated:
            break
    return out


def test_reward_is_minus_squared_position_error_minus_weighted_effort():
    """Reward = -(|p_HO - p_HO,trim|^2 + w |clip(a, -1, 1)|^2), p_HO of the true state after
    the step by eqs 43-45: weight 1 on the squared position error [m^2], w = effort_weight on
    the clipped action, both negative."""
    params = Params.paper()
    arm = _arm(params)
    scenario = Scenario(duration=1.5, wind=PULSE)
    w = 0.3
    env = TetheredHoverEnv(scenario, wind=PULSE, max_episode_time=1.5, effort_weight=w)
    rng = np.random.default_rng(1)
    actions = rng.uniform(-2.0, 2.0, size=(150, 4)).astype(np.float32) * 0.1
    actions[::7] = [3.0, -2.0, 0.5, -0.25]  # some clipped: |clip(a)|^2 = 1 + 1 + 0.25 + 0.0625
    p_ref = _position(env.trim.x, arm)
    steps = _episode(env, actions)
    assert len(steps) == 150 and steps[-1][3]  # ran to truncation
    for (_, reward, terminated, _, _, x), a in zip(steps, actions, strict=False):
        assert not terminated
        e = _position(x, arm) - p_ref
        effort = np.clip(a.astype(float), -1.0, 1.0)
        assert reward == pytest.approx(-(e @ e) - w * (effort @ effort), rel=1e-9, abs=1e-15)
    # the pulse moved the helicopter: the position term is not trivially zero
    errors = [np.linalg.norm(_position(s[5], arm) - p_ref) for s in steps]
    assert max(errors) > 0.05


def test_effort_weight_changes_only_the_reward():
    """Same seed and actions, effort weights 0 and 0.5: identical states and observations, and
    rewards that differ by exactly -0.5 |clip(a)|^2 at every step (the effort term's sign and
    weight, independent of the dynamics)."""
    scenario = Scenario(duration=0.5, wind=PULSE)
    actions = np.tile(np.array([0.2, -1.7, 0.0, 0.4], dtype=np.float32), (50, 1))
    a = _episode(
        TetheredHoverEnv(scenario, wind=PULSE, max_episode_time=0.5, effort_weight=0.0), actions
    )
    b = _episode(
        TetheredHoverEnv(scenario, wind=PULSE, max_episode_time=0.5, effort_weight=0.5), actions
    )
    assert len(a) == len(b) == 50
    clipped = np.clip(actions[0].astype(float), -1.0, 1.0)  # the float32 values, clipped
    effort = float(clipped @ clipped)
    assert effort == pytest.approx(0.2**2 + 1.0 + 0.4**2, rel=1e-7)
    for sa, sb in zip(a, b, strict=True):
        np.testing.assert_array_equal(sa[0], sb[0])
        np.testing.assert_array_equal(sa[5], sb[5])
        assert sb[1] - sa[1] == pytest.approx(-0.5 * effort, rel=1e-12)
        assert sa[1] <= 0.0


def test_reward_uses_the_true_state_not_the_measurement():
    """With noisy tether sensors the observation's position is measured (it differs from the
    truth) while the reward is the true squared position error of eqs 43-45."""
    arm = _arm(Params.paper())
    sensors = SensorConfig(position_source="tether", encoder_std=0.002, altimeter_std=0.05)
    scenario = Scenario(duration=0.3, wind=PULSE, sensors=sensors)
    env = TetheredHoverEnv(scenario, wind=PULSE, max_episode_time=0.3, effort_weight=0.0)
    p_ref = _position(env.trim.x, arm)
    steps = _episode(env, np.zeros((30, 4), dtype=np.float32))
    measured_differs = False
    for obs, reward, _, _, _, x in steps:
        e = _position(x, arm) - p_ref
        assert reward == pytest.approx(-(e @ e), rel=1e-9, abs=1e-15)
        measured_differs |= bool(np.abs(obs[:3] - e).max() > 1e-3)
    assert measured_differs


def test_truncation_after_max_episode_time_with_the_ordinary_reward():
    """truncated exactly at step max_episode_time / dt (not before), never with terminated;
    the truncating step's reward is the ordinary one, not a penalty."""
    env = TetheredHoverEnv(wind="none", max_episode_time=0.4, termination_penalty=100.0)
    steps = _episode(env, np.zeros((100, 4), dtype=np.float32))
    assert len(steps) == 40
    assert [s[3] for s in steps] == [False] * 39 + [True]
    assert not any(s[2] for s in steps)
    assert steps[-1][4]["time"] == pytest.approx(0.4) and -1e-12 < steps[-1][1] <= 0.0
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(4, dtype=np.float32))


def _status_by_hand(
    x: np.ndarray, p: np.ndarray, p_ref: np.ndarray, limits: Limits, K_C: float
) -> int:
    """Episode-end rules of the module docstring, from the state (tension by eq 28)."""
    tension = K_C * max(x[5] - x[12], 0.0)
    if tension > limits.max_tension:
        return engine.STATUS_MAX_TENSION
    a = math.radians(limits.max_angle_deg)
    if max(abs(x[0]), abs(x[1]), abs(x[3]), abs(x[4])) > a:
        return engine.STATUS_DIVERGED
    if np.abs(p - p_ref).max() > limits.max_deviation:
        return engine.STATUS_DIVERGED
    return engine.STATUS_OK


@pytest.mark.parametrize(
    ("limits", "status"),
    [
        (Limits(max_tension=25.02), engine.STATUS_MAX_TENSION),
        (Limits(max_deviation=0.05), engine.STATUS_DIVERGED),
        (Limits(max_angle_deg=6.0), engine.STATUS_DIVERGED),
    ],
)
def test_termination_at_the_first_step_that_breaks_a_limit(limits, status):
    """terminated at the first step whose true state breaks a limit (tension by eq 28 above
    limits.max_tension, |q4|, |q5|, |q7|, |q8| above max_angle_deg, a position deviation
    (eqs 43-45) above max_deviation), with reward -termination_penalty, and not before."""
    params = Params.paper()
    arm = _arm(params)
    scenario = Scenario(duration=3.0, wind=PULSE, limits=limits)
    env = TetheredHoverEnv(scenario, wind=PULSE, max_episode_time=3.0, termination_penalty=7.0)
    p_ref = _position(env.trim.x, arm)
    steps = _episode(env, np.zeros((300, 4), dtype=np.float32))
    for k, (_, reward, terminated, truncated, info, x) in enumerate(steps):
        expected = _status_by_hand(x, _position(x, arm), p_ref, limits, params.tether.K_C)
        assert info["status"] == expected, k
        assert terminated == (expected != engine.STATUS_OK) and not truncated
        if terminated:
            assert reward == -7.0
    assert steps[-1][2] and steps[-1][4]["status"] == status and len(steps) < 300
