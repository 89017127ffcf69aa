"""Closed-loop speed: the compiled engine against a straightforward SciPy implementation.

Run: python benchmarks/bench_closed_loop.py [--skip-cold]
Prints, measured in this run:
(a) wall time of one 60 s tethered paper scenario (simulation 1) with the compiled engine
    after warm-up (best of several), the same closed loop written here the way a researcher
    would in SciPy (solve_ivp restarted at every 10 ms zero-order-hold sample, Python
    right-hand side and controller), their agreement and the ratio;
(b) Monte Carlo throughput on all cores: ``run_batch`` of 1000 dispersed paper runs in this
    process, and ``tetherheli montecarlo`` of 1000 draws (2000 runs: each draw free and
    tethered) counted over the whole fresh process (start-up, draws, runs, table, figures);
(c) the cold start of ``tetherheli paper`` end to end (a fresh process; Numba's on-disk cache
    as it is: run it twice to see the warm-cache figure).
Timings vary with the machine and its load; no test asserts them.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

from tetherheli import simulate
from tetherheli.engine import loop as engine
from tetherheli.runs.batch import run_unrecorded
from tetherheli.runs.setup import engine_setup, run_setup
from tetherheli.scenario.core import paper_scenario


def scipy_baseline(scenario):
    """The paper's closed loop in plain NumPy/SciPy: eqs 28, 30-35 via the model's Python
    method, LQI + feed-forward + PI at every sample, solve_ivp (RK45) between samples."""
    model, trim, gain, _, _ = run_setup(scenario)
    dt = scenario.control.dt
    K, x_ref, y_ref, u0 = gain.K, trim.x[:12], trim.y, trim.u
    T_ref = scenario.params.tension_control.T_ref
    K_P, K_I = scenario.params.tension_control.K_P, scenario.params.tension_control.K_I
    wind = scenario.wind
    x = trim.x.copy()
    z = np.zeros(4)
    integral = 0.0
    ys = []
    for k in range(scenario.n_samples + 1):
        t = k * dt
        tension = model.tension(x)
        y = model.outputs(x)
        ys.append(y)
        u = u0 - K @ np.concatenate([x[:12] - x_ref, z])
        c1, c2 = model.tether_torque(x, tension)
        u[1] -= c1
        u[2] -= c2
        z += dt * (y_ref - y)
        error = tension - T_ref
        rate = K_P * error + K_I * integral
        integral += dt * error
        if k == scenario.n_samples:
            break
        mid = t + 0.5 * dt

        def rhs(tt, xx, u=u, rate=rate, mid=mid):
            # one-sided wind at the interval ends, like the engine
            return model.derivative(xx, u, wind.force(tt + (1e-12 if tt < mid else -1e-12)), rate)

        x = solve_ivp(rhs, (t, t + dt), x, rtol=1e-8, atol=1e-10).y[:, -1]
    return np.array(ys)


def monte_carlo(n_draws: int) -> tuple[float, float]:
    """(runs/s of run_batch over 2 n_draws runs in this process, runs/s of the CLI's whole
    process for the same draws)."""
    from pathlib import Path

    from tetherheli.runs.batch import run_batch
    from tetherheli.studies.montecarlo import CONFIGURATIONS, draw, load_montecarlo

    path = Path(__file__).resolve().parents[1] / "scenarios" / "montecarlo_paper_sim1.toml"
    base, config = load_montecarlo(path)
    children = np.random.SeedSequence(1).spawn(n_draws)
    t0 = time.perf_counter()
    scenarios = [
        draw(base, config, ch, i).scenario.replace(configuration=cfg)
        for i, ch in enumerate(children)
        for cfg in CONFIGURATIONS
    ]
    batch = run_batch(scenarios, design_params=base.params)
    t_batch = time.perf_counter() - t0
    assert bool(batch.ok.all())
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "tetherheli", "montecarlo", str(path), "--quiet"]
        cmd += ["--runs", str(n_draws), "--seed", "1", "--out", f"{tmp}/mc"]
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        t_cli = time.perf_counter() - t0
    return 2 * n_draws / t_batch, 2 * n_draws / t_cli


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--skip-cold", action="store_true")
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--draws", type=int, default=1000, help="Monte Carlo draws for (b)")
    opts = parser.parse_args()

    s = paper_scenario(1, "tethered")
    simulate(s)  # warm-up (compile or load the cache)
    times = []
    for _ in range(opts.repeat):
        t0 = time.perf_counter()
        result = simulate(s)
        times.append(time.perf_counter() - t0)
    t_sim = min(times)

    args = engine_setup(s).engine_args(s.n_samples)
    summary = np.zeros(len(engine.SUMMARY_FIELDS))
    run_unrecorded(args, summary)
    engine_times = []
    for _ in range(opts.repeat):
        t0 = time.perf_counter()
        run_unrecorded(args, summary)
        engine_times.append(time.perf_counter() - t0)
    t_engine = min(engine_times)

    t0 = time.perf_counter()
    ys = scipy_baseline(s)
    t_scipy = time.perf_counter() - t0
    agreement = float(np.abs(ys[:, :3] - result.outputs[:, :3]).max())

    print("(a) one 60 s tethered paper scenario (simulation 1), dt = 10 ms, RK4 2 substeps")
    print(
        f"    compiled, simulate() with recording:   {t_sim * 1e3:9.2f} ms (best of {opts.repeat})"
    )
    print(f"    compiled engine, summaries only:       {t_engine * 1e3:9.2f} ms")
    print(f"    SciPy baseline (solve_ivp per sample): {t_scipy * 1e3:9.1f} ms")
    print(f"    ratio SciPy / compiled engine:         {t_scipy / t_engine:9.0f} x")
    print(f"    ratio SciPy / simulate():              {t_scipy / t_sim:9.0f} x")
    print(
        f"    max |q1..q3 difference|:               {agreement:9.2e} m "
        "(the baseline's own RK45 tolerance)"
    )
    print(f"    single-core throughput, summaries only:{1.0 / t_engine:9.0f} runs/s")
    batch_rate, cli_rate = monte_carlo(opts.draws)
    n_runs = 2 * opts.draws
    print(f"(b) Monte Carlo, {opts.draws} draws x (free, tethered) = {n_runs} runs, all cores")
    print(f"    run_batch in this process:             {batch_rate:9.0f} runs/s")
    print(f"    `tetherheli montecarlo`, whole process:{cli_rate:9.0f} runs/s")
    if not opts.skip_cold:
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "tetherheli", "paper", "--out", f"{tmp}/out"],
                check=True,
                capture_output=True,
            )
            t_cold = time.perf_counter() - t0
        print(f"(c) `tetherheli paper` end to end, fresh process: {t_cold:6.2f} s")


if __name__ == "__main__":
    main()
