"""Tethered landing (after the paper's refs [7], [8]): the paper's controller
flying a descent toward the winch, relative to the base, while the winch reels in under a
tension schedule.

The reference is a schedule of the descent, ``LandingSchedule``: the helicopter hovers
until ``start_time``, then HO's height above the winch falls at ``descent_rate`` down to
``final_height`` (below the touchdown height, so the touchdown happens while descending) and
holds there; the tension reference goes linearly with the height from the run's T_ref to
``landing_tension``. At each sample ``LandingController`` moves the paper law's references
along it: q9 and q3 (the tether is vertical at the paper's trim, whose attitude does not
depend on the tether's length: a test checks it), u3 the descent's velocity, the trim input
u0 and T_ref at the scheduled tension (hover trims at tensions spaced along the schedule,
interpolated), and a reel-rate feed-forward dLN/dt of the reference (LN = q9 - T / KC by eq 28,
or q9 EA / (EA + T) by the rope's law, ``params.TetherParams.natural_length``) added to eq 56's
PI. The gain follows the tether's length: the paper's LQI is designed on the
free helicopter in tethered coordinates, where HO's horizontal position is q9 times the tether
angles (q1 ~ q9 q8, q2 ~ -q9 q7), so its columns on q7 and q8 scale with q9 / q9_design and
the position feedback stays the one designed (exactly: the design at another length gives
the same gain so scaled; a test checks it). Without it the feedback on the angles grows as
1 / q9 and the last metre of the descent goes unstable. Touchdown (the landing gear at
``gear_height`` below HO reaching the deck) is the loop's to detect (``runs.closed_loop``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..layout import CTRL_T_REF
from ..model.kinematics import tether_angles
from ..params import TetherParams
from .base import Command, Measurement
from .paper import PaperController

__all__ = [
    "GroundHoldController",
    "LandingController",
    "LandingSchedule",
    "MovingReferenceController",
    "References",
]


@dataclass(frozen=True)
class LandingSchedule:
    """The descent's reference as a function of time (relative to the base).

    Parameters
    ----------
    start_time : float
        When the descent starts [s].
    descent_rate : float
        The height's rate of fall [m/s], > 0.
    start_height, final_height : float
        HO's height above the winch at the start and where the reference stops [m].
    start_tension, landing_tension : float
        The tension reference at the start and at ``final_height`` [N].
    tether : TetherParams
        The tether and its law (eq 28's KC or the rope's EA).
    """

    start_time: float
    descent_rate: float
    start_height: float
    final_height: float
    start_tension: float
    landing_tension: float
    tether: TetherParams

    @property
    def end_time(self) -> float:
        """When the reference reaches ``final_height`` [s]."""
        return self.start_time + (self.start_height - self.final_height) / self.descent_rate

    def at(self, t: float) -> tuple[float, float, float, float]:
        """(height [m], its rate [m/s], tension [N], its rate [N/s]) of the reference at t.

        Parameters
        ----------
        t : float
            Time [s] (relative to the run's start).

        Returns
        -------
        height : float
            HO's reference height above the winch [m].
        rate : float
            Its rate [m/s] (negative while descending).
        tension : float
            The tension reference [N].
        tension_rate : float
            Its rate [N/s].
        """
        if t <= self.start_time:
            return self.start_height, 0.0, self.start_tension, 0.0
        if t >= self.end_time:
            return self.final_height, 0.0, self.landing_tension, 0.0
        height = self.start_height - self.descent_rate * (t - self.start_time)
        span = self.start_height - self.final_height
        slope = (self.landing_tension - self.start_tension) / span  # [N/m] of descent
        tension = self.start_tension + slope * (self.start_height - height)
        return height, -self.descent_rate, tension, slope * self.descent_rate

    def natural_length_rate(self, t: float, q9: float) -> float:
        """dLN/dt of the reference [m/s]: LN = q9 - T / KC (eq 28) or q9 EA / (EA + T) (the
        rope), with dq9/dt the height's rate (the tether vertical).

        Parameters
        ----------
        t : float
            Time [s] (relative to the run's start).
        q9 : float
            The reference's tether length at t [m] (the rope's law depends on it).

        Returns
        -------
        float
            dLN/dt of the reference [m/s].
        """
        _, rate, tension, tension_rate = self.at(t)
        EA = self.tether.EA
        if EA > 0.0:
            return (rate * (EA + tension) - q9 * tension_rate) * EA / (EA + tension) ** 2
        return rate - tension_rate / self.tether.K_C


class References(NamedTuple):
    """The paper law's references at one sample (``MovingReferenceController``).

    Parameters
    ----------
    x_ref : numpy.ndarray, shape (12,) or (13,)
        The law's state reference q4..u6 (and LN for the tethered LQI): q4..q8 [rad], q9 [m],
        u1..u3 [m/s], u4..u6 [rad/s].
    y_ref : numpy.ndarray, shape (4,)
        The output reference [q1, q2, q3 in m, q6 in rad].
    u0 : numpy.ndarray, shape (4,)
        The trim input about which the law works [N, N m, N m, N].
    tension : float
        T_ref of eq 56 [N].
    reel_rate : float
        The reel rate fed forward, dLN/dt of the reference [m/s].
    """

    x_ref: np.ndarray  #: the law's state reference (q4..u6)
    y_ref: np.ndarray  #: (4,) the output reference q1, q2, q3, q6
    u0: np.ndarray  #: (4,) the trim input about which the law works
    tension: float  #: T_ref of eq 56 [N]
    reel_rate: float  #: the reel rate fed forward, dLN/dt of the reference [m/s]


class MovingReferenceController(PaperController):
    """The paper's controller (eqs 50-56) on references that move with time: a subclass
    gives ``references_at(t)``; at each sample the law flies them, its tether-angle gain
    columns scaled with the reference's q9 (module docstring: the design's position feedback
    at that length) and the reel rate fed forward added to eq 56's PI.

    Parameters
    ----------
    *args, **paper
        ``PaperController``'s arguments (gain, trim_state, trim_output, trim_input, ctrl,
        constants, free_trim_input, z_init), the start's trim.
    """

    def __init__(self, *args, **paper) -> None:
        super().__init__(*args, **paper)
        # the references move at every sample in ``PaperController``'s own copies (the
        # set-up's trim stays); the start's are kept here
        self._gain0 = self.gain.copy()
        self._x_ref0 = self.x_ref.copy()
        self._y_ref0 = self.y_ref.copy()
        self._u00 = self.u0.copy()

    def reset(self) -> None:
        """``PaperController.reset``, and the references back at the start's."""
        super().reset()
        if hasattr(self, "_x_ref0"):  # (PaperController.__init__ resets before they exist)
            self.x_ref[:] = self._x_ref0
            self.y_ref[:] = self._y_ref0
            self.u0[:] = self._u00
            self.gain[:] = self._gain0

    def references_at(self, t: float) -> References:
        """The references at t (a subclass's).

        Parameters
        ----------
        t : float
            Time [s] (relative to the run's start).

        Returns
        -------
        References
            The paper law's references at t.
        """
        raise NotImplementedError

    def step(self, t: float, measurement: Measurement) -> Command:
        """The paper's law on ``references_at(t)``, with the reel rate fed forward.

        Parameters
        ----------
        t : float
            Sample time [s].
        measurement : Measurement
            The measured state (relative to the base), tension and attachment.

        Returns
        -------
        Command
        """
        ref = self.references_at(t)
        self.x_ref[:] = ref.x_ref
        self.y_ref[:] = ref.y_ref
        # the design's position feedback at this tether length (module docstring)
        self.gain[:, 3:5] = self._gain0[:, 3:5] * (ref.x_ref[5] / self._x_ref0[5])
        self.u0[:] = ref.u0
        self.ctrl[CTRL_T_REF] = ref.tension
        command = super().step(t, measurement)
        if not measurement.attached:
            return command
        rate = command.reel_rate + ref.reel_rate
        return Command(inputs=command.inputs, reel_rate=rate, feedforward=command.feedforward)


