"""Wind disturbances: a force on the helicopter's centre of mass HO, in the inertial frame N.

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

Turbulence: ``DrydenGust`` (MIL-F-8785C low-altitude Dryden model; it assumes forward flight)
and ``HoverTurbulence`` (first-order filtered white noise, in the spirit of the CETI models
used for hovering helicopters) generate gust *velocities*; ``DragModel`` turns the
air-relative velocity into a force; ``Turbulence`` ties a gust model, a drag model, a seed and
a time grid into a ``Disturbance``.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import MISSING, dataclass, field, fields
from typing import Any, ClassVar

import numpy as np
import scipy.linalg

from ._validation import check_integer, check_number, check_vector
from .errors import ParameterError

__all__ = [
    "ConstantForce",
    "Disturbance",
    "DragModel",
    "DrydenGust",
    "GustModel",
    "HoverTurbulence",
    "NoWind",
    "Pulse",
    "Sine",
    "Step",
    "Turbulence",
    "WindSum",
    "check_wind_covers",
    "disturbance_from_dict",
    "paper_wind",
]

Vec3 = tuple[float, float, float]

_FT = 0.3048  # metres per foot (exact)

# --------------------------------------------------------------------------------------------
# validation helpers (field names are "Class.field"; the dict loader re-prefixes them)
# --------------------------------------------------------------------------------------------


def _unit(where: str, value: object) -> Vec3:
    """Normalise a nonzero 3-vector; idempotent (a unit vector is returned unchanged)."""
    vec = check_vector(where, value, 3, nonzero=True)
    norm = math.sqrt(sum(v * v for v in vec))
    if abs(norm - 1.0) <= 4.0 * np.finfo(float).eps:
        return vec
    return tuple(v / norm for v in vec)  # type: ignore[return-value]


def _times(t: object) -> tuple[np.ndarray, bool]:
    """Validate times: returns a 1-D float array and whether the input was a scalar."""
    allowed = "a real number or a 1-D array of times [s]"
    if t is None or isinstance(t, (str, bytes)):
        raise ParameterError("t", t, allowed)
    try:
        arr = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("t", t, allowed) from None
    if arr.ndim > 1:
        raise ParameterError("t", t, allowed)
    if not np.all(np.isfinite(arr)):
        raise ParameterError("t", t, "finite times [s]")
    return np.atleast_1d(arr), arr.ndim == 0


def _velocities(N_v_HO: object, n: int) -> np.ndarray:
    """Validate velocities of HO: returns an (n, 3) float array."""
    try:
        v = np.asarray(N_v_HO, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("N_v_HO", N_v_HO, "an array of shape (3,) or (n, 3) [m/s]") from None
    if v.shape == (3,):
        v = np.broadcast_to(v, (n, 3))
    if v.shape != (n, 3):
        raise ParameterError(
            "N_v_HO", N_v_HO, f"an array of shape (3,) or ({n}, 3) matching the times [m/s]"
        )
    if not np.all(np.isfinite(v)):
        raise ParameterError("N_v_HO", N_v_HO, "finite velocities [m/s]")
    return v


def _set(obj: object, name: str, value: object) -> None:
    object.__setattr__(obj, name, value)


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
        """A TOML-friendly table that ``disturbance_from_dict`` maps back to an equal object."""
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


def _plain_dict(obj: Any) -> dict[str, Any]:
    """``{"type": ..., field: value}`` with tuples as lists (TOML arrays)."""
    out: dict[str, Any] = {"type": obj.type_name} if getattr(obj, "type_name", "") else {}
    for f in fields(obj):
        if not f.init:
            continue
        value = getattr(obj, f.name)
        out[f.name] = list(value) if isinstance(value, tuple) else value
    return out


# --------------------------------------------------------------------------------------------
# deterministic profiles
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Pulse(Disturbance):
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

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``."""
        return _plain_dict(self)


@dataclass(frozen=True)
class Step(Disturbance):
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

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``."""
        return _plain_dict(self)


@dataclass(frozen=True)
class Sine(Disturbance):
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

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``."""
        return _plain_dict(self)


@dataclass(frozen=True)
class ConstantForce(Disturbance):
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

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``."""
        return _plain_dict(self)


@dataclass(frozen=True)
class NoWind(Disturbance):
    """No disturbance: zero force at all times."""

    type_name: ClassVar[str] = "none"

    def _force(self, t: np.ndarray) -> np.ndarray:
        return np.zeros((t.size, 3))

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``."""
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
        """See ``Disturbance.to_dict``."""
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


