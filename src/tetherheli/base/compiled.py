"""A base motion in the engine's packed form, and its compiled evaluation.

One float64 array of ``BASE_COLUMNS`` columns (``layout.BASE_*``) holds every motion:
row 0 the counts, the constant offset and velocity; then one row per sinusoid (axis,
amplitude, angular frequency, phase); then one row per spline knot (its time and the four
cubic coefficients of each axis on the interval that starts there). ``base_state_into``
sums the parts at any time, so the engine, its lumped chain and the cable driver evaluate
every motion with one compiled function, and ``BaseMotion.state`` (NumPy) is its check.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._compile import compiled
from ..layout import (
    BASE_COLUMNS,
    BASE_CUBIC,
    BASE_KNOT_TIME,
    BASE_KNOTS,
    BASE_OFFSET,
    BASE_VELOCITY,
    BASE_WAVE_AMPLITUDE,
    BASE_WAVE_AXIS,
    BASE_WAVE_OMEGA,
    BASE_WAVE_PHASE,
    BASE_WAVES,
)
from .motion import BaseMotion, FixedBase

__all__ = ["CompiledBase", "base_state", "base_state_into", "compile_base"]

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")


class CompiledBase(NamedTuple):
    """A base motion packed for the engine.

    Attributes
    ----------
    packed : (rows, BASE_COLUMNS) float64, read-only
    moving : False for a still winch (the engine then flies the paper's fixed-winch step)
    """

    packed: np.ndarray
    moving: bool


def compile_base(motion: BaseMotion | None) -> CompiledBase:
    """The packed form of ``motion`` (None: the paper's still winch at the origin)."""
    motion = FixedBase() if motion is None else motion
    offset, velocity, waves, knots, coef = motion.parts()
    n_knots = 0 if knots is None else knots.size
    packed = np.zeros((1 + waves.shape[0] + n_knots, BASE_COLUMNS))
    packed[0, BASE_WAVES] = waves.shape[0]
    packed[0, BASE_KNOTS] = n_knots
    packed[0, BASE_OFFSET : BASE_OFFSET + 3] = offset
    packed[0, BASE_VELOCITY : BASE_VELOCITY + 3] = velocity
    rows = 1 + waves.shape[0]
    packed[1:rows, BASE_WAVE_AXIS] = waves[:, 0]
    packed[1:rows, BASE_WAVE_AMPLITUDE] = waves[:, 1]
    packed[1:rows, BASE_WAVE_OMEGA] = waves[:, 2]
    packed[1:rows, BASE_WAVE_PHASE] = waves[:, 3]
    if n_knots:
        packed[rows:, BASE_KNOT_TIME] = knots
        packed[rows : rows + n_knots - 1, BASE_CUBIC:] = coef.reshape(n_knots - 1, 12)
    packed.setflags(write=False)
    moving = not (motion.fixed and not np.any(offset))
    return CompiledBase(packed, moving)


@_jit_inline
def _knot_interval(base, first, n_knots, t):
    """Index (from ``first``) of the knot interval holding t, by bisection; the first or last
    interval outside the knots."""
    lo = 0
    hi = n_knots - 2
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if base[first + mid, BASE_KNOT_TIME] <= t:
            lo = mid
        else:
            hi = mid - 1
    return first + lo


@_jit_inline
def base_state_into(base, t, out):
    """Position out[0:3] [m], velocity out[3:6] [m/s] and acceleration out[6:9] [m/s^2] of the
    base at time t, N components, from its packed form."""
    n_waves = int(base[0, BASE_WAVES])
    n_knots = int(base[0, BASE_KNOTS])
    for i in range(3):
        out[i] = base[0, BASE_OFFSET + i] + t * base[0, BASE_VELOCITY + i]
        out[3 + i] = base[0, BASE_VELOCITY + i]
        out[6 + i] = 0.0
    for r in range(1, 1 + n_waves):
        axis = int(base[r, BASE_WAVE_AXIS])
        amp = base[r, BASE_WAVE_AMPLITUDE]
        omega = base[r, BASE_WAVE_OMEGA]
        arg = omega * t + base[r, BASE_WAVE_PHASE]
        s = math.sin(arg)
        out[axis] += amp * s
        out[3 + axis] += amp * omega * math.cos(arg)
        out[6 + axis] -= amp * omega * omega * s
    if n_knots > 0:
        k = _knot_interval(base, 1 + n_waves, n_knots, t)
        h = t - base[k, BASE_KNOT_TIME]
        for i in range(3):
            c0 = base[k, BASE_CUBIC + i]
            c1 = base[k, BASE_CUBIC + 3 + i]
            c2 = base[k, BASE_CUBIC + 6 + i]
            c3 = base[k, BASE_CUBIC + 9 + i]
            out[i] += ((c0 * h + c1) * h + c2) * h + c3
            out[3 + i] += (3.0 * c0 * h + 2.0 * c1) * h + c2
            out[6 + i] += 6.0 * c0 * h + 2.0 * c1


@_jit
def base_states(base, times, out):
    """``base_state_into`` at each of ``times`` into out (n, 9)."""
    for j in range(times.size):
        base_state_into(base, times[j], out[j])


def base_state(base: CompiledBase, times: np.ndarray) -> np.ndarray:
    """Position, velocity and acceleration of a packed base at ``times``: (n, 3, 3) as
    ``BaseMotion.state``."""
    times = np.ascontiguousarray(np.atleast_1d(times), dtype=np.float64)
    out = np.empty((times.size, 9))
    base_states(base.packed, times, out)
    return out.reshape(times.size, 3, 3)
