"""Numeric dynamics of the free and the tethered helicopter: the public model classes.

``TetheredHelicopter`` and ``FreeHelicopter`` share one implementation (``_Helicopter``):
validation, batching and dispatch to the compiled kernels. They differ only in the position
coordinates (Cartesian q1..q3 for the free model, spherical q7..q9 plus the winch length for
the tethered one); the free helicopter is the tethered model with no tension.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

import numpy as np

from ..errors import SingularConfigurationError
from ..names import FREE_STATE, INPUT, OUTPUT, TETHERED_STATE
from ..params import Params
from . import kernels
from .trim import TrimPoint, _hover_trim, hover_trim

__all__ = ["FreeHelicopter", "TetheredHelicopter"]

#: |cos| below this counts as the Euler / spherical singularity (|q5| or |q8| at 90 deg).
_SINGULAR_COS = 1e-9


def _as_array(name: str, value: object, width: int) -> np.ndarray:
    """float64 array of shape (width,) or (n, width), finite, else ValueError naming it."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numeric with shape ({width},) or (n, {width})") from None
    if arr.ndim not in (1, 2) or arr.shape[-1] != width:
        raise ValueError(f"{name} has shape {arr.shape}; allowed: ({width},) or (n, {width})")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} has non-finite entries; allowed: finite numbers")
    return arr


class _Helicopter:
    """Shared machinery of the two model classes (not public)."""

    STATE: ClassVar[tuple[str, ...]]
    _KIND: ClassVar[str]
    INPUT: ClassVar[tuple[str, ...]] = INPUT
    OUTPUT: ClassVar[tuple[str, ...]] = OUTPUT
    #: the compiled outputs kernel (x, constants, out), set by each subclass
    _outputs_kernel: ClassVar[staticmethod[[np.ndarray, np.ndarray, np.ndarray], None]]

    def __init__(self, params: Params | None = None) -> None:
        if params is not None and not isinstance(params, Params):
            raise TypeError(f"params must be a tetherheli.Params or None, not {type(params)}")
        self.params = params if params is not None else Params.paper()
        self._c = kernels.model_constants(self._KIND, self.params.helicopter)

    @property
    def constants(self) -> np.ndarray:
        """The generated code's constants for these parameters (read-only, see ``kernels``)."""
        return self._c

    @property
    def n_state(self) -> int:
        return len(self.STATE)

    def _check_state(self, x: object) -> np.ndarray:
        x = _as_array("x", x, self.n_state)
        rows = np.atleast_2d(x)
        if np.any(np.abs(np.cos(rows[:, 1 if self.n_state == 13 else 4])) < _SINGULAR_COS):
            raise SingularConfigurationError(
                "x: |q5| is at 90 deg, the Euler-angle singularity (eqs 10, 12); "
                "allowed: |q5| < 90 deg"
            )
        self._check_position(rows)
        return x

    def _check_position(self, rows: np.ndarray) -> None:
        """Model-specific singularity checks (override)."""

    def _broadcast(self, x: np.ndarray, name: str, value: object, width: int) -> np.ndarray:
        arr = _as_array(name, value, width)
        if x.ndim == 1:
            if arr.ndim != 1:
                raise ValueError(f"{name} has shape {arr.shape}; allowed: ({width},) for one state")
            return arr
        if arr.ndim == 1:
            return np.broadcast_to(arr, (x.shape[0], width))
        if arr.shape[0] != x.shape[0]:
            raise ValueError(
                f"{name} has {arr.shape[0]} rows; allowed: {x.shape[0]} (one per state)"
            )
        return arr

    def _in_base_frame(self, x: np.ndarray, wind: object, base_acceleration: object) -> np.ndarray:
        """The wind force plus the base frame's inertial force -m b'' at HO (N)."""
        wind = self._broadcast(x, "wind", wind, 3)
        accel = self._broadcast(x, "base_acceleration", base_acceleration, 3)
        if not np.any(accel):
            return wind
        return wind - self.params.helicopter.m * accel

    def outputs(self, x: object) -> np.ndarray:
        """The controlled outputs y = (q1, q2, q3, q6) (eqs 4, 43-45, eq 43 with sin q5).

        Parameters
        ----------
        x : array_like, shape (n_state,) or (n, n_state)
            One state or a batch, in the order of ``STATE``.

        Returns
        -------
        numpy.ndarray, shape (4,) or (n, 4)
            Position of HO in N (m) and yaw angle (rad).
        """
        x = self._check_state(x)
        rows = np.atleast_2d(x)
        y = np.empty((rows.shape[0], 4))
        for i in range(rows.shape[0]):
            self._outputs_kernel(rows[i], self._c, y[i])
        return y[0] if x.ndim == 1 else y

    def __repr__(self) -> str:
        return f"{type(self).__name__}(params={self.params!r})"