# --------------------------------------------------------------------------------------------
# turbulence: linear gust filters, exactly discretised
# --------------------------------------------------------------------------------------------


def _propagate(
    Ad: np.ndarray, G: np.ndarray, C: np.ndarray, x0: np.ndarray, noise: np.ndarray
) -> np.ndarray:
    """Outputs y_k = C x_k of x_{k+1} = Ad x_k + G e_k, x_0 = x0, for k = 0..n-1.

    Vectorised and exact: in the complex Schur basis (Ad = Z U Z^H, U upper triangular) each
    state obeys a scalar recursion z_{i,k+1} = U_ii z_{i,k} + (input from z_j, j > i, and the
    noise), solved from the last state to the first with ``scipy.signal.lfilter``.
    noise (n-1, m), x0 (m,) -> y (n, p).
    """
    from scipy.signal import lfilter  # imported here: scipy.signal takes ~0.8 s to import

    n, m = noise.shape[0] + 1, x0.shape[0]
    U, Z = scipy.linalg.schur(Ad, output="real")
    if np.any(np.tril(U, -1)):  # complex-conjugate eigenvalues: use the triangular form
        U, Z = scipy.linalg.schur(Ad, output="complex")
    drive = Z.conj().T @ G @ noise.T  # (m, n-1): column k is Z^H G e_k
    z = np.empty((m, n), dtype=U.dtype)  # row i: the i-th Schur coordinate over time
    z[:, 0] = Z.conj().T @ x0
    for i in reversed(range(m)):
        u = drive[i] + U[i, i + 1 :] @ z[i + 1 :, :-1]
        lam = U[i, i]
        z[i, 1:] = lfilter([1.0], [1.0, -lam], u, zi=[lam * z[i, 0]])[0]
    return (C @ Z @ z).real.T


def _psd_sqrt(S: np.ndarray) -> np.ndarray:
    """A square root F of a symmetric positive semi-definite matrix (F F' = S)."""
    w, V = np.linalg.eigh(0.5 * (S + S.T))
    return V * np.sqrt(np.clip(w, 0.0, None))


