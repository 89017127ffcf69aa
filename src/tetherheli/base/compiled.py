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
    BASE_MASS,
    BASE_MOVING,
    BASE_OFFSET,
    BASE_VELOCITY,
    BASE_WAVE_AMPLITUDE,
    BASE_WAVE_AXIS,
    BASE_WAVE_OMEGA,
    BASE_WAVE_PHASE,
    BASE_WAVES,
)
from .motion import BaseMotion, FixedBase

__all__ = ["STILL_BASE", "CompiledBase", "base_at", "base_state", "base_state_into", "compile_base"]

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


def compile_base(motion: BaseMotion | None, mass: float = 0.0) -> CompiledBase:
    """The packed form of ``motion`` (None: the paper's still winch at the origin), with the
    mass [kg] the engine's inertial force -m b'' acts on (``layout.BASE_MASS``).

    Parameters
    ----------
    motion : BaseMotion or None
        The base's motion b(t); None: ``FixedBase()``, the still winch at the origin of N.
    mass : float, optional
        The mass m = mF + mMR [kg] the inertial force -m b'' acts on, stored at
        ``layout.BASE_MASS`` (default 0).

    Returns
    -------
    CompiledBase
        The packed array, (rows, ``BASE_COLUMNS``) float64, read-only (row 0 the counts
        ``BASE_WAVES``, ``BASE_KNOTS``, the ``BASE_OFFSET`` [m], ``BASE_VELOCITY`` [m/s],
        ``BASE_MOVING`` and ``BASE_MASS``; then one row per sinusoid, then one per spline
        knot), and whether the base moves.
    """
    motion = FixedBase() if motion is None else motion
    parts = motion.parts()
    waves, knots = parts.waves, parts.knots
    n_knots = 0 if knots is None else knots.size
    packed = np.zeros((1 + waves.shape[0] + n_knots, BASE_COLUMNS))
    packed[0, BASE_WAVES] = waves.shape[0]
    packed[0, BASE_KNOTS] = n_knots
    packed[0, BASE_OFFSET : BASE_OFFSET + 3] = parts.offset
    packed[0, BASE_VELOCITY : BASE_VELOCITY + 3] = parts.velocity
    rows = 1 + waves.shape[0]
    packed[1:rows, BASE_WAVE_AXIS] = waves[:, 0]
    packed[1:rows, BASE_WAVE_AMPLITUDE] = waves[:, 1]
    packed[1:rows, BASE_WAVE_OMEGA] = waves[:, 2]
    packed[1:rows, BASE_WAVE_PHASE] = waves[:, 3]
    if knots is not None and n_knots:
        assert parts.coefficients is not None  # a spline has both
        packed[rows:, BASE_KNOT_TIME] = knots
        packed[rows : rows + n_knots - 1, BASE_CUBIC:] = parts.coefficients.reshape(n_knots - 1, 12)
    moving = not (motion.fixed and not np.any(parts.offset))
    packed[0, BASE_MOVING] = 1.0 if moving else 0.0
    packed[0, BASE_MASS] = mass
    packed.setflags(write=False)
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
def base_at(base, t):
    """Position (3), velocity (3) and acceleration (3) of the base at time t [m, m/s, m/s^2],
    N components, from its packed form: a tuple of nine floats.

    Parameters
    ----------
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The packed base (``CompiledBase.packed``; layout ``layout.BASE_*``).
    t : float
        The time [s].

    Returns
    -------
    tuple of 9 float
        b1, b2, b3 [m], b1', b2', b3' [m/s], b1'', b2'', b3'' [m/s^2], N components.
    """
    n_waves = int(base[0, BASE_WAVES])
    n_knots = int(base[0, BASE_KNOTS])
    v1 = base[0, BASE_VELOCITY]
    v2 = base[0, BASE_VELOCITY + 1]
    v3 = base[0, BASE_VELOCITY + 2]
    b1 = base[0, BASE_OFFSET] + t * v1
    b2 = base[0, BASE_OFFSET + 1] + t * v2
    b3 = base[0, BASE_OFFSET + 2] + t * v3
    a1 = 0.0
    a2 = 0.0
    a3 = 0.0
    for r in range(1, 1 + n_waves):
        amp = base[r, BASE_WAVE_AMPLITUDE]
        omega = base[r, BASE_WAVE_OMEGA]
        arg = omega * t + base[r, BASE_WAVE_PHASE]
        s = math.sin(arg)
        db, dv, da = amp * s, amp * omega * math.cos(arg), -amp * omega * omega * s
        axis = base[r, BASE_WAVE_AXIS]
        if axis == 0.0:
            b1 += db
            v1 += dv
            a1 += da
        elif axis == 1.0:
            b2 += db
            v2 += dv
            a2 += da
        else:
            b3 += db
            v3 += dv
            a3 += da
    if n_knots > 0:
        k = _knot_interval(base, 1 + n_waves, n_knots, t)
        h = t - base[k, BASE_KNOT_TIME]
        c = BASE_CUBIC
        b1 += ((base[k, c] * h + base[k, c + 3]) * h + base[k, c + 6]) * h + base[k, c + 9]
        b2 += ((base[k, c + 1] * h + base[k, c + 4]) * h + base[k, c + 7]) * h + base[k, c + 10]
        b3 += ((base[k, c + 2] * h + base[k, c + 5]) * h + base[k, c + 8]) * h + base[k, c + 11]
        v1 += (3.0 * base[k, c] * h + 2.0 * base[k, c + 3]) * h + base[k, c + 6]
        v2 += (3.0 * base[k, c + 1] * h + 2.0 * base[k, c + 4]) * h + base[k, c + 7]
        v3 += (3.0 * base[k, c + 2] * h + 2.0 * base[k, c + 5]) * h + base[k, c + 8]
        a1 += 6.0 * base[k, c] * h + 2.0 * base[k, c + 3]
        a2 += 6.0 * base[k, c + 1] * h + 2.0 * base[k, c + 4]
        a3 += 6.0 * base[k, c + 2] * h + 2.0 * base[k, c + 5]
    return b1, b2, b3, v1, v2, v3, a1, a2, a3