class TetheredHelicopter(_Helicopter):
    """The tethered helicopter (Sec. III): spherical coordinates, elastic tether, ground winch.

    State ``STATE`` (13,): q4, q5, q6 body-123 Euler angles (rad); q7, q8 tether angles at
    the ground (rad); q9 tether length (m); u1..u3 velocity of HO in N (m/s); u4..u6 angular
    velocity of F in F (rad/s); LN the tether's natural length (m).
    Inputs ``INPUT`` (4,): fMR3 (N), tMR1 (N m), tMR2 (N m), fTR2 (N).

    Parameters
    ----------
    params : Params, optional
        The parameter set (default ``Params.paper()``, Tables II and III).
    """

    STATE: ClassVar[tuple[str, ...]] = TETHERED_STATE
    _KIND = "tethered"
    _outputs_kernel = staticmethod(kernels.tethered_outputs)

    def _check_position(self, rows: np.ndarray) -> None:
        if np.any(np.abs(np.cos(rows[:, 4])) < _SINGULAR_COS):
            raise SingularConfigurationError(
                "x: |q8| is at 90 deg, the tether-angle singularity (eq 29); allowed: |q8| < 90 deg"
            )
        if np.any(rows[:, 5] <= 0.0):
            raise SingularConfigurationError(
                f"x: q9 = {rows[:, 5].min()!r} m; allowed: a tether length q9 > 0 (eq 29)"
            )

    def derivative(
        self,
        x: object,
        u: object,
        wind: object = (0.0, 0.0, 0.0),
        reel_rate: object = 0.0,
        base_acceleration: object = (0.0, 0.0, 0.0),
    ) -> np.ndarray:
        """dx/dt (eqs 10-12, 29-35, 37) for one state (13,) or a batch (n, 13).

        Parameters
        ----------
        x : array_like, shape (13,) or (n, 13)
            State, in the order of ``STATE``.
        u : array_like, shape (4,) or (n, 4)
            Inputs fMR3, tMR1, tMR2, fTR2 (N, N m, N m, N).
        wind : array_like, shape (3,) or (n, 3), optional
            Wind force on HO, N components (N); default zero.
        reel_rate : float or array_like of shape (n,), optional
            dLN/dt = RC (m/s, eq 37); default 0.
        base_acceleration : array_like, shape (3,) or (n, 3), optional
            b'' of a moving winch, N components (m/s^2); the state is then relative to the
            base and b'' acts as the inertial force -m b'' at HO (``derive(moving_base=True)``).

        Returns
        -------
        numpy.ndarray, shape of ``x``
            The time derivative of the state.
        """
        x = self._check_state(x)
        u = self._broadcast(x, "u", u, 4)
        wind = self._in_base_frame(x, wind, base_acceleration)
        rate = np.asarray(reel_rate, dtype=np.float64)
        if not np.all(np.isfinite(rate)):
            raise ValueError("reel_rate is not finite; allowed: finite numbers [m/s]")
        out = np.empty_like(x)
        K_C, EA = self.params.tether.K_C, self.params.tether.EA
        if x.ndim == 1:
            if rate.ndim != 0:
                raise ValueError(f"reel_rate has shape {rate.shape}; allowed: a scalar")
            kernels.tethered_derivative(x, u, wind, float(rate), self._c, K_C, EA, out)
        else:
            rate = np.ascontiguousarray(np.broadcast_to(rate, (x.shape[0],)))
            kernels.tethered_derivative_batch(
                np.ascontiguousarray(x),
                np.ascontiguousarray(u),
                np.ascontiguousarray(wind),
                rate,
                self._c,
                K_C,
                EA,
                out,
            )
        return out

    def tension(self, x: object) -> np.ndarray | float:
        """Tether tension TC by the tether's law: KC max(q9 - LN, 0) (eq 28) or the rope's
        EA max(q9 - LN, 0) / LN (``params.TetherParams.tension``).

        Parameters
        ----------
        x : array_like, shape (13,) or (n, 13)
            One state or a batch.

        Returns
        -------
        float or numpy.ndarray of shape (n,)
            The tension (N); zero where the tether is slack.
        """
        x = self._check_state(x)
        rows = np.atleast_2d(x)
        t = np.array([self.params.tether.tension(q9, L_N) for q9, L_N in rows[:, [5, 12]]])
        return float(t[0]) if x.ndim == 1 else t

    def tether_torque(self, x: object, tension: float | None = None) -> np.ndarray:
        """Tether torque about HO on f1 and f2 (eqs 33-34; eq 55's C1, C2 with TC).

        Parameters
        ----------
        x : array_like, shape (13,)
            One state.
        tension : float, optional
            The tension TC (N) to use; default: the state's own (``tension``).

        Returns
        -------
        numpy.ndarray, shape (2,)
            The torque's f1 and f2 components (N m).
        """
        x = self._check_state(x)
        if x.ndim != 1:
            raise ValueError(f"x has shape {x.shape}; allowed: (13,)")
        t = self.tension(x) if tension is None else float(tension)
        out = np.empty(2)
        kernels.tethered_tether_torque(x, t, self._c, out)
        return out

    def trim(self, tension: float, q9: float = 10.0, *, N_F_wind: object = None) -> TrimPoint:
        """Hover trim at a tether tension and length (Tables IV, V; ``model.trim.hover_trim``).

        Parameters
        ----------
        tension : float
            Tether tension TC at hover (N); 25 N gives Table V, 0 N Table IV.
        q9 : float, optional
            Tether length (m); default 10 m, the paper's.
        N_F_wind : array_like, shape (3,), optional
            A steady wind force on HO, N components (N), to trim in; default none.

        Returns
        -------
        TrimPoint
            The trim state, input and feed-forward.
        """
        return hover_trim(self.params, tension, q9, N_F_wind=N_F_wind)


