# not-for-ci: trains a policy for minutes and needs the `rl` extra (stable-baselines3, torch)
"""Train a PPO policy (Stable-Baselines3) on the tethered-hover environment.

The policy acts on top of the paper's controller (``residual=True``, the default): a zero
action flies the paper's LQI + feed-forward, so the question is whether PPO learns a
correction that holds the helicopter closer to its trim in wind. The script prints the mean
episode return of the zero action (the paper's controller alone), of the untrained policy
and of the trained one, each over the same seeded evaluation episodes, and the training
rate in environment steps per second.

Needs the ``rl`` extra: ``pip install "tetherheli[rl]"`` (Gymnasium, Stable-Baselines3 and
its PyTorch). Not run in CI. Example (a few minutes on one core)::

    python examples/train_sb3.py --timesteps 50000
"""

from __future__ import annotations

import argparse
import time

import gymnasium
import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy

import tetherheli.envs.env  # registers tetherheli/TetheredHover-v0

ENV_ID = tetherheli.envs.env.ENV_ID


def zero_action_return(env_kwargs: dict, seeds: list[int]) -> float:
    """Mean return of the zero action (the paper's controller alone) over seeded episodes."""
    env = gymnasium.make(ENV_ID, **env_kwargs)
    returns = []
    for seed in seeds:
        env.reset(seed=seed)
        total, done = 0.0, False
        while not done:
            _, reward, terminated, truncated, _ = env.step(np.zeros(4, dtype=np.float32))
            total += float(reward)
            done = terminated or truncated
        returns.append(total)
    env.close()
    return float(np.mean(returns))


def policy_return(model: PPO, env_kwargs: dict, seeds: list[int]) -> float:
    """Mean deterministic return of the policy over the same seeded episodes."""
    returns = []
    for seed in seeds:
        env = make_vec_env(ENV_ID, n_envs=1, seed=seed, env_kwargs=env_kwargs)
        mean, _ = evaluate_policy(model, env, n_eval_episodes=1, deterministic=True)
        returns.append(mean)
        env.close()
    return float(np.mean(returns))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timesteps", type=int, default=50_000, help="training steps")
    parser.add_argument("--n-envs", type=int, default=4, help="parallel environments")
    parser.add_argument("--episode-time", type=float, default=5.0, help="episode length [s]")
    parser.add_argument("--eval-episodes", type=int, default=10, help="evaluation episodes")
    parser.add_argument("--seed", type=int, default=0, help="seed of training and policy")
    parser.add_argument("--threads", type=int, default=1, help="PyTorch threads")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)

    env_kwargs = {"max_episode_time": args.episode_time}
    seeds = [10_000 + i for i in range(args.eval_episodes)]  # not the training seeds
    env = make_vec_env(ENV_ID, n_envs=args.n_envs, seed=args.seed, env_kwargs=env_kwargs)
    model = PPO("MlpPolicy", env, seed=args.seed, device="cpu", verbose=0)

    baseline = zero_action_return(env_kwargs, seeds)
    before = policy_return(model, env_kwargs, seeds)
    start = time.perf_counter()
    model.learn(total_timesteps=args.timesteps)
    seconds = time.perf_counter() - start
    after = policy_return(model, env_kwargs, seeds)

    print(f"environment: {ENV_ID}, {args.n_envs} envs, episodes of {args.episode_time:g} s")
    print(
        f"training: {model.num_timesteps} steps in {seconds:.1f} s = "
        f"{model.num_timesteps / seconds:.0f} steps/s"
    )
    print(f"mean return over {len(seeds)} evaluation episodes (higher is better):")
    print(f"  zero action (paper controller alone): {baseline:10.3f}")
    print(f"  policy before training:               {before:10.3f}")
    print(f"  policy after training:                {after:10.3f}")
    env.close()


if __name__ == "__main__":
    main()
