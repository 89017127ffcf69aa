"""CPU-time A/B of the compiled paper run and the MPC's Python loop in two source trees.

Run: python benchmarks/cpu_time_ab.py --baseline OTHER/src [--rounds 3]

Each round starts one process per tree (alternating: this tree, then the baseline), each
warming its own compile cache first, then prints the least process CPU time of 40
``simulate`` calls of ``paper_sim1_tethered`` (60 s, the compiled loop), of 5 calls of a
2 s MPC run (the Python loop), and of 5 calls of a 10 s run of the paper's law as a Python
``PaperController`` (the Python loop's own cost: no solver). CPU time, not wall time, so
that other work on a shared machine counts less; on 2 shared cores the figures still vary
by about 10 %. Ratios are this tree / baseline; no test asserts them.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

_PROBE = """
import dataclasses, time
from tetherheli.shipped import shipped_scenario
from tetherheli import simulate
s = shipped_scenario("paper_sim1_tethered")
simulate(s)
best = min((lambda t: (simulate(s), time.process_time() - t)[1])(time.process_time())
           for _ in range(40))
m = s.replace(duration=2.0, control=dataclasses.replace(s.control, controller="mpc"))
simulate(m)
best_m = min((lambda t: (simulate(m), time.process_time() - t)[1])(time.process_time())
             for _ in range(5))
from tetherheli.control.paper import PaperController
try:
    from tetherheli.runs.setup import engine_setup
except ImportError:  # a baseline from before the rooms (sim/ split)
    from tetherheli.sim.setup import engine_setup
p = s.replace(duration=10.0)
su = engine_setup(p)
K, _, y_ref, u0, u0_free, z0 = su.law
ctl = PaperController(K, su.trim.x, y_ref, u0, su.ctrl, su.model.constants,
                      free_trim_input=u0_free, z_init=z0)
simulate(p, controller=ctl)
best_p = min((lambda t: (simulate(p, controller=ctl), time.process_time() - t)[1])(
    time.process_time()) for _ in range(5))
print(best * 1e3, best_m * 1e3, best_p * 1e3)
"""


def _run(src: Path, cache: Path) -> tuple[float, float, float]:
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache)}
    out = subprocess.run(
        [sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, check=True
    ).stdout.split()
    return float(out[-3]), float(out[-2]), float(out[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", type=Path, required=True, help="the other tree's src/")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    here = Path(__file__).resolve().parents[1] / "src"
    stamp = int(time.time())
    trees = {"this": here, "baseline": args.baseline.resolve()}
    caches = {k: Path(f"/tmp/tetherheli-ab-{k}-{stamp}") for k in trees}
    best: dict[str, list[float]] = {k: [1e9, 1e9, 1e9] for k in trees}
    for r in range(args.rounds):
        for k, src in trees.items():
            got = _run(src, caches[k])
            best[k] = [min(a, b) for a, b in zip(best[k], got, strict=True)]
            print(f"round {r + 1} {k:<8} paper run {got[0]:8.3f} ms   MPC 2 s {got[1]:8.1f} ms"
                  f"   Python paper law 10 s {got[2]:8.1f} ms")  # fmt: skip
    what_ = ("paper run (compiled)", "MPC run (Python loop)", "paper law (Python loop)")
    for i, what in enumerate(what_):
        a, b = best["this"][i], best["baseline"][i]
        print(f"{what}: this {a:.3f} ms, baseline {b:.3f} ms, this / baseline {a / b:.3f}")


if __name__ == "__main__":
    main()
