"""Cost of one derivative evaluation: compiled path vs the Python call (issue: core model).

Run: python benchmarks/bench_derivative.py
Prints the time per derivative of one tethered state (a) inside compiled code, (b) through
the public Python method ``TetheredHelicopter.derivative``, (c) per state of a batch, and the
ratios, all measured in this run. Timings vary with the machine; no test asserts them.
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit

from tetherheli import TetheredHelicopter
from tetherheli.model import kernels


@njit  # not cached: a benchmark must measure the current kernels
def _loop(x, u, wind, p, K_C, out, n):
    acc = 0.0
    for i in range(n):
        x[6] = 1e-3 * (i % 7)  # defeat hoisting
        kernels.tethered_derivative(x, u, wind, 0.0, p, K_C, 0.0, out)
        acc += out[7]
    return acc


def best_of(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    model = TetheredHelicopter()
    trim = model.trim(25.0)
    x = trim.x.copy()
    u = trim.u_total.copy()
    wind = np.array([3.0, -1.0, 0.5])
    p = model.constants
    out = np.empty(13)
    n = 2_000_000
    _loop(x, u, wind, p, 40.0, out, 10)
    t_compiled = best_of(lambda: _loop(x, u, wind, p, 40.0, out, n)) / n
    m = 20_000
    t_python = best_of(lambda: [model.derivative(x, u, wind) for _ in range(m)]) / m
    xs = np.tile(x, (100_000, 1))
    t_batch = best_of(lambda: model.derivative(xs, u, wind)) / xs.shape[0]
    print(f"compiled derivative, one state:        {t_compiled * 1e9:8.1f} ns")
    print(f"TetheredHelicopter.derivative (Python): {t_python * 1e9:8.1f} ns per call")
    print(f"batch of 100000 states:                 {t_batch * 1e9:8.1f} ns per state")
    print(f"Python-call overhead ratio:             {t_python / t_compiled:8.1f} x")


if __name__ == "__main__":
    main()
