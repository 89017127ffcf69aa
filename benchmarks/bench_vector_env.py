"""Vector environment speed: ``TetheredHoverVectorEnv`` (all copies in one compiled call per
step) against ``gymnasium.vector.SyncVectorEnv`` of ``TetheredHoverEnv``, in the same process.

Run: python benchmarks/bench_vector_env.py [--copies 16,64,256] [--steps 200] [--rounds 3]
Prints, for each number of copies, env steps/s (copies x steps / time) of both over the same
seeded random actions in [-0.1, 0.1] (residual on the paper's controller, the default winds,
30 s episodes, so no autoreset within the steps), best of the rounds (interleaved), and their
ratio. Resets and compilation are not timed. Timings vary with the machine and its load; no
test asserts them.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from gymnasium.vector import SyncVectorEnv

from tetherheli.envs import TetheredHoverEnv
from tetherheli.vector_env import TetheredHoverVectorEnv


def _rate(env, actions: np.ndarray) -> float:
    """Env steps/s of one timed run of ``actions`` (steps, copies, 4) from a seeded reset."""
    env.reset(seed=0)
    t0 = time.perf_counter()
    for a in actions:
        env.step(a)
    return actions.shape[0] * actions.shape[1] / (time.perf_counter() - t0)


def compare(n: int, steps: int, rounds: int) -> dict:
    """Best env steps/s of the vector env and of SyncVectorEnv for n copies."""
    actions = np.random.default_rng(1).uniform(-0.1, 0.1, size=(steps, n, 4)).astype(np.float32)
    envs = {
        "vector": TetheredHoverVectorEnv(n),
        "sync": SyncVectorEnv([TetheredHoverEnv for _ in range(n)]),
    }
    for env in envs.values():  # compile / load the compiled code
        _rate(env, actions[:2])
    best = dict.fromkeys(envs, 0.0)
    for r in range(rounds):
        for name in envs if r % 2 == 0 else reversed(list(envs)):
            best[name] = max(best[name], _rate(envs[name], actions))
    for env in envs.values():
        env.close()
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copies", default="16,64,256")
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    print(f"{'copies':>6} {'vector [steps/s]':>17} {'SyncVectorEnv [steps/s]':>24} {'ratio':>6}")
    for n in (int(v) for v in args.copies.split(",")):
        best = compare(n, args.steps, args.rounds)
        ratio = best["vector"] / best["sync"]
        print(f"{n:>6} {best['vector']:>17,.0f} {best['sync']:>24,.0f} {ratio:>6.1f}")


if __name__ == "__main__":
    main()