def _discretize(A: np.ndarray, B: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact discretisation of the stable dx = A x dt + B dW (unit-intensity white noise):
    x_{k+1} = Ad x_k + w_k, Ad = e^{A dt}, w_k ~ N(0, Qd), Qd = int_0^dt e^{A s} B B' e^{A' s} ds.

    Short steps (|eig(A)| dt <= 1) use Van Loan's block exponential; longer steps use
    Qd = P - Ad P Ad' with the stationary covariance P (A P + P A' + B B' = 0), which avoids
    the e^{|A| dt} growth of Van Loan's block and has no cancellation there (Ad P Ad' < P/e^2).
    """
    m = A.shape[0]
    Ad = scipy.linalg.expm(A * dt)
    if np.max(np.abs(np.linalg.eigvals(A))) * dt <= 1.0:
        M = np.zeros((2 * m, 2 * m))
        M[:m, :m] = -A
        M[:m, m:] = B @ B.T
        M[m:, m:] = A.T
        E = scipy.linalg.expm(M * dt)
        Qd = E[m:, m:].T @ E[:m, m:]
    else:
        P = scipy.linalg.solve_continuous_lyapunov(A, -B @ B.T)
        Qd = P - Ad @ P @ Ad.T
    return Ad, 0.5 * (Qd + Qd.T)


class GustModel(ABC):
    """Base class of turbulence models: three independent linear filters driven by
    unit-intensity Gaussian white noise (E[w(t) w(s)] = delta(t - s)), one per gust axis;
    the gust axes are mapped to N by ``axes``.

    Subclasses give the filters (``_filters``) and the axes; the base class samples them
    exactly and gives the analytic variance and power spectral density.
    """

    type_name: ClassVar[str] = ""

    @abstractmethod
    def _filters(self) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]:
        """Three state-space filters (A, B, C), one per gust axis, strictly proper, stable."""

    @property
    def axes(self) -> np.ndarray:
        """Gust axes in N, shape (3, 3): column j holds gust axis j in n-components."""
        return np.eye(3)

    def _block(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        A, B, C = (scipy.linalg.block_diag(*mats) for mats in zip(*self._filters(), strict=True))
        return A, B, C

    @property
    def axis_variance(self) -> np.ndarray:
        """Stationary variance of each gust-axis component, shape (3,) [m^2/s^2]."""
        out = []
        for A, B, C in self._filters():
            P = scipy.linalg.solve_continuous_lyapunov(A, -B @ B.T)
            out.append((C @ P @ C.T).item())
        return np.array(out)

    @property
    def variance(self) -> np.ndarray:
        """Stationary variance of the gust's n1, n2, n3 components, shape (3,) [m^2/s^2]."""
        return self.axes**2 @ self.axis_variance

    def psd(self, f: np.ndarray) -> np.ndarray:
        """One-sided power spectral density of the gust's N components.

        Parameters
        ----------
        f : ndarray, shape (nf,)
            Frequencies [Hz], >= 0.

        Returns
        -------
        ndarray, shape (nf, 3)
            G(f) [(m/s)^2/Hz] with ``integral_0^inf G df = variance``; per gust axis
            G(f) = 2 |H(j 2 pi f)|^2 for unit-intensity white noise (the same scaling as
            ``scipy.signal.welch`` with its default ``scaling='density'``).
        """
        f = np.atleast_1d(np.asarray(f, dtype=float))
        if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
            raise ParameterError("f", f, "a 1-D array of finite frequencies >= 0 [Hz]")
        cols = []
        for A, B, C in self._filters():
            m = A.shape[0]
            H = np.array(
                [(C @ np.linalg.solve(2j * np.pi * fk * np.eye(m) - A, B)).item() for fk in f]
            )
            cols.append(2.0 * np.abs(H) ** 2)
        return np.column_stack(cols) @ (self.axes**2).T

    def sample(self, t_grid: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """A realisation of the gust velocity on a uniform time grid.

        The filters are discretised exactly at the grid step (zero-order transition matrix
        and the exact noise covariance), and the state starts from its stationary
        distribution, so every sample has exactly the analytic variance, whatever the step.

        Parameters
        ----------
        t_grid : ndarray, shape (n,)
            Uniformly spaced, increasing times [s] (n >= 1).
        rng : numpy.random.Generator
            Source of the white noise; draws ``n * m`` standard normals (m = filter order).

        Returns
        -------
        ndarray, shape (n, 3)
            Gust velocity, n1, n2, n3 components [m/s].
        """
        if not isinstance(rng, np.random.Generator):
            raise ParameterError("rng", rng, "a numpy.random.Generator")
        t = np.asarray(t_grid, dtype=float)
        if t.ndim != 1 or t.size < 1 or not np.all(np.isfinite(t)):
            raise ParameterError("t_grid", t_grid, "a 1-D array of finite times [s]")
        dt = 1.0
        if t.size > 1:
            steps = np.diff(t)
            dt = (t[-1] - t[0]) / (t.size - 1)
            if dt <= 0 or not np.allclose(steps, dt, rtol=1e-6, atol=0.0):
                raise ParameterError("t_grid", t_grid, "uniformly spaced increasing times")
        A, B, C = self._block()
        Ad, Qd = _discretize(A, B, dt)
        P = scipy.linalg.solve_continuous_lyapunov(A, -B @ B.T)
        m = A.shape[0]
        x0 = _psd_sqrt(P) @ rng.standard_normal(m)
        noise = rng.standard_normal((t.size - 1, m))
        y = _propagate(Ad, _psd_sqrt(Qd), C, x0, noise)
        return y @ self.axes.T

    def to_dict(self) -> dict[str, Any]:
        """A TOML-friendly table (``type`` and the fields) for ``disturbance_from_dict``."""
        return _plain_dict(self)


@dataclass(frozen=True)
class DrydenGust(GustModel):
    """Dryden turbulence, MIL-F-8785C low-altitude form (also MIL-HDBK-1797).

    With h the altitude in feet (10 ft <= h <= 1000 ft) and W20 the wind speed at 20 ft:

    - intensities: sigma_w = 0.1 W20, sigma_u = sigma_v = sigma_w / (0.177 + 0.000823 h)^0.4;
    - scale lengths: L_u = L_v = h / (0.177 + 0.000823 h)^1.2 ft, L_w = h ft;
    - spectra (one-sided, rad/s, V the airspeed), e.g.
      Phi_u(w) = sigma_u^2 (2 L_u / (pi V)) / (1 + (L_u w / V)^2) and
      Phi_v(w) = sigma_v^2 (L_v / (pi V)) (1 + 3 (L_v w / V)^2) / (1 + (L_v w / V)^2)^2
      (likewise w);
    - filters for unit-intensity white noise, which give exactly those spectra and variances:
      H_u(s) = sigma_u sqrt(2 L_u / V) / (1 + (L_u / V) s),
      H_v(s) = sigma_v sqrt(L_v / V) (1 + sqrt(3) (L_v / V) s) / (1 + (L_v / V) s)^2,
      and H_w like H_v. (The MIL-spec transfer functions carry sqrt(1/pi) instead of 1: they
      are meant for white noise of one-sided density 1, i.e. intensity pi; ours is 1.)

    Dryden (like von Karman) uses Taylor's frozen-field hypothesis and is valid in forward
    flight only: the airspeed must be positive, and the spectra move to zero frequency as it
    goes to zero. For a hovering helicopter use ``HoverTurbulence``. For a helicopter hovering
    in a mean wind, the airspeed is the mean wind speed and ``heading_rad`` its direction.

    Parameters
    ----------
    altitude_m : float
        Altitude h above ground [m], 3.048 m (10 ft) <= h <= 304.8 m (1000 ft).
    wind_speed_20ft_mps : float
        Wind speed at 20 ft, W20 [m/s], > 0 (MIL-F-8785C: 15 kt light, 30 kt moderate,
        45 kt severe).
    airspeed_mps : float
        Speed V of the aircraft relative to the mean air mass [m/s], > 0.
    heading_rad : float, optional
        Azimuth of the longitudinal gust axis u in N, from n1 towards n2 [rad] (default 0:
        u along n1, v along n2, w along n3). The signs of the axes do not matter: the gusts
        are zero-mean Gaussian with symmetric statistics.
    """

    type_name: ClassVar[str] = "dryden"

    altitude_m: float
    wind_speed_20ft_mps: float
    airspeed_mps: float
    heading_rad: float = 0.0

    def __post_init__(self) -> None:
        _set(
            self,
            "altitude_m",
            check_number(
                "DrydenGust.altitude_m",
                self.altitude_m,
                low=10 * _FT,
                high=1000 * _FT,
                allowed="3.048 <= h <= 304.8 [m] (10 to 1000 ft, MIL-F-8785C low altitude)",
            ),
        )
        _set(
            self,
            "wind_speed_20ft_mps",
            check_number(
                "DrydenGust.wind_speed_20ft_mps", self.wind_speed_20ft_mps, low=0.0, low_open=True
            ),
        )
        _set(
            self,
            "airspeed_mps",
            check_number("DrydenGust.airspeed_mps", self.airspeed_mps, low=0.0, low_open=True),
        )
        _set(self, "heading_rad", check_number("DrydenGust.heading_rad", self.heading_rad))

    @property
    def _h_ft(self) -> float:
        return self.altitude_m / _FT

    @property
    def sigma_w(self) -> float:
        """Vertical intensity sigma_w = 0.1 W20 [m/s]."""
        return 0.1 * self.wind_speed_20ft_mps

    @property
    def sigma_u(self) -> float:
        """Longitudinal intensity sigma_u = sigma_w / (0.177 + 0.000823 h)^0.4 [m/s]."""
        return self.sigma_w / (0.177 + 0.000823 * self._h_ft) ** 0.4

    @property
    def sigma_v(self) -> float:
        """Lateral intensity sigma_v = sigma_u [m/s]."""
        return self.sigma_u

    @property
    def L_u(self) -> float:
        """Longitudinal scale length h / (0.177 + 0.000823 h)^1.2 (h in ft) [m]."""
        return self._h_ft / (0.177 + 0.000823 * self._h_ft) ** 1.2 * _FT

    @property
    def L_v(self) -> float:
        """Lateral scale length L_v = L_u [m]."""
        return self.L_u

    @property
    def L_w(self) -> float:
        """Vertical scale length L_w = h [m]."""
        return self.altitude_m

    @property
    def axes(self) -> np.ndarray:
        """Gust axes (u, v, w) in N, shape (3, 3), columns: u horizontal at ``heading_rad``,
        v horizontal to its left, w = n3."""
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    def _filters(self) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]:
        V = self.airspeed_mps
        T = self.L_u / V
        u = (
            np.array([[-1.0 / T]]),
            np.array([[self.sigma_u * math.sqrt(2.0 * self.L_u / V) / T]]),
            np.array([[1.0]]),
        )
        return (u, _dryden_2nd(self.sigma_v, self.L_v, V), _dryden_2nd(self.sigma_w, self.L_w, V))


