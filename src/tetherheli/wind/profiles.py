"""Wind profiles: the ``Disturbance`` base class and the deterministic force profiles.

All forces are newtons with components along n1, n2, n3 (n3 up); all times are seconds.

The ``Disturbance`` contract
----------------------------
A disturbance is an immutable object with

``force(t)``
    the force on HO at time ``t``: a scalar time gives shape (3,), a 1-D array of n times
    gives shape (n, 3). It depends on time only, so the same object gives the same numbers
    every time it is asked (no hidden state, no random draws at call time).
``force_at(t, N_v_HO)``
    the force when the velocity of HO in N is known (shape (3,) or (n, 3), m/s). Only
    air-relative models (``Turbulence``) use the velocity; for every other disturbance it
    equals ``force(t)``. A simulator that knows the state should call this one.
``to_dict()``
    a plain, TOML-friendly table that ``disturbance_from_dict`` turns back into an equal
    object, so a run can record its configuration.

To plug in a custom disturbance, subclass ``Disturbance`` (a frozen dataclass is best) and
implement ``_force(t)``, which receives a 1-D float array of finite times and returns an
(n, 3) array; the public ``force`` validates the times and handles the scalar case. Override
``_force_at`` as well if the force depends on the velocity of HO, and ``to_dict`` if the
disturbance should be recordable. Disturbances add: ``a + b`` is a ``WindSum``.

Profiles
--------
Deterministic profiles: ``Pulse``, ``Step``, ``Sine``, ``ConstantForce``, ``NoWind`` and their
sum ``WindSum``; ``paper_wind(1)`` and ``paper_wind(2)`` are the wind of the paper's
simulations 1 and 2 (Sec. VI).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .._validation import check_number, check_vector
from ..errors import ParameterError
from ._common import PlainTable, Vec3, _set, _times, _unit, _velocities

__all__ = [
    "ConstantForce",
    "Disturbance",
    "NoWind",
    "Pulse",
    "Sine",
    "Step",
    "WindSum",
    "paper_wind",
]

# --------------------------------------------------------------------------------------------
# the protocol
# --------------------------------------------------------------------------------------------


class Disturbance(ABC):
    """Base class of wind disturbances: a force on HO in frame N [N] as a function of time.

    Subclasses implement ``_force``; see the module docstring for the full contract.
    """

    #: the ``type`` key of the disturbance's table in ``to_dict`` / ``disturbance_from_dict``.
    type_name: ClassVar[str] = ""

    def force(self, t: float | np.ndarray) -> np.ndarray:
        """Force on HO in N.

        Parameters
        ----------
        t : float or ndarray, shape (n,)
            Time(s) [s], finite.

        Returns
        -------
        ndarray, shape (3,) for a scalar ``t``, else (n, 3)
            Force components along n1, n2, n3 [N].
        """
        ts, scalar = _times(t)
        out = np.asarray(self._force(ts), dtype=float)
        return out[0] if scalar else out

    def force_at(self, t: float | np.ndarray, N_v_HO: np.ndarray) -> np.ndarray:
        """Force on HO in N when the velocity of HO is known.

        Parameters
        ----------
        t : float or ndarray, shape (n,)
            Time(s) [s], finite.
        N_v_HO : ndarray, shape (3,) or (n, 3)
            Velocity of HO in N, n-components [m/s] (the paper's u1, u2, u3).

        Returns
        -------
        ndarray, shape (3,) for a scalar ``t``, else (n, 3)
            Force components along n1, n2, n3 [N]. Equal to ``force(t)`` unless the
            disturbance depends on the air-relative velocity (``Turbulence``).
        """
        ts, scalar = _times(t)
        v = _velocities(N_v_HO, ts.size)
        out = np.asarray(self._force_at(ts, v), dtype=float)
        return out[0] if scalar else out

    @abstractmethod
    def _force(self, t: np.ndarray) -> np.ndarray:
        """Core: times (n,) [s], finite -> force (n, 3) [N]."""

    def _force_at(self, t: np.ndarray, N_v_HO: np.ndarray) -> np.ndarray:
        """Core of ``force_at``: times (n,), velocities (n, 3) -> force (n, 3). Default:
        the force does not depend on the velocity."""
        return self._force(t)

    def to_dict(self) -> dict[str, Any]:
        """A TOML-friendly table that ``disturbance_from_dict`` maps back to an equal object.
        Returns
        -------
        dict of str to object
            ``type`` and the fields, as TOML writes them.
        """
        raise NotImplementedError(f"{type(self).__name__} does not define to_dict()")

    def __add__(self, other: object) -> WindSum:
        if not isinstance(other, Disturbance):
            return NotImplemented
        return WindSum(_flatten(self) + _flatten(other))

    def __radd__(self, other: object) -> Disturbance:
        # lets ``sum(disturbances)`` start from the integer 0
        if isinstance(other, int) and not isinstance(other, bool) and other == 0:
            return self
        return NotImplemented


def _flatten(d: Disturbance) -> tuple[Disturbance, ...]:
    return d.components if isinstance(d, WindSum) else (d,)


# --------------------------------------------------------------------------------------------
# deterministic profiles
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Pulse(PlainTable, Disturbance):
    """A rectangular force pulse: ``magnitude`` along ``direction`` for
    ``start <= t < start + duration``, zero otherwise.

    Parameters
    ----------
    start : float
        Onset time [s], >= 0.
    duration : float
        Length of the pulse [s], > 0. (The paper's simulations do not state it; ``paper_wind``
        uses 1 s by default.)
    magnitude : float
        Signed force magnitude [N].
    direction : sequence of 3 floats
        Direction in N; normalised on construction, must not be zero.
    """

    type_name: ClassVar[str] = "pulse"

    start: float
    duration: float
    magnitude: float
    direction: Vec3

    def __post_init__(self) -> None:
        _set(self, "start", check_number("Pulse.start", self.start, low=0.0))
        _set(
            self, "duration", check_number("Pulse.duration", self.duration, low=0.0, low_open=True)
        )
        _set(self, "magnitude", check_number("Pulse.magnitude", self.magnitude))
        _set(self, "direction", _unit("Pulse.direction", self.direction))

    def _force(self, t: np.ndarray) -> np.ndarray:
        on = (t >= self.start) & (t < self.start + self.duration)
        return np.outer(np.where(on, self.magnitude, 0.0), self.direction)


@dataclass(frozen=True)
class Step(PlainTable, Disturbance):
    """A force step: ``magnitude`` along ``direction`` for ``t >= start``, zero before.

    Parameters
    ----------
    start : float
        Onset time [s], >= 0.
    magnitude : float
        Signed force magnitude [N].
    direction : sequence of 3 floats
        Direction in N; normalised on construction, must not be zero.
    """

    type_name: ClassVar[str] = "step"

    start: float
    magnitude: float
    direction: Vec3

    def __post_init__(self) -> None:
        _set(self, "start", check_number("Step.start", self.start, low=0.0))
        _set(self, "magnitude", check_number("Step.magnitude", self.magnitude))
        _set(self, "direction", _unit("Step.direction", self.direction))

    def _force(self, t: np.ndarray) -> np.ndarray:
        return np.outer(np.where(t >= self.start, self.magnitude, 0.0), self.direction)


@dataclass(frozen=True)
class Sine(PlainTable, Disturbance):
    """A sinusoidal force switched on at ``start``:
    ``amplitude * sin(2 pi frequency t + phase)`` along ``direction`` for ``t >= start``,
    zero before.

    The sine uses the absolute time ``t``, not ``t - start``: this is the paper's convention
    (Sec. VI, "Fw1 = 20 sin(2 pi 0.1 t) n1 starting at time t = 30 s"), where
    ``2 pi 0.1 * 30 = 6 pi`` makes the switch-on continuous. With other values the force may
    jump at ``start``; use ``phase`` to choose.

    Parameters
    ----------
    amplitude : float
        Signed amplitude [N].
    frequency : float
        Frequency [Hz], >= 0.
    start : float
        Switch-on time [s], >= 0.
    direction : sequence of 3 floats
        Direction in N; normalised on construction, must not be zero.
    phase : float, optional
        Phase at t = 0 [rad] (default 0).
    """

    type_name: ClassVar[str] = "sine"

    amplitude: float
    frequency: float
    start: float
    direction: Vec3
    phase: float = 0.0

    def __post_init__(self) -> None:
        _set(self, "amplitude", check_number("Sine.amplitude", self.amplitude))
        _set(self, "frequency", check_number("Sine.frequency", self.frequency, low=0.0))
        _set(self, "start", check_number("Sine.start", self.start, low=0.0))
        _set(self, "direction", _unit("Sine.direction", self.direction))
        _set(self, "phase", check_number("Sine.phase", self.phase))

    def _force(self, t: np.ndarray) -> np.ndarray:
        value = self.amplitude * np.sin(2.0 * np.pi * self.frequency * t + self.phase)
        return np.outer(np.where(t >= self.start, value, 0.0), self.direction)


@dataclass(frozen=True)
class ConstantForce(PlainTable, Disturbance):
    """A constant force at all times.

    Parameters
    ----------
    vector : sequence of 3 floats
        Force components along n1, n2, n3 [N].
    """

    type_name: ClassVar[str] = "constant"

    vector: Vec3

    def __post_init__(self) -> None:
        _set(self, "vector", check_vector("ConstantForce.vector", self.vector, 3))

    def _force(self, t: np.ndarray) -> np.ndarray:
        return np.tile(np.asarray(self.vector), (t.size, 1))


@dataclass(frozen=True)
class NoWind(Disturbance):
    """No disturbance: zero force at all times."""

    type_name: ClassVar[str] = "none"

    def _force(self, t: np.ndarray) -> np.ndarray:
        return np.zeros((t.size, 3))

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``.
        Returns
        -------
        dict of str to object
            ``type`` and the fields, as TOML writes them.
        """
        return {"type": self.type_name}


@dataclass(frozen=True)
class WindSum(Disturbance):
    """The sum of several disturbances (also built by ``a + b``).

    Parameters
    ----------
    components : tuple of Disturbance
        The summands (may be empty: zero force).
    """

    type_name: ClassVar[str] = "sum"

    components: tuple[Disturbance, ...]

    def __post_init__(self) -> None:
        comps = self.components
        if not isinstance(comps, (list, tuple)):
            raise ParameterError("WindSum.components", comps, "a tuple of Disturbance objects")
        for i, c in enumerate(comps):
            if not isinstance(c, Disturbance):
                raise ParameterError(f"WindSum.components[{i}]", c, "a Disturbance")
        _set(self, "components", tuple(comps))

    def _force(self, t: np.ndarray) -> np.ndarray:
        out = np.zeros((t.size, 3))
        for c in self.components:
            out += c._force(t)
        return out

    def _force_at(self, t: np.ndarray, N_v_HO: np.ndarray) -> np.ndarray:
        out = np.zeros((t.size, 3))
        for c in self.components:
            out += c._force_at(t, N_v_HO)
        return out

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``.
        Returns
        -------
        dict of str to object
            ``type`` and the fields, as TOML writes them.
        """
        return {"type": self.type_name, "components": [c.to_dict() for c in self.components]}


def paper_wind(simulation: int, *, pulse_duration: float = 1.0) -> WindSum:
    """The wind force of the paper's simulations (Sec. VI).

    A 20 N pulse at t = 10 s, then 20 sin(2 pi 0.1 t) N from t = 30 s, along n1 (simulation
    1) or n2 (simulation 2). The paper does not state the pulse duration.

    Parameters
    ----------
    simulation : {1, 2}
        Which of the paper's simulations.
    pulse_duration : float, optional
        Duration of the pulse [s] (default 1 s, our assumption).

    Returns
    -------
    WindSum
        ``Pulse(10, pulse_duration, 20, n_i) + Sine(20, 0.1, 30, n_i)``.
    """
    if simulation not in (1, 2) or isinstance(simulation, bool):
        raise ParameterError("simulation", simulation, "1 (wind along n1) or 2 (along n2)")
    direction = (1.0, 0.0, 0.0) if simulation == 1 else (0.0, 1.0, 0.0)
    return Pulse(10.0, pulse_duration, 20.0, direction) + Sine(20.0, 0.1, 30.0, direction)
