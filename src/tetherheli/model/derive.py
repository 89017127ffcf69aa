"""Equations of motion by Kane's method (``sympy.physics.mechanics``), paper Secs. II-III.

The mechanical description: the fuselage F and the stiff main rotor MR are rigid bodies; the
rotor spins at the constant rate omega_MR about f3 relative to F (eq 1). The points of eq 2 are
fixed in F. Loads (Sec. II-D): the rotor lift fMR,3 f3 at MRO; the rotor torques tMR,i f_i on
MR, with the drag torque tMR,3 = rotor_drag_arm fMR,3; the tail-rotor force fTR,2 f2 at TRO and
torque tTR,2 f2 on F; gravity at FO and MRO; the tether tension -TC c3 at P (eq 28); a wind
force at HO.

Generalized speeds are the same for both models (eqs 7-8): u1..u3 the velocity of HO in N,
u4..u6 the angular velocity of F in N, in F. The free helicopter positions HO with Cartesian
q1..q3 (eq 4); the tethered one with the spherical q7, q8, q9 (eq 27). The tethered kinematics
(eq 29) are written in the tether frame C (c1, c2, c3), where the velocity of P has the compact
components (-q9 c8 q7', q9 q8', q9'); this keeps M of eq 29 small.

The free helicopter is the tethered derivation's dynamics with no tether: both models share
every body, point and load here; only the position coordinates differ.

A moving winch: with ``moving_base=True`` the winch sits at B = NO + b(t), a
specified motion, and the coordinates and u1..u3 are taken relative to B (the base's
translating frame): HO's velocity in N is b' + u. Kane's method then finds b'' in the
forcing only as the inertial force -m b'' at HO (m = mF + mMR), which ``derive`` checks; the
numerical model therefore takes the base's acceleration through the wind input.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import sympy as sp
from sympy.physics.mechanics import (
    KanesMethod,
    Point,
    ReferenceFrame,
    RigidBody,
    dynamicsymbols,
    inertia,
)

from ..names import INPUT
from ..params import PARAM_ORDER

__all__ = ["Derivation", "Kinematics", "ModelKind", "derive", "kinematics", "parameter_symbols"]

ModelKind = Literal["free", "tethered"]

INPUT_NAMES = INPUT


def parameter_symbols() -> dict[str, sp.Symbol]:
    """SymPy symbols of the helicopter parameters, keyed by their ``HelicopterParams`` name.

    Returns
    -------
    dict of str to sympy.Symbol
        One real symbol per name of ``PARAM_ORDER``, in that order.
    """
    return {name: sp.Symbol(name, real=True) for name in PARAM_ORDER}


@dataclass(frozen=True)
class Derivation:
    """The derived model: x' = f(x, inputs, wind, TC) and the outputs y = h(x).

    Parameters
    ----------
    kind : {"free", "tethered"}
        Which model.
    q : tuple of sympy.Expr
        The coordinates (SymPy functions of time): q1..q6 (free; [m], [rad]) or q4..q9
        (tethered; [rad], q9 [m]).
    u : tuple of sympy.Expr
        The generalized speeds u1..u6 (functions of time): HO's velocity [m/s] (eq 7) and
        F's angular velocity in F [rad/s] (eq 8).
    qdot : sympy.Matrix, shape (6, 1)
        The kinematic differential equations, q' in terms of q and u (eqs 9-12, 29).
    udot : sympy.Matrix, shape (6, 1)
        The dynamic equations, u' (eqs 13-18, 30-35).
    mass_matrix : sympy.Matrix, shape (6, 6)
        Kane's M (diagonal, parameters only) with M u' = f.
    forcing : sympy.Matrix, shape (6, 1)
        Kane's f(q, u, inputs, wind, TC).
    outputs : sympy.Matrix, shape (4, 1)
        [q1, q2, q3, q6] of HO in N [m, m, m, rad] (eqs 4, 43-45); relative to the base B
        when the base moves.
    tether_torque : sympy.Matrix, shape (2, 1)
        The tether's generalized forces on u4, u5 [N m] (the C1, C2 of eq 55).
    inputs : tuple of sympy.Symbol
        The input symbols (fMR3, tMR1, tMR2, fTR2) [N, N m, N m, N].
    wind : tuple of sympy.Symbol
        The wind force on HO (w1, w2, w3) [N], N components.
    tension : sympy.Symbol
        The tension magnitude TC [N] (a symbol; eq 28's slack law is applied numerically).
    params : tuple of sympy.Symbol
        The parameter symbols in ``PARAM_ORDER``.
    dcm : sympy.Matrix, shape (3, 3)
        N.dcm(F), the direction cosine matrix of Table I.
    base_acceleration : tuple of sympy.Symbol, optional
        (a1, a2, a3), the symbols of b'' [m/s^2] in N standing in the forcing for the base's
        acceleration, or () (default) for the paper's fixed winch.
    """

    kind: ModelKind
    q: tuple[sp.Expr, ...]
    u: tuple[sp.Expr, ...]
    qdot: sp.Matrix
    udot: sp.Matrix
    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    outputs: sp.Matrix
    tether_torque: sp.Matrix
    inputs: tuple[sp.Symbol, ...]
    wind: tuple[sp.Symbol, ...]
    tension: sp.Symbol
    params: tuple[sp.Symbol, ...]
    dcm: sp.Matrix
    base_acceleration: tuple[sp.Symbol, ...] = ()

    def state_symbols(self) -> tuple[sp.Symbol, ...]:
        """Plain symbols standing for (q, u), in state order, for code generation.

        Returns
        -------
        tuple of sympy.Symbol
            One symbol per entry of q then u, named as the function (e.g. ``q4``, ``u1``).
        """
        return tuple(sp.Symbol(str(s.func)) for s in (*self.q, *self.u))

    def to_plain(self, expr: sp.Expr | sp.Matrix) -> sp.Expr | sp.Matrix:
        """Replace the time functions q(t), u(t) by plain symbols.

        Parameters
        ----------
        expr : sympy.Expr or sympy.Matrix
            An expression of the derivation (e.g. ``udot``).

        Returns
        -------
        sympy.Expr or sympy.Matrix
            ``expr`` with q(t), u(t) replaced by ``state_symbols()``.
        """
        return expr.subs(dict(zip((*self.q, *self.u), self.state_symbols(), strict=True)))


def derive(kind: ModelKind, moving_base: bool = False) -> Derivation:
    """Derive the free (eqs 9-18) or the tethered (eqs 10-12, 29-35) equations of motion.

    With ``moving_base`` the winch point moves as a specified b(t) in N and the coordinates,
    u1..u3 and the outputs are relative to it; the base's acceleration appears as the symbols
    ``Derivation.base_acceleration`` (raises if it enters other than as -m b'' at HO).

    Parameters
    ----------
    kind : {"free", "tethered"}
        Which model.
    moving_base : bool, optional
        Whether the winch moves as a specified b(t) (default False: the paper's still
        winch at the origin of N).

    Returns
    -------
    Derivation
        The equations of motion, outputs and symbols.

    Raises
    ------
    ValueError
        A ``kind`` other than "free" or "tethered".
    RuntimeError
        Kane's mass matrix is not diagonal, or the base's motion enters the forcing other
        than as -m b'' at HO.
    """
    if kind not in ("free", "tethered"):
        raise ValueError(f"kind = {kind!r} is invalid; allowed: 'free' or 'tethered'")
    p = parameter_symbols()
    g, m_F, m_MR = p["g"], p["m_F"], p["m_MR"]
    t = dynamicsymbols._t

    q4, q5, q6 = dynamicsymbols("q4 q5 q6")
    u1, u2, u3, u4, u5, u6 = dynamicsymbols("u1:7")
    f_MR3, t_MR1, t_MR2, f_TR2 = sp.symbols(INPUT_NAMES, real=True)
    wind = sp.symbols("w1 w2 w3", real=True)
    T_C = sp.Symbol("T_C", real=True)

    # Frames: N inertial; F by body-fixed 1-2-3 Euler angles (Table I); MR spins about f3.
    N = ReferenceFrame("N")
    F = _fuselage_frame(N, (q4, q5, q6))
    w_F_from_angles = F.ang_vel_in(N)
    F.set_ang_vel(N, u4 * F.x + u5 * F.y + u6 * F.z)  # eq 8
    MR = ReferenceFrame("MR")
    MR.orient_axis(F, F.z, p["omega_MR"] * t)

    # Points of eq 2 and the centre of mass HO of eq 3.
    d_O_HO3 = (m_F * p["d_O_FO3"] + m_MR * p["d_O_MRO3"]) / (m_F + m_MR)
    NO = Point("NO")
    NO.set_vel(N, 0)
    base = dynamicsymbols("b1 b2 b3") if moving_base else (0, 0, 0)
    base_rate = [sp.diff(bi, t) for bi in base]
    B = NO.locatenew("B", base[0] * N.x + base[1] * N.y + base[2] * N.z)  # the winch
    B.set_vel(N, base_rate[0] * N.x + base_rate[1] * N.y + base_rate[2] * N.z)
    kd_eqs = [
        u4 - w_F_from_angles.dot(F.x),
        u5 - w_F_from_angles.dot(F.y),
        u6 - w_F_from_angles.dot(F.z),
    ]  # eq 8
    if kind == "free":
        q1, q2, q3 = dynamicsymbols("q1 q2 q3")
        q = (q1, q2, q3, q4, q5, q6)
        HO = B.locatenew("HO", q1 * N.x + q2 * N.y + q3 * N.z)  # eq 4
        kd_eqs = [u1 - q1.diff(t), u2 - q2.diff(t), u3 - q3.diff(t), *kd_eqs]  # eq 7
    else:
        q7, q8, q9 = dynamicsymbols("q7 q8 q9")
        q = (q4, q5, q6, q7, q8, q9)
        C = _tether_frame(N, (q7, q8))
        P_from_ground, HO = _tethered_points(B, C, F, q9, p["d_O_P3"] - d_O_HO3)
        v_P_from_q = P_from_ground.pos_from(B).dt(N)
    # eq 7, relative to the base: HO's velocity in N is b' + u
    HO.set_vel(N, (base_rate[0] + u1) * N.x + (base_rate[1] + u2) * N.y + (base_rate[2] + u3) * N.z)
    point_O, FO, MRO, TRO, P = _body_points(HO, F, p)
    for point in (point_O, FO, MRO, TRO, P):
        point.v2pt_theory(HO, N, F)
    if kind == "tethered":
        # eq 29: the velocity of P from the spherical rates equals the one from u, in C.
        v_P_from_u = P.vel(N) - B.vel(N)
        kd_eqs += [(v_P_from_q - v_P_from_u).dot(c) for c in (C.x, C.y, C.z)]

    fuselage = RigidBody(
        "F", FO, F, m_F, (inertia(F, p["I_F11"], p["I_F22"], p["I_F33"]), FO)
    )  # eq 1
    # eq 1: the thin disc's dyadic IMR11 (mr1 mr1 + mr2 mr2) + 2 IMR11 mr3 mr3 is axisymmetric
    # about mr3 = f3, so it equals the same dyadic written in F (tests check the identity);
    # writing it in F keeps the spin angle omega_MR t out of the equations.
    rotor = RigidBody("MR", MRO, MR, m_MR, (rotor_inertia_dyadic(F, p["I_MR11"]), MRO))
    t_MR3 = p["rotor_drag_arm"] * f_MR3
    loads = [
        (MRO, f_MR3 * F.z),
        (MR, t_MR1 * F.x + t_MR2 * F.y + t_MR3 * F.z),
        (TRO, f_TR2 * F.y),
        (F, p["t_TR2"] * F.y),
        (FO, -m_F * g * N.z),
        (MRO, -m_MR * g * N.z),
        (HO, wind[0] * N.x + wind[1] * N.y + wind[2] * N.z),
    ]
    if kind == "tethered":
        loads.append((P, -T_C * C.z))  # eq 28

    speeds = (u1, u2, u3, u4, u5, u6)
    kane = KanesMethod(N, q_ind=list(q), u_ind=list(speeds), kd_eqs=kd_eqs)
    kane.kanes_equations([fuselage, rotor], loads)
    accel = sp.symbols("a1 a2 a3", real=True) if moving_base else ()
    kane_forcing = kane.forcing
    if moving_base:
        kane_forcing = kane_forcing.subs(
            {sp.diff(bi, t, 2): ai for bi, ai in zip(base, accel, strict=True)}
        )
        _check_base_enters_as_inertial_force(kane_forcing, accel, wind, m_F + m_MR, base)
    mass = kane.mass_matrix.applyfunc(sp.factor)  # constant: depends on parameters only
    if any(mass[i, j] != 0 for i in range(6) for j in range(6) if i != j):
        raise RuntimeError("Kane's mass matrix is not diagonal; the generalized speeds are off")
    # Each forcing row is linear in TC: expand the tension-free part (the centre-of-mass terms
    # cancel), keep the tether term factored as the paper prints it (eqs 30-35).
    kane_forcing = kane_forcing.subs(dict.fromkeys(accel, 0))
    forcing = sp.Matrix(
        [sp.expand(row.subs(T_C, 0)) + T_C * sp.factor_terms(row.diff(T_C)) for row in kane_forcing]
    )
    if moving_base:  # restore b'' as the inertial force it was checked to be
        forcing = forcing.subs(
            {w: w - (m_F + m_MR) * a for w, a in zip(wind, accel, strict=True)}, simultaneous=True
        )
    udot = sp.Matrix([forcing[i] / mass[i, i] for i in range(6)])
    kd_map = kane.kindiffdict()
    euler = (q4, q5, q6)
    qdot_list = [
        _pythagoras(kd_map[qi.diff(t)], euler) if qi in euler else kd_map[qi.diff(t)] for qi in q
    ]
    if kind == "tethered":
        # eq 29 in the tether frame: v_P = q9' c3 + q9 q8' c1 - q9 c8 q7' c2, so each rate is
        # one projection of v_P (from u) on C; algebraically the solution Kane's method found.
        qdot_list[3] = -v_P_from_u.dot(C.y) / (q9 * sp.cos(q8))
        qdot_list[4] = v_P_from_u.dot(C.x) / q9
        qdot_list[5] = v_P_from_u.dot(C.z)
    qdot = sp.Matrix(qdot_list)
    r_HO = HO.pos_from(B).to_matrix(N)
    outputs = sp.Matrix([sp.factor_terms(r_HO[i]) for i in range(3)] + [q6])
    tether_torque = sp.Matrix([T_C * forcing[3].diff(T_C), T_C * forcing[4].diff(T_C)])
    return Derivation(
        kind=kind,
        q=q,
        u=speeds,
        qdot=qdot,
        udot=udot,
        mass_matrix=mass,
        forcing=forcing,
        outputs=outputs,
        tether_torque=tether_torque,
        inputs=(f_MR3, t_MR1, t_MR2, f_TR2),
        wind=tuple(wind),
        tension=T_C,
        params=tuple(p[name] for name in PARAM_ORDER),
        dcm=N.dcm(F),
        base_acceleration=tuple(accel),
    )


def _check_base_enters_as_inertial_force(forcing, accel, wind, mass, base) -> None:
    """Raise unless b'' enters Kane's forcing exactly as a force -m b'' at HO would (the
    translating frame's inertial force): f(a, w) = f(0, w - m a), and b, b' do not enter."""
    t = dynamicsymbols._t
    still = forcing.subs(dict.fromkeys(accel, 0))
    as_force = still.subs(
        {w: w - mass * a for w, a in zip(wind, accel, strict=True)}, simultaneous=True
    )
    residual = (forcing - as_force).applyfunc(sp.expand)
    moving = {*base, *(sp.diff(bi, t) for bi in base)}
    spurious = any(row.has(*moving) for row in forcing)
    if spurious or any(r != 0 for r in residual):
        raise RuntimeError("the base's motion enters the forcing other than as -m b'' at HO")


def _fuselage_frame(N: ReferenceFrame, angles: tuple[sp.Expr, ...]) -> ReferenceFrame:
    """F by the body-fixed 1-2-3 Euler angles (q4, q5, q6) from N (Table I)."""
    F = ReferenceFrame("F")
    F.orient_body_fixed(N, angles, "123")
    return F


def _tether_frame(N: ReferenceFrame, angles: tuple[sp.Expr, sp.Expr]) -> ReferenceFrame:
    """C by q7 about n1, then q8 about the new 2-axis: c3 along the tether (eq 27)."""
    C = ReferenceFrame("C")
    C.orient_body_fixed(N, (*angles, 0), "123")
    return C


def _tethered_points(
    NO: Point, C: ReferenceFrame, F: ReferenceFrame, q9: sp.Expr, arm: sp.Expr
) -> tuple[Point, Point]:
    """P = q9 c3 from the winch NO (eq 27) and HO = P - arm f3 with arm = dO-P,3 - dO-HO,3
    (eqs 43-45)."""
    P = NO.locatenew("P", q9 * C.z)
    return P, P.locatenew("HO", -arm * F.z)


def _body_points(HO: Point, F: ReferenceFrame, p: dict[str, sp.Symbol]) -> tuple[Point, ...]:
    """The points of eq 2 located from HO: O, FO, MRO, TRO and the tether attachment P."""
    m_F, m_MR = p["m_F"], p["m_MR"]
    d_O_HO3 = (m_F * p["d_O_FO3"] + m_MR * p["d_O_MRO3"]) / (m_F + m_MR)  # eq 3
    # FO and MRO relative to HO: with d = dO-FO,3 - dO-MRO,3 they sit at +mMR d / m and
    # -mF d / m along f3 (eq 3), so mF p_HO->FO + mMR p_HO->MRO = 0 holds term by term.
    d_FO_MRO = p["d_O_FO3"] - p["d_O_MRO3"]
    point_O = HO.locatenew("O", -d_O_HO3 * F.z)
    FO = HO.locatenew("FO", m_MR * d_FO_MRO / (m_F + m_MR) * F.z)
    MRO = HO.locatenew("MRO", -m_F * d_FO_MRO / (m_F + m_MR) * F.z)
    TRO = point_O.locatenew("TRO", p["d_O_TRO1"] * F.x)
    P = point_O.locatenew("P_F", p["d_O_P3"] * F.z)
    return point_O, FO, MRO, TRO, P


@dataclass(frozen=True)
class Kinematics:
    """The derivation's geometry as functions of plain coordinate symbols (no time).

    Parameters
    ----------
    q : tuple of sympy.Symbol
        (q1, ..., q9), plain real symbols ([m] q1..q3, q9; [rad] q4..q8).
    dcm : sympy.Matrix, shape (3, 3)
        N.dcm(F) of (q4, q5, q6): column j holds f_j in N components (Table I).
    points : sympy.Matrix, shape (5, 3)
        HO, O, MRO, TRO, P from NO [m] in N components, for HO at (q1, q2, q3) (eqs 2-4),
        the helicopter parameters as symbols.
    tethered_HO : sympy.Matrix, shape (3, 1)
        HO from NO [m] by the tethered coordinates q4, q5, q7, q8, q9 and the lever ``arm``
        (eqs 27, 43-45).
    tether_length : sympy.Expr
        q9 [m] solved from eq 45, the altitude q3 of HO given (Sec. IV-F).
    tether_direction : sympy.Matrix, shape (3, 1)
        c3 of (q7, q8) in N components, the unit tether direction (eq 27).
    tether_angles : sympy.Matrix, shape (3, 1)
        Its inverse: (q7, q8, q9) of P = ``tether_point`` from the winch, P = q9 c3 (eqs 27,
        43-45), on the branch |q7|, |q8| < pi/2 of the tethered hover.
    tether_point : tuple of sympy.Symbol
        (P1, P2, P3): P from the winch NO in N components [m], the inverse's argument.
    P_motion : sympy.Matrix, shape (6, 1)
        P = q9 c3 from the winch [m] and its velocity in N [m/s], v_P = v_HO + w x (arm f3),
        of the tethered coordinates and the generalized speeds ``u`` (eqs 7-8, 27, 43-45).
    u : tuple of sympy.Symbol
        (u1, ..., u6): HO's velocity in N [m/s] and F's angular velocity in F [rad/s].
    arm : sympy.Symbol
        The lever dO-P,3 - dO-HO,3 [m].
    altitude : sympy.Symbol
        HO's altitude q3 [m].
    params : tuple of sympy.Symbol
        The parameter symbols in ``PARAM_ORDER``.
    """

    q: tuple[sp.Symbol, ...]
    dcm: sp.Matrix
    points: sp.Matrix
    tethered_HO: sp.Matrix
    tether_length: sp.Expr
    tether_direction: sp.Matrix
    tether_angles: sp.Matrix
    tether_point: tuple[sp.Symbol, ...]
    P_motion: sp.Matrix
    u: tuple[sp.Symbol, ...]
    arm: sp.Symbol
    altitude: sp.Symbol
    params: tuple[sp.Symbol, ...]


def kinematics() -> Kinematics:
    """Positions of the helicopter's points and the rotation N -> F (eqs 2-4, 27, 43-45,
    Table I), the tether direction c3, its inverse and P's motion, built with the frames and
    points of ``derive``.

    Returns
    -------
    Kinematics
        The geometry as expressions of plain symbols.
    """
    p = parameter_symbols()
    q = sp.symbols("q1:10", real=True)
    arm, altitude = sp.symbols("arm altitude", real=True)
    N = ReferenceFrame("N")
    F = _fuselage_frame(N, q[3:6])
    NO = Point("NO")
    HO = NO.locatenew("HO", q[0] * N.x + q[1] * N.y + q[2] * N.z)  # eq 4
    points = [HO, *(_body_points(HO, F, p)[i] for i in (0, 2, 3, 4))]  # HO, O, MRO, TRO, P
    C = _tether_frame(N, q[6:8])
    P_tethered, HO_tethered = _tethered_points(NO, C, F, q[8], arm)
    r_HO = HO_tethered.pos_from(NO).to_matrix(N)
    (length,) = sp.solve(sp.Eq(r_HO[2], altitude), q[8])
    # P's velocity from the generalized speeds (eqs 7-8): HO moves at u1..u3 in N and F turns
    # at u4..u6 in F, so P = HO + arm f3 moves at v_HO + w x (arm f3)
    u = sp.symbols("u1:7", real=True)
    HO_u = Point("HO_u")
    HO_u.set_vel(N, u[0] * N.x + u[1] * N.y + u[2] * N.z)
    F_u = _fuselage_frame(N, q[3:6])
    F_u.set_ang_vel(N, u[3] * F_u.x + u[4] * F_u.y + u[5] * F_u.z)
    P_u = HO_u.locatenew("P_u", arm * F_u.z)
    v_P = P_u.v2pt_theory(HO_u, N, F_u).to_matrix(N)
    # the inverse of P = q9 c3: q9 = |P|, then c3 = P / q9 = [s8, -s7 c8, c7 c8] (eq 27); in
    # floating point |P1| / |P| never exceeds 1 (sqrt(fl(x^2)) = |x| and rounding is
    # monotonic), so asin needs no clamp
    P = sp.symbols("P1:4", real=True)
    norm = sp.sqrt(P[0] ** 2 + P[1] ** 2 + P[2] ** 2)
    angles = sp.Matrix([sp.atan2(-P[1], P[2]), sp.asin(P[0] / norm), norm])
    return Kinematics(
        q=q,
        dcm=N.dcm(F),
        points=sp.Matrix([list(pt.pos_from(NO).to_matrix(N)) for pt in points]),
        tethered_HO=r_HO,
        tether_length=length,
        tether_direction=C.z.to_matrix(N),
        tether_angles=angles,
        tether_point=P,
        P_motion=sp.Matrix([*P_tethered.pos_from(NO).to_matrix(N), *v_P]),
        u=u,
        arm=arm,
        altitude=altitude,
        params=tuple(p[name] for name in PARAM_ORDER),
    )


def rotor_inertia_dyadic(frame: ReferenceFrame, I_MR11: sp.Expr):
    """Central inertia dyadic of the thin-disc rotor (eq 1), written in ``frame``.

    Parameters
    ----------
    frame : sympy.physics.mechanics.ReferenceFrame
        The frame the dyadic is written in (F or MR: the disc is axisymmetric about f3).
    I_MR11 : sympy.Expr
        The rotor's diametral moment of inertia IMR11 [kg m^2] (Table II).

    Returns
    -------
    sympy.physics.vector.Dyadic
        IMR11 (e1 e1 + e2 e2) + 2 IMR11 e3 e3 in ``frame``'s unit vectors.
    """
    return inertia(frame, I_MR11, I_MR11, 2 * I_MR11)


def _pythagoras(expr: sp.Expr, coordinates: tuple[sp.Expr, ...]) -> sp.Expr:
    """Cancel a kinematic expression and fold sin^2 + cos^2 = 1 (cheap, exact)."""
    expr = sp.cancel(expr)
    for qi in coordinates:
        expr = expr.subs(sp.sin(qi) ** 2, 1 - sp.cos(qi) ** 2)
    return sp.cancel(expr)
