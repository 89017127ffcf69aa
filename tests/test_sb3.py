"""``tetherheli.envs.sb3.TetheredHoverSB3VecEnv``: Stable-Baselines3's ``VecEnv`` contract on the
compiled vector environment (issue 25, item 3).

SB3's autoreset: the step that ends an episode returns the next episode's first observation,
the last one in ``infos[i]["terminal_observation"]``, no dummy transition. Checked against the
Gymnasium vector environment's next-step autoreset on the same seeds, and by SB3 itself
(``VecCheckNan``, ``VecMonitor``, a short PPO run).
"""

from __future__ import annotations

import numpy as np
import pytest

from tetherheli.envs.vector import TetheredHoverVectorEnv

# Stable-Baselines3 (and PyTorch under it, about 2.5 s) is imported by the tests that use it,
# not while every worker collects the suite
pytestmark = pytest.mark.extra("rl")

STEPS = 6


def _actions(n: int, k: int) -> np.ndarray:
    return np.full((n, 4), 0.05 * ((k % 3) - 1))


def test_same_step_autoreset_equals_gymnasium_next_step():
    from stable_baselines3.common.vec_env import VecEnv

    from tetherheli.envs.sb3 import TetheredHoverSB3VecEnv

    n = 3
    sb3 = TetheredHoverSB3VecEnv(n, max_episode_steps=STEPS)
    gym = TetheredHoverVectorEnv(n, max_episode_steps=STEPS)
    assert isinstance(sb3, VecEnv)
    sb3.seed(7)
    obs = sb3.reset()
    g_obs, _ = gym.reset(seed=7)
    np.testing.assert_array_equal(obs, g_obs)
    for k in range(STEPS):
        obs, rewards, dones, infos = sb3.step(_actions(n, k))
        g_obs, g_rew, term, trunc, _ = gym.step(_actions(n, k))
        np.testing.assert_array_equal(rewards, g_rew.astype(np.float32))
        if k < STEPS - 1:
            assert not dones.any()
            np.testing.assert_array_equal(obs, g_obs)
    # the last step: every copy truncated; its last observation is the terminal one, and the
    # returned one is the first of the next episode (Gymnasium gives it one step later)
    assert dones.all() and trunc.all() and not term.any()
    for i in range(n):
        np.testing.assert_array_equal(infos[i]["terminal_observation"], g_obs[i])
        assert infos[i]["TimeLimit.truncated"] is True
    g_next, g_rew, *_ = gym.step(_actions(n, 99))
    assert np.all(g_rew == 0.0)  # Gymnasium's dummy transition, which SB3 never sees
    np.testing.assert_array_equal(obs, g_next)
    # and the next episode goes on as Gymnasium's does
    for k in range(3):
        obs, _, dones, _ = sb3.step(_actions(n, k))
        g_obs, *_ = gym.step(_actions(n, k))
        np.testing.assert_array_equal(obs, g_obs)


def test_restart_leaves_other_copies_untouched():
    venv = TetheredHoverVectorEnv(4, max_episode_steps=50)
    venv.reset(seed=1)
    for k in range(3):
        venv.step(_actions(4, k))
    before = venv.states
    mask = np.array([False, True, False, False])
    obs = venv.restart(mask)
    after = venv.states
    np.testing.assert_array_equal(after[~mask], before[~mask])
    assert not np.array_equal(after[1], before[1])
    fresh = TetheredHoverVectorEnv(4, max_episode_steps=50)
    fresh_obs, _ = fresh.reset(seed=1)
    # copy 1's second episode differs in wind draw, but it starts at the trim time t = 0
    assert obs.shape == fresh_obs.shape and np.isfinite(obs).all()
    with pytest.raises(Exception, match="mask"):
        venv.restart(np.ones(3, dtype=bool))


def test_sb3_wrappers_and_ppo_run():
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecCheckNan, VecMonitor

    from tetherheli.envs.sb3 import TetheredHoverSB3VecEnv

    env = VecMonitor(
        VecCheckNan(TetheredHoverSB3VecEnv(4, max_episode_steps=32), raise_exception=True)
    )
    model = PPO("MlpPolicy", env, n_steps=32, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=256)
    episodes = model.ep_info_buffer
    assert len(episodes) >= 4
    assert all(ep["l"] == 32 for ep in episodes)  # no dummy transition lengthens an episode
