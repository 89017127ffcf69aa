"""Numba-compiled kernels built on the generated model code (no SymPy at run time).

Every kernel takes plain float64 arrays in the fixed order of ``codegen``: x the state,
inp the inputs [fMR3, tMR1, tMR2, fTR2], wind the force on HO in N, p the helicopter
parameters (``params.PARAM_ORDER``). The tethered state has a 13th entry, the winch's natural
length LN, driven by the reel rate (eq 37).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from . import _generated as gen

__all__ = [
    "free_derivative",
    "free_derivative_batch",
    "tension_from_state",
    "tethered_derivative",
    "tethered_derivative_batch",
]

_jit = njit(cache=True, fastmath=False, error_model="numpy")

free_rhs = _jit(gen.free_rhs)
free_jacobian = _jit(gen.free_jacobian)
free_outputs = _jit(gen.free_outputs)
free_output_jacobian = _jit(gen.free_output_jacobian)
tethered_rhs = _jit(gen.tethered_rhs)
tethered_jacobian = _jit(gen.tethered_jacobian)
tethered_outputs = _jit(gen.tethered_outputs)
tethered_output_jacobian = _jit(gen.tethered_output_jacobian)
tethered_tether_torque = _jit(gen.tethered_tether_torque)


@_jit
def tension_from_state(q9: float, L_N: float, K_C: float) -> float:
    """Eq 28: TC = KC (q9 - LN) when taut, 0 when slack [N]."""
    stretch = q9 - L_N
    return K_C * stretch if stretch > 0.0 else 0.0


@_jit
def tethered_derivative(x, inp, wind, reel_rate, p, K_C, out):
    """out (13,) = dx/dt of the tethered model: eqs 10-12, 29-35 and dLN/dt = RC (eq 37)."""
    tension = tension_from_state(x[5], x[12], K_C)
    tethered_rhs(x, inp, wind, tension, p, out)
    out[12] = reel_rate


@_jit
def free_derivative(x, inp, wind, p, out):
    """out (12,) = dx/dt of the free model: eqs 9-18."""
    free_rhs(x, inp, wind, 0.0, p, out)


@_jit
def tethered_derivative_batch(x, inp, wind, reel_rate, p, K_C, out):
    """Row-wise ``tethered_derivative`` over (n, 13) states."""
    for i in range(x.shape[0]):
        tethered_derivative(x[i], inp[i], wind[i], reel_rate[i], p, K_C, out[i])


@_jit
def free_derivative_batch(x, inp, wind, p, out):
    """Row-wise ``free_derivative`` over (n, 12) states."""
    for i in range(x.shape[0]):
        free_derivative(x[i], inp[i], wind[i], p, out[i])


def warm_up() -> None:
    """Compile (or load from Numba's on-disk cache) the scalar kernels."""
    p = np.ones(14)
    x = np.full(13, 0.1)
    x[5] = 10.0
    out = np.empty(13)
    tethered_derivative(x, np.zeros(4), np.zeros(3), 0.0, p, 40.0, out)
    free_derivative(x[:12], np.zeros(4), np.zeros(3), p, out[:12])
