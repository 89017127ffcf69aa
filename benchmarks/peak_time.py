"""Where a Monte Carlo's peak q1 deviations fall in time: a check for start-up artefacts.

Run: python benchmarks/peak_time.py SCENARIO.toml N
Draws the first N draws of the scenario's ``[montecarlo]`` table (the same draws as
``tetherheli montecarlo``), runs each free and tethered with ``simulate`` (the controller
designed on each draw's own parameters), finds the time of its largest |q1 - q1_trim| within
the metrics window [metrics_start, duration], and prints, per configuration, the fraction of
peaks in the window's first 15 s and in its last 15 s. Without a start-up artefact the first
fraction is no larger than the last. It takes a few minutes for N = 500.
"""

from __future__ import annotations

import argparse

import numpy as np

import tetherheli as th
from tetherheli.studies.montecarlo.config import load_montecarlo
from tetherheli.studies.montecarlo.draws import draw

EDGE_S = 15.0  # [s] the spans compared at the window's start and end


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", help="a scenario with a [montecarlo] table")
    parser.add_argument("draws", type=int, help="how many draws")
    args = parser.parse_args()
    base, config = load_montecarlo(args.scenario)
    start = getattr(base, "metrics_start", 0.0)  # earlier versions have none
    children = np.random.SeedSequence(config.seed).spawn(args.draws)
    first: dict[str, list[bool]] = {"free": [], "tethered": []}
    last: dict[str, list[bool]] = {"free": [], "tethered": []}
    for i, child in enumerate(children):
        scenario = draw(base, config, child, i).scenario
        if scenario is None:
            continue
        for configuration in first:
            r = th.simulate(scenario.replace(configuration=configuration))
            if not r.ok:
                continue
            window = r.time >= start - 1e-9
            dev = np.abs(r.outputs[window, 0] - r.trim_output[0])
            t_peak = r.time[window][np.argmax(dev)]
            first[configuration].append(bool(t_peak < start + EDGE_S))
            last[configuration].append(bool(t_peak > r.time[-1] - EDGE_S))
    print(f"metrics window [{start:g}, {base.duration:g}] s")
    for configuration, flags in first.items():
        print(
            f"{configuration}: {np.mean(flags):.1%} of {len(flags)} peak-q1 times in the first "
            f"{EDGE_S:g} s, {np.mean(last[configuration]):.1%} in the last {EDGE_S:g} s"
        )


if __name__ == "__main__":
    main()
