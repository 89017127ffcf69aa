"""The multirotor's compiled derivative: rotor and air loads, then Kane's rigid body.

``multirotor_derivative(p, s, cmd, wind, f_p, out)`` on the packed parameters p
(``layout.MR_*``, ``Multirotor.packed``) and the state s (``layout.MRS_*``: RotorPy's state
without its wind slot). The loads are RotorPy 3.0.0's ``Multirotor.compute_body_wrench``
(body frame B, z along the rotor axes): each rotor i at r_i with speed w_i gives the thrust
k_eta w_i^2 along b3 and the yaw moment dir_i k_m w_i^2 about b3; with the drag terms on
(``MR_AERO``), the air's velocity relative to the body va = R^T (v - wind) and at hub i
va_i = va + w x r_i give the parasitic drag -|va| diag(c_D) va at O, the rotor drag
-w_i diag(k_d, k_d, k_z) va_i and translational lift k_h (va_i,x^2 + va_i,y^2) b3 at hub i
and the flapping moment -k_flap w_i (va_i x b3). The motors follow the commanded speeds,
clipped to [min, max] as RotorPy's ``Multirotor.step`` clips them, with the first-order lag
dw_i/dt = (cmd_i - w_i) / tau_m. The rigid body is the generated code of
``multirotor_derive`` (Kane), with the tether's pull f_p (N components) at P.
"""

from __future__ import annotations

import math

import numpy as np

from .. import layout as L
from .._compile import compiled
from . import _multirotor_generated as gen

__all__ = ["multirotor_derivative"]

_jit = compiled(fastmath={"nnan", "ninf"}, error_model="numpy")
_jit_inline = compiled(fastmath={"nnan", "ninf"}, error_model="numpy", inline="always")

mr_dcm = _jit_inline(gen.mr_dcm)
mr_qdot = _jit_inline(gen.mr_qdot)
mr_forcing = _jit_inline(gen.mr_forcing)


@_jit
def multirotor_derivative(p, s, cmd, wind, f_p, out):
    """ds/dt of the multirotor (RotorPy 3.0.0's ``Multirotor._s_dot_fn``, module docstring).

    Parameters
    ----------
    p : numpy.ndarray, shape (MR_HEADER + 4 n,)
        The packed parameters (``Multirotor.packed``, slots ``layout.MR_*``).
    s : numpy.ndarray, shape (13 + n,)
        The state (``layout.MRS_*``): x [m], v [m/s] in N, q (x, y, z, w) [-], body rates
        w [rad/s] in B, rotor speeds [rad/s].
    cmd : numpy.ndarray, shape (n,)
        The commanded rotor speeds [rad/s] (clipped to the rotors' limits here).
    wind : numpy.ndarray, shape (3,)
        The wind velocity in N [m/s] (acts only with the drag terms on).
    f_p : numpy.ndarray, shape (3,)
        The tether's pull at P in N components [N].
    out : numpy.ndarray, shape (13 + n,)
        Written: ds/dt.
    """
    n = int(p[L.MR_ROTORS])
    work = np.empty(31)
    qn = work[0:4]
    R = work[4:13].reshape((3, 3))
    wrench = work[13:19]
    forcing = work[19:25]
    va = work[25:28]
    w = s[L.MRS_W : L.MRS_W + 3]
    q = s[L.MRS_Q : L.MRS_Q + 4]
    norm = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    for i in range(4):
        qn[i] = q[i] / norm
    mr_dcm(qn, R)
    aero = p[L.MR_AERO] > 0.5
    for j in range(3):  # va = R^T (v - wind), the air's velocity relative to B, in B
        va[j] = (
            R[0, j] * (s[L.MRS_V] - wind[0])
            + R[1, j] * (s[L.MRS_V + 1] - wind[1])
            + R[2, j] * (s[L.MRS_V + 2] - wind[2])
        )
    fx = 0.0
    fy = 0.0
    fz = 0.0
    mx = 0.0
    my = 0.0
    mz = 0.0
    k_eta = p[L.MR_K_ETA]
    k_m = p[L.MR_K_M]
    k_d = p[L.MR_K_D]
    k_z = p[L.MR_K_Z]
    k_h = p[L.MR_K_H]
    k_flap = p[L.MR_K_FLAP]
    lo = p[L.MR_SPEED_MIN]
    hi = p[L.MR_SPEED_MAX]
    inv_tau = 1.0 / p[L.MR_TAU_M]
    for i in range(n):
        row = L.MR_HEADER + L.MR_ROTOR_COLUMNS * i
        rx = p[row + L.MR_ROTOR_POSITION]
        ry = p[row + L.MR_ROTOR_POSITION + 1]
        rz = p[row + L.MR_ROTOR_POSITION + 2]
        speed = s[L.MRS_ROTORS + i]
        # the rotor's force in B: thrust along b3, then the drag terms at its hub
        hx = 0.0
        hy = 0.0
        hz = k_eta * speed * speed
        if aero:
            lx = va[0] + w[1] * rz - w[2] * ry  # va_i = va + w x r_i
            ly = va[1] + w[2] * rx - w[0] * rz
            lz = va[2] + w[0] * ry - w[1] * rx
            hz += k_h * (lx * lx + ly * ly)
            hx -= speed * k_d * lx
            hy -= speed * k_d * ly
            hz -= speed * k_z * lz
            # flapping: -k_flap w_i (va_i x b3) = -k_flap w_i (ly, -lx, 0)
            mx -= k_flap * speed * ly
            my += k_flap * speed * lx
        fx += hx
        fy += hy
        fz += hz
        mx += ry * hz - rz * hy  # r_i x (hx, hy, hz)
        my += rz * hx - rx * hz
        mz += rx * hy - ry * hx + p[row + L.MR_ROTOR_DIRECTION] * k_m * speed * speed
        c = min(max(cmd[i], lo), hi)
        out[L.MRS_ROTORS + i] = (c - speed) * inv_tau
    if aero:  # parasitic drag at O
        speed_air = math.sqrt(va[0] * va[0] + va[1] * va[1] + va[2] * va[2])
        fx -= speed_air * p[L.MR_DRAG] * va[0]
        fy -= speed_air * p[L.MR_DRAG + 1] * va[1]
        fz -= speed_air * p[L.MR_DRAG + 2] * va[2]
    wrench[0] = fx
    wrench[1] = fy
    wrench[2] = fz
    wrench[3] = mx
    wrench[4] = my
    wrench[5] = mz
    mr_forcing(qn, s[L.MRS_V : L.MRS_V + 3], w, wrench, f_p, p, forcing)
    mr_qdot(q, w, out[L.MRS_Q : L.MRS_Q + 4])
    inv_m = 1.0 / p[L.MR_MASS]
    for j in range(3):
        out[L.MRS_X + j] = s[L.MRS_V + j]
        out[L.MRS_V + j] = forcing[j] * inv_m
        out[L.MRS_W + j] = (
            p[L.MR_INERTIA_INV + 3 * j] * forcing[3]
            + p[L.MR_INERTIA_INV + 3 * j + 1] * forcing[4]
            + p[L.MR_INERTIA_INV + 3 * j + 2] * forcing[5]
        )
