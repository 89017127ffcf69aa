"""Numba-compiled kernels built on the generated model code (no SymPy at run time).

Every kernel takes plain float64 arrays in the fixed order of ``codegen``: x the state,
inp the inputs [fMR3, tMR1, tMR2, fTR2], wind the force on HO in N, c the model's constants
(``model_constants``, from ``constants``: the parameter-only subexpressions, computed once per
parameter set, as plain Python).

Compiled with the ``nnan``/``ninf`` fast-math flags only: they allow no reassociation, so
finite results are bit-identical to strict IEEE evaluation of the generated code (a test
checks it); non-finite states are caught by the callers' checks. The tethered state has
a 13th entry, the winch's natural length LN, driven by the reel rate (eq 37).
"""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled
from ..layout import LANES
from ..params import HelicopterParams
from . import _generated as gen
from .constants import model_constants

__all__ = [
    "free_derivative",
    "free_derivative_batch",
    "kinematics_P_motion_sc",
    "kinematics_dcm",
    "kinematics_points",
    "kinematics_tether_angles",
    "kinematics_tether_direction",
    "kinematics_tether_length",
    "kinematics_tethered_HO",
    "model_constants",
    "tension_from_state",
    "tether_tension",
    "tethered_derivative",
    "tethered_derivative_batch",
    "wrench_loads_sc",
]

_jit = compiled(fastmath={"nnan", "ninf"}, error_model="numpy")
# Hot kernels are inlined at Numba-IR level into their callers: a call between separately
# compiled Numba functions costs ~30 ns here, a third of a derivative evaluation.
_jit_inline = compiled(fastmath={"nnan", "ninf"}, error_model="numpy", inline="always")

free_rhs = _jit_inline(gen.free_rhs)
free_outputs = _jit(gen.free_outputs)
tethered_rhs = _jit_inline(gen.tethered_rhs)
tethered_outputs = _jit(gen.tethered_outputs)
tethered_tether_torque = _jit(gen.tethered_tether_torque)
tethered_rhs_sc = _jit_inline(gen.tethered_rhs_sc)
tethered_outputs_sc = _jit_inline(gen.tethered_outputs_sc)
tethered_tether_torque_sc = _jit_inline(gen.tethered_tether_torque_sc)
tethered_rhs_lanes = _jit_inline(gen.tethered_rhs_lanes)
tethered_outputs_lanes = _jit_inline(gen.tethered_outputs_lanes)
tethered_tether_torque_lanes = _jit_inline(gen.tethered_tether_torque_lanes)
# the geometry of eqs 2-4, 27, 43-45 and Table I (``model.kinematics`` for arrays)
kinematics_dcm = _jit(gen.kinematics_dcm)
kinematics_points = _jit(gen.kinematics_points)
kinematics_tethered_HO = _jit(gen.kinematics_tethered_HO)
kinematics_tether_length = _jit(gen.kinematics_tether_length)
kinematics_tether_direction = _jit(gen.kinematics_tether_direction)
kinematics_tether_angles = _jit(gen.kinematics_tether_angles)
kinematics_P_motion_sc = _jit_inline(gen.kinematics_P_motion_sc)  # the lumped chain's stages

#: Angle steps up to this size [rad] are applied by the angle-addition formulas with the
#: Taylor series of sin and cos (truncation below 1e-19 relative); larger ones call libm.
TRIG_STEP_MAX = 0.05
# Taylor coefficients of sin and cos (multiplications only: no division in the hot loop)
_S3, _S5, _S7, _S9 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0
_C2, _C4, _C6, _C8 = -0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0


@_jit_inline
def angle_trig(x, sc):
    """sc (10,) = [sin x[0..4], cos x[0..4]] of the angles q4..q8 (libm).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The tethered state; x[0:5] the angles q4..q8 [rad].
    sc : numpy.ndarray, shape (10,)
        Written: sin of q4..q8, then cos of q4..q8 [-].
    """
    for i in range(5):
        a = x[i]  # one load: sin and cos of it fuse into one sincos call
        s = math.sin(a)
        c = math.cos(a)
        sc[i] = s
        sc[5 + i] = c


