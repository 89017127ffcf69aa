"""Weight search for the tethered LQI (``[control] controller = "tether_lqi"``).

Run: python benchmarks/tune_tether_lqi.py [--evaluations N] [--start Qxy,...]
(PYTHONPATH=src; a few minutes for the default 400 evaluations on one core).

Objective: the worst of the paper's four numbers (peak and RMS of q1 in simulation 1, of q2 in
simulation 2) as a fraction of the free helicopter under the paper's controller (the paper's
free runs, no saturation: with eq 40's saturation the free run of simulation 2 diverges), the
tethered LQI flown with eq 40's cyclic limit as saturation (``controllers.eq40_saturated``).
Constraints (a penalty per unit of violation; a failed run scores 10):
- effort: RMS of each rotor input minus trim <= the paper's tethered controller's on the same
  saturated run, per input and simulation;
- tension within [T_ref / 2, 1.5 T_ref] (taut, and no "swing the tension" solutions);
- peak altitude deviation q3 <= ``MAX_Q3`` and peak off-axis deviation (q2 in sim 1, q1 in
  sim 2) <= ``MAX_OFF_AXIS`` (a search without them trades these for the metric).
The objective is ``goal`` (``references`` flies the references), which
``benchmarks/bench_mpc.py`` imports for the MPC.
Search: Nelder-Mead (scipy) on the log10 of 11 diagonal weights (q1 = q2 tied, their
integrators tied, tMR1 = tMR2 tied), from the start point below. It prints the best weights
as a ``[control.tether_lqi]`` table and their four ratios, effort ratios and tension range.
Deterministic: the same command prints the same weights. ``--evaluations 0`` only evaluates
the shipped defaults (``TetherLQISettings()``) and prints the reductions against the free
helicopter, 100 (1 - ratio) %, of the paper's tethered controller and of the tethered LQI.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

import numpy as np
from scipy.optimize import minimize

from tetherheli.errors import TetherheliError
from tetherheli.names import INPUT
from tetherheli.scenario import Scenario, load_scenario
from tetherheli.scenario.core import TetherLQISettings
from tetherheli.studies.controllers import eq40_saturated, fly, with_controller

SCENARIOS = "scenarios/paper_sim{}_{}.toml"
MAX_Q3 = 0.3  # [m]
MAX_OFF_AXIS = 0.5  # [m]
#: log10 weights: Qy q1=q2, q3, q6, integrators q1=q2, q3, q6; q_tension; Ru fMR3,
#: tMR1=tMR2, fTR2, RC. Start: the paper's weights with position x10, a small tension weight.
START = (1.0, 0.0, 0.0, 1.0, 1.0, 1.0, -3.0, 0.0, 0.0, 0.0, 0.0)
STEP = 0.5  # the initial simplex's edge [decades]


def weights(p: np.ndarray) -> dict:
    w = 10.0 ** np.asarray(p)
    return {
        "Qy": (w[0], w[0], w[1], w[2], w[3], w[3], w[4], w[5]),
        "q_tension": w[6],
        "Ru": (w[7], w[8], w[8], w[9], w[10]),
    }


def references() -> dict:
    """The goal's references per simulation n (1, 2): (axis, free metrics, paper tethered
    metrics with eq 40, the eq-40 tethered scenario); prints them."""
    sims = {}
    for n, axis in ((1, 0), (2, 1)):
        free = fly(load_scenario(SCENARIOS.format(n, "free")))[1]
        tethered = eq40_saturated(load_scenario(SCENARIOS.format(n, "tethered")))
        paper = fly(tethered)[1]
        sims[n] = (axis, free, paper, tethered)
        q = f"q{axis + 1}"
        print(
            f"sim {n}: free peak/RMS {free[f'peak_{q}']:.3f}/{free[f'rms_{q}']:.3f} m; paper "
            f"tethered (eq 40) {paper[f'peak_{q}']:.3f}/{paper[f'rms_{q}']:.3f} m, reductions "
            f"{100 * (1 - paper[f'peak_{q}'] / free[f'peak_{q}']):.1f}/"
            f"{100 * (1 - paper[f'rms_{q}'] / free[f'rms_{q}']):.1f} %"
        )
    return sims


def goal(sims: dict, flown: Callable[[Scenario], dict]) -> tuple[float, dict]:
    """The objective of the module docstring: ``flown(scenario)`` flies an eq-40 tethered
    paper run with the candidate controller and returns its ``controller_metrics`` (a
    ``TetherheliError`` or an incomplete run scores 10). Returns (score, info: the four
    ratios, the eight effort ratios, the tension ranges)."""
    info: dict = {"ratios": [], "effort": [], "tension": []}
    score, penalty = 0.0, 0.0
    for axis, free, paper, scenario in sims.values():
        try:
            m = flown(scenario)
        except TetherheliError:
            return 10.0, info
        if not m["completed"]:
            return 10.0, info
        T_ref = scenario.params.tension_control.T_ref
        q = axis + 1
        ratios = [m[f"peak_q{q}"] / free[f"peak_q{q}"], m[f"rms_q{q}"] / free[f"rms_q{q}"]]
        info["ratios"] += ratios
        score = max(score, *ratios)
        eff = [m[f"rms_d{i}"] / paper[f"rms_d{i}"] for i in INPUT]
        info["effort"] += eff
        penalty += sum(max(0.0, e - 1.0) for e in eff)
        info["tension"] += [m["tension_min"], m["tension_max"]]
        penalty += max(0.0, 0.5 * T_ref - m["tension_min"]) / T_ref
        penalty += max(0.0, m["tension_max"] - 1.5 * T_ref) / T_ref
        penalty += max(0.0, m["peak_q3"] - MAX_Q3) / MAX_Q3
        penalty += max(0.0, m[f"peak_q{2 - axis}"] - MAX_OFF_AXIS) / MAX_OFF_AXIS
    return score + 5.0 * penalty, info


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--evaluations", type=int, default=400)
    parser.add_argument("--start", default=",".join(map(str, START)))
    args = parser.parse_args()
    sims = references()

    def evaluate(p: np.ndarray) -> tuple[float, dict]:
        return evaluate_weights(weights(p))

    def evaluate_weights(w: dict) -> tuple[float, dict]:
        return goal(sims, lambda s: fly(with_controller(s, "tether_lqi", **w))[1])

    best = {"f": math.inf}

    def objective(p: np.ndarray) -> float:
        f, info = evaluate(p)
        if f < best["f"]:
            best.update(f=f, p=np.array(p), info=info)
            print(f"best {f:.4f} at", ",".join(f"{v:.3f}" for v in p), flush=True)
        return f

    if args.evaluations == 0:
        d = TetherLQISettings()
        shipped = {"Qy": d.Qy, "q_tension": d.q_tension, "Ru": d.Ru}
        report(*evaluate_weights(shipped), "the shipped defaults")
        return
    p0 = np.array([float(v) for v in args.start.split(",")])
    simplex = np.vstack([p0, p0 + STEP * np.eye(p0.size)])  # steps of STEP decades
    minimize(
        objective, p0, method="Nelder-Mead",
        options={"maxfev": args.evaluations, "initial_simplex": simplex, "xatol": 1e-3},
    )  # fmt: skip
    w = weights(best["p"])
    print("log10 weights:", ",".join(f"{v:.4f}" for v in best["p"]))
    print("[control.tether_lqi]")
    print("Qy = [" + ", ".join(f"{v:.6g}" for v in w["Qy"]) + "]")
    print(f"q_tension = {w['q_tension']:.6g}")
    print("Ru = [" + ", ".join(f"{v:.6g}" for v in w["Ru"]) + "]")
    report(best["f"], best["info"], "the best weights")


def report(score: float, info: dict, what: str) -> None:
    print(f"{what}: score {score:.4f} (worst of the four ratios; + penalties)")
    print("ratios vs free (sim1 peak, RMS q1; sim2 peak, RMS q2):", np.round(info["ratios"], 4))
    print("reductions [%]:", np.round(100 * (1 - np.array(info["ratios"])), 1))
    print("effort vs paper tethered (sim1 4 inputs, sim2 4 inputs):", np.round(info["effort"], 3))
    print("tension range [N] (sim1 min max, sim2 min max):", np.round(info["tension"], 2))


if __name__ == "__main__":
    main()
