"""Numba-compiled kernels built on the generated model code (no SymPy at run time).

Every kernel takes plain float64 arrays in the fixed order of ``codegen``: x the state,
inp the inputs [fMR3, tMR1, tMR2, fTR2], wind the force on HO in N, c the model's constants
(``model_constants``: the parameter-only subexpressions, computed once per parameter set).

Compiled with the ``nnan``/``ninf`` fast-math flags only: they allow no reassociation, so
finite results are bit-identical to strict IEEE evaluation of the generated code (a test
checks it); non-finite states are caught by the callers' checks. The tethered state has
a 13th entry, the winch's natural length LN, driven by the reel rate (eq 37).
"""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled
from ..params import HelicopterParams
from . import _generated as gen

__all__ = [
    "free_derivative",
    "free_derivative_batch",
    "kinematics_dcm",
    "kinematics_points",
    "kinematics_tether_length",
    "kinematics_tethered_HO",
    "model_constants",
    "tension_from_state",
    "tethered_derivative",
    "tethered_derivative_batch",
]

_jit = compiled(fastmath={"nnan", "ninf"}, error_model="numpy")
# Hot kernels are inlined at Numba-IR level into their callers: a call between separately
# compiled Numba functions costs ~30 ns here, a third of a derivative evaluation.
_jit_inline = compiled(fastmath={"nnan", "ninf"}, error_model="numpy", inline="always")

free_constants = _jit(gen.free_constants)
tethered_constants = _jit(gen.tethered_constants)
free_rhs = _jit_inline(gen.free_rhs)
free_jacobian = _jit(gen.free_jacobian)
free_outputs = _jit(gen.free_outputs)
free_output_jacobian = _jit(gen.free_output_jacobian)
tethered_rhs = _jit_inline(gen.tethered_rhs)
tethered_jacobian = _jit(gen.tethered_jacobian)
tethered_outputs = _jit(gen.tethered_outputs)
tethered_output_jacobian = _jit(gen.tethered_output_jacobian)
tethered_tether_torque = _jit(gen.tethered_tether_torque)
tethered_rhs_sc = _jit_inline(gen.tethered_rhs_sc)
tethered_outputs_sc = _jit_inline(gen.tethered_outputs_sc)
tethered_tether_torque_sc = _jit_inline(gen.tethered_tether_torque_sc)
# the geometry of eqs 2-4, 27, 43-45 and Table I (``model.kinematics`` for arrays)
kinematics_dcm = _jit(gen.kinematics_dcm)
kinematics_points = _jit(gen.kinematics_points)
kinematics_tethered_HO = _jit(gen.kinematics_tethered_HO)
kinematics_tether_length = _jit(gen.kinematics_tether_length)

#: Angle steps up to this size [rad] are applied by the angle-addition formulas with the
#: Taylor series of sin and cos (truncation below 1e-19 relative); larger ones call libm.
TRIG_STEP_MAX = 0.05
# Taylor coefficients of sin and cos (multiplications only: no division in the hot loop)
_S3, _S5, _S7, _S9 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0
_C2, _C4, _C6, _C8 = -0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0


@_jit_inline
def angle_trig(x, sc):
    """sc (10,) = [sin x[0..4], cos x[0..4]] of the angles q4..q8 (libm)."""
    for i in range(5):
        a = x[i]  # one load: sin and cos of it fuse into one sincos call
        s = math.sin(a)
        c = math.cos(a)
        sc[i] = s
        sc[5 + i] = c


@_jit_inline
def angle_trig_from(x, x_base, sc_base, sc):
    """``angle_trig(x, sc)`` from the values sc_base at a nearby x_base, without libm:
    sin(a + d) = sin a cos d + cos a sin d with d = x - x_base and the Taylor series of
    sin d, cos d (to d^9, d^10). Agrees with libm to a few units in the last place; steps
    larger than TRIG_STEP_MAX fall back to libm. The RK4 stages use it: sin and cos are
    half of a derivative's cost."""
    for i in range(5):
        d = x[i] - x_base[i]
        if abs(d) > TRIG_STEP_MAX:
            a = x[i]
            s = math.sin(a)
            c = math.cos(a)
            sc[i] = s
            sc[5 + i] = c
            continue
        d2 = d * d
        sin_d = d + d * d2 * (_S3 + d2 * (_S5 + d2 * (_S7 + d2 * _S9)))
        cos_d = 1.0 + d2 * (_C2 + d2 * (_C4 + d2 * (_C6 + d2 * _C8)))
        s, c = sc_base[i], sc_base[5 + i]
        sc[i] = s * cos_d + c * sin_d
        sc[5 + i] = c * cos_d - s * sin_d


def model_constants(kind: str, helicopter: HelicopterParams) -> np.ndarray:
    """The constants vector c of the "free" or "tethered" generated functions (read-only)."""
    if kind == "tethered":
        c = np.empty(gen.N_TETHERED_CONSTANTS)
        tethered_constants(helicopter.as_array(), c)
    elif kind == "free":
        c = np.empty(gen.N_FREE_CONSTANTS)
        free_constants(helicopter.as_array(), c)
    else:
        raise ValueError(f"kind = {kind!r} is invalid; allowed: 'free' or 'tethered'")
    c.setflags(write=False)
    return c


@_jit_inline
def tension_from_state(q9: float, L_N: float, K_C: float) -> float:
    """Eq 28: TC = KC (q9 - LN) when taut, 0 when slack [N]."""
    stretch = q9 - L_N
    return K_C * stretch if stretch > 0.0 else 0.0


@_jit
def tethered_derivative(x, inp, wind, reel_rate, c, K_C, out):
    """out (13,) = dx/dt of the tethered model: eqs 10-12, 29-35 and dLN/dt = RC (eq 37)."""
    tension = tension_from_state(x[5], x[12], K_C)
    tethered_rhs(x, inp, wind, tension, c, out)
    out[12] = reel_rate


@_jit
def free_derivative(x, inp, wind, c, out):
    """out (12,) = dx/dt of the free model: eqs 9-18."""
    free_rhs(x, inp, wind, 0.0, c, out)


@_jit
def tethered_derivative_batch(x, inp, wind, reel_rate, c, K_C, out):
    """Row-wise ``tethered_derivative`` over (n, 13) states."""
    for i in range(x.shape[0]):
        tethered_derivative(x[i], inp[i], wind[i], reel_rate[i], c, K_C, out[i])


@_jit
def free_derivative_batch(x, inp, wind, c, out):
    """Row-wise ``free_derivative`` over (n, 12) states."""
    for i in range(x.shape[0]):
        free_derivative(x[i], inp[i], wind[i], c, out[i])


def warm_up() -> None:
    """Compile (or load from Numba's on-disk cache) the scalar kernels."""
    h = HelicopterParams(**dict.fromkeys(HelicopterParams.__dataclass_fields__, 1.0))
    x = np.full(13, 0.1)
    x[5] = 10.0
    out = np.empty(13)
    c = model_constants("tethered", h)
    tethered_derivative(x, np.zeros(4), np.zeros(3), 0.0, c, 40.0, out)
    free_derivative(x[:12], np.zeros(4), np.zeros(3), model_constants("free", h), out[:12])