@_jit_inline
def base_state_into(base, t, out):
    """``base_at`` into out (9,): position out[0:3] [m], velocity out[3:6] [m/s],
    acceleration out[6:9] [m/s^2].

    Parameters
    ----------
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The packed base (``CompiledBase.packed``; layout ``layout.BASE_*``).
    t : float
        The time [s].
    out : numpy.ndarray, shape (9,)
        Written: position [m], velocity [m/s], acceleration [m/s^2], N components.
    """
    state = base_at(base, t)
    for i in range(9):
        out[i] = state[i]


@_jit
def base_states(base, times, out):
    """``base_state_into`` at each of ``times`` into out (n, 9).

    Parameters
    ----------
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The packed base (``CompiledBase.packed``; layout ``layout.BASE_*``).
    times : numpy.ndarray, shape (n,)
        The times [s].
    out : numpy.ndarray, shape (n, 9)
        Written: row j the position [m], velocity [m/s] and acceleration [m/s^2] at
        ``times[j]``, N components.
    """
    for j in range(times.size):
        base_state_into(base, times[j], out[j])


def base_state(base: CompiledBase, times: np.ndarray) -> np.ndarray:
    """Position, velocity and acceleration of a packed base at ``times``: (n, 3, 3), rows
    position, velocity, acceleration (``BaseMotion.state`` is this on its own packed form).

    Parameters
    ----------
    base : CompiledBase
        The packed base (``compile_base``).
    times : float or numpy.ndarray, shape (n,)
        The times [s].

    Returns
    -------
    numpy.ndarray, shape (n, 3, 3)
        ``out[j, 0]`` position [m], ``out[j, 1]`` velocity [m/s], ``out[j, 2]``
        acceleration [m/s^2] at ``times[j]``, N components.
    """
    # a writable copy: one compiled signature of ``base_states`` (a result's times are
    # read-only)
    times = np.array(np.atleast_1d(times), dtype=np.float64, order="C")
    out = np.empty((times.size, 9))
    base_states(base.packed, times, out)
    return out.reshape(times.size, 3, 3)


#: the paper's still winch at the origin, packed (read-only): the base of every run without a
#: ``[base]`` table, and of the loops that fly no base (the Gymnasium environments)
STILL_BASE = compile_base(None).packed