class FreeHelicopter(_Helicopter):
    """The free helicopter (Sec. II): the tethered model with no tether, Cartesian position.

    State ``STATE`` (12,): q1..q3 position of HO in N [m]; q4..q6 Euler angles [rad];
    u1..u6 as for ``TetheredHelicopter``. Inputs as for ``TetheredHelicopter``.

    Parameters
    ----------
    params : Params, optional
        The parameter set (default ``Params.paper()``, Table II).
    """

    STATE: ClassVar[tuple[str, ...]] = FREE_STATE
    _KIND = "free"
    _outputs_kernel = staticmethod(kernels.free_outputs)

    def derivative(
        self,
        x: object,
        u: object,
        wind: object = (0.0, 0.0, 0.0),
        base_acceleration: object = (0.0, 0.0, 0.0),
    ) -> np.ndarray:
        """dx/dt (eqs 9-18) for one state (12,) or a batch (n, 12).

        Parameters
        ----------
        x : array_like, shape (12,) or (n, 12)
            State, in the order of ``STATE``.
        u : array_like, shape (4,) or (n, 4)
            Inputs fMR3, tMR1, tMR2, fTR2 (N, N m, N m, N).
        wind : array_like, shape (3,) or (n, 3), optional
            Wind force on HO, N components (N); default zero.
        base_acceleration : array_like, shape (3,) or (n, 3), optional
            b'' of the moving base the position is taken from (m/s^2), as for the tethered
            model.

        Returns
        -------
        numpy.ndarray, shape of ``x``
            The time derivative of the state.
        """
        x = self._check_state(x)
        u = self._broadcast(x, "u", u, 4)
        wind = self._in_base_frame(x, wind, base_acceleration)
        out = np.empty_like(x)
        if x.ndim == 1:
            kernels.free_derivative(x, u, wind, self._c, out)
        else:
            kernels.free_derivative_batch(
                np.ascontiguousarray(x),
                np.ascontiguousarray(u),
                np.ascontiguousarray(wind),
                self._c,
                out,
            )
        return out

    def trim(self, position: Sequence[float] | None = None) -> TrimPoint:
        """Hover trim of the free helicopter (Table IV).

        Parameters
        ----------
        position : sequence of 3 floats, optional
            HO's position q1, q2, q3 (m). None places it where Table IV does: above the
            ground point with a 10 m vertical tether (q1 = 0, q2 = -0.0189, q3 = 10.2037 m).

        Returns
        -------
        TrimPoint
            Its ``x`` is the free state (12,).
        """
        tethered = _hover_trim(self.params, 0.0, 10.0)  # constants: nothing to check
        y = tethered.y.copy()
        if position is not None:
            pos = _as_array("position", position, 3)
            if pos.ndim != 1:
                raise ValueError(f"position has shape {pos.shape}; allowed: (3,)")
            y[:3] = pos
        x = np.zeros(12)
        x[:3] = y[:3]
        x[3:6] = tethered.x[:3]
        return TrimPoint(x=x, u=tethered.u, y=y, tension=0.0, feedforward=np.zeros(4))


def state_index(model: type[_Helicopter] | _Helicopter, name: str) -> int:
    """Index of a named state entry, e.g. ``state_index(TetheredHelicopter, "q9")``.

    Parameters
    ----------
    model : type or instance of FreeHelicopter or TetheredHelicopter
        The model whose ``STATE`` names are searched.
    name : str
        A state entry's name, e.g. "q9" or "LN" (``docs/notation.md``).

    Returns
    -------
    int
        Its index in the model's state vector.

    Raises
    ------
    ValueError
        A name not in the model's ``STATE``.
    """
    try:
        return model.STATE.index(name)
    except ValueError:
        raise ValueError(f"state name {name!r} is unknown; allowed: {model.STATE}") from None
