"""The controller contract: a measurement in, a command out, at every control sample.

To plug in your own controller, subclass ``Controller`` and implement ``reset()`` and
``step(t, measurement) -> Command``; pass it to ``tetherheli.simulate(scenario,
controller=...)``. The simulator calls ``reset()`` once, then ``step`` at t_k = k dt and holds
the command constant until the next sample (zero-order hold).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Command", "Controller", "Measurement"]


@dataclass(frozen=True)
class Measurement:
    """What the controller sees at a sample.

    Parameters
    ----------
    state : ndarray, shape (13,)
        [q4..q9, u1..u6, LN] in tethered coordinates [rad, m, rad/s, m/s, m] (for the free
        configuration q7..q9 locate the attachment point P as a virtual tether would).
    tension : float
        Measured tether tension (load cell, T_C^est) [N].
    attached : bool, optional
        False once the tether is removed or released by the safety device (Sec. IV-C): the
        winch then does nothing and the tether exerts no force. Default True.
    """

    state: np.ndarray
    tension: float
    attached: bool = True


@dataclass(frozen=True)
class Command:
    """What the controller commands until the next sample.

    Parameters
    ----------
    inputs : ndarray, shape (4,)
        [fMR3, tMR1, tMR2, fTR2] applied to the rotors [N, N m, N m, N].
    reel_rate : float, optional
        RC = dLN/dt [m/s] (eq 37). Default 0.
    feedforward : ndarray, shape (4,), optional
        The part of ``inputs`` that is feed-forward [N, N m, N m, N] (recorded only).
        Default zeros.
    """

    inputs: np.ndarray
    reel_rate: float = 0.0
    feedforward: np.ndarray = field(default_factory=lambda: np.zeros(4))


class Controller(ABC):
    """Base class of controllers (see the module docstring for the contract)."""

    @abstractmethod
    def reset(self) -> None:
        """Clear internal state (integrators) before a run."""

    def recorded(self) -> dict[str, np.ndarray]:
        """Per-sample columns the controller adds to the result's ``extra`` (one value per
        ``step`` since ``reset``); none by default.

        Returns
        -------
        dict of str to ndarray
        """
        return {}

    @abstractmethod
    def step(self, t: float, measurement: Measurement) -> Command:
        """The command for the sample at time t [s].

        Parameters
        ----------
        t : float
            Sample time t_k = k dt [s].
        measurement : Measurement
            What the sensors report at t_k.

        Returns
        -------
        Command
            Held constant until the next sample (zero-order hold).
        """