def _dryden_2nd(sigma: float, L: float, V: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """sigma sqrt(L/V) (1 + sqrt3 T s)/(1 + T s)^2, T = L/V, in controllable canonical form."""
    T = L / V
    k = sigma * math.sqrt(T) / T**2
    A = np.array([[0.0, 1.0], [-1.0 / T**2, -2.0 / T]])
    B = np.array([[0.0], [1.0]])
    C = k * np.array([[1.0, math.sqrt(3.0) * T]])
    return A, B, C


@dataclass(frozen=True)
class HoverTurbulence(GustModel):
    """Turbulence for hover and low speed: on each N axis, unit-intensity white noise through
    a first-order filter K / (s + a).

    This is the structure of the CETI (control equivalent turbulence input) models identified
    for hovering helicopters, applied here to the gust velocity itself. Each component is a
    stationary Ornstein-Uhlenbeck process with variance sigma^2 = K^2 / (2 a), correlation
    time 1/a and one-sided spectrum G(f) = 2 K^2 / ((2 pi f)^2 + a^2) [(m/s)^2/Hz].

    Parameters
    ----------
    gain : sequence of 3 floats, optional
        K per N axis [m s^-3/2], >= 0. Default (0.3, 0.3, 0.2).
    pole_rad_s : sequence of 3 floats, optional
        a per N axis [rad/s], > 0. Default (0.5, 0.5, 0.5): a 2 s correlation time, so the
        default standard deviations are (0.3, 0.3, 0.2) m/s.
    """

    type_name: ClassVar[str] = "hover"

    gain: Vec3 = (0.3, 0.3, 0.2)
    pole_rad_s: Vec3 = (0.5, 0.5, 0.5)

    def __post_init__(self) -> None:
        _set(self, "gain", check_vector("HoverTurbulence.gain", self.gain, 3, low=0.0))
        pole = check_vector(
            "HoverTurbulence.pole_rad_s", self.pole_rad_s, 3, low=0.0, low_open=True
        )
        _set(self, "pole_rad_s", pole)

    @property
    def std(self) -> np.ndarray:
        """Standard deviation K / sqrt(2 a) per N axis, shape (3,) [m/s]."""
        return np.array(self.gain) / np.sqrt(2.0 * np.array(self.pole_rad_s))

    def _filters(self) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]:
        return tuple(
            (np.array([[-a]]), np.array([[K]]), np.array([[1.0]]))
            for K, a in zip(self.gain, self.pole_rad_s, strict=True)
        )


