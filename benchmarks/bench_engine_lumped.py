"""Cost of a closed-loop run with the lumped-mass tether in the engine (issue 13, item 4).

Run: python benchmarks/bench_engine_lumped.py [--repeat R]
Prints, measured in this run: the milliseconds of one 60 s run of the paper's simulation 1
(tethered, dt = 10 ms, 2 substeps; ``sim.batch.run_unrecorded``, the compiled loop without
recording) with eq 28's massless tether and with the lumped chain of N = 5, 10, 20, 40
segments (20 g/m, 5 mm, the paper's stiffness), side by side, and each one's ratio to the
massless run. Timings vary with the machine; no test asserts them.
"""

from __future__ import annotations

import argparse

import numpy as np

# the timer of bench_derivative.py (this folder is on sys.path when a script here runs)
from bench_derivative import best_of

from tetherheli.sim import engine
from tetherheli.sim.batch import run_unrecorded
from tetherheli.sim.scenario import TetherSettings, paper_scenario
from tetherheli.sim.setup import engine_setup

SEGMENTS = (5, 10, 20, 40)


def _ms_per_run(scenario, repeat: int) -> float:
    """Best-of-``repeat`` milliseconds of one unrecorded run (a fresh chain each time)."""
    setup = engine_setup(scenario)
    n = scenario.n_samples
    summary = np.zeros(len(engine.SUMMARY_FIELDS))
    status, _ = run_unrecorded(setup.engine_args(n), summary)  # warm-up (compile or cache)
    if status != 0:
        raise RuntimeError(f"{scenario.name}: the run failed (status {status})")
    return 1e3 * best_of(lambda: run_unrecorded(setup.engine_args(n), summary), repeat)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5, help="runs per case (best taken)")
    opts = parser.parse_args()
    base = paper_scenario(1, "tethered")
    rows = [("massless (eq 28)", _ms_per_run(base, opts.repeat))]
    for n in SEGMENTS:
        lumped = base.replace(tether=TetherSettings(model="lumped", segments=n))
        rows.append((f"lumped, N = {n}", _ms_per_run(lumped, opts.repeat)))
    print("one 60 s run of paper simulation 1 (tethered), dt = 10 ms, 2 substeps, unrecorded")
    print(f"{'tether':<20} {'ms per run':>11} {'ratio':>7}")
    for name, ms in rows:
        print(f"{name:<20} {ms:>11.1f} {ms / rows[0][1]:>7.1f}")


if __name__ == "__main__":
    main()
