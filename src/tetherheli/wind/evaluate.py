"""The built-in winds evaluated in compiled code (``wind.compiled.CompiledWind``'s arrays): the
force profiles' rows (``layout.WIND_*``), the gust table's air velocity and the quadratic drag
|v_rel| v_rel of the helicopter in it. Every loop evaluates its wind here (the single run's
``engine.loop``, the lumped chain's nodes, the lanes and the environments)."""

from __future__ import annotations

import math

from .._compile import compiled, frozen, inline_here, plain
from ..base.compiled import base_at
from ..layout import (
    BASE_MASS,
    BASE_MOVING,
    WIND_CONSTANT,
    WIND_DIRECTION,
    WIND_DURATION,
    WIND_FREQUENCY,
    WIND_KIND,
    WIND_MAGNITUDE,
    WIND_PHASE,
    WIND_PULSE,
    WIND_SINE,
    WIND_START,
)
from ..model.kernels import sin_branchless

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")


@_jit_inline
def profile_value(kind, start, duration, magnitude, frequency, phase, t, side, any_sine):
    """The force magnitude [N] of one built-in wind profile (a program row's columns) at t,
    zero while the profile is off; side = +1 right limit, -1 left limit. Branch-free (selects
    and ``sin_branchless``), so the lane engine evaluates it for a block of runs in one
    vectorised pass; every loop uses it, so lanes and single runs agree bit for bit.
    ``any_sine`` False skips the sine where no profile evaluated together is one.

    Parameters
    ----------
    kind : float
        The profile's kind: ``layout.WIND_PULSE``, ``WIND_SINE``, ``WIND_STEP`` or
        ``WIND_CONSTANT``.
    start : float
        When the profile starts [s].
    duration : float
        A pulse's length [s].
    magnitude : float
        The force's magnitude (a sine's amplitude) [N].
    frequency : float
        A sine's frequency [Hz].
    phase : float
        A sine's phase [rad].
    t : float
        Time [s].
    side : float
        +1: the right limit at t, -1: the left limit (a profile's switching instants).
    any_sine : bool
        False: no profile evaluated together is a sine (the sine is skipped).

    Returns
    -------
    float
        The force magnitude [N] along the profile's direction (0 while off).
    """
    end = start + duration
    right = side > 0
    started = (start <= t) if right else (start < t)
    before_end = (t < end) if right else (t <= end)
    # pulse: [start, end); step and sine: from start (absolute time, Sec. VI); constant: always
    active = kind == WIND_CONSTANT or (started and (kind != WIND_PULSE or before_end))
    wave = sin_branchless(2.0 * math.pi * frequency * t + phase) if any_sine else 1.0
    value = magnitude * (wave if kind == WIND_SINE else 1.0)
    return value if active else 0.0


@_jit_inline
def _wind_program_force(program, t, side, out):
    """Add the built-in profiles' force at time t; side = +1 right limit, -1 left limit."""
    for r in range(program.shape[0]):
        row = program[r]
        value = profile_value(
            row[WIND_KIND], row[WIND_START], row[WIND_DURATION], row[WIND_MAGNITUDE],
            row[WIND_FREQUENCY], row[WIND_PHASE], t, side, row[WIND_KIND] == WIND_SINE,
        )  # fmt: skip
        out[0] += value * row[WIND_DIRECTION]
        out[1] += value * row[WIND_DIRECTION + 1]
        out[2] += value * row[WIND_DIRECTION + 2]


@_jit_inline
def gust_velocity(gust, gust_dt, t):
    """The gust table's air velocity at t [m/s], linear between its rows and held after the
    last one (``gust`` (m, 3) on a grid of step gust_dt [s]; zeros without a table).

    Parameters
    ----------
    gust : numpy.ndarray, shape (m, 3)
        The gust table's air velocity in N [m/s], one row per step.
    gust_dt : float
        The table's step [s] (0: no table).
    t : float
        Time [s].

    Returns
    -------
    g1, g2, g3 : float
        The air velocity in N [m/s].
    """
    if gust_dt <= 0.0 or gust.shape[0] == 0:
        return 0.0, 0.0, 0.0
    s = t / gust_dt
    i = int(s) if s > 0.0 else 0  # floor for s >= 0
    if s <= 0.0:
        w = 0.0
    elif i >= gust.shape[0] - 1:
        i, w = gust.shape[0] - 1, 0.0
    else:
        w = s - i
    if w == 0.0:
        return gust[i, 0], gust[i, 1], gust[i, 2]
    return (
        gust[i, 0] * (1.0 - w) + gust[i + 1, 0] * w,
        gust[i, 1] * (1.0 - w) + gust[i + 1, 1] * w,
        gust[i, 2] * (1.0 - w) + gust[i + 1, 2] * w,
    )


