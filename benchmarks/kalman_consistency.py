"""The MPC's Kalman filter's consistency (``studies.estimation.kalman_consistency``) on every
shipped scenario with sensors, flown by the MPC (``[control] controller = "mpc"``).

Run: PYTHONPATH=src python benchmarks/kalman_consistency.py [--set key=value ...]

Printed per scenario: the outcome, the peak and RMS deviation of q1 from the trim [m], the
mean NEES of the 16 states [x; d] with its 95 % band (one independent sample per error time
constant, the stride) and verdict, the force's part (dimension 3) and the mean NIS with its
dimension. ``--set`` overrides a ``[control.mpc]`` key for every run, e.g. ``--set
kalman_force_accel=0 --set kalman_tether_angle_std=none --set
kalman_input_std=1,0.5,0.5,0.3,0.01`` for the filter before issue 23's item 7.
Deterministic (each scenario's seeds).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from tetherheli import simulate
from tetherheli.scenario.core import load_scenario
from tetherheli.studies.estimation import kalman_consistency

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def _value(text: str):
    if text == "none":
        return None
    if "," in text:
        return tuple(float(v) for v in text.split(","))
    return float(text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", action="append", default=[], help="control.mpc key=value")
    args = parser.parse_args()
    overrides = {k: _value(v) for k, v in (a.split("=", 1) for a in args.set)}
    paths = sorted(p for p in SCENARIOS.glob("*sensing*.toml") if "montecarlo" not in p.stem)
    print("| scenario | outcome | peak q1 | RMS q1 | mean NEES (16) | 95 % band | stride "
          "| consistent | force NEES (3) | mean NIS (p) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|")
    for path in paths:
        s = load_scenario(path)
        mpc = dataclasses.replace(s.control.mpc, **overrides)
        s = dataclasses.replace(
            s, control=dataclasses.replace(s.control, controller="mpc", mpc=mpc)
        )
        r = simulate(s)
        c = kalman_consistency(r, s)
        q1 = r.outputs[:, 0] - r.trim_output[0]
        lo, hi = c.nees.band
        print(
            f"| {s.name} | {'completed' if r.ok else r.message} | {np.max(np.abs(q1)):.3f} "
            f"| {np.sqrt(np.mean(q1**2)):.3f} | {c.nees.mean:.2f} | {lo:.2f}-{hi:.2f} "
            f"| {c.nees.stride} | {'yes' if c.nees.consistent else 'no'} "
            f"| {c.force_nees.mean:.2f} | {c.nis.mean:.2f} ({c.nis.dim}) |",
            flush=True,
        )


if __name__ == "__main__":
    main()