class LandingController(MovingReferenceController):
    """The paper's controller (eqs 50-56) on the references of a ``LandingSchedule``.

    Parameters
    ----------
    schedule : LandingSchedule
        The descent.
    trim_tensions : array_like, shape (k,)
        Tensions [N], increasing, at which ``trim_inputs`` and ``trim_states`` were trimmed.
    trim_inputs : array_like, shape (k, 4)
        u0 at those tensions (Tables IV, V's inputs; interpolated linearly between them).
    trim_states : array_like, shape (k, 13)
        The trims' states (their attitude is interpolated likewise).
    height_offset : float
        HO's height above P at the trim [m] (y3 - q9 of the trim, eqs 43-45).
    *args, **paper
        ``PaperController``'s arguments, the start's trim.
    """

    def __init__(
        self,
        schedule: LandingSchedule,
        trim_tensions,
        trim_inputs,
        trim_states,
        height_offset: float,
        *args,
        **paper,
    ) -> None:
        super().__init__(*args, **paper)
        self.schedule = schedule
        self._tensions = np.asarray(trim_tensions, dtype=float)
        self._inputs = np.asarray(trim_inputs, dtype=float)
        self._states = np.asarray(trim_states, dtype=float)
        self._offset = float(height_offset)

    def references_at(self, t: float) -> References:
        """The schedule's references at t: the trim's attitude, u0 and T_ref at the scheduled
        tension, q9 and q3 at the scheduled height, u3 its rate, and dLN/dt fed forward.

        Parameters
        ----------
        t : float
            Time [s] (relative to the run's start).

        Returns
        -------
        References
            The paper law's references at t.
        """
        height, rate, tension, _ = self.schedule.at(t)
        x_ref = self._x_ref0.copy()
        states = np.array([np.interp(tension, self._tensions, self._states[:, j])
                           for j in range(5)])  # fmt: skip
        x_ref[:5] = states  # the trim's attitude and tether angles at this tension
        x_ref[5] = height - self._offset  # q9: HO above P by the trim's offset
        x_ref[8] = rate  # u3, HO's vertical velocity
        y_ref = self._y_ref0.copy()
        y_ref[2] = height
        u0 = np.array([np.interp(tension, self._tensions, self._inputs[:, i]) for i in range(4)])
        return References(x_ref, y_ref, u0, tension, self.schedule.natural_length_rate(t, x_ref[5]))