@_jit_inline
def wind_force(program, gust, gust_dt, drag, t, side, v1, v2, v3, out):
    """Wind force on HO in N [N]: the profiles plus the bluff-body drag of the air velocity
    relative to HO, F_i = 0.5 rho CdA_i |v_rel| v_rel,i with |v_rel| the norm of the whole
    relative velocity (drag[i] = 0.5 rho CdA_i; ``wind.drag.DragModel``).

    Parameters
    ----------
    program : numpy.ndarray, shape (k, WIND_COLUMNS)
        The force profiles' rows (``layout.WIND_*``).
    gust : numpy.ndarray, shape (m, 3)
        The gust table's air velocity in N [m/s] (zero rows: none).
    gust_dt : float
        The gust table's step [s] (0: no table).
    drag : numpy.ndarray, shape (3,)
        0.5 rho CdA per axis of N [kg/m] (``wind.compiled.CompiledWind.drag``).
    t : float
        Time [s].
    side : float
        +1: the right limit at t, -1: the left limit (a profile's switching instants).
    v1, v2, v3 : float
        HO's velocity in N [m/s] (the drag acts on the air's velocity relative to it).
    out : numpy.ndarray, shape (3,)
        Filled with the force on HO in N [N].
    """
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    _wind_program_force(program, t, side, out)
    if gust_dt > 0.0 and gust.shape[0] > 0:
        g1, g2, g3 = gust_velocity(gust, gust_dt, t)
        r1, r2, r3 = g1 - v1, g2 - v2, g3 - v3
        speed = math.sqrt(r1 * r1 + r2 * r2 + r3 * r3)
        out[0] += drag[0] * speed * r1
        out[1] += drag[1] * speed * r2
        out[2] += drag[2] * speed * r3


@_jit_inline
def air_relative_to_base(base, t, a1, a2, a3):
    """The air's velocity (a1, a2, a3) in N seen from the base's translating frame at t:
    a - b'(t) [m/s]; a still base leaves it alone. The one rule of the air over a moving
    base (``derive(moving_base=True)``: the coordinates and u1..u3 are relative to the base,
    so HO meets a - b'(t) - u): the helicopter's drag (``base_frame_force``,
    ``air_force_on_base``), the lumped chain's nodes (``engine.lumped_step``) and the start
    (``runs.setup.base_velocity``) take it, as the still air's a = 0 seen from the base,
    -b'(t), added to the air.

    Parameters
    ----------
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``layout.BASE_*``, ``base.compiled``).
    t : float
        Time [s].
    a1, a2, a3 : float
        The air's velocity in N [m/s].

    Returns
    -------
    r1, r2, r3 : float
        The air's velocity relative to the base, along n1, n2, n3 [m/s].
    """
    if base[0, BASE_MOVING] > 0.5:
        bv1, bv2, bv3, _, _, _ = base_rates(frozen(base), t)
        return a1 - bv1, a2 - bv2, a3 - bv3
    return a1, a2, a3


