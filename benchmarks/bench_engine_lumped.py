"""Cost of a closed-loop run with the lumped-mass tether in the engine (issue 13, item 4).

Run: python benchmarks/bench_engine_lumped.py [--repeat R] [--EA N] [--coupling]
Prints, measured in this run: the milliseconds of one 60 s run of the paper's simulation 1
(tethered, dt = 10 ms, 2 substeps; ``runs.batch.run_unrecorded``, the compiled loop without
recording) with eq 28's massless tether and with the lumped chain of N = 5, 10, 20, 40
segments (20 g/m, 5 mm, the paper's stiffness), side by side, and each one's ratio to the
massless run, the helicopter's RK4 steps per sample (the coupled step's rule,
``tether.lumped.coupling_substeps``) and the chain's ROS2 sub-steps per RK4 step (issue 23's
step-size rule, ``tether.lumped.chain_substeps``; ``--EA`` another stiffness). Timings vary with the
machine; no test asserts them. With ``--coupling`` instead: the coupled step's error
against SciPy's Radau on the joint helicopter + chain ODE
(``tests/test_engine_lumped.py``'s ``coupling_errors``: 2 s open loop, 10 N on HO) for the
staggered and the condensed coupling, EA = 375 N at N = 10 and 20, 20 kN at N = 10 (a few
minutes).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

# the timer of bench_derivative.py (this folder is on sys.path when a script here runs)
from bench_derivative import best_of

from tetherheli.engine import loop as engine
from tetherheli.layout import CHAIN_PARAMS
from tetherheli.runs.batch import run_unrecorded
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import TetherSettings, paper_scenario
from tetherheli.tether.lumped import chain_substeps, coupling_substeps

SEGMENTS = (5, 10, 20, 40)
#: (EA [N], N) of ``--coupling``: the stiff cable at N = 20 is left out, its Radau reference
#: (rtol 1e-9, a Python right-hand side) takes more than a quarter of an hour
COUPLING_CASES = ((375.0, 10), (375.0, 20), (20_000.0, 10))


def _ms_per_run(scenario, repeat: int) -> float:
    """Best-of-``repeat`` milliseconds of one unrecorded run (a fresh chain each time)."""
    setup = engine_setup(scenario)
    n = scenario.n_samples
    summary = np.zeros(len(engine.SUMMARY_FIELDS))
    status, _ = run_unrecorded(setup.engine_args(n), summary)  # warm-up (compile or cache)
    if status != 0:
        raise RuntimeError(f"{scenario.name}: the run failed (status {status})")
    return 1e3 * best_of(lambda: run_unrecorded(setup.engine_args(n), summary), repeat)


def coupling_table() -> None:
    """The coupling errors of ``tests/test_engine_lumped.py``'s ``coupling_errors``."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.test_engine_lumped import coupling_errors

    print("error against Radau (rtol 1e-9), 2 s open loop: P [m] (q7, q8 x 10 m, q9), nodes [m]")
    print(f"{'EA [N]':>8} {'N':>3} {'staggered P':>12} {'condensed P':>12} {'nodes':>9}")
    for EA, n in COUPLING_CASES:
        e = coupling_errors(EA, n)
        print(
            f"{EA:>8g} {n:>3} {e['staggered'][0]:>12.2e} {e['condensed'][0]:>12.2e} "
            f"{e['condensed'][1]:>9.2e}"
        )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5, help="runs per case (best taken)")
    parser.add_argument("--coupling", action="store_true", help="the coupling's error instead")
    parser.add_argument("--EA", type=float, default=0.0,
                        help="the lumped cable's EA [N] (0: the paper's stiffness)")  # fmt: skip
    opts = parser.parse_args()
    if opts.coupling:
        coupling_table()
        return
    base = paper_scenario(1, "tethered")
    rows = [("massless (eq 28)", _ms_per_run(base, opts.repeat), base.control.substeps, 0)]
    for n in SEGMENTS:
        lumped = base.replace(tether=TetherSettings(model="lumped", segments=n, EA=opts.EA))
        setup = engine_setup(lumped)
        L0 = setup.start.x[12]
        p = setup.chain[CHAIN_PARAMS]
        rk4 = coupling_substeps(p, L0, n, lumped.control.dt, lumped.control.substeps)
        m = chain_substeps(p, L0, n, lumped.control.dt / rk4)  # issue 23's step-size rule
        rows.append((f"lumped, N = {n}", _ms_per_run(lumped, opts.repeat), rk4, m))
    print("one 60 s run of paper simulation 1 (tethered), dt = 10 ms, 2 substeps, unrecorded;")
    print(f"EA = {opts.EA:g} N (0: the paper's); RK4 steps per sample, chain ROS2 sub-steps per")
    print("RK4 step (issue 23)")
    print(
        f"{'tether':<20} {'ms per run':>11} {'ratio':>7} {'RK4 steps':>10} {'chain sub-steps':>16}"
    )
    for name, ms, rk4, m in rows:
        print(f"{name:<20} {ms:>11.1f} {ms / rows[0][1]:>7.1f} {rk4:>10d} {m:>16d}")


if __name__ == "__main__":
    main()
