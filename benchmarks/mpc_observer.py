"""The MPC's Kalman filter (``[control.mpc] observer``, ``control.observer``): which noise
setting flies the shipped scenarios with sensors and the lumped tether.

Run: PYTHONPATH=src python benchmarks/mpc_observer.py [--rates 1,2,3] [--force-std 1] [--eq40]

For each density of the wind force's random walk (``kalman_force_rate`` [N/sqrt(s)], the
white force ``kalman_force_std`` [N] fixed: their ratio sets how fast the estimate follows
the residual), the MPC flies every shipped scenario that selects the filter ("auto":
imperfect sensors or the lumped chain), tethered; printed per run: the outcome, the peak
deviations of q1, q2, q3 from the trim [m], RMS q1 [m], and the paper controller's peak q1
on the same scenario. ``--eq40``: every run (the paper's too) with eq 40's cyclic limit as
saturation (``studies.controllers.eq40_saturated``). Deterministic (each scenario's seeds).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

from tetherheli.scenario.core import Scenario, load_scenario
from tetherheli.studies.controllers import eq40_saturated, fly, with_controller

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def filtered_scenarios() -> list[Scenario]:
    """The shipped tethered scenarios whose MPC uses the filter under "auto"."""
    out = []
    for path in sorted(SCENARIOS.glob("*.toml")):
        if path.name.startswith("montecarlo"):
            continue
        s = load_scenario(path)
        if s.configuration == "tethered" and (
            not s.sensors.is_perfect or s.tether.model == "lumped"
        ):
            out.append(s)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rates", default="1,2,3", help="kalman_force_rate values [N/s^0.5]")
    parser.add_argument("--force-std", type=float, default=1.0, help="kalman_force_std [N]")
    parser.add_argument("--eq40", action="store_true", help="eq 40's cyclic limit as saturation")
    args = parser.parse_args()
    scenarios = filtered_scenarios()
    if args.eq40:
        scenarios = [eq40_saturated(s) for s in scenarios]
    paper = {}
    for s in scenarios:
        r, m = fly(s)
        paper[s.name] = f"{m['peak_q1']:.3f}" + ("" if r.ok else f" (failed at {r.end_time:.1f} s)")
    print("kalman_force_rate | scenario | outcome | peak q1 | peak q2 | peak q3 | RMS q1 "
          "| paper's peak q1")  # fmt: skip
    for rate in (float(r) for r in args.rates.split(",")):
        for s in scenarios:
            mpc = dataclasses.replace(
                s.control.mpc, kalman_force_rate=rate, kalman_force_std=args.force_std
            )
            flown = with_controller(s, "mpc")
            flown = flown.replace(control=dataclasses.replace(flown.control, mpc=mpc))
            r, m = fly(flown)
            p1, p2, p3, rms = (m[k] for k in ("peak_q1", "peak_q2", "peak_q3", "rms_q1"))
            outcome = "completed" if r.ok else f"{r.message} at {r.end_time:.1f} s"
            print(f"{rate:g} | {s.name} | {outcome} | {p1:.3f} | {p2:.3f} | {p3:.3f} | "
                  f"{rms:.3f} | {paper[s.name]}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
