"""The geometric tracking controller on SE(3) for a multirotor, as RotorPy 3.0.0 writes it.

T. Lee, M. Leok, N. H. McClamroch, "Geometric tracking control of a quadrotor UAV on SE(3)",
CDC 2010 (eqs 15-19), in RotorPy's ``SE3Control.update`` form (z up, quaternions x, y, z, w):

- F_des = m (-Kp e_x - Kd e_v + a_ref + g n3), e_x = x - x_ref, e_v = v - v_ref;
- thrust u1 = F_des . b3;
- b3_des = F_des / |F_des|, b2_des = b3_des x c1 / |.|, c1 = (cos yaw, sin yaw, 0),
  b1_des = b2_des x b3_des;
- e_R = vee(R_des^T R - R^T R_des) / 2, e_w = w - (0, 0, yaw rate);
- moment u2 = J (-kp_att e_R - kd_att e_w) + w x J w;
- the mixer: rotor thrusts = M^-1 [u1, u2] (``Multirotor.mixer``), rotor speeds
  sign(f) sqrt(|f| / k_eta).

The returned speeds are not clipped, as RotorPy's; the vehicle clips them to its limits
(``Multirotor``'s kernel, as RotorPy's ``Multirotor.step``). The optional tether
feed-forward (not in RotorPy) removes a measured tether pull f_p (N components) at P from
what the rotors must give: F_des - f_p and u2 - r_P x R^T f_p.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .._validation import check_number, check_vector
from ..errors import ParameterError
from ..model._multirotor_generated import mr_dcm
from ..model.multirotor import MULTIROTOR_PRESETS, Multirotor

__all__ = ["SE3Controller"]

#: RotorPy's SE3Control position gains (kp_pos, kd_pos) and attitude gains' defaults
_KP_POS = (6.5, 6.5, 15.0)
_KD_POS = (4.0, 4.0, 9.0)
_KP_ATT = 310.0
_KD_ATT = 57.0


def _vee(S: np.ndarray) -> np.ndarray:
    """The vector of a skew-symmetric matrix (RotorPy's ``vee_map``)."""
    return np.array([-S[1, 2], S[0, 2], -S[0, 1]])


def _normalize(x: np.ndarray) -> np.ndarray:
    """x / |x|."""
    return x / np.linalg.norm(x)


def _rotation_matrix(q: Any) -> np.ndarray:
    """N.dcm(B) of the quaternion q = (x, y, z, w), normalised (the derivation's DCM)."""
    qn = np.asarray(q, dtype=np.float64)
    R = np.empty((3, 3))
    mr_dcm(qn / np.linalg.norm(qn), R)
    return R


def _quaternion(R: np.ndarray) -> np.ndarray:
    """The unit quaternion (x, y, z, w) of a rotation matrix (Shepperd, J. Guid. Control 1978:
    from the largest of the diagonal and the trace, SciPy's ``from_matrix`` branch and sign)."""
    trace = R[0, 0] + R[1, 1] + R[2, 2]
    choice = int(np.argmax([R[0, 0], R[1, 1], R[2, 2], trace]))
    q = np.empty(4)
    if choice == 3:
        q[0] = R[2, 1] - R[1, 2]
        q[1] = R[0, 2] - R[2, 0]
        q[2] = R[1, 0] - R[0, 1]
        q[3] = 1 + trace
    else:
        i = choice
        j = (i + 1) % 3
        k = (j + 1) % 3
        q[i] = 1 - trace + 2 * R[i, i]
        q[j] = R[j, i] + R[i, j]
        q[k] = R[k, i] + R[i, k]
        q[3] = R[k, j] - R[j, k]
    return q / np.linalg.norm(q)


class SE3Controller:
    """Lee, Leok and McClamroch's SE(3) controller (module docstring), RotorPy's form.

    Parameters
    ----------
    vehicle : Multirotor
        The vehicle (mass, inertia, mixer, k_eta, tether point).
    kp_pos, kd_pos : sequence of float, shape (3,), optional
        Position and velocity gains [1/s^2], [1/s] (RotorPy's 6.5, 6.5, 15 and 4, 4, 9).
    kp_att, kd_att : float, optional
        Attitude and body-rate gains [1/s^2], [1/s] (RotorPy's defaults 310, 57).
    """

    def __init__(
        self,
        vehicle: Multirotor,
        *,
        kp_pos: Sequence[float] = _KP_POS,
        kd_pos: Sequence[float] = _KD_POS,
        kp_att: float = _KP_ATT,
        kd_att: float = _KD_ATT,
    ) -> None:
        if not isinstance(vehicle, Multirotor):
            raise ParameterError("vehicle", vehicle, "a Multirotor")
        self.vehicle = vehicle
        self.kp_pos = np.array(check_vector("kp_pos", kp_pos, 3, low=0.0))
        self.kd_pos = np.array(check_vector("kd_pos", kd_pos, 3, low=0.0))
        self.kp_att = check_number("kp_att", kp_att, low=0.0)
        self.kd_att = check_number("kd_att", kd_att, low=0.0)
        self.kp_vel = 0.1 * self.kp_pos  # RotorPy's cmd_v gain

    @classmethod
    def from_rotorpy(cls, quad_params: Mapping[str, Any], **gains: Any) -> SE3Controller:
        """The controller RotorPy's ``SE3Control(quad_params)`` builds.

        Parameters
        ----------
        quad_params : mapping
            RotorPy's parameter dictionary (``Multirotor.from_rotorpy``); its kp_att, kd_att
            if present.
        **gains
            kp_pos, kd_pos, kp_att, kd_att overriding RotorPy's.

        Returns
        -------
        SE3Controller
            The controller.
        """
        gains.setdefault("kp_att", quad_params.get("kp_att", _KP_ATT))
        gains.setdefault("kd_att", quad_params.get("kd_att", _KD_ATT))
        return cls(Multirotor.from_rotorpy(quad_params), **gains)

    @classmethod
    def preset(cls, name: str, **gains: Any) -> SE3Controller:
        """The controller of a ``MULTIROTOR_PRESETS`` vehicle with RotorPy's gains.

        Parameters
        ----------
        name : str
            "crazyflie", "hummingbird" or "px4_quadx".
        **gains
            As for ``from_rotorpy``.

        Returns
        -------
        SE3Controller
            The controller.
        """
        if name not in MULTIROTOR_PRESETS:
            raise ParameterError("preset", name, "one of " + ", ".join(MULTIROTOR_PRESETS))
        return cls.from_rotorpy(MULTIROTOR_PRESETS[name], **gains)

    def update(
        self,
        t: float,
        state: Mapping[str, Any],
        flat_output: Mapping[str, Any],
        tether_force: Sequence[float] | None = None,
    ) -> dict[str, Any]:
        """The commands at one instant (RotorPy's ``SE3Control.update``).

        Parameters
        ----------
        t : float
            Time [s] (unused, as in RotorPy).
        state : mapping
            x (3,) [m], v (3,) [m/s], q (4,) (x, y, z, w), w (3,) [rad/s].
        flat_output : mapping
            x (3,) [m], x_dot (3,) [m/s], x_ddot (3,) [m/s^2], yaw [rad], yaw_dot [rad/s]
            (RotorPy's flat outputs; x_dddot and x_ddddot unused).
        tether_force : sequence of float, shape (3,), optional
            A measured tether pull at P in N [N]: the feed-forward (module docstring).

        Returns
        -------
        dict
            cmd_motor_speeds (n,) [rad/s], cmd_motor_thrusts (n,) [N], cmd_thrust [N],
            cmd_moment (3,) [N m], cmd_q (4,) the desired attitude, cmd_w (3,) [rad/s],
            cmd_v (3,) [m/s], cmd_acc (3,) [m/s^2].
        """
        veh = self.vehicle
        J = veh.inertia
        pos_err = np.asarray(state["x"]) - flat_output["x"]
        dpos_err = np.asarray(state["v"]) - flat_output["x_dot"]
        F_des = veh.mass * (
            -self.kp_pos * pos_err
            - self.kd_pos * dpos_err
            + flat_output["x_ddot"]
            + np.array([0, 0, veh.g])
        )
        R = _rotation_matrix(state["q"])
        if tether_force is not None:
            f_p = np.array(check_vector("tether_force", tether_force, 3, unit="N"))
            F_des = F_des - f_p
        b3 = R @ np.array([0, 0, 1])
        u1 = np.dot(F_des, b3)
        b3_des = _normalize(F_des)
        yaw_des = flat_output["yaw"]
        c1_des = np.array([np.cos(yaw_des), np.sin(yaw_des), 0])
        b2_des = _normalize(np.cross(b3_des, c1_des))
        b1_des = np.cross(b2_des, b3_des)
        R_des = np.stack([b1_des, b2_des, b3_des]).T
        att_err = _vee(0.5 * (R_des.T @ R - R.T @ R_des))
        w = np.asarray(state["w"])
        w_err = w - np.array([0, 0, flat_output["yaw_dot"]])
        cmd_w = -self.kp_att * att_err - self.kd_att * w_err
        u2 = J @ cmd_w + np.cross(w, J @ w)
        if tether_force is not None:
            u2 = u2 - np.cross(np.asarray(veh.tether_point), R.T @ f_p)
        TM = np.array([u1, u2[0], u2[1], u2[2]])
        cmd_rotor_thrusts = veh.mixer @ TM
        cmd_motor_speeds = cmd_rotor_thrusts / veh.k_eta
        cmd_motor_speeds = np.sign(cmd_motor_speeds) * np.sqrt(np.abs(cmd_motor_speeds))
        return {
            "cmd_motor_speeds": cmd_motor_speeds,
            "cmd_motor_thrusts": cmd_rotor_thrusts,
            "cmd_thrust": u1,
            "cmd_moment": u2,
            "cmd_q": _quaternion(R_des),
            "cmd_w": cmd_w,
            "cmd_v": -self.kp_vel * pos_err + flat_output["x_dot"],
            "cmd_acc": F_des / veh.mass,
        }
