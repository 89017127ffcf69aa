"""Flight beyond hover: the paper's controller (eqs 50-56) flying a ``control.trajectory``
(a scenario's ``[reference]``) by moving its references, as the landing moves them
(``control.landing.MovingReferenceController``).

At each sample the trajectory gives HO's position p, velocity v and yaw relative to the
start's hover point (N, n3 up; over a moving base relative to the base). The law's
references follow:

- the outputs: y_ref = y_ref(0) + (p, yaw) (q1, q2, q3 and q6);
- HO's velocity u1..u3 = v, and the yaw rate u6;
- the tether follows from its geometry from the winch: P_ref = y_ref - d (d = HO - P at the
  trim's attitude), q9 = |P_ref|, c3 = P_ref / q9 and q7, q8 from eq 27 inverted; the gain's
  tether-angle columns scale with q9 (the design's position feedback at that length, as the
  landing's do);
- tethered: T_ref held (or a take-off's tension schedule), LN's reference q9 - T / KC
  (eq 28) and its rate dLN/dt = c3 . v - (dT/dt) / KC fed forward to the winch's PI (eq 56).
  The free helicopter flies the same references without the tether's (no winch).

No acceleration feed-forward: the trajectories are rest-to-rest and smooth (minimum-jerk or
minimum-snap), and the LQI's integrators take up the rest.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..layout import CTRL_T_REF
from ..model.kinematics import tether_angles
from .landing import MovingReferenceController, References
from .trajectory import Trajectory

__all__ = ["ReferenceController"]


class ReferenceController(MovingReferenceController):
    """The paper's controller on the references of a trajectory (module docstring).

    Parameters
    ----------
    trajectory : Trajectory
        HO's path relative to the start's hover point (``control.trajectory``).
    trim_P : array_like, shape (3,)
        P relative to the winch at the start's trim [m] (q9 c3 of the trim).
    K_C : float
        The tether's elasticity of eq 28 [N/m].
    *args, **paper
        ``PaperController``'s arguments, the start's trim.
    tension : callable, optional
        t [s] -> (T_ref [N], dT_ref/dt [N/s]), a tension schedule (the take-off's); None:
        T_ref held at the start's.
    trim_tables : tuple of arrays, optional
        (tensions (k,) increasing [N], inputs (k, 4), states (k, 13)): hover trims at those
        tensions, whose u0 and attitude are interpolated at the scheduled tension (as
        ``LandingController``'s); None: the start's.
    """

    def __init__(
        self,
        trajectory: Trajectory,
        trim_P,
        K_C: float,
        *args,
        tension: Callable[[float], tuple[float, float]] | None = None,
        trim_tables: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        **paper,
    ) -> None:
        super().__init__(*args, **paper)
        self.trajectory = trajectory
        self._d = self._y_ref0[:3] - np.asarray(trim_P, dtype=float)
        self._K_C = float(K_C)
        self._T_ref = float(self.ctrl[CTRL_T_REF])
        self._tension = tension
        self._tables = trim_tables

    def references_at(self, t: float) -> References:
        """The trajectory's references at t (module docstring).

        Parameters
        ----------
        t : float
            Time [s] (relative to the run's start).

        Returns
        -------
        References
            The paper law's references at t.
        """
        point = self.trajectory.at(t)
        T, T_rate = (self._T_ref, 0.0) if self._tension is None else self._tension(t)
        x_ref = self._x_ref0.copy()
        u0 = self._u00
        if self._tables is not None:
            tensions, inputs, states = self._tables
            x_ref[:5] = [np.interp(T, tensions, states[:, j]) for j in range(5)]
            u0 = np.array([np.interp(T, tensions, inputs[:, i]) for i in range(4)])
        y_ref = self._y_ref0.copy()
        y_ref[:3] += point.position
        y_ref[3] += point.yaw
        x_ref[2] += point.yaw  # q6
        P = y_ref[:3] - self._d
        x_ref[3:6] = tether_angles(P)  # q7, q8, q9: P = q9 c3 inverted (eq 27)
        c3 = P / x_ref[5]
        x_ref[6:9] = point.velocity  # HO's velocity u1..u3
        x_ref[11] = point.yaw_rate  # u6
        reel = float(c3 @ point.velocity) - T_rate / self._K_C  # dLN/dt, LN = q9 - T/KC
        return References(x_ref, y_ref, u0, T, reel)