@_jit_inline
def wrench_loads_sc(sc, inp, wind, force_N, moment_F, tail, inp_out, wind_out):
    """The rotor inputs and wind force under which the generated equations (free or tethered)
    feel an added force ``force_N`` at HO and moment ``moment_F`` about HO: the one mapping of
    a load into the model's inputs (the tether's force at P, the landing gear's contact).

    Sec. II-D's loads are linear in the inputs and the generalised speeds are HO's velocity
    and F's body rates (eqs 7-8), so a wrench has exact equivalent loads: a force at HO enters
    where the wind force does; a moment about f1, f2 where the rotor torques tMR1, tMR2 do
    (the rotor's partial angular velocities are F's). The model has no free torque about f3:
    a moment M3 is carried by an increment d = M3 / a of the tail-rotor force fTR2 at TRO =
    HO + (a, 0, h) in F, whose own force d f2 is taken back out of the wind force and whose
    moment -h d about f1 out of tMR1. Tests check it against the Newton-Euler route.

    Parameters
    ----------
    sc : numpy.ndarray, shape (10,)
        sin, cos of the angles q4..q8 (``angle_trig``).
    inp : numpy.ndarray, shape (4,)
        The rotor inputs fMR3 [N], tMR1, tMR2 [N m], fTR2 [N].
    wind : numpy.ndarray, shape (3,)
        The wind force on HO [N], N components.
    force_N : numpy.ndarray, shape (3,)
        The added force at HO [N], N components.
    moment_F : numpy.ndarray, shape (3,)
        The added moment about HO [N m], F components.
    tail : numpy.ndarray, shape (2,)
        TRO from HO in F, its f1 and f3 offsets (a, h) [m] (``model.contact.tail_lever``);
        read only when ``moment_F[2]`` is not zero.
    inp_out : numpy.ndarray, shape (4,)
        Receives the equivalent inputs.
    wind_out : numpy.ndarray, shape (3,)
        Receives the equivalent wind force [N].
    """
    inp_out[0] = inp[0]
    inp_out[1] = inp[1] + moment_F[0]
    inp_out[2] = inp[2] + moment_F[1]
    inp_out[3] = inp[3]
    for j in range(3):
        wind_out[j] = wind[j] + force_N[j]
    if moment_F[2] != 0.0:
        s4, s5, s6 = sc[0], sc[1], sc[2]
        c4, c5, c6 = sc[5], sc[6], sc[7]
        d = moment_F[2] / tail[0]
        inp_out[1] += tail[1] * d
        inp_out[3] += d
        wind_out[0] -= d * (-c5 * s6)  # f2 in N (Table I's second column)
        wind_out[1] -= d * (c6 * c4 - s5 * s6 * s4)
        wind_out[2] -= d * (s5 * s6 * c4 + c6 * s4)


@_jit_inline
def angle_trig_lanes(x, sc):
    """``angle_trig`` for every lane of flat (variable, lane) arrays (``layout.LANES``): x
    (13 LANES,), sc (10 LANES,). libm's sine and cosine lane by lane, in a loop of their own
    (libm has no vector form equal to its scalar one; the lane engine's other loops
    vectorise), so every lane equals ``angle_trig`` bit for bit.

    Parameters
    ----------
    x : numpy.ndarray, shape (13 LANES,)
        The lanes' tethered states, entry i of lane j at ``i * LANES + j``; entries 0..4
        the angles q4..q8 [rad].
    sc : numpy.ndarray, shape (10 LANES,)
        Written: sin of q4..q8, then cos of q4..q8 [-], in the same (variable, lane) layout.
    """
    for i in range(5):
        for j in range(LANES):
            a = x[i * LANES + j]
            s = math.sin(a)
            c = math.cos(a)
            sc[i * LANES + j] = s
            sc[(5 + i) * LANES + j] = c


@_jit_inline
def rotate_trig(s, c, d):
    """(sin(a + d), cos(a + d)) from s = sin a, c = cos a by the angle-addition formulas with
    the Taylor series of sin d, cos d (to d^9, d^10; exact to 1e-19 relative for
    |d| <= TRIG_STEP_MAX). No branch, no call: it vectorises over lanes.

    Parameters
    ----------
    s : float
        sin a [-].
    c : float
        cos a [-].
    d : float
        The angle step [rad], |d| <= ``TRIG_STEP_MAX``.

    Returns
    -------
    tuple of 2 float
        sin(a + d), cos(a + d) [-].
    """
    d2 = d * d
    sin_d = d + d * d2 * (_S3 + d2 * (_S5 + d2 * (_S7 + d2 * _S9)))
    cos_d = 1.0 + d2 * (_C2 + d2 * (_C4 + d2 * (_C6 + d2 * _C8)))
    return s * cos_d + c * sin_d, c * cos_d - s * sin_d


