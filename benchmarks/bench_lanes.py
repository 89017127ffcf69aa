"""Batch speed: the lane engine (blocks of LANES runs, ``lanes.run_lanes``) against one run
per thread (``engine.run_closed_loop``), measured in the same process.

Run: python benchmarks/bench_lanes.py [--draws 1000] [--rounds 3] [--cli] [--lanes 8,16,32]
Prints, measured in this run:
(a) runs/s of ``run_batch`` over 2 x draws dispersed paper runs (the Monte Carlo's draws of
    simulation 1, free and tethered) on all cores, lanes against one run per thread,
    interleaved over the rounds (best of each), their ratio, and that the two gave the same
    summaries bit for bit;
(b) with --cli: the whole-process rate of ``tetherheli montecarlo`` over the same draws
    (start-up, draws, runs, table, figures);
(c) with --lanes: (a) again in a fresh process per block size (``TETHERHELI_LANES``), to
    choose ``layout.DEFAULT_LANES`` (each size compiles once, about two minutes).
Timings vary with the machine and its load; no test asserts them.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from tetherheli.layout import LANES
from tetherheli.runs.batch import run_batch
from tetherheli.studies.montecarlo import CONFIGURATIONS, draw, load_montecarlo

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "montecarlo_paper_sim1.toml"


def draws(n_draws: int) -> tuple[list, object]:
    base, config = load_montecarlo(SCENARIO)
    children = np.random.SeedSequence(1).spawn(n_draws)
    runs = [
        draw(base, config, ch, i).scenario.replace(configuration=cfg)
        for i, ch in enumerate(children)
        for cfg in CONFIGURATIONS
    ]
    return runs, base.params


def compare(n_draws: int, rounds: int) -> dict:
    """Best runs/s of each engine over interleaved rounds, and their agreement."""
    runs, nominal = draws(n_draws)
    warm = runs[: 2 * LANES]
    run_batch(warm, design_params=nominal)  # compile / load both engines
    run_batch(warm, design_params=nominal, lanes=False)
    best = {"lanes_rate": 0.0, "single_rate": 0.0}
    results = {}
    for r in range(rounds):
        for name in ("lanes", "single") if r % 2 == 0 else ("single", "lanes"):
            t0 = time.perf_counter()
            results[name] = run_batch(runs, design_params=nominal, lanes=name == "lanes")
            rate = len(runs) / (time.perf_counter() - t0)
            best[f"{name}_rate"] = max(best[f"{name}_rate"], rate)
    same = np.array_equal(results["lanes"].summaries, results["single"].summaries, equal_nan=True)
    return {"block": LANES, "runs": len(runs), **best, "bit_identical": bool(same)}


def cli_rate(n_draws: int) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "tetherheli", "montecarlo", str(SCENARIO), "--quiet"]
        cmd += ["--runs", str(n_draws), "--seed", "1", "--out", f"{tmp}/mc"]
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        return 2 * n_draws / (time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=1000, help="Monte Carlo draws (2 runs each)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--cli", action="store_true", help="also time `tetherheli montecarlo`")
    ap.add_argument("--lanes", help="block sizes to compare in fresh processes, e.g. 8,16,32")
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.lanes:
        print(f"block size (fresh process each), {2 * args.draws} runs, best of {args.rounds}:")
        for size in args.lanes.split(","):
            env = {**os.environ, "TETHERHELI_LANES": size.strip()}
            cmd = [sys.executable, __file__, "--draws", str(args.draws)]
            cmd += ["--rounds", str(args.rounds), "--json"]
            out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True)
            m = json.loads(out.stdout.strip().splitlines()[-1])
            print(
                f"  LANES = {m['block']:3d}: lanes {m['lanes_rate']:7.0f} runs/s, one per thread"
                f" {m['single_rate']:6.0f} runs/s, ratio {m['lanes_rate'] / m['single_rate']:.2f}"
                f", bit-identical {m['bit_identical']}"
            )
        return
    m = compare(args.draws, args.rounds)
    if args.json:
        print(json.dumps(m))
        return
    print(f"run_batch of {m['runs']} dispersed paper runs on all cores, best of {args.rounds}:")
    print(f"  lanes (blocks of {LANES}):      {m['lanes_rate']:8.0f} runs/s")
    print(f"  one run per thread:          {m['single_rate']:8.0f} runs/s")
    print(f"  ratio lanes / one per thread: {m['lanes_rate'] / m['single_rate']:7.2f}")
    print(f"  summaries bit-identical:      {m['bit_identical']}")
    if args.cli:
        print(f"  `tetherheli montecarlo`, whole process: {cli_rate(args.draws):6.0f} runs/s")


if __name__ == "__main__":
    main()
