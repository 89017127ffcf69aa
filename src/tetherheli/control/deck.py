"""Feed-forward of a moving base's known acceleration.

Over a moving base the controllers fly on the state relative to it, where the base's
acceleration b'' acts on the helicopter as the inertial force -m b'' (``model.derive``,
``moving_base=True``). Where the deck's motion is known (a deck motion sensor, or the
prescribed motion), ``DeckFeedforward`` cancels its vertical part with the main rotor's
thrust: fMR3 += m b''_3 / (cos q4 cos q5), the thrust whose n3 component is m b''_3 at the
measured attitude (f3 . n3 = cos q4 cos q5, Table I). The horizontal part is left to the
controller (cancelling it takes an attitude change, not an input).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .base import Command, Controller, Measurement

__all__ = ["DeckFeedforward"]


class DeckFeedforward(Controller):
    """Any controller with the base's vertical acceleration fed forward to the thrust.

    Parameters
    ----------
    controller : Controller
        The controller flying on the state relative to the base.
    base_acceleration : callable
        t [s] -> b''(t) (3,) [m/s^2] in N (e.g. ``BaseMotion.state(t)[0, 2]``).
    mass : float
        The helicopter's mass m = mF + mMR [kg].
    """

    def __init__(
        self,
        controller: Controller,
        base_acceleration: Callable[[float], np.ndarray],
        mass: float,
    ) -> None:
        self.controller = controller
        self.base_acceleration = base_acceleration
        self.mass = float(mass)

    def reset(self) -> None:
        """Reset the wrapped controller."""
        self.controller.reset()

    def recorded(self) -> dict[str, np.ndarray]:
        """The wrapped controller's recorded columns.

        Returns
        -------
        dict of str to numpy.ndarray
            The wrapped controller's ``recorded()``: its extra columns, one row per sample.
        """
        return self.controller.recorded()

    def step(self, t: float, measurement: Measurement) -> Command:
        """The wrapped controller's command plus m b''_3 / (cos q4 cos q5) on fMR3.

        Parameters
        ----------
        t : float
            Sample time [s].
        measurement : Measurement
            The measured state (relative to the base).

        Returns
        -------
        Command
            The command; its ``feedforward`` includes the thrust added.
        """
        command = self.controller.step(t, measurement)
        q4, q5 = measurement.state[0], measurement.state[1]
        thrust = self.mass * float(self.base_acceleration(t)[2]) / (math.cos(q4) * math.cos(q5))
        inputs = np.array(command.inputs, dtype=float)
        ffwd = np.array(command.feedforward, dtype=float)
        inputs[0] += thrust
        ffwd[0] += thrust
        return Command(inputs=inputs, reel_rate=command.reel_rate, feedforward=ffwd)