# sin and cos on [-pi/4, pi/4]: the minimax polynomials of fdlibm's __kernel_sin and
# __kernel_cos (Sun Microsystems, 1993), and pi/2 in three parts for Cody-Waite reduction
_K_S1 = -1.66666666666666324348e-01
_K_S2 = 8.33333333332248946124e-03
_K_S3 = -1.98412698298579493134e-04
_K_S4 = 2.75573137070700676789e-06
_K_S5 = -2.50507602534068634195e-08
_K_S6 = 1.58969099521155010221e-10
_K_C1 = 4.16666666666666019037e-02
_K_C2 = -1.38888888888741095749e-03
_K_C3 = 2.48015872894767294178e-05
_K_C4 = -2.75573143513906633035e-07
_K_C5 = 2.08757232129817482790e-09
_K_C6 = -1.13596475577881948265e-11
_PIO2_1 = 1.57079632673412561417e00  # the first 33 bits of pi/2
_PIO2_2 = 6.07710050630396597660e-11  # the next 33 bits
_PIO2_3 = 2.02226624879595063154e-21  # pi/2 - _PIO2_1 - _PIO2_2
_TWO_OVER_PI = 0.63661977236758134308
#: |x| up to which ``sin_branchless`` is within a few ulp of libm (Cody-Waite reduction)
SIN_BRANCHLESS_MAX_ARG = 1.0e5


