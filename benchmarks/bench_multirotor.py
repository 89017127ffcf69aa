"""The multirotor's compiled derivative against RotorPy 3.0.0's, in the same process (issue 45).

Prints the first call of ``multirotor_derivative`` (its compilation from an empty cache, or
the cache's load), the time of one call (timeit, the best of five) beside one call of
RotorPy's ``Multirotor(quad_params, aero=True)._s_dot_fn`` at the same state, and their
ratio, on the Hummingbird with drag on, wind and a tether pull. Needs rotorpy (the
``validation`` extra). For a cold compile run it with an empty ``NUMBA_CACHE_DIR``.

Run: python benchmarks/bench_multirotor.py. Timings vary with the machine and
its load; no test asserts them.
"""

from __future__ import annotations

import platform
import time
import timeit

import numpy as np


def main() -> None:
    import rotorpy.vehicles.hummingbird_params as hummingbird
    from rotorpy.vehicles.multirotor import Multirotor as RotorPyMultirotor

    from tetherheli.model.multirotor import Multirotor
    from tetherheli.model.multirotor_kernels import multirotor_derivative

    vehicle = Multirotor.from_rotorpy(hummingbird.quad_params)
    rng = np.random.default_rng(0)
    q = rng.normal(size=4)
    state = {
        "x": np.array([0.0, 0.0, 5.0]),
        "v": rng.normal(size=3),
        "q": q / np.linalg.norm(q),
        "w": rng.normal(size=3),
        "rotor_speeds": np.full(4, 900.0),
    }
    s = vehicle.pack_state(state)
    cmd, wind, pull = np.full(4, 1000.0), rng.normal(size=3), np.array([0.3, -0.2, -1.0])
    out = np.empty_like(s)
    p = vehicle.packed
    start = time.perf_counter()
    multirotor_derivative(p, s, cmd, wind, pull, out)
    first = time.perf_counter() - start

    def ours() -> None:
        multirotor_derivative(p, s, cmd, wind, pull, out)

    theirs_vehicle = RotorPyMultirotor(hummingbird.quad_params, aero=True)
    full = np.concatenate((s[:13], wind, s[13:]))

    def theirs() -> None:
        theirs_vehicle._s_dot_fn(0.0, full, cmd)

    n_ours, n_theirs = 100_000, 1_000
    t_ours = min(timeit.repeat(ours, number=n_ours, repeat=5)) / n_ours
    t_theirs = min(timeit.repeat(theirs, number=n_theirs, repeat=5)) / n_theirs
    print(f"processor: {platform.processor() or platform.machine()}")
    print(f"multirotor_derivative first call: {first:.2f} s (compile or cache load)")
    print(f"multirotor_derivative: {t_ours * 1e6:.2f} us a call")
    print(f"RotorPy _s_dot_fn:     {t_theirs * 1e6:.1f} us a call ({t_theirs / t_ours:.0f}x)")


if __name__ == "__main__":
    main()
