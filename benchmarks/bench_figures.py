"""The time to save a figure as a PNG: ``viz.figure.save_figure`` (one Agg drawing, the
layout inside it) against Matplotlib's own ``savefig`` (a layout pass without rendering, then
the rendering pass) of an identical, freshly made figure, as a ratio in the same run.

Figures: a run's outputs and inputs (the paper's simulation 1, free and tethered, stacked
axes under constrained layout) and the Monte Carlo histogram, CDF and paired scatter of 50
draws. Each figure is the best of ``--repeat`` CPU timings (``time.process_time``), ours and
Matplotlib's interleaved; a shared machine drifts, so compare the ratios of one run.

Run: python benchmarks/bench_figures.py [--dpi 300] [--repeat 5]
"""

from __future__ import annotations

import argparse
import io
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from tetherheli import simulate
from tetherheli.shipped import shipped_scenario
from tetherheli.viz import plots


def figures() -> dict:
    """name -> a function making that figure afresh."""
    runs = [simulate(shipped_scenario(n)) for n in ("paper_sim1_tethered", "paper_sim1_free")]
    rng = np.random.default_rng(1)
    values = {"free": rng.uniform(0.5, 1.0, 50), "tethered": rng.uniform(0.2, 0.5, 50)}
    ok = {k: np.ones(50, bool) for k in values}
    return {
        "run outputs": lambda: plots.figure_outputs(runs, "outputs"),
        "run inputs": lambda: plots.figure_inputs(runs, "inputs"),
        "Monte Carlo histogram": lambda: plots.figure_montecarlo(values, ok, "hist"),
        "Monte Carlo CDF": lambda: plots.figure_montecarlo(values, ok, "cdf"),
        "paired scatter": lambda: plots.figure_paired(
            values["free"], values["tethered"], ok["free"], ok["tethered"]
        ),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dpi", type=float, default=plots.PRINT_DPI)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()

    def ours(fig, folder: Path) -> None:
        plots.save_figure(fig, folder / "f.png", dpi=args.dpi)

    def matplotlibs(fig, folder: Path) -> None:
        fig.savefig(io.BytesIO(), format="png", dpi=args.dpi)

    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, make in figures().items():
            best = {"save_figure": np.inf, "savefig": np.inf}
            for _ in range(args.repeat):
                for key, save in (("save_figure", ours), ("savefig", matplotlibs)):
                    fig = make()
                    t = time.process_time()
                    save(fig, folder)
                    best[key] = min(best[key], time.process_time() - t)
            out[name] = {
                "save_figure_ms": round(1e3 * best["save_figure"], 1),
                "savefig_ms": round(1e3 * best["savefig"], 1),
                "ratio": round(best["save_figure"] / best["savefig"], 3),
            }
            print(f"{name:24s} {out[name]}", flush=True)
    print(json.dumps({"dpi": args.dpi, "figures": out}))


if __name__ == "__main__":
    main()
