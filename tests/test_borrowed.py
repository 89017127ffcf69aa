"""Borrowed arrays (``_compile.borrowed``, issue 24): views without reference counting that the
compiled loops work on. They must write their owner's memory, leave Numba's allocations
balanced (nothing leaked, nothing freed twice) and change no result."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
from numba import njit

from tetherheli._compile import borrowed, keep_alive


@njit(cache=False)
def _write_through(a, pair):
    own = np.zeros(3)
    view, (first, second), scratch = borrowed((a, pair, own))
    for i in range(view.shape[0]):
        view[i] = 2.0 * i
    first[0] = 7.0
    second[0, 1] = 8.0
    scratch[1] = 5.0
    row = view[1:]  # a slice of a borrowed array
    row[0] += 0.5
    total = scratch.sum()
    keep_alive(own)
    return total


def test_borrowed_views_write_their_owners_memory():
    a = np.zeros(4)
    first, second = np.zeros(2), np.zeros((2, 2))
    assert _write_through(a, (first, second)) == 5.0
    np.testing.assert_array_equal(a, [0.0, 2.5, 4.0, 6.0])
    assert first[0] == 7.0 and second[0, 1] == 8.0


_BALANCE = """
from numba.core.runtime import rtsys
from tetherheli.shipped import shipped_scenario
from tetherheli.runs import simulate
runs = [shipped_scenario(n).replace(duration=0.5)
        for n in ("paper_sim1_tethered", "paper_sim1_lumped", "sensing_tether")]
for s in runs:
    simulate(s)  # compiled and warmed
def balance():
    st = rtsys.get_allocation_stats()
    return st.alloc - st.free, st.mi_alloc - st.mi_free
before = balance()
results = [simulate(s) for s in runs for _ in range(3)]
assert all(r.ok for r in results)
del results
print(before == balance(), before, balance())
"""


def test_runs_on_borrowed_arrays_leave_the_allocations_balanced():
    """Every block the compiled loop allocates is freed once (Numba's own counters,
    ``NUMBA_NRT_STATS=1`` in a process of its own), in massless, lumped and sensed runs."""
    done = subprocess.run(
        [sys.executable, "-c", _BALANCE],
        env={**os.environ, "NUMBA_NRT_STATS": "1"},
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.split()[0] == "True", done.stdout