@_jit_inline
def base_frame_force(program, gust, gust_dt, drag, base, t, side, velocity, out):
    """``wind_force`` on a helicopter flown in the frame of a moving base (``base``'s packed
    form, ``base.compiled``): ``velocity`` is HO's relative to the base, so the drag sees the
    air relative to the base less it (``air_relative_to_base``), and the frame's inertial
    force -m b''(t) is added (``derive(moving_base=True)``). A still base (the paper's winch)
    is ``wind_force`` itself.

    Parameters
    ----------
    program : numpy.ndarray, shape (k, WIND_COLUMNS)
        The force profiles' rows (``layout.WIND_*``).
    gust : numpy.ndarray, shape (m, 3)
        The gust table's air velocity in N [m/s] (zero rows: none).
    gust_dt : float
        The gust table's step [s] (0: no table).
    drag : numpy.ndarray, shape (3,)
        0.5 rho CdA per axis of N [kg/m] (``wind.compiled.CompiledWind.drag``).
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``layout.BASE_*``, ``base.compiled``).
    t : float
        Time [s].
    side : float
        +1: the right limit at t, -1: the left limit (a profile's switching instants).
    velocity : tuple of float
        (v1, v2, v3): HO's velocity relative to the base in N [m/s].
    out : numpy.ndarray, shape (3,)
        Filled with the force on HO in N [N], the frame's inertial force included.
    """
    _base_frame(frozen(program), frozen(gust), gust_dt, frozen(drag), frozen(base), t,
                plain(side), velocity, out, plain(True))  # fmt: skip


@_jit_inline
def air_force_on_base(program, gust, gust_dt, drag, base, t, side, velocity, out):
    """The air's force alone (the recorded wind) on a helicopter moving at ``velocity``
    relative to the base: the profiles and the drag of the air relative to the base less it
    (``air_relative_to_base``).

    Parameters
    ----------
    program : numpy.ndarray, shape (k, WIND_COLUMNS)
        The force profiles' rows (``layout.WIND_*``).
    gust : numpy.ndarray, shape (m, 3)
        The gust table's air velocity in N [m/s] (zero rows: none).
    gust_dt : float
        The gust table's step [s] (0: no table).
    drag : numpy.ndarray, shape (3,)
        0.5 rho CdA per axis of N [kg/m] (``wind.compiled.CompiledWind.drag``).
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``layout.BASE_*``, ``base.compiled``).
    t : float
        Time [s].
    side : float
        +1: the right limit at t, -1: the left limit (a profile's switching instants).
    velocity : tuple of float
        (v1, v2, v3): HO's velocity relative to the base in N [m/s].
    out : numpy.ndarray, shape (3,)
        Filled with the air's force on HO in N [N].
    """
    _base_frame(frozen(program), frozen(gust), gust_dt, frozen(drag), frozen(base), t,
                plain(side), velocity, out, plain(False))  # fmt: skip


@_jit
def _base_frame(program, gust, gust_dt, drag, base, t, side, velocity, out, inertial):
    # One inlined ``wind_force`` for a still and a moving base: the base's rates come from a
    # call (``base_rates``), so a still base's run compiles neither a second copy of the wind
    # nor ``base_at`` inline (a shorter first compilation). The still air seen from the base,
    # w = -b'(t) (``air_relative_to_base``; 0 for a still base), joins the air: the drag of
    # g + w - v is ``wind_force``'s at HO's velocity v - w. Typed once for every caller,
    # inlined by LLVM (``inline_here``).
    inline_here()
    v1, v2, v3 = velocity
    w1, w2, w3 = air_relative_to_base(base, t, 0.0, 0.0, 0.0)
    wind_force(program, gust, gust_dt, drag, t, side, v1 - w1, v2 - w2, v3 - w3, out)
    if inertial and base[0, BASE_MOVING] > 0.5:
        _, _, _, a1, a2, a3 = base_rates(frozen(base), t)
        m = base[0, BASE_MASS]
        out[0] -= m * a1
        out[1] -= m * a2
        out[2] -= m * a3


@_jit
def base_rates(base, t):
    """b'(t) and b''(t) of the base in N [m/s, m/s^2], six floats (``base_at``'s last six):
    a call, compiled once for every loop.

    Parameters
    ----------
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``layout.BASE_*``, ``base.compiled``).
    t : float
        Time [s].

    Returns
    -------
    v1, v2, v3 : float
        The base's velocity b'(t) in N [m/s].
    a1, a2, a3 : float
        Its acceleration b''(t) in N [m/s^2].
    """
    _, _, _, v1, v2, v3, a1, a2, a3 = base_at(base, t)
    return v1, v2, v3, a1, a2, a3