@dataclass(frozen=True)
class DragModel:
    """Quadratic drag of the helicopter, per N axis:
    F_i = 0.5 rho CdA_i |v_rel,i| v_rel,i, v_rel = air velocity - velocity of HO.

    A deliberately simple model: the areas are along the N axes (not rotated with the
    fuselage, which is near level in hover) and the axes do not couple.

    Parameters
    ----------
    cd_area_m2 : sequence of 3 floats
        Drag coefficient times reference area along n1, n2, n3 [m^2], >= 0. For a helicopter
        of the paper's size (12.7 kg) a few tenths of a square metre sideways; vertically the
        rotor disc dominates.
    rho : float, optional
        Air density [kg/m^3], > 0 (default 1.225, ISA sea level).
    """

    cd_area_m2: Vec3
    rho: float = 1.225

    def __post_init__(self) -> None:
        _set(self, "cd_area_m2", check_vector("DragModel.cd_area_m2", self.cd_area_m2, 3, low=0.0))
        _set(self, "rho", check_number("DragModel.rho", self.rho, low=0.0, low_open=True))

    def force(self, N_v_air: np.ndarray, N_v_HO: np.ndarray | None = None) -> np.ndarray:
        """Drag force on HO.

        Parameters
        ----------
        N_v_air : ndarray, shape (3,) or (n, 3)
            Air velocity at HO (mean wind plus gust) in N [m/s].
        N_v_HO : ndarray, shape (3,) or (n, 3), optional
            Velocity of HO in N [m/s] (default: at rest). Broadcasts against ``N_v_air``.

        Returns
        -------
        ndarray, shape of the broadcast inputs
            Force along n1, n2, n3 [N].
        """
        v_rel = np.asarray(N_v_air, dtype=float)
        if N_v_HO is not None:
            v_rel = v_rel - np.asarray(N_v_HO, dtype=float)
        if v_rel.shape[-1:] != (3,) or v_rel.ndim > 2:
            raise ParameterError("N_v_air", N_v_air, "an array of shape (3,) or (n, 3) [m/s]")
        return 0.5 * self.rho * np.asarray(self.cd_area_m2) * np.abs(v_rel) * v_rel

    def to_dict(self) -> dict[str, Any]:
        """A TOML-friendly table of the fields."""
        return _plain_dict(self)


