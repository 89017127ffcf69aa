"""Interleaved A/B speed comparison of two source trees of tetherheli (e.g. before and after a
refactor), measured in the same run so that the machine's drift hits both alike.

Run: python benchmarks/bench_ab.py --baseline SRC_A [--candidate SRC_B] [--rounds 5]
where SRC_A, SRC_B are ``src`` folders (the candidate defaults to this checkout's), e.g. a
``git worktree add /tmp/base <commit>`` of the baseline commit's ``/tmp/base/src``.
Each round runs, in a fresh process per tree and alternating their order, (a) the compiled
engine on the 60 s tethered paper scenario (best of 20, summaries only), (b) the same with
the tether as the position sensor (``sensing_scenario("tether")``, noisy sensors) and (c)
``run_batch`` of 400 dispersed paper runs on all cores. Prints each tree's best figures over
the rounds and the ratio candidate / baseline. Timings vary with the machine and its load;
no test asserts them.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

PROBE = r"""
import json, time
import numpy as np
try:
    from tetherheli.engine import loop as engine
    from tetherheli.runs.batch import run_batch
    from tetherheli.scenario.core import paper_scenario
except ImportError:  # a baseline from before the rooms (sim/ split)
    from tetherheli.sim import engine
    from tetherheli.sim.batch import run_batch
    from tetherheli.sim.scenario import paper_scenario
try:
    from tetherheli.wind import Pulse, Sine
except ImportError:  # a baseline from before the wind package
    from tetherheli.disturbances import Pulse, Sine

s = paper_scenario(1, "tethered")
try:
    try:
        from tetherheli.runs.batch import run_unrecorded
        from tetherheli.runs.setup import engine_setup
    except ImportError:  # a baseline from before the rooms (sim/ split)
        from tetherheli.sim.batch import run_unrecorded
        from tetherheli.sim.setup import engine_setup

    def prepare(scenario):
        return engine_setup(scenario).engine_args(scenario.n_samples)
except ImportError:  # a baseline tree from before the set-up was public (0ac3184 and older)
    from tetherheli.sim.batch import _prepare, _run_nogil as run_unrecorded

    def prepare(scenario):
        return _prepare(scenario, None)
try:
    from tetherheli.report.paper import sensing_scenario
except ImportError:  # a baseline from before the report package
    from tetherheli.report import sensing_scenario

summary = np.zeros(len(engine.SUMMARY_FIELDS))


def best_of(args, repeat):
    run_unrecorded(args, summary)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        run_unrecorded(args, summary)
        times.append(time.perf_counter() - t0)
    return min(times)


best = best_of(prepare(s), 20)
best_sensed = best_of(prepare(sensing_scenario("tether")), 10)
rng = np.random.default_rng(1)
runs = [
    s.replace(wind=Pulse(10.0, 1.0, 20.0 * a, (1.0, 0.0, 0.0)) + Sine(20.0 * a, 0.1, 30.0,
              (1.0, 0.0, 0.0)))
    for a in rng.uniform(0.8, 1.2, 400)
]
run_batch(runs[:4])
t0 = time.perf_counter()
run_batch(runs)
rate = len(runs) / (time.perf_counter() - t0)
print(json.dumps(
    {"engine_ms": best * 1e3, "sensed_ms": best_sensed * 1e3, "batch_runs_per_s": rate}
))
"""


def measure(src: Path) -> dict[str, float]:
    env = {**os.environ, "PYTHONPATH": str(src)}
    done = subprocess.run(
        [sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    here = Path(__file__).resolve().parents[1] / "src"
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", type=Path, required=True, help="src folder of tree A")
    parser.add_argument("--candidate", type=Path, default=here, help="src folder of tree B")
    parser.add_argument("--rounds", type=int, default=5)
    opts = parser.parse_args()
    trees = {"baseline": opts.baseline.resolve(), "candidate": opts.candidate.resolve()}
    for src in trees.values():  # compile both once, outside the timed rounds
        measure(src)
    best: dict[str, dict[str, float]] = {}
    for r in range(opts.rounds):
        order = list(trees) if r % 2 == 0 else list(reversed(trees))
        for name in order:
            m = measure(trees[name])
            b = best.setdefault(name, m)
            b["engine_ms"] = min(b["engine_ms"], m["engine_ms"])
            b["sensed_ms"] = min(b["sensed_ms"], m["sensed_ms"])
            b["batch_runs_per_s"] = max(b["batch_runs_per_s"], m["batch_runs_per_s"])
            print(
                f"round {r + 1} {name:<9} engine {m['engine_ms']:6.2f} ms/run, sensed "
                f"{m['sensed_ms']:6.2f} ms/run, batch {m['batch_runs_per_s']:6.0f} runs/s",
                flush=True,
            )
    a, b = best["baseline"], best["candidate"]
    print(
        f"best engine time per 60 s run: baseline {a['engine_ms']:.2f} ms, candidate "
        f"{b['engine_ms']:.2f} ms, ratio {b['engine_ms'] / a['engine_ms']:.3f}"
    )
    print(
        f"best run with the tether as sensor: baseline {a['sensed_ms']:.2f} ms, candidate "
        f"{b['sensed_ms']:.2f} ms, ratio {b['sensed_ms'] / a['sensed_ms']:.3f}"
    )
    print(
        f"best batch throughput: baseline {a['batch_runs_per_s']:.0f} runs/s, candidate "
        f"{b['batch_runs_per_s']:.0f} runs/s, ratio "
        f"{b['batch_runs_per_s'] / a['batch_runs_per_s']:.3f}"
    )


if __name__ == "__main__":
    main()
