"""Numeric multirotor code generated from model/multirotor_derive.py.

Do not edit by hand: a test fails if this file and a fresh derivation disagree.
Generated with SymPy 1.14.0.
"""

# ruff: noqa
import math

SYMPY_VERSION = '1.14.0'


def mr_dcm(q, R):
    """R (3, 3) = N.dcm(B) at the unit quaternion q (4,) = (x, y, z, w): column j holds b_j in N."""
    t0 = (q[3])*(q[3])
    t1 = (q[2])*(q[2])
    t2 = -t1
    t3 = (q[0])*(q[0])
    t4 = (q[1])*(q[1])
    t5 = t3 - t4
    t6 = q[0]*q[1]
    t7 = q[2]*q[3]
    t8 = q[0]*q[2]
    t9 = q[1]*q[3]
    t10 = -t0
    t11 = q[0]*q[3]
    R[0, 0] = t0 + t2 + t5
    R[0, 1] = 2*t6 - 2*t7
    R[0, 2] = 2*t8 + 2*t9
    R[1, 0] = 2*t6 + 2*t7
    R[1, 1] = -t1 - t10 - t5
    R[1, 2] = 2*q[1]*q[2] - 2*t11
    R[2, 0] = 2*t8 - 2*t9
    R[2, 1] = 2*q[1]*q[2] + 2*t11
    R[2, 2] = -t10 - t2 - t3 - t4


def mr_qdot(q, w, out):
    """out (4,) = dq/dt = G(q)^T w / 2 (RotorPy's quat_dot) at q (4,), body rates w (3,) [rad/s]."""
    out[0] = (1/2)*(q[1]*w[2] - q[2]*w[1] + q[3]*w[0])
    out[1] = (1/2)*(-q[0]*w[2] + q[2]*w[0] + q[3]*w[1])
    out[2] = (1/2)*(q[0]*w[1] - q[1]*w[0] + q[3]*w[2])
    out[3] = -1/2*(q[0]*w[0] + q[1]*w[1] + q[2]*w[2])


def mr_forcing(q, v, w, wrench, ft, p, out):
    """out (6,) = Kane's F of M du/dt = F, M = diag(m, m, m, J): q (4,) the unit quaternion, v (3,) [m/s], w (3,) [rad/s], wrench (6,) = [fb (B) N, mb (B) N m], ft (3,) the tether's pull at P in N [N], p the packed parameters (layout.MR_*)."""
    t0 = q[0]*q[2]
    t1 = q[1]*q[3]
    t2 = t0 + t1
    t3 = 2*wrench[2]
    t4 = q[0]*q[1]
    t5 = q[2]*q[3]
    t6 = t4 - t5
    t7 = 2*wrench[1]
    t8 = (q[3])*(q[3])
    t9 = (q[2])*(q[2])
    t10 = -t9
    t11 = (q[0])*(q[0])
    t12 = (q[1])*(q[1])
    t13 = t11 - t12
    t14 = t10 + t13 + t8
    t15 = t4 + t5
    t16 = 2*wrench[0]
    t17 = q[0]*q[3]
    t18 = q[1]*q[2]
    t19 = t17 - t18
    t20 = -t8
    t21 = t13 + t20 + t9
    t22 = t17 + t18
    t23 = t0 - t1
    t24 = t10 + t11 + t12 + t20
    t25 = p[10]*w[2] + p[4]*w[0] + p[7]*w[1]
    t26 = p[3]*w[0] + p[6]*w[1] + p[7]*w[2]
    t27 = 2*ft[0]
    t28 = 2*ft[1]
    t29 = ft[2]*t24 + t19*t28 - t2*t27
    t30 = 2*ft[2]
    t31 = -ft[1]*t21 + t22*t30 + t27*t6
    t32 = p[2]*w[0] + p[3]*w[1] + p[4]*w[2]
    t33 = ft[0]*t14 + t15*t28 + t23*t30
    out[0] = ft[0] + t14*wrench[0] + t2*t3 + t6*t7
    out[1] = ft[1] + t15*t16 - t19*t3 - t21*wrench[1]
    out[2] = ft[2] - p[0]*p[1] + t16*t23 + t22*t7 - t24*wrench[2]
    out[3] = -p[21]*t29 - p[22]*t31 - t25*w[1] + t26*w[2] + wrench[3]
    out[4] = p[20]*t29 + p[22]*t33 + t25*w[0] - t32*w[2] + wrench[4]
    out[5] = p[20]*t31 - p[21]*t33 - t26*w[0] + t32*w[1] + wrench[5]
