"""The multirotor's rigid-body equations by Kane's method, and their generated code.

A rigid body B (centre of mass O, mass m, inertia J about O in body axes) moves in the
inertial frame N (n3 up, gravity -g n3: the paper's N, docs/notation.md, and RotorPy's world
frame). Generalised coordinates: the position of O in N (x1, x2, x3) and the attitude
quaternion (qx, qy, qz, qw) of B in N (RotorPy's order, scalar last). Generalised speeds: the
velocity of O in N components (v1, v2, v3) and the body rates in B components (w1, w2, w3).
The quaternion's kinematic differential equations are RotorPy's (``quat_dot``, after B. Graf,
"Quaternions and dynamics", 2008): dq/dt = G(q)^T w / 2, with no normalisation term.

Loads: the rotors' and the air's resultant force fb (B components) at O and moment mb (B
components) about O, computed per rotor outside the derivation (``multirotor_kernels``:
the number of rotors is a parameter); gravity -m g n3 at O; and the tether's pull ft
(N components) at the attachment point P = O + P1 b1 + P2 b2 + P3 b3. Kane's equations give
M(q) du/dt = F(q, u, fb, mb, ft) with M = diag(m, m, m, J) (checked by ``derive``).

``generate_source`` writes ``_multirotor_generated.py`` with ``codegen``'s printer (CSE,
integer powers as products, ``math`` only); ``write_generated`` commits it. A test checks
the committed file against a fresh derivation.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import sympy as sp
import sympy.physics.mechanics as me

from .. import layout as L
from .._io import atomic_write_text
from .codegen import _emit, _Printer

__all__ = ["MR_GENERATED_PATH", "MultirotorDerivation", "derive", "generate_source"]

MR_GENERATED_PATH = Path(__file__).with_name("_multirotor_generated.py")


class MultirotorDerivation(NamedTuple):
    """The symbolic multirotor (``derive``).

    Parameters
    ----------
    q : tuple of sympy.Function
        x1, x2, x3 [m], qx, qy, qz, qw [-].
    u : tuple of sympy.Function
        v1, v2, v3 [m/s] (N components), w1, w2, w3 [rad/s] (B components).
    qdot : sympy.Matrix
        (7,) dq/dt from the kinematic differential equations.
    mass_matrix, forcing : sympy.Matrix
        (6, 6) and (6,): Kane's M du/dt = F.
    dcm : sympy.Matrix
        (3, 3) N.dcm(B): column j holds b_j in N components.
    params : dict
        The parameter symbols by name (m, g, Ixx, Iyy, Izz, Ixy, Iyz, Ixz, P1, P2, P3).
    wrench : tuple of sympy.Symbol
        fb1..fb3 [N], mb1..mb3 [N m]: the rotors' and air's resultant in B components.
    tether : tuple of sympy.Symbol
        ft1..ft3 [N]: the tether's pull at P in N components.
    """

    q: tuple
    u: tuple
    qdot: sp.Matrix
    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    dcm: sp.Matrix
    params: dict
    wrench: tuple
    tether: tuple


def derive() -> MultirotorDerivation:
    """Kane's equations of the multirotor's rigid body with a force at P.

    Returns
    -------
    MultirotorDerivation
        The coordinates, speeds, kinematic equations, M, F and the DCM (module docstring).
    """
    t = me.dynamicsymbols._t
    x = me.dynamicsymbols("x1:4")
    quat = me.dynamicsymbols("qx qy qz qw")
    v = me.dynamicsymbols("v1:4")
    w = me.dynamicsymbols("w1:4")
    names = ("m", "g", "Ixx", "Iyy", "Izz", "Ixy", "Iyz", "Ixz", "P1", "P2", "P3")
    par = dict(zip(names, sp.symbols(names, real=True), strict=True))
    fb = sp.symbols("fb1:4", real=True)
    mb = sp.symbols("mb1:4", real=True)
    ft = sp.symbols("ft1:4", real=True)

    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_quaternion(N, (quat[3], quat[0], quat[1], quat[2]))
    B.set_ang_vel(N, w[0] * B.x + w[1] * B.y + w[2] * B.z)
    NO = me.Point("NO")
    NO.set_vel(N, 0)
    CM = NO.locatenew("O", x[0] * N.x + x[1] * N.y + x[2] * N.z)
    CM.set_vel(N, v[0] * N.x + v[1] * N.y + v[2] * N.z)
    P = CM.locatenew("P", par["P1"] * B.x + par["P2"] * B.y + par["P3"] * B.z)
    P.v2pt_theory(CM, N, B)
    inertia = me.inertia(B, par["Ixx"], par["Iyy"], par["Izz"], par["Ixy"], par["Iyz"], par["Ixz"])
    body = me.RigidBody("B", CM, B, par["m"], (inertia, CM))
    qx, qy, qz, qw = quat
    G = sp.Matrix([[qw, qz, -qy, -qx], [-qz, qw, qx, -qy], [qy, -qx, qw, -qz]])
    qdot_quat = G.T * sp.Matrix(w) / 2
    qdot = sp.Matrix([*v, *qdot_quat])
    kd = [qi.diff(t) - qd for qi, qd in zip((*x, *quat), qdot, strict=True)]
    loads = [
        (CM, fb[0] * B.x + fb[1] * B.y + fb[2] * B.z - par["m"] * par["g"] * N.z),
        (B, mb[0] * B.x + mb[1] * B.y + mb[2] * B.z),
        (P, ft[0] * N.x + ft[1] * N.y + ft[2] * N.z),
    ]
    kane = me.KanesMethod(N, q_ind=[*x, *quat], u_ind=[*v, *w], kd_eqs=kd)
    kane.kanes_equations([body], loads)
    mass_matrix = sp.simplify(kane.mass_matrix)
    J = inertia.to_matrix(B)
    expected = sp.diag(par["m"] * sp.eye(3), J)
    if sp.simplify(mass_matrix - expected) != sp.zeros(6, 6):
        raise RuntimeError("the multirotor's mass matrix is not diag(m, m, m, J)")
    return MultirotorDerivation(
        q=(*x, *quat),
        u=(*v, *w),
        qdot=qdot,
        mass_matrix=mass_matrix,
        forcing=kane.forcing,
        dcm=N.dcm(B),
        params=par,
        wrench=(*fb, *mb),
        tether=ft,
    )


def _substitutions(d: MultirotorDerivation) -> dict:
    """Symbols -> array elements of the generated functions' arguments: q (4,) the attitude
    quaternion, w (3,) body rates, v (3,) velocity, wrench (6,) = [fb, mb], ft (3,), p the
    packed parameters (``layout.MR_*``)."""
    subs: dict = {}
    for i, s in enumerate(d.q[3:]):
        subs[s] = sp.Symbol(f"q[{i}]")
    for i, s in enumerate(d.u[:3]):
        subs[s] = sp.Symbol(f"v[{i}]")
    for i, s in enumerate(d.u[3:]):
        subs[s] = sp.Symbol(f"w[{i}]")
    for i, s in enumerate(d.wrench):
        subs[s] = sp.Symbol(f"wrench[{i}]")
    for i, s in enumerate(d.tether):
        subs[s] = sp.Symbol(f"ft[{i}]")
    par = d.params
    slots = {
        "m": L.MR_MASS,
        "g": L.MR_G,
        "Ixx": L.MR_INERTIA + 0,
        "Ixy": L.MR_INERTIA + 1,
        "Ixz": L.MR_INERTIA + 2,
        "Iyy": L.MR_INERTIA + 4,
        "Iyz": L.MR_INERTIA + 5,
        "Izz": L.MR_INERTIA + 8,
        "P1": L.MR_TETHER_POINT + 0,
        "P2": L.MR_TETHER_POINT + 1,
        "P3": L.MR_TETHER_POINT + 2,
    }
    for name, slot in slots.items():
        subs[par[name]] = sp.Symbol(f"p[{slot}]")
    return subs


def generate_source(d: MultirotorDerivation | None = None) -> str:
    """The source text of ``_multirotor_generated.py`` from a fresh derivation.

    Parameters
    ----------
    d : MultirotorDerivation, optional
        A derivation (default: ``derive()``).

    Returns
    -------
    str
        The module's source: ``mr_dcm``, ``mr_qdot`` and ``mr_forcing``.
    """
    d = derive() if d is None else d
    subs = _substitutions(d)
    printer = _Printer({"fully_qualified_modules": True, "standard": "python3"})
    specs = [
        (
            "mr_dcm",
            "q, R",
            "R (3, 3) = N.dcm(B) at the unit quaternion q (4,) = (x, y, z, w): column j holds "
            "b_j in N.",
            [("R", d.dcm)],
        ),
        (
            "mr_qdot",
            "q, w, out",
            "out (4,) = dq/dt = G(q)^T w / 2 (RotorPy's quat_dot) at q (4,), body rates w (3,) "
            "[rad/s].",
            [("out", d.qdot[3:, :])],
        ),
        (
            "mr_forcing",
            "q, v, w, wrench, ft, p, out",
            "out (6,) = Kane's F of M du/dt = F, M = diag(m, m, m, J): q (4,) the unit "
            "quaternion, v (3,) [m/s], w (3,) [rad/s], wrench (6,) = [fb (B) N, mb (B) N m], "
            "ft (3,) the tether's pull at P in N [N], p the packed parameters (layout.MR_*).",
            [("out", d.forcing)],
        ),
    ]
    parts = [
        '"""Numeric multirotor code generated from model/multirotor_derive.py.\n\n'
        "Do not edit by hand: a test fails if this file and a fresh derivation disagree.\n"
        f"Generated with SymPy {sp.__version__}.\n"
        '"""\n\n'
        "# ruff: noqa\n"
        "import math\n\n"
        f"SYMPY_VERSION = {sp.__version__!r}\n"
    ]
    for name, args, doc, outs in specs:
        prepared = [(o, m.xreplace(subs)) for o, m in outs]
        parts.append("\n\n" + _emit(name, args, doc, prepared, printer))
    return "".join(parts)


def write_generated(path: Path = MR_GENERATED_PATH) -> Path:
    """Regenerate the committed multirotor code, atomically.

    Parameters
    ----------
    path : pathlib.Path, optional
        The file to write (default ``MR_GENERATED_PATH``).

    Returns
    -------
    pathlib.Path
        ``path``, written.
    """
    atomic_write_text(path, generate_source())
    return path