class GroundHoldController(MovingReferenceController):
    """The paper's controller holding a point of N over a moving base (``[control]
    reference = "ground"``): the engine flies on the state relative to the base, so the
    point's position relative to the base moves, y_ref(t) = y_ref(0) - (b(t) - b(0)), with
    the velocity -b'(t). The tether's references follow by the tether's geometry from the
    winch: P_ref = y_ref - d (d = HO - P at the trim's attitude), q9 = |P_ref|, c3 = P_ref /
    q9 = (sin q8, -sin q7 cos q8, cos q7 cos q8) (eq 27); the gain's tether-angle columns
    scale with q9 as the landing's do, and the reel rate gets the feed-forward dq9/dt =
    c3 . (-b'). Valid while the tether stays near the trim's direction (the design's).

    Parameters
    ----------
    base_state : callable
        t [s] -> (3, 3) position, velocity, acceleration of the base in N (``BaseMotion``'s
        ``state(t)[0]``).
    trim_P : array_like, shape (3,)
        P relative to the winch at the trim [m] (q9 c3 of the trim).
    *args, **paper
        ``PaperController``'s arguments, the start's trim.
    """

    def __init__(self, base_state: Callable[[float], np.ndarray], trim_P, *args, **paper):
        super().__init__(*args, **paper)
        self.base_state = base_state
        self._b0 = np.array(base_state(0.0)[0], dtype=float)
        self._d = self._y_ref0[:3] - np.asarray(trim_P, dtype=float)
        self._T_ref = float(self.ctrl[CTRL_T_REF])

    def references_at(self, t: float) -> References:
        """The held point's references relative to the base at t (class docstring); u0 and
        T_ref are the start's.

        Parameters
        ----------
        t : float
            Time [s] (relative to the run's start).

        Returns
        -------
        References
            The paper law's references at t.
        """
        b = np.asarray(self.base_state(t), dtype=float)
        y_ref = self._y_ref0.copy()
        y_ref[:3] -= b[0] - self._b0
        P = y_ref[:3] - self._d
        x_ref = self._x_ref0.copy()
        x_ref[3:6] = tether_angles(P)  # q7, q8, q9: P = q9 c3 inverted (eq 27)
        c3 = P / x_ref[5]
        x_ref[6:9] = -b[1]  # HO's velocity relative to the base
        return References(x_ref, y_ref, self._u00, self._T_ref, float(c3 @ -b[1]))