@_jit_inline
def sin_branchless(x):
    """sin x with no branch and no call (Cody-Waite reduction by pi/2, then fdlibm's kernel
    polynomials), so a loop over lanes that uses it vectorises. Agrees with libm to a few
    units in the last place for |x| <= SIN_BRANCHLESS_MAX_ARG (a test checks it). The
    quadrant is rounded as a float (``np.floor``; ``math.floor`` returns an integer, and
    without AVX-512 a vector of doubles has no conversion to 64-bit integers and back: each
    lane was converted alone); its values are the same.

    Parameters
    ----------
    x : float
        The angle [rad], |x| <= ``SIN_BRANCHLESS_MAX_ARG``.

    Returns
    -------
    float
        sin x [-].
    """
    k = np.floor(x * _TWO_OVER_PI + 0.5)
    r = ((x - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3
    z = r * r
    sin_r = r + r * z * (_K_S1 + z * (_K_S2 + z * (_K_S3 + z * (_K_S4 + z * (_K_S5 + z * _K_S6)))))
    cos_r = (
        1.0
        - 0.5 * z
        + z * z * (_K_C1 + z * (_K_C2 + z * (_K_C3 + z * (_K_C4 + z * (_K_C5 + z * _K_C6)))))
    )
    quadrant = k - 4.0 * np.floor(0.25 * k)  # k mod 4, in {0, 1, 2, 3}
    value = cos_r if (quadrant == 1.0 or quadrant == 3.0) else sin_r
    return -value if quadrant >= 2.0 else value


@_jit_inline
def angle_trig_from(x, x_base, sc_base, sc):
    """``angle_trig(x, sc)`` from the values sc_base at a nearby x_base, without libm
    (``rotate_trig`` with d = x - x_base). Agrees with libm to a few units in the last place;
    steps larger than TRIG_STEP_MAX fall back to libm. The RK4 stages use it: sin and cos
    are half of a derivative's cost.

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The tethered state; x[0:5] the angles q4..q8 [rad].
    x_base : numpy.ndarray, shape (13,)
        A nearby state whose sines and cosines are ``sc_base`` [rad].
    sc_base : numpy.ndarray, shape (10,)
        ``angle_trig`` of ``x_base`` [-].
    sc : numpy.ndarray, shape (10,)
        Written: sin of q4..q8, then cos of q4..q8 [-].
    """
    for i in range(5):
        d = x[i] - x_base[i]
        if abs(d) > TRIG_STEP_MAX:
            a = x[i]
            s = math.sin(a)
            c = math.cos(a)
            sc[i] = s
            sc[5 + i] = c
            continue
        sc[i], sc[5 + i] = rotate_trig(sc_base[i], sc_base[5 + i], d)


@_jit_inline
def angle_trig_from_lanes(x, x_base, sc_base, sc):
    """``angle_trig_from`` for every lane of flat (variable, lane) arrays (``layout.LANES``):
    x, x_base (13 LANES,), sc_base, sc (10 LANES,). One branch-free pass over the lanes
    (vectorised), then libm for the entries whose step exceeds TRIG_STEP_MAX, so every lane
    equals ``angle_trig_from`` bit for bit.

    Parameters
    ----------
    x : numpy.ndarray, shape (13 LANES,)
        The lanes' tethered states, entry i of lane j at ``i * LANES + j``; entries 0..4
        the angles q4..q8 [rad].
    x_base : numpy.ndarray, shape (13 LANES,)
        Nearby states whose sines and cosines are ``sc_base`` [rad], the same layout.
    sc_base : numpy.ndarray, shape (10 LANES,)
        ``angle_trig_lanes`` of ``x_base`` [-].
    sc : numpy.ndarray, shape (10 LANES,)
        Written: sin of q4..q8, then cos of q4..q8 [-], in the (variable, lane) layout.
    """
    big = False
    n_lanes = x.shape[0] // 13  # LANES, at run time: the loop vectorises, not unrolls
    for i in range(5):
        for j in range(n_lanes):
            d = x[i * LANES + j] - x_base[i * LANES + j]
            s, c = rotate_trig(sc_base[i * LANES + j], sc_base[(5 + i) * LANES + j], d)
            sc[i * LANES + j] = s
            sc[(5 + i) * LANES + j] = c
            big |= abs(d) > TRIG_STEP_MAX
    if big:
        for i in range(5):
            for j in range(LANES):
                a = x[i * LANES + j]
                if abs(a - x_base[i * LANES + j]) > TRIG_STEP_MAX:
                    s = math.sin(a)
                    c = math.cos(a)
                    sc[i * LANES + j] = s
                    sc[(5 + i) * LANES + j] = c


@_jit_inline
def tension_from_state(q9: float, L_N: float, K_C: float) -> float:
    """Eq 28: TC = KC (q9 - LN) when taut, 0 when slack [N].

    Parameters
    ----------
    q9 : float
        The tether's length, winch to P [m].
    L_N : float
        Its natural length LN [m].
    K_C : float
        Its stiffness KC [N/m].

    Returns
    -------
    float
        The tension TC [N], >= 0.
    """
    stretch = q9 - L_N
    return K_C * stretch if stretch > 0.0 else 0.0


@_jit_inline
def tether_tension(q9: float, L_N: float, K_C: float, EA: float) -> float:
    """The massless tether's tension [N] by its law (``params.TetherParams.tension``, the
    Python twin): eq 28's KC (q9 - LN) when EA = 0, the rope's EA (q9 - LN) / LN when EA > 0;
    0 when slack (q9 <= LN).

    Parameters
    ----------
    q9 : float
        The tether's length, winch to P [m].
    L_N : float
        Its natural length LN [m].
    K_C : float
        Eq 28's stiffness KC [N/m] (the paper's law).
    EA : float
        The rope's axial stiffness EA [N]; 0: the paper's law.

    Returns
    -------
    float
        The tension TC [N], >= 0.
    """
    stretch = q9 - L_N
    if stretch <= 0.0:
        return 0.0
    stiffness = EA / L_N if EA > 0.0 else K_C
    return stiffness * stretch


@_jit
def tethered_derivative(x, inp, wind, reel_rate, c, K_C, EA, out):
    """out (13,) = dx/dt of the tethered model: eqs 10-12, 29-35 and dLN/dt = RC (eq 37).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The tethered state q4..q9, u1..u6, LN ([rad], q9 [m], [m/s], [rad/s], LN [m]).
    inp : numpy.ndarray, shape (4,)
        The inputs fMR3, tMR1, tMR2, fTR2 [N, N m, N m, N] (``names.INPUT``).
    wind : numpy.ndarray, shape (3,)
        The force on HO [N], N components (wind, and -m b'' of a moving base).
    reel_rate : float
        The reel rate RC = dLN/dt [m/s].
    c : numpy.ndarray, shape (N_TETHERED_CONSTANTS,)
        The model's constants (``model_constants("tethered", ...)``).
    K_C : float
        The tether's stiffness KC [N/m] (eq 28, the paper's law).
    EA : float
        The rope's axial stiffness EA [N]; 0: the paper's law (``tether_tension``).
    out : numpy.ndarray, shape (13,)
        Written: dx/dt ([rad/s], [m/s], [m/s^2], [rad/s^2], [m/s]).
    """
    tension = tether_tension(x[5], x[12], K_C, EA)
    tethered_rhs(x, inp, wind, tension, c, out)
    out[12] = reel_rate


@_jit
def free_derivative(x, inp, wind, c, out):
    """out (12,) = dx/dt of the free model: eqs 9-18.

    Parameters
    ----------
    x : numpy.ndarray, shape (12,)
        The free state q1..q6, u1..u6 ([m], [rad], [m/s], [rad/s]).
    inp : numpy.ndarray, shape (4,)
        The inputs fMR3, tMR1, tMR2, fTR2 [N, N m, N m, N] (``names.INPUT``).
    wind : numpy.ndarray, shape (3,)
        The force on HO [N], N components (wind, and -m b'' of a moving base).
    c : numpy.ndarray, shape (N_FREE_CONSTANTS,)
        The model's constants (``model_constants("free", ...)``).
    out : numpy.ndarray, shape (12,)
        Written: dx/dt ([m/s], [rad/s], [m/s^2], [rad/s^2]).
    """
    free_rhs(x, inp, wind, 0.0, c, out)


@_jit
def tethered_derivative_batch(x, inp, wind, reel_rate, c, K_C, EA, out):
    """Row-wise ``tethered_derivative`` over (n, 13) states.

    Parameters
    ----------
    x : numpy.ndarray, shape (n, 13)
        The tethered states, one per row (as ``tethered_derivative``'s x).
    inp : numpy.ndarray, shape (n, 4)
        The inputs fMR3, tMR1, tMR2, fTR2 [N, N m, N m, N], one row per state.
    wind : numpy.ndarray, shape (n, 3)
        The force on HO [N], N components, one row per state.
    reel_rate : numpy.ndarray, shape (n,)
        The reel rate RC [m/s] of each state.
    c : numpy.ndarray, shape (N_TETHERED_CONSTANTS,)
        The model's constants (``model_constants("tethered", ...)``).
    K_C : float
        The tether's stiffness KC [N/m] (eq 28, the paper's law).
    EA : float
        The rope's axial stiffness EA [N]; 0: the paper's law.
    out : numpy.ndarray, shape (n, 13)
        Written: dx/dt of each row.
    """
    for i in range(x.shape[0]):
        tethered_derivative(x[i], inp[i], wind[i], reel_rate[i], c, K_C, EA, out[i])


@_jit
def free_derivative_batch(x, inp, wind, c, out):
    """Row-wise ``free_derivative`` over (n, 12) states.

    Parameters
    ----------
    x : numpy.ndarray, shape (n, 12)
        The free states, one per row (as ``free_derivative``'s x).
    inp : numpy.ndarray, shape (n, 4)
        The inputs fMR3, tMR1, tMR2, fTR2 [N, N m, N m, N], one row per state.
    wind : numpy.ndarray, shape (n, 3)
        The force on HO [N], N components, one row per state.
    c : numpy.ndarray, shape (N_FREE_CONSTANTS,)
        The model's constants (``model_constants("free", ...)``).
    out : numpy.ndarray, shape (n, 12)
        Written: dx/dt of each row.
    """
    for i in range(x.shape[0]):
        free_derivative(x[i], inp[i], wind[i], c, out[i])


def warm_up() -> None:
    """Compile (or load from Numba's on-disk cache) the scalar kernels."""
    h = HelicopterParams(**dict.fromkeys(HelicopterParams.__dataclass_fields__, 1.0))
    x = np.full(13, 0.1)
    x[5] = 10.0
    out = np.empty(13)
    c = model_constants("tethered", h)
    tethered_derivative(x, np.zeros(4), np.zeros(3), 0.0, c, 40.0, 0.0, out)
    free_derivative(x[:12], np.zeros(4), np.zeros(3), model_constants("free", h), out[:12])
