"""The engine against a minimal closed loop written in one compiled function (issue 24).

The minimal loop flies the same plant (the generated tethered model), the paper's LQI with the
tether-torque feed-forward (eqs 50-55), the winch PI (eq 56) and fixed-step RK4, with nothing
else: no sensors, actuators, checks or recording, sin and cos from libm at every stage. It is
the yardstick of the engine's speed measured in the same run, so that the figures printed
here are ratios that hold on a loaded or slower machine:

- ``simulate_ms / minimal_ms``: ``engine.run_closed_loop`` (summaries only, ``run_unrecorded``)
  on the 60 s tethered paper scenario, against the minimal loop on the same run;
- ``batch / minimal batch``: ``run_batch`` of N dispersed paper runs (pulse and sine scaled by
  U(0.8, 1.2)) against the minimal loop's batch over the cores (``prange``): the median of
  the ratios of ``--pairs`` interleaved pairs, with their range.

Run: python benchmarks/bench_minimal_loop.py [--runs 400] [--repeat 15] [--pairs 5]. It also
prints the largest difference of the minimal loop's peak deviations from the engine's (about 1e-9 m:
the loops differ only in how they take sin and cos). Timings vary with the machine and its
load; no test asserts them.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np
from numba import njit, prange

from tetherheli.engine import loop as engine
from tetherheli.layout import (
    CFG_DT,
    CFG_K_C,
    CFG_N_SUB,
    CTRL_K_I,
    CTRL_K_P,
    CTRL_T_REF,
    LAW_GAIN,
    LAW_U0,
    LAW_X_REF,
    LAW_Y_REF,
)
from tetherheli.model.kernels import (
    angle_trig,
    tethered_outputs_sc,
    tethered_rhs_sc,
    tethered_tether_torque_sc,
)
from tetherheli.runs.batch import run_batch, run_unrecorded
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import paper_scenario
from tetherheli.wind import Pulse, Sine, evaluate


@njit(error_model="numpy", inline="always", cache=True)
def _derivative(x, inp, rate, t, side, k_c, c, program, sc, wind, out):
    """dx/dt of the tethered plant with the built-in wind profiles' force at t."""
    angle_trig(x, sc)
    wind[:] = 0.0
    evaluate._wind_program_force(program, t, side, wind)
    stretch = x[5] - x[12]
    tension = k_c * stretch if stretch > 0.0 else 0.0
    tethered_rhs_sc(x, sc, inp, wind, tension, c, out)
    out[12] = rate


@njit(error_model="numpy", cache=True)
def minimal_loop(x0, n_samples, dt, n_sub, k_c, kp, ki, t_ref, c, gain, x_ref, y_ref, u0, program):
    """The paper's closed loop in one function; returns the peak |q1..q3 - ref| [m] (3,)."""
    x = x0.copy()
    z = np.zeros(4)
    integral = 0.0
    sc = np.empty(10)
    y = np.empty(4)
    inp = np.empty(4)
    ffwd = np.empty(2)
    wind = np.empty(3)
    k1, k2, k3, k4, tmp = np.empty(13), np.empty(13), np.empty(13), np.empty(13), np.empty(13)
    peak = np.zeros(3)
    n_x = gain.shape[1] - 4
    h = dt / n_sub
    for k in range(n_samples + 1):
        t = k * dt
        stretch = x[5] - x[12]
        tension = k_c * stretch if stretch > 0.0 else 0.0
        angle_trig(x, sc)
        tethered_outputs_sc(x, sc, c, y)
        for a in range(3):
            peak[a] = max(peak[a], abs(y[a] - y_ref[a]))
        for i in range(4):
            acc = u0[i]
            for j in range(n_x):
                acc -= gain[i, j] * (x[j] - x_ref[j])
            for j in range(4):
                acc -= gain[i, n_x + j] * z[j]
            inp[i] = acc
        tethered_tether_torque_sc(x, sc, tension, c, ffwd)
        inp[1] -= ffwd[0]
        inp[2] -= ffwd[1]
        for j in range(4):
            z[j] += dt * (y_ref[j] - y[j])
        error = tension - t_ref
        rate = kp * error + ki * integral
        integral += dt * error
        if k == n_samples:
            break
        for s in range(n_sub):
            ta = t + s * h
            _derivative(x, inp, rate, ta, 1, k_c, c, program, sc, wind, k1)
            for i in range(13):
                tmp[i] = x[i] + 0.5 * h * k1[i]
            _derivative(tmp, inp, rate, ta + 0.5 * h, 1, k_c, c, program, sc, wind, k2)
            for i in range(13):
                tmp[i] = x[i] + 0.5 * h * k2[i]
            _derivative(tmp, inp, rate, ta + 0.5 * h, 1, k_c, c, program, sc, wind, k3)
            for i in range(13):
                tmp[i] = x[i] + h * k3[i]
            _derivative(tmp, inp, rate, t + (s + 1) * h, -1, k_c, c, program, sc, wind, k4)
            for i in range(13):
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    return peak


