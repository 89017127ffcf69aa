"""An independent Newton-Euler formulation of the helicopter, for tests only.

Cartesian position of HO, the rotation matrix typed from the paper's Table I, the inertia J
and rotor momentum h of docs/paper.md (J w' + w x (J w + h) = torque about HO), and the tether force
computed from the Cartesian position of P. Shares no code with the package's derivation.
"""

from __future__ import annotations

import numpy as np

from tetherheli import Params


def dcm_table_i(q4: float, q5: float, q6: float) -> np.ndarray:
    """Table I: column j holds f_j in N components."""
    s4, c4, s5, c5, s6, c6 = np.sin(q4), np.cos(q4), np.sin(q5), np.cos(q5), np.sin(q6), np.cos(q6)
    return np.array([
        [c5 * c6, -c5 * s6, s5],
        [c4 * s6 + s4 * s5 * c6, c4 * c6 - s4 * s5 * s6, -s4 * c5],
        [s4 * s6 - c4 * s5 * c6, s4 * c6 + c4 * s5 * s6, c4 * c5],
    ])  # fmt: skip


def euler_rates(q4: float, q5: float, q6: float, w: np.ndarray) -> np.ndarray:
    """Solve eq 6 (w in F from Euler rates, typed from the paper) for the Euler rates."""
    s5, c5, s6, c6 = np.sin(q5), np.cos(q5), np.sin(q6), np.cos(q6)
    W = np.array([[c5 * c6, s6, 0.0], [-s6 * c5, c6, 0.0], [s5, 0.0, 1.0]])
    return np.linalg.solve(W, w)


class NewtonEuler:
    def __init__(self, params: Params):
        h = params.helicopter
        self.h = h
        self.K_C = params.tether.K_C
        self.m = h.m_F + h.m_MR
        self.d_HO = (h.m_F * h.d_O_FO3 + h.m_MR * h.d_O_MRO3) / self.m
        mu = h.m_F * h.m_MR / self.m
        d = h.d_O_FO3 - h.d_O_MRO3
        self.J = np.diag([
            h.I_F11 + h.I_MR11 + mu * d**2,
            h.I_F22 + h.I_MR11 + mu * d**2,
            h.I_F33 + 2 * h.I_MR11,
        ])  # fmt: skip
        self.h_rotor = np.array([0.0, 0.0, 2 * h.I_MR11 * h.omega_MR])

    def accelerations(self, R, v, w, inp, wind, tether_force_N):
        """Linear acceleration of HO in N and angular acceleration of F in F."""
        h = self.h
        f_MR3, t_MR1, t_MR2, f_TR2 = inp
        f2, f3 = R[:, 1], R[:, 2]
        force = f_MR3 * f3 + f_TR2 * f2 - self.m * h.g * np.array([0, 0, 1.0]) + wind
        force = force + tether_force_N
        r_TRO = np.array([h.d_O_TRO1, 0.0, -self.d_HO])  # HO -> TRO in F
        r_P = np.array([0.0, 0.0, h.d_O_P3 - self.d_HO])  # HO -> P in F
        torque = np.array([t_MR1, t_MR2 + h.t_TR2, h.rotor_drag_arm * f_MR3])
        torque = torque + np.cross(r_TRO, [0.0, f_TR2, 0.0])
        torque = torque + np.cross(r_P, R.T @ tether_force_N)
        w_dot = np.linalg.solve(self.J, torque - np.cross(w, self.J @ w + self.h_rotor))
        return force / self.m, w_dot

    def tethered(self, x, inp, wind=(0.0, 0.0, 0.0), reel_rate=0.0, base_acceleration=None):
        """dx/dt of the 13-state tethered model, by Newton-Euler in Cartesian terms.

        With ``base_acceleration`` b'' the winch moves and the state is relative to it:
        Newton's law in N reads m (b'' + u') = F, so u' = F / m - b''."""
        q4, q5, q6, q7, q8, q9 = x[:6]
        v, w, L_N = np.asarray(x[6:9]), np.asarray(x[9:12]), x[12]
        R = dcm_table_i(q4, q5, q6)
        c3 = np.array([np.sin(q8), -np.sin(q7) * np.cos(q8), np.cos(q7) * np.cos(q8)])
        r_P_N = R @ np.array([0.0, 0.0, self.h.d_O_P3 - self.d_HO])
        p_HO = q9 * c3 - r_P_N  # Cartesian position of HO
        p_P = p_HO + r_P_N
        length = np.linalg.norm(p_P)
        tension = self.K_C * max(length - L_N, 0.0)
        a, w_dot = self.accelerations(R, v, w, inp, np.asarray(wind), -tension * p_P / length)
        if base_acceleration is not None:
            a = a - np.asarray(base_acceleration)
        # spherical rates: d(q9 c3)/dt = v_P, with the partials of q9 c3 typed here
        s7, c7, s8, c8 = np.sin(q7), np.cos(q7), np.sin(q8), np.cos(q8)
        jac = np.column_stack([
            q9 * np.array([0.0, -c7 * c8, -s7 * c8]),
            q9 * np.array([c8, s7 * s8, -c7 * s8]),
            c3,
        ])  # fmt: skip
        v_P = v + R @ np.cross(w, [0.0, 0.0, self.h.d_O_P3 - self.d_HO])
        sph = np.linalg.solve(jac, v_P)
        return np.concatenate([euler_rates(q4, q5, q6, w), sph, a, w_dot, [reel_rate]])

    def free(self, x, inp, wind=(0.0, 0.0, 0.0), base_acceleration=None):
        """dx/dt of the 12-state free model (relative to a base accelerating at b'')."""
        q4, q5, q6 = x[3:6]
        v, w = np.asarray(x[6:9]), np.asarray(x[9:12])
        R = dcm_table_i(q4, q5, q6)
        a, w_dot = self.accelerations(R, v, w, inp, np.asarray(wind), np.zeros(3))
        if base_acceleration is not None:
            a = a - np.asarray(base_acceleration)
        return np.concatenate([v, euler_rates(q4, q5, q6, w), a, w_dot])
