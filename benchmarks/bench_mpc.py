"""The MPC (``[control] controller = "mpc"``) on the paper's runs 1 and 2, tethered, with eq 40's
cyclic limit as saturation: OSQP's time per sample and the issue-14 goal.

Run: PYTHONPATH=src python benchmarks/bench_mpc.py [--tune EVALUATIONS]

Timing (pinned to one CPU): each sample's OSQP update + solve, as wall-clock time and as the
thread's CPU time (which a loaded machine does not inflate), median, 99th percentile and
maximum against the 10 ms sample time; the whole MPC run's wall time against the paper
controller's compiled run of the same scenario (each timed on a second run: the first
compiles). The samples where OSQP stopped short (``mpc_fallback``) are counted.

Goal (``tune_tether_lqi.goal``, the same objective and penalties as the tethered LQI's
search): peak and RMS of q1 in sim 1 and of q2 in sim 2 against the free helicopter under the
paper's controller, as reductions 100 (1 - ratio) %; the RMS effort of each rotor input
against the paper's tethered controller (and the tethered LQI's) on the same saturated runs;
the tension range. ``--tune N`` runs a Nelder-Mead of N evaluations (each two 60 s runs) on
the log10 of four factors applied to ``start_settings()`` (the tethered LQI's weights and a
0.1 s time constant; ``--start`` the factors' first values): the disturbance estimate's
time constant, the position weights (q1 = q2 and their integrators), the cyclic input
weights (tMR1 = tMR2) and the tail-rotor weight (first steps: 0.3 decade down, down, up,
up); it prints the best as a ``[control.mpc]``
table. Deterministic: the same command prints the same numbers (the times aside).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import time

import numpy as np
from scipy.optimize import minimize
from tune_tether_lqi import goal, references

from tetherheli import simulate
from tetherheli.control.mpc import mpc_controller
from tetherheli.names import INPUT
from tetherheli.sim import Scenario
from tetherheli.sim.scenario import MPCSettings, TetherLQISettings
from tetherheli.sim.setup import engine_setup
from tetherheli.studies.controllers import fly, with_controller
from tetherheli.studies.sweep import scenario_cyclic_limit

STEP = 0.3  # the initial simplex's edge [decades]


def start_settings() -> MPCSettings:
    """Where ``--tune`` starts: the tethered LQI's shipped weights, a disturbance estimate of
    time constant 0.1 s, the other keys at their defaults (fixed, so that the search is
    reproducible whatever the shipped defaults are)."""
    w = TetherLQISettings()
    return MPCSettings(Qy=w.Qy, q_tension=w.q_tension, Ru=w.Ru, disturbance_time_constant=0.1)


def with_mpc(scenario: Scenario, settings: MPCSettings) -> Scenario:
    """``scenario`` flown by the MPC with ``settings``."""
    s = with_controller(scenario, "mpc")
    return s.replace(control=dataclasses.replace(s.control, mpc=settings))


def tuned(p: np.ndarray, base: MPCSettings) -> MPCSettings:
    """``base`` with the four factors 10**p (module docstring) applied."""
    f = 10.0 ** np.asarray(p)
    Qy = list(base.Qy)
    for i in (0, 1, 4, 5):
        Qy[i] *= f[1]
    Ru = list(base.Ru)
    Ru[1] *= f[2]
    Ru[2] *= f[2]
    Ru[3] *= f[3]
    return dataclasses.replace(
        base,
        disturbance_time_constant=base.disturbance_time_constant * f[0],
        Qy=tuple(float(f"{v:.6g}") for v in Qy),
        Ru=tuple(float(f"{v:.6g}") for v in Ru),
    )


def timing(sims: dict, settings: MPCSettings) -> None:
    for n, (_, _, _, scenario) in sims.items():
        s = with_mpc(scenario, settings)
        c = mpc_controller(s, engine_setup(s))
        t0 = time.perf_counter()
        r = simulate(s, controller=c)
        wall = time.perf_counter() - t0
        simulate(scenario)  # compiled already; the second run is timed
        t0 = time.perf_counter()
        simulate(scenario)
        paper = time.perf_counter() - t0
        dt_ms = 1e3 * s.control.dt
        print(f"sim {n}: {r.message}; {r.time.size} samples, OSQP fell back on "
              f"{int(r.extra['mpc_fallback'].sum())}, iterations median "
              f"{np.median(c.iterations):.0f} max {max(c.iterations)}")  # fmt: skip
        for what, t in (("wall", c.solve_times), ("CPU", c.solve_cpu_times)):
            ms = 1e3 * np.array(t)
            print(f"  solve time per sample ({what}) [ms]: median {np.median(ms):.3f}, 99th "
                  f"percentile {np.percentile(ms, 99):.3f}, max {ms.max():.3f} (sample time "
                  f"{dt_ms:g} ms; over it: {np.count_nonzero(ms > dt_ms)})")  # fmt: skip
        print(f"  whole run: MPC {wall:.2f} s ({1e6 * wall / r.time.size:.0f} us/sample), "
              f"paper controller compiled {paper:.3f} s: {wall / paper:.0f}x")  # fmt: skip


def report(sims: dict, settings: MPCSettings, what: str) -> float:
    flown = {}

    def fly_mpc(s: Scenario) -> dict:
        flown[s.name] = fly(with_mpc(s, settings))[1]
        return flown[s.name]

    score, info = goal(sims, fly_mpc)
    _, lqi = goal(sims, lambda s: fly(with_controller(s, "tether_lqi"))[1])
    print(f"{what}: score {score:.4f} (worst of the four ratios; + penalties)")
    print("reductions vs free [%] (sim1 peak, RMS q1; sim2 peak, RMS q2):",
          np.round(100 * (1 - np.array(info["ratios"])), 1),
          "; tether_lqi:", np.round(100 * (1 - np.array(lqi["ratios"])), 1))  # fmt: skip
    for label, eff in (("mpc", info["effort"]), ("tether_lqi", lqi["effort"])):
        print(f"effort of {label} / paper tethered ({', '.join(INPUT)}; sim1 | sim2):",
              np.round(eff[:4], 3), "|", np.round(eff[4:], 3))  # fmt: skip
    print("tension range [N] (sim1 min max, sim2 min max):", np.round(info["tension"], 2))
    for n, (axis, _, _, scenario) in sims.items():
        m = flown[scenario.name]
        print(f"sim {n}: peak q3 {m['peak_q3']:.3f} m, off-axis peak q{2 - axis} "
              f"{m[f'peak_q{2 - axis}']:.3f} m, peak cyclic {m['peak_cyclic']:.3f} / "
              f"{scenario_cyclic_limit(scenario):.3f} N m")  # fmt: skip
    return score


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tune", type=int, default=0, metavar="EVALUATIONS")
    parser.add_argument("--start", default="0,0,0,0", help="log10 factors the search starts at")
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one core
    sims = references()
    base = MPCSettings()
    if args.tune > 0:
        base = start_settings()
        best = {"f": math.inf, "p": np.zeros(4)}

        def objective(p: np.ndarray) -> float:
            f, _ = goal(sims, lambda s: fly(with_mpc(s, tuned(p, base)))[1])
            if f < best["f"]:
                best.update(f=f, p=np.array(p))
                print(f"best {f:.4f} at", ",".join(f"{v:.3f}" for v in p), flush=True)
            return f

        p0 = np.array([float(v) for v in args.start.split(",")])
        simplex = np.vstack([p0, p0 + STEP * np.diag([-1.0, -1.0, 1.0, 1.0])])
        minimize(objective, p0, method="Nelder-Mead", options={
            "maxfev": args.tune, "initial_simplex": simplex, "xatol": 1e-3})  # fmt: skip
        base = tuned(best["p"], base)
        print("log10 factors:", ",".join(f"{v:.4f}" for v in best["p"]))
        print("[control.mpc]")
        for f in ("disturbance_time_constant", "Qy", "Ru"):
            v = getattr(base, f)
            print(f"{f} = " + (f"[{', '.join(f'{x:.6g}' for x in v)}]" if isinstance(v, tuple)
                               else f"{v:.6g}"))  # fmt: skip
    report(sims, base, "the tuned settings" if args.tune else "the shipped defaults")
    timing(sims, base)


if __name__ == "__main__":
    main()