@njit(error_model="numpy", parallel=True, cache=True)
def minimal_batch(x0, n_samples, dt, n_sub, k_c, kp, ki, t_ref, c, gain, x_ref, y_ref, u0,
                  programs):  # fmt: skip
    """``minimal_loop`` of each wind program of programs (N, rows, columns) over the cores."""
    peaks = np.empty((programs.shape[0], 3))
    for r in prange(programs.shape[0]):
        peaks[r] = minimal_loop(x0, n_samples, dt, n_sub, k_c, kp, ki, t_ref, c, gain, x_ref,
                                y_ref, u0, programs[r])  # fmt: skip
    return peaks


def _minimal_args(setup, n_samples):
    law = setup.law
    cfg, ctrl = setup.cfg, setup.ctrl
    return (
        setup.start.x.copy(), n_samples, cfg[CFG_DT], int(cfg[CFG_N_SUB]), cfg[CFG_K_C],
        ctrl[CTRL_K_P], ctrl[CTRL_K_I], ctrl[CTRL_T_REF], setup.model.constants,
        law[LAW_GAIN], law[LAW_X_REF], law[LAW_Y_REF], law[LAW_U0],
    )  # fmt: skip


def dispersed_runs(scenario, n):
    """n copies of ``scenario`` in the paper's pulse and sine, each scaled by U(0.8, 1.2)
    (seed 1): the batch of this benchmark and of ``lane_profile.py``."""
    scales = np.random.default_rng(1).uniform(0.8, 1.2, n)
    return [
        scenario.replace(
            wind=Pulse(10.0, 1.0, 20.0 * a, (1.0, 0.0, 0.0))
            + Sine(20.0 * a, 0.1, 30.0, (1.0, 0.0, 0.0))
        )
        for a in scales
    ]


def best_warm(function, repeat):
    """The best of ``repeat`` timings of ``function()`` [s], after one call to warm it."""
    function()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        function()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=400, help="runs of the batch")
    parser.add_argument("--repeat", type=int, default=15, help="timings of a single run")
    parser.add_argument(
        "--pairs", type=int, default=5, help="interleaved batch pairs (median of their ratios)"
    )
    options = parser.parse_args()
    scenario = paper_scenario(1, "tethered")
    setup = engine_setup(scenario)
    args = setup.engine_args(scenario.n_samples)
    minimal = _minimal_args(setup, scenario.n_samples)
    program = setup.wind.program
    summary = np.zeros(len(engine.SUMMARY_FIELDS))
    run_unrecorded(args, summary)
    peak = minimal_loop(*minimal, program)
    fields = engine.SUMMARY_FIELDS
    engine_peak = summary[[fields.index(f"peak_q{a}") for a in (1, 2, 3)]]
    runs = dispersed_runs(scenario, options.runs)
    programs = np.stack([engine_setup(run).wind.program for run in runs])
    # interleaved: engine, minimal, engine, minimal (the machine's drift hits both alike)
    engine_s, minimal_s = [], []
    for _ in range(2):
        engine_s.append(best_warm(lambda: run_unrecorded(args, summary), options.repeat))
        minimal_s.append(best_warm(lambda: minimal_loop(*minimal, program), options.repeat))
    run_batch(runs[:4])
    minimal_batch(*minimal, programs[:4])
    # interleaved pairs, the ratio taken within each pair: a shared machine's speed drifts
    # over seconds (on a loaded host one pair's ratio ranged 1.3-2.1 within one run), so the
    # median of the pairs' ratios is the figure, its range the spread
    batch_rate, minimal_rate = [], []
    for _ in range(options.pairs):
        t0 = time.perf_counter()
        run_batch(runs)
        batch_rate.append(len(runs) / (time.perf_counter() - t0))
        t0 = time.perf_counter()
        minimal_batch(*minimal, programs)
        minimal_rate.append(len(runs) / (time.perf_counter() - t0))
    pair_ratios = np.array(batch_rate) / np.array(minimal_rate)
    figures = {
        "engine_ms": min(engine_s) * 1e3,
        "minimal_ms": min(minimal_s) * 1e3,
        "engine_over_minimal": min(engine_s) / min(minimal_s),
        "batch_runs_per_s": max(batch_rate),
        "minimal_batch_runs_per_s": max(minimal_rate),
        "batch_over_minimal_batch": float(np.median(pair_ratios)),
        "batch_over_minimal_batch_range": [float(pair_ratios.min()), float(pair_ratios.max())],
        "peak_difference_m": float(np.max(np.abs(peak - engine_peak))),
    }
    print(json.dumps(figures, indent=1))
    assert math.isfinite(figures["peak_difference_m"])


if __name__ == "__main__":
    main()
