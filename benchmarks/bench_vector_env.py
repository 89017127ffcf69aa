"""Vector environment speed: ``TetheredHoverVectorEnv`` (all copies in one compiled call per
step) against ``gymnasium.vector.SyncVectorEnv`` of ``TetheredHoverEnv``, and the cost of the
vector environment's resets.

Run: python benchmarks/bench_vector_env.py [--copies 16,64,256] [--steps 200] [--rounds 3]
Prints, for each number of copies, env steps/s (copies x steps / time) of both over the same
seeded random actions in [-0.1, 0.1] (residual on the paper's controller, the default winds,
30 s episodes, so no autoreset within the steps), best of the rounds (interleaved), and their
ratio. Resets and compilation are not timed.

Run: python benchmarks/bench_vector_env.py --autoreset [--copies 64] [--episodes 2]
[--rounds 3] [--baseline SRC]
Prints, for each number of copies: the time of one ``reset`` of all copies (new seeds, the
default winds; median of 7), and env steps/s over whole 30 s episodes with Gymnasium's
next-step autoreset (every step counted, the reset steps included) against the rate of the
same run's steps in which no copy reset (the in-run baseline), best of the rounds. With
``--baseline SRC`` (a ``src`` folder of another tree, e.g. ``git archive <commit> src | tar
-x -C /tmp/base``) both trees are measured, each in a fresh process, alternating, and the
ratios printed. Timings vary with the machine and its load; no test asserts them.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from gymnasium.vector import SyncVectorEnv

from tetherheli.envs.env import TetheredHoverEnv
from tetherheli.envs.vector import TetheredHoverVectorEnv


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


def autoreset(n: int, episodes: int, rounds: int) -> dict[str, float]:
    """Reset time [ms] of n copies and env steps/s with autoreset and without (in-run).

    Each round resets with a new seed and steps through ``episodes`` whole episodes (each
    copy's episode ends by truncation or failure; the step after it resets that copy), timing
    every step; the steps in which some copy reset are the reset steps."""
    env = TetheredHoverVectorEnv(n)
    steps = episodes * (env.env.n_max + 1)
    actions = np.random.default_rng(1).uniform(-0.1, 0.1, size=(steps, n, 4)).astype(np.float32)
    env.reset(seed=0)
    for a in actions[:3]:  # compile / load the compiled code
        env.step(a)
    resets = []
    for s in range(7):
        t0 = time.perf_counter()
        env.reset(seed=1000 + n * s)
        resets.append(time.perf_counter() - t0)
    best = {"reset_ms": 1e3 * statistics.median(resets), "noreset": 0.0, "autoreset": 0.0}
    for r in range(rounds):
        env.reset(seed=r)
        pending = np.zeros(n, dtype=bool)
        total = quiet = 0.0
        quiet_steps = 0
        for a in actions:
            t0 = time.perf_counter()
            _, _, terminated, truncated, _ = env.step(a)
            dt = time.perf_counter() - t0
            total += dt
            if not pending.any():
                quiet += dt
                quiet_steps += 1
            pending = terminated | truncated
        best["autoreset"] = max(best["autoreset"], steps * n / total)
        best["noreset"] = max(best["noreset"], quiet_steps * n / quiet)
    env.close()
    return best


def _measure(src: Path, n: int, episodes: int, rounds: int) -> dict[str, float]:
    """``autoreset`` in a fresh process importing tetherheli from the ``src`` folder."""
    argv = [sys.executable, __file__, "--probe", f"--copies={n}", f"--episodes={episodes}"]
    done = subprocess.run(
        [*argv, f"--rounds={rounds}"],
        env={**os.environ, "PYTHONPATH": str(src)},
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def _print_autoreset(name: str, n: int, m: dict[str, float]) -> None:
    print(
        f"{name:<15} {n:>6} {m['reset_ms']:>9.1f} {m['noreset']:>17,.0f} "
        f"{m['autoreset']:>19,.0f} {m['autoreset'] / m['noreset']:>6.3f}",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copies", default=None, help="default 16,64,256 (--autoreset: 64)")
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--autoreset", action="store_true", help="time resets and autoreset")
    parser.add_argument("--episodes", type=int, default=2, help="episodes per round")
    parser.add_argument("--baseline", type=Path, help="src folder of a tree to compare with")
    parser.add_argument("--probe", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.probe:
        print(json.dumps(autoreset(int(args.copies), args.episodes, args.rounds)))
        return
    if args.autoreset or args.baseline is not None:
        copies = [int(v) for v in (args.copies or "64").split(",")]
        head = f"{'tree':<15} {'copies':>6} {'reset ms':>9} {'no reset [st/s]':>17}"
        print(f"{head} {'autoreset [st/s]':>19} {'ratio':>6}")
        here = Path(__file__).resolve().parents[1] / "src"
        trees = {"candidate": here}
        if args.baseline is not None:
            trees = {"baseline": args.baseline.resolve(), **trees}
        order = [*trees, *reversed(trees)]  # A B B A: the machine's drift hits both alike
        for n in copies:
            best: dict[str, dict[str, float]] = {}
            for name in order:
                m = _measure(trees[name], n, args.episodes, args.rounds)
                _print_autoreset(name, n, m)
                b = best.setdefault(name, m)
                b["reset_ms"] = min(b["reset_ms"], m["reset_ms"])
                b["noreset"] = max(b["noreset"], m["noreset"])
                b["autoreset"] = max(b["autoreset"], m["autoreset"])
            for name, m in best.items():
                _print_autoreset(f"best {name}", n, m)
        return
    print(f"{'copies':>6} {'vector [steps/s]':>17} {'SyncVectorEnv [steps/s]':>24} {'ratio':>6}")
    for n in (int(v) for v in (args.copies or "16,64,256").split(",")):
        best = compare(n, args.steps, args.rounds)
        ratio = best["vector"] / best["sync"]
        print(f"{n:>6} {best['vector']:>17,.0f} {best['sync']:>24,.0f} {ratio:>6.1f}")


if __name__ == "__main__":
    main()