_MAX_SAMPLES = 20_000_000


@dataclass(frozen=True)
class Turbulence(Disturbance):
    """Turbulence as a disturbance: a gust series drawn once from a seed, turned into a drag
    force on HO.

    On construction the gust model is sampled on the grid t_k = k dt, k = 0..n, with
    n = ceil(duration / dt) (the grid covers [0, duration]); between grid points the gust
    velocity is interpolated linearly. Equal parameters give identical series. ``force(t)``
    is the drag with HO at rest; ``force_at(t, N_v_HO)`` uses the air-relative velocity.

    Parameters
    ----------
    model : GustModel
        ``DrydenGust`` or ``HoverTurbulence`` (or a custom ``GustModel``).
    drag : DragModel
        Turns the air-relative velocity into a force.
    seed : int
        Seed of the ``numpy.random.SeedSequence`` (>= 0); recorded by ``to_dict``.
    duration : float
        Time span covered [s], > 0. Asking for the force outside [0, end of grid] is an error.
    dt : float
        Grid step [s], 0 < dt <= duration.
    spawn_key : tuple of int, optional
        Spawn key of the seed sequence (default ()): ``spawn_key=(i,)`` gives the same
        generator as ``SeedSequence(seed).spawn(n)[i]``, for batches of independent runs.
    N_v_mean_wind : sequence of 3 floats, optional
        Mean wind in N added to the gusts [m/s] (default zero).
    """

    type_name: ClassVar[str] = "turbulence"

    model: GustModel
    drag: DragModel
    seed: int
    duration: float
    dt: float
    spawn_key: tuple[int, ...] = ()
    N_v_mean_wind: Vec3 = (0.0, 0.0, 0.0)
    _gust: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.model, GustModel):
            raise ParameterError("Turbulence.model", self.model, "a GustModel")
        if not isinstance(self.drag, DragModel):
            raise ParameterError("Turbulence.drag", self.drag, "a DragModel")
        _set(self, "seed", check_integer("Turbulence.seed", self.seed, low=0))
        key = self.spawn_key
        allowed = "a tuple of integers >= 0"
        if not isinstance(key, (list, tuple)):
            raise ParameterError("Turbulence.spawn_key", key, allowed)
        _set(
            self,
            "spawn_key",
            tuple(check_integer("Turbulence.spawn_key", k, low=0, allowed=allowed) for k in key),
        )
        duration = check_number("Turbulence.duration", self.duration, low=0.0, low_open=True)
        dt = check_number("Turbulence.dt", self.dt, low=0.0, low_open=True, high=duration)
        n = math.ceil(duration / dt - 1e-9)
        if n + 1 > _MAX_SAMPLES:
            raise ParameterError(
                "Turbulence.dt", self.dt, f"a step giving at most {_MAX_SAMPLES} samples"
            )
        _set(self, "duration", duration)
        _set(self, "dt", dt)
        _set(self, "N_v_mean_wind", check_vector("Turbulence.N_v_mean_wind", self.N_v_mean_wind, 3))
        gust = self.model.sample(dt * np.arange(n + 1), self.rng())
        gust.setflags(write=False)
        _set(self, "_gust", gust)

    def rng(self) -> np.random.Generator:
        """A fresh generator in the state used to draw the gusts."""
        return np.random.default_rng(np.random.SeedSequence(self.seed, spawn_key=self.spawn_key))

    @property
    def t_grid(self) -> np.ndarray:
        """Grid times, shape (n + 1,) [s]."""
        return self.dt * np.arange(self._gust.shape[0])

    @property
    def N_v_gust_grid(self) -> np.ndarray:
        """Gust velocity on the grid (without the mean wind), shape (n + 1, 3) [m/s]."""
        return self._gust

    def gust_velocity(self, t: float | np.ndarray) -> np.ndarray:
        """Gust velocity (without the mean wind), linearly interpolated.

        Parameters
        ----------
        t : float or ndarray, shape (n,)
            Time(s) [s] within the grid.

        Returns
        -------
        ndarray, shape (3,) for a scalar ``t``, else (n, 3)
            n1, n2, n3 components [m/s].
        """
        ts, scalar = _times(t)
        out = self._interp(ts)
        return out[0] if scalar else out

    @property
    def t_end(self) -> float:
        """The end of the gust grid [s] (>= ``duration``)."""
        return self.dt * (self._gust.shape[0] - 1)

    def covers(self, t: float | np.ndarray) -> bool | np.ndarray:
        """Whether time(s) ``t`` [s] lie within the gust grid [0, ``t_end``] (relative
        tolerance 1e-12 at the end)."""
        return (t >= 0.0) & (t <= self.t_end * (1.0 + 1e-12))

    def _interp(self, t: np.ndarray) -> np.ndarray:
        end = self.t_end
        inside = self.covers(t)
        if not np.all(inside):
            bad = t[~inside][0]
            raise ParameterError(
                "t", float(bad), f"a time within the turbulence grid [0, {end:g}] s"
            )
        s = np.clip(t / self.dt, 0.0, self._gust.shape[0] - 1)
        k = np.minimum(np.floor(s).astype(np.intp), self._gust.shape[0] - 2)
        w = (s - k)[:, None]
        return (1.0 - w) * self._gust[k] + w * self._gust[k + 1]

    def _force(self, t: np.ndarray) -> np.ndarray:
        return self.drag.force(self._interp(t) + np.asarray(self.N_v_mean_wind))

    def _force_at(self, t: np.ndarray, N_v_HO: np.ndarray) -> np.ndarray:
        return self.drag.force(self._interp(t) + np.asarray(self.N_v_mean_wind), N_v_HO)

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``; the gusts themselves are regenerated from the seed."""
        out = _plain_dict(self)
        out["model"] = self.model.to_dict()
        out["drag"] = self.drag.to_dict()
        return out


# --------------------------------------------------------------------------------------------
# strict loader
# --------------------------------------------------------------------------------------------


class _Missing:
    def __repr__(self) -> str:
        return "<missing>"


_MISSING_VALUE = _Missing()

_DISTURBANCES: dict[str, type] = {
    cls.type_name: cls for cls in (Pulse, Step, Sine, ConstantForce, NoWind, WindSum, Turbulence)
}
_GUST_MODELS: dict[str, type] = {cls.type_name: cls for cls in (DrydenGust, HoverTurbulence)}


def _convert(kind: str, value: Any, where: str, source: str | None) -> Any:
    # types and finiteness here; each class checks its ranges in __post_init__
    if kind == "float":
        return check_number(where, value, source=source)
    if kind == "Vec3":
        return check_vector(where, value, 3, source=source)
    if kind == "int":
        return check_integer(where, value, source=source)
    if kind == "tuple[int, ...]":
        if not isinstance(value, (list, tuple)):
            raise ParameterError(where, value, "an array of integers", source=source)
        return tuple(
            check_integer(where, v, allowed="an array of integers", source=source) for v in value
        )
    if kind == "GustModel":
        return _build_typed(value, _GUST_MODELS, where, source)
    if kind == "DragModel":
        return _build(DragModel, value, where, source)
    if kind == "tuple[Disturbance, ...]":
        if not isinstance(value, (list, tuple)):
            raise ParameterError(where, value, "an array of disturbance tables", source=source)
        return tuple(
            _build_typed(v, _DISTURBANCES, f"{where}[{i}]", source) for i, v in enumerate(value)
        )
    raise AssertionError(f"no loader for field type {kind!r}")  # pragma: no cover


def _build(cls: type, spec: Any, where: str, source: str | None, *, typed: bool = False) -> Any:
    if not isinstance(spec, Mapping):
        raise ParameterError(where, spec, "a table (key = value)", source=source)
    init = {f.name: f for f in fields(cls) if f.init}
    allowed = set(init) | ({"type"} if typed else set())
    for key in spec:
        if key not in allowed:
            raise ParameterError(
                f"{where}.{key}", spec[key], f"a key among {sorted(allowed)}", source=source
            )
    kwargs = {}
    for name, f in init.items():
        if name not in spec:
            if f.default is MISSING and f.default_factory is MISSING:
                raise ParameterError(
                    f"{where}.{name}", _MISSING_VALUE, "a required key", source=source
                )
            continue
        kwargs[name] = _convert(str(f.type), spec[name], f"{where}.{name}", source)
    try:
        return cls(**kwargs)
    except ParameterError as exc:
        prefix = cls.__name__ + "."
        rest = exc.field[len(prefix) :] if exc.field.startswith(prefix) else exc.field
        raise ParameterError(f"{where}.{rest}", exc.value, exc.allowed, source=source) from None


def _build_typed(spec: Any, registry: dict[str, type], where: str, source: str | None) -> Any:
    if not isinstance(spec, Mapping):
        raise ParameterError(where, spec, "a table with a 'type' key", source=source)
    kind = spec.get("type", _MISSING_VALUE)
    if kind not in registry:
        raise ParameterError(f"{where}.type", kind, f"one of {sorted(registry)}", source=source)
    return _build(registry[kind], spec, where, source, typed=True)


def check_wind_covers(
    wind: Disturbance, duration: float, *, name: str = "wind", source: str | None = None
) -> None:
    """Refuse a turbulence whose gust grid ends before a run of ``duration`` [s] does.

    The one check for every path: the compiled engine would hold the last gust value for the
    rest of the run and the Python loop would stop with an error mid-run; ``Scenario``
    calls it on construction, the Gymnasium environment on every episode's wind.

    Raises
    ------
    ParameterError
        Naming the turbulence's ``duration`` field (``wind.duration``, ``wind[i].duration``).
    """
    if isinstance(wind, WindSum):
        for i, part in enumerate(wind.components):
            check_wind_covers(part, duration, name=f"{name}[{i}]", source=source)
    elif isinstance(wind, Turbulence) and not wind.covers(duration):
        raise ParameterError(
            f"{name}.duration",
            wind.duration,
            f"a gust series covering the whole run: >= the run's duration ({duration:g} s; "
            f"the gust grid ends at {wind.t_end:g} s)",
            source=source,
        )


def disturbance_from_dict(
    spec: Mapping[str, Any] | Sequence[Mapping[str, Any]],
    *,
    source: str | None = None,
    name: str = "wind",
) -> Disturbance:
    """Build a disturbance from a TOML-style table, strictly.

    Parameters
    ----------
    spec : mapping or sequence of mappings
        A table with a ``type`` key (``"pulse"``, ``"step"``, ``"sine"``, ``"constant"``,
        ``"none"``, ``"sum"``, ``"turbulence"``) and the class's fields, e.g.
        ``{"type": "pulse", "start": 10.0, "duration": 1.0, "magnitude": 20.0,
        "direction": [1, 0, 0]}``; a list of tables gives their ``WindSum``. A turbulence
        table holds a ``model`` table (``type`` ``"dryden"`` or ``"hover"``) and a ``drag``
        table. ``Disturbance.to_dict()`` gives tables of this form.
    source : str, optional
        Where the table came from (a file name), passed to the errors.
    name : str, optional
        Prefix of field names in error messages (default ``"wind"``: ``wind[0].duration``).

    Returns
    -------
    Disturbance

    Raises
    ------
    ParameterError
        Unknown ``type``, unknown or missing keys, values of the wrong type or out of range;
        the error names the key.
    """
    if isinstance(spec, Mapping):
        return _build_typed(spec, _DISTURBANCES, name, source)
    if isinstance(spec, (list, tuple)):
        return WindSum(
            tuple(
                _build_typed(item, _DISTURBANCES, f"{name}[{i}]", source)
                for i, item in enumerate(spec)
            )
        )
    raise ParameterError(name, spec, "a table or an array of tables", source=source)
