"""Coupling: a general force at P in the tethered helicopter's equations. The
force the tether exerts on P enters the generated equations as a wind force at HO plus the
rotor torques of its moment about HO (``force_at_P_as_loads``; ``force_at_P_loads_sc``, the
one mapping, with the angles' sin and cos given, as the engine's lumped step calls it), with
eq 28's tension set to zero; q7..q9 then only locate P (``tethered_derivative_force_at_P``)."""

from __future__ import annotations

import numpy as np

from .._compile import compiled
from ..model import kernels

__all__ = ["force_at_P_as_loads", "force_at_P_loads_sc", "tethered_derivative_force_at_P"]

_jit = compiled(fastmath={"nnan", "ninf"}, error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")


@_jit
def force_at_P_as_loads(x, inp, wind, force_P, arm, inp_out, wind_out):
    """The inputs and wind force under which the generated tethered RHS at zero tension feels
    a force ``force_P`` [N, N components] at P.

    Kane's generalised speeds of the tethered model are those of the free one (eq 7: u1..u3
    the velocity of HO in N; eq 8: u4..u6 the body rates), so a force F at P = HO + arm f3
    has the partial velocities of a force at HO (generalised forces F . n1..n3, exactly where
    the wind force at HO enters) plus a torque arm f3 x F about HO, i.e.
    (-arm F.f2, arm F.f1, 0) in F, exactly where the rotor torques tMR1, tMR2 enter (the
    rotor's partial angular velocities for u4, u5 are f1, f2, as the fuselage's). Hence:
    wind_out = wind + F, inp_out = inp with tMR1 - arm F.f2 and tMR2 + arm F.f1; q7..q9 only
    locate P. (The radial force -TC c3 reproduces ``kernels.tethered_derivative``; a test
    checks it, and a non-radial one against the Newton-Euler route.)

    Parameters
    ----------
    x : ndarray, shape (13,)
        The tethered state (q4..q6 [rad] used).
    inp : ndarray, shape (4,)
        Rotor inputs fMR3 [N], tMR1, tMR2 [N m], fTR2 [N].
    wind : ndarray, shape (3,)
        Wind force on HO [N], along n1, n2, n3.
    force_P : ndarray, shape (3,)
        The force at P [N], along n1, n2, n3.
    arm : float
        ``HelicopterParams.tether_arm`` [m].
    inp_out : ndarray, shape (4,)
        Receives the equivalent inputs.
    wind_out : ndarray, shape (3,)
        Receives the equivalent wind force [N].

    Returns
    -------
    None
    """
    sc = np.empty(10)
    kernels.angle_trig(x, sc)
    force_at_P_loads_sc(sc, inp, wind, force_P, arm, inp_out, wind_out)


@_jit_inline
def force_at_P_loads_sc(sc, inp, wind, force_P, arm, inp_out, wind_out):
    """``force_at_P_as_loads`` with the sin, cos sc (10,) of the angles given (the engine's
    lumped stages have them): a force F [N, in N] at P = HO + arm f3 enters the generated
    equations as wind + F and the rotor torques tMR1 - arm F.f2, tMR2 + arm F.f1 (f1, f2 the
    columns of Table I's N_R_F).

    Parameters
    ----------
    sc : numpy.ndarray, shape (10,)
        sin, cos of the angles x[0..4] (q4..q8; ``kernels.angle_trig``).
    inp : numpy.ndarray, shape (4,)
        The rotor inputs [N, N m, N m, N].
    wind : numpy.ndarray, shape (3,)
        The wind force on HO in N [N].
    force_P : numpy.ndarray, shape (3,)
        The force on P in N [N].
    arm : float
        ``HelicopterParams.tether_arm`` [m].
    inp_out : numpy.ndarray, shape (4,)
        Receives the inputs with the force's torques [N, N m, N m, N].
    wind_out : numpy.ndarray, shape (3,)
        Receives wind + F [N].

    Returns
    -------
    None
    """
    s4, s5, s6 = sc[0], sc[1], sc[2]
    c4, c5, c6 = sc[5], sc[6], sc[7]
    f1 = (
        force_P[0] * (c5 * c6)
        + force_P[1] * (s5 * c6 * s4 + s6 * c4)
        + force_P[2] * (s6 * s4 - c6 * s5 * c4)
    )
    f2 = (
        force_P[0] * (-c5 * s6)
        + force_P[1] * (c6 * c4 - s5 * s6 * s4)
        + force_P[2] * (s5 * s6 * c4 + c6 * s4)
    )
    # the moment arm f3 x F about HO, F components (no f3 part: no tail lever is read)
    moment = np.empty(3)
    moment[0] = -arm * f2
    moment[1] = arm * f1
    moment[2] = 0.0
    kernels.wrench_loads_sc(sc, inp, wind, force_P, moment, _NO_TAIL, inp_out, wind_out)


#: ``wrench_loads_sc``'s tail lever, never read for a moment without an f3 part
_NO_TAIL = np.ones(2)


@_jit
def tethered_derivative_force_at_P(x, inp, wind, force_P, reel_rate, c, arm, out):
    """out (13,) = dx/dt of the tethered helicopter with the force ``force_P`` [N, in N] at P
    in place of eq 28's tension (``force_at_P_as_loads``); out[12] = reel_rate.

    Parameters
    ----------
    x : ndarray, shape (13,)
        The tethered state [q4..q9, u1..u6, LN].
    inp : ndarray, shape (4,)
        Rotor inputs fMR3 [N], tMR1, tMR2 [N m], fTR2 [N].
    wind : ndarray, shape (3,)
        Wind force on HO [N].
    force_P : ndarray, shape (3,)
        The force at P [N], along n1, n2, n3.
    reel_rate : float
        dLN/dt [m/s] (eq 37).
    c : ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    arm : float
        ``HelicopterParams.tether_arm`` [m].
    out : ndarray, shape (13,)
        Receives dx/dt.

    Returns
    -------
    None
    """
    inp2 = np.empty(4)
    wind2 = np.empty(3)
    force_at_P_as_loads(x, inp, wind, force_P, arm, inp2, wind2)
    kernels.tethered_rhs(x, inp2, wind2, 0.0, c, out)
    out[12] = reel_rate
