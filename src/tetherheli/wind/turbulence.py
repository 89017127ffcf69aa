"""Turbulence: gust models (linear filters driven by white noise, sampled exactly) and
``Turbulence``, the disturbance that turns a gust series into a drag force on HO.

Turbulence: ``DrydenGust`` (MIL-F-8785C low-altitude Dryden model; it assumes forward flight)
and ``GaussMarkovTurbulence`` (first-order Gauss-Markov gusts: white noise through K/(s + a)
per axis; ``CalibratedGaussMarkovTurbulence`` takes K and a from MIL-HDBK-1797 or IEC 61400-1,
``gust_calibration``) generate gust *velocities*; ``DragModel`` turns the
air-relative velocity into a force; ``Turbulence`` ties a gust model, a drag model, a seed and
a time grid into a ``Disturbance``.
"""

from __future__ import annotations

import functools
import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import scipy.linalg

from .._validation import check_integer, check_number, check_vector
from ..errors import ParameterError
from ._common import Vec3, _plain_dict, _set, _times
from .drag import DragModel
from .profiles import Disturbance, WindSum

__all__ = [
    "CALIBRATIONS",
    "CalibratedGaussMarkovTurbulence",
    "DrydenGust",
    "GaussMarkovTurbulence",
    "GustCalibration",
    "GustModel",
    "Turbulence",
    "check_wind_covers",
    "gust_calibration",
    "heading_axes",
    "initial_wind_force",
]

_FT = 0.3048  # metres per foot (exact)


# --------------------------------------------------------------------------------------------
# turbulence: linear gust filters, exactly discretised
# --------------------------------------------------------------------------------------------


def _schur(Ad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The Schur form (U, Z) of Ad = Z U Z^H that ``_propagate`` runs in: real if it is upper
    triangular, else complex (complex-conjugate eigenvalues)."""
    U, Z = scipy.linalg.schur(Ad, output="real")
    if np.any(np.tril(U, -1)):  # complex-conjugate eigenvalues: use the triangular form
        U, Z = scipy.linalg.schur(Ad, output="complex")
    return U, Z


def _propagate(
    U: np.ndarray, Z: np.ndarray, G: np.ndarray, C: np.ndarray, x0: np.ndarray, noise: np.ndarray
) -> np.ndarray:
    """Outputs y_k = C x_k of x_{k+1} = Ad x_k + G e_k, x_0 = x0, for k = 0..n-1.

    Vectorised and exact: in the complex Schur basis (Ad = Z U Z^H, U upper triangular,
    ``_schur``) each state obeys a scalar recursion z_{i,k+1} = U_ii z_{i,k} + (input from
    z_j, j > i, and the noise), solved from the last state to the first with
    ``scipy.signal.lfilter``. noise (n-1, m), x0 (m,) -> y (n, p).
    """
    from scipy.signal import lfilter  # imported here: scipy.signal takes ~0.8 s to import

    n, m = noise.shape[0] + 1, x0.shape[0]
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
        f = _sampled_filter(self, dt)
        m = f.start.shape[0]
        x0 = f.start @ rng.standard_normal(m)
        noise = rng.standard_normal((t.size - 1, m))
        y = _propagate(f.U, f.Z, f.drive, f.C, x0, noise)
        return y @ f.axes.T

    def to_dict(self) -> dict[str, Any]:
        """A TOML-friendly table (``type`` and the fields) for ``disturbance_from_dict``.
        Returns
        -------
        dict of str to object
            ``type`` and the fields, as TOML writes them.
        """
        return _plain_dict(self)


@dataclass(frozen=True)
class _SampledFilter:
    """What ``GustModel.sample`` needs of a model at a grid step, whatever the draw: the
    stationary covariance's square root (``start``: x0 = start e), the exact noise gain
    (``drive``: G with G G' = Qd, ``_discretize``), the Schur form (U, Z) of Ad (``_schur``),
    the output matrix C and the gust axes (all read-only)."""

    start: np.ndarray
    drive: np.ndarray
    U: np.ndarray
    Z: np.ndarray
    C: np.ndarray
    axes: np.ndarray


def _sampled_filter(model: GustModel, dt: float) -> _SampledFilter:
    """``model``'s ``_SampledFilter`` at step dt; kept (``_cached_filter``) for frozen
    dataclass models, whose filters are a function of their fields: every episode of an
    environment samples the same model at the same step, and the matrix exponentials and
    Lyapunov solve cost far more than the draw itself. Other models are discretised anew."""
    params = getattr(type(model), "__dataclass_params__", None)
    if params is not None and params.frozen:
        try:
            return _cached_filter(model, float(dt))
        except TypeError:  # a field that cannot be hashed
            pass
    return _filter_at(model, float(dt))


def _filter_at(model: GustModel, dt: float) -> _SampledFilter:
    """``_SampledFilter`` of ``model`` at step dt, computed."""
    A, B, C = model._block()
    Ad, Qd = _discretize(A, B, dt)
    P = scipy.linalg.solve_continuous_lyapunov(A, -B @ B.T)
    U, Z = _schur(Ad)
    arrays = (_psd_sqrt(P), _psd_sqrt(Qd), U, Z, C, np.asarray(model.axes, dtype=float))
    for a in arrays:
        a.setflags(write=False)
    return _SampledFilter(*arrays)


_cached_filter = functools.lru_cache(maxsize=32)(_filter_at)


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
    goes to zero. For a hovering helicopter use ``CalibratedGaussMarkovTurbulence``. For a
    helicopter hovering in a mean wind, the airspeed is the mean wind speed and
    ``heading_rad`` its direction.

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
        """Gust axes (u, v, w) in N, shape (3, 3) (``heading_axes``)."""
        return heading_axes(self.heading_rad)

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
class GaussMarkovTurbulence(GustModel):
    """First-order Gauss-Markov gusts: on each gust axis, unit-intensity white noise through
    K / (s + a).

    Each component is a stationary Ornstein-Uhlenbeck process with variance
    sigma^2 = K^2 / (2 a), correlation time 1/a and one-sided spectrum
    G(f) = 2 K^2 / ((2 pi f)^2 + a^2) [(m/s)^2/Hz]. The gust axes are u along ``heading_rad``,
    v horizontal to its left and w = n3 (with the default heading 0: n1, n2, n3).

    This is a model of the gust *velocity*. It is not a CETI (control equivalent turbulence
    input) model: CETI models put filtered noise on the control inputs, with gains and poles
    identified from flight data of a given helicopter; tetherheli offers none, since no
    published coefficients exist for the paper's 12.7 kg helicopter. For K and a from a
    published turbulence model (MIL-HDBK-1797 or IEC 61400-1), use
    ``CalibratedGaussMarkovTurbulence``.

    Parameters
    ----------
    gain : sequence of 3 floats, optional
        K per gust axis [m s^-3/2], >= 0. Default (0.3, 0.3, 0.2).
    pole_rad_s : sequence of 3 floats, optional
        a per gust axis [rad/s], > 0. Default (0.5, 0.5, 0.5): a 2 s correlation time, so the
        default standard deviations are (0.3, 0.3, 0.2) m/s.
    heading_rad : float, optional
        Azimuth of the gust axis u in N, from n1 towards n2 [rad] (default 0).
    """

    type_name: ClassVar[str] = "gauss_markov"

    gain: Vec3 = (0.3, 0.3, 0.2)
    pole_rad_s: Vec3 = (0.5, 0.5, 0.5)
    heading_rad: float = 0.0

    def __post_init__(self) -> None:
        name = type(self).__name__
        _set(self, "gain", check_vector(f"{name}.gain", self.gain, 3, low=0.0))
        pole = check_vector(f"{name}.pole_rad_s", self.pole_rad_s, 3, low=0.0, low_open=True)
        _set(self, "pole_rad_s", pole)
        _set(self, "heading_rad", check_number(f"{name}.heading_rad", self.heading_rad))

    @property
    def std(self) -> np.ndarray:
        """Standard deviation K / sqrt(2 a) per gust axis (u, v, w), shape (3,) [m/s]."""
        return np.array(self.gain) / np.sqrt(2.0 * np.array(self.pole_rad_s))

    @property
    def correlation_time_s(self) -> np.ndarray:
        """Correlation time 1 / a per gust axis (u, v, w), shape (3,) [s]."""
        return 1.0 / np.array(self.pole_rad_s)

    @property
    def axes(self) -> np.ndarray:
        """Gust axes (u, v, w) in N, shape (3, 3) (``heading_axes``)."""
        return heading_axes(self.heading_rad)

    def _filters(self) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]:
        return tuple(
            (np.array([[-a]]), np.array([[K]]), np.array([[1.0]]))
            for K, a in zip(self.gain, self.pole_rad_s, strict=True)
        )


#: the calibrations ``gust_calibration`` knows
CALIBRATIONS = ("iec_61400_1", "mil_hdbk_1797_low_altitude")
#: Taylor's frozen-turbulence conversion (time = length / mean wind) is refused above this
#: turbulence intensity sigma_u / V: a common rule of thumb for its validity
TAYLOR_MAX_INTENSITY = 0.5
_KNOT = 1852.0 / 3600.0  # m/s per knot (exact)


@dataclass(frozen=True)
class GustCalibration:
    """Standard deviations, length scales and correlation times of the gust axes (u, v, w)
    that a published turbulence model gives (``gust_calibration``).

    Parameters
    ----------
    sigma_m_s : tuple of 3 floats
        Standard deviations [m/s].
    length_scale_m : tuple of 3 floats
        The model's length scales [m].
    correlation_time_s : tuple of 3 floats
        The Gauss-Markov correlation time 1/a of each axis [s]: the integral time scale of
        the model's spectrum at the convection speed (its value at zero frequency divided by
        4 sigma^2).
    """

    sigma_m_s: tuple[float, float, float]
    length_scale_m: tuple[float, float, float]
    correlation_time_s: tuple[float, float, float]

    @property
    def pole_rad_s(self) -> tuple[float, float, float]:
        """a = 1 / correlation time per axis [rad/s]."""
        return tuple(1.0 / T for T in self.correlation_time_s)  # type: ignore[return-value]

    @property
    def gain(self) -> tuple[float, float, float]:
        """K = sigma sqrt(2 a) per axis [m s^-3/2]."""
        return tuple(  # type: ignore[return-value]
            s * math.sqrt(2.0 * a) for s, a in zip(self.sigma_m_s, self.pole_rad_s, strict=True)
        )


def gust_calibration(
    calibration: str,
    *,
    height_m: float,
    mean_wind_m_s: float,
    wind_speed_20ft_m_s: float | None = None,
    i_ref: float | None = None,
    prefix: str = "",
) -> GustCalibration:
    """Gust standard deviations and correlation times from quantities a user knows.

    Both models give spatial statistics; the mean wind V convects them past the hovering
    helicopter (Taylor's frozen-turbulence hypothesis), so a length L becomes a time L / V.
    That conversion means nothing as V goes to zero, and it is refused (one-line
    ``ParameterError`` naming ``mean_wind_m_s``) when the intensity sigma_u / V exceeds
    ``TAYLOR_MAX_INTENSITY`` = 0.5.

    ``"mil_hdbk_1797_low_altitude"`` (MIL-F-8785C / MIL-HDBK-1797 low-altitude Dryden model;
    the formulas are ``DrydenGust``'s): with h in ft (10 ft <= h <= 1000 ft) and W20 the wind
    at 20 ft, sigma_w = 0.1 W20, sigma_u = sigma_v = sigma_w / (0.177 + 0.000823 h)^0.4,
    L_u = L_v = h / (0.177 + 0.000823 h)^1.2, L_w = h. The longitudinal Dryden spectrum is
    first-order, so T_u = L_u / V reproduces it exactly. The lateral and vertical Dryden
    spectra are second-order with autocorrelation sigma^2 e^(-x/L) (1 - x / (2 L)), whose
    integral scale is L / 2: T_v = L_v / (2 V), T_w = L_w / (2 V), which keeps each axis's
    variance and low-frequency spectral level 4 sigma^2 T.

    ``"iec_61400_1"`` (IEC 61400-1 ed. 3, 2005: normal turbulence model eq. 11, Sec. 6.3, and
    the Kaimal model of Annex B, Table B.1): sigma_1 = I_ref (0.75 V + 5.6 m/s),
    sigma_2 = 0.8 sigma_1, sigma_3 = 0.5 sigma_1; Lambda_1 = 0.7 z for z <= 60 m (42 m above);
    Kaimal lengths L = 8.1, 2.7, 0.66 Lambda_1. The Kaimal spectrum
    S(f) = 4 sigma^2 (L / V) / (1 + 6 f L / V)^(5/3) has integral time scale L / V, so
    T = L / V per axis. I_ref is 0.16 for turbulence class A, 0.14 for B, 0.12 for C. The
    standard is written for wind-turbine hub heights; at a few metres it is an extrapolation.

    Parameters
    ----------
    calibration : str
        One of ``CALIBRATIONS``.
    height_m : float
        Height above ground [m]: MIL h in [3.048, 304.8] m (10 to 1000 ft); IEC z > 0.
    mean_wind_m_s : float
        Mean wind speed at that height [m/s], > 0: the convection speed V (IEC: V_hub).
    wind_speed_20ft_m_s : float, optional
        MIL only, required there: W20, the wind speed at 20 ft [m/s], > 0 (MIL-F-8785C:
        15 kt light, 30 kt moderate, 45 kt severe turbulence).
    i_ref : float, optional
        IEC only, required there: the reference turbulence intensity I_ref in (0, 1].
    prefix : str, optional
        Prefix of the field names in error messages (e.g. ``"wind.model."``).

    Returns
    -------
    GustCalibration
    """
    allowed = f"one of {list(CALIBRATIONS)}"
    if calibration not in CALIBRATIONS:
        raise ParameterError(f"{prefix}calibration", calibration, allowed)
    mil = calibration == "mil_hdbk_1797_low_altitude"
    unused = ("i_ref", i_ref) if mil else ("wind_speed_20ft_m_s", wind_speed_20ft_m_s)
    needed = ("wind_speed_20ft_m_s", wind_speed_20ft_m_s) if mil else ("i_ref", i_ref)
    if unused[1] is not None:
        raise ParameterError(f"{prefix}{unused[0]}", unused[1], f"absent with {calibration}")
    if needed[1] is None:
        raise ParameterError(f"{prefix}{needed[0]}", None, f"a required key with {calibration}")
    V = check_number(f"{prefix}mean_wind_m_s", mean_wind_m_s, low=0.0, low_open=True, unit="[m/s]")
    if mil:
        h = check_number(
            f"{prefix}height_m",
            height_m,
            low=10 * _FT,
            high=1000 * _FT,
            allowed="3.048 <= h <= 304.8 [m] (10 to 1000 ft, MIL-F-8785C low altitude)",
        )
        w20 = check_number(
            f"{prefix}wind_speed_20ft_m_s", wind_speed_20ft_m_s, low=0.0, low_open=True
        )
        d = DrydenGust(h, w20, V)
        sigma = (d.sigma_u, d.sigma_v, d.sigma_w)
        length = (d.L_u, d.L_v, d.L_w)
        times = (d.L_u / V, d.L_v / (2.0 * V), d.L_w / (2.0 * V))
    else:
        z = check_number(f"{prefix}height_m", height_m, low=0.0, low_open=True, unit="[m]")
        iref = check_number(f"{prefix}i_ref", i_ref, low=0.0, high=1.0, low_open=True)
        s1 = iref * (0.75 * V + 5.6)
        lam = 0.7 * min(z, 60.0)
        sigma = (s1, 0.8 * s1, 0.5 * s1)
        length = (8.1 * lam, 2.7 * lam, 0.66 * lam)
        times = tuple(L / V for L in length)
    if sigma[0] > TAYLOR_MAX_INTENSITY * V:
        raise ParameterError(
            f"{prefix}mean_wind_m_s",
            V,
            f"a mean wind at which sigma_u / V <= {TAYLOR_MAX_INTENSITY:g} (here sigma_u = "
            f"{sigma[0]:.3g} m/s): the frozen-turbulence time L/V means nothing in near-calm air",
        )
    return GustCalibration(sigma, length, times)  # type: ignore[arg-type]


@dataclass(frozen=True, kw_only=True)
class CalibratedGaussMarkovTurbulence(GaussMarkovTurbulence):
    """``GaussMarkovTurbulence`` with K and a from a published turbulence model
    (``gust_calibration``): a = 1 / T and K = sigma sqrt(2 a) per gust axis (u, v, w).

    In a scenario: ``[wind.model] type = "gauss_markov"`` with ``calibration`` and the
    calibration's inputs instead of ``gain`` and ``pole_rad_s``. A ``Turbulence`` checks that
    ``mean_wind_m_s`` is the speed of its mean wind and ``heading_rad`` its direction.

    Parameters
    ----------
    calibration : str
        ``"iec_61400_1"`` or ``"mil_hdbk_1797_low_altitude"``.
    height_m, mean_wind_m_s, wind_speed_20ft_m_s, i_ref : float
        As for ``gust_calibration``.
    heading_rad : float, optional
        Azimuth of the gust axis u (along the mean wind) in N [rad] (default 0).
    """

    gain: Vec3 = field(init=False, default=(0.0, 0.0, 0.0))
    pole_rad_s: Vec3 = field(init=False, default=(1.0, 1.0, 1.0))
    calibration: str
    height_m: float
    mean_wind_m_s: float
    wind_speed_20ft_m_s: float | None = None
    i_ref: float | None = None

    def __post_init__(self) -> None:
        cal = gust_calibration(
            self.calibration,
            height_m=self.height_m,
            mean_wind_m_s=self.mean_wind_m_s,
            wind_speed_20ft_m_s=self.wind_speed_20ft_m_s,
            i_ref=self.i_ref,
            prefix="CalibratedGaussMarkovTurbulence.",
        )
        _set(self, "height_m", float(self.height_m))
        _set(self, "mean_wind_m_s", float(self.mean_wind_m_s))
        for name in ("wind_speed_20ft_m_s", "i_ref"):
            if getattr(self, name) is not None:
                _set(self, name, float(getattr(self, name)))
        _set(self, "gain", cal.gain)
        _set(self, "pole_rad_s", cal.pole_rad_s)
        super().__post_init__()

    @property
    def calibrated(self) -> GustCalibration:
        """The calibration's sigma, length scales and correlation times."""
        return gust_calibration(
            self.calibration,
            height_m=self.height_m,
            mean_wind_m_s=self.mean_wind_m_s,
            wind_speed_20ft_m_s=self.wind_speed_20ft_m_s,
            i_ref=self.i_ref,
        )

    def to_dict(self) -> dict[str, Any]:
        """The calibration's inputs (absent optional ones left out); K and a follow.
        Returns
        -------
        dict of str to object
            ``type`` and the calibration's given fields.
        """
        return {k: v for k, v in _plain_dict(self).items() if v is not None}


def heading_axes(heading_rad: float) -> np.ndarray:
    """Gust axes (u, v, w) in N, shape (3, 3), columns: u horizontal at azimuth
    ``heading_rad`` (from n1 towards n2), v horizontal to its left, w = n3.

    Parameters
    ----------
    heading_rad : float
        Azimuth of the gust axis u from n1 towards n2 [rad].

    Returns
    -------
    ndarray, shape (3, 3)
        Columns u, v, w in N (a rotation about n3).
    """
    c, s = math.cos(heading_rad), math.sin(heading_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


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
        ``DrydenGust`` or ``GaussMarkovTurbulence`` (or a custom ``GustModel``).
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
        if isinstance(self.model, CalibratedGaussMarkovTurbulence):
            _check_calibrated_mean_wind(self.model, self.N_v_mean_wind)
        gust = self.model.sample(dt * np.arange(n + 1), self.rng())
        gust.setflags(write=False)
        _set(self, "_gust", gust)

    def rng(self) -> np.random.Generator:
        """A fresh generator in the state used to draw the gusts.

        Returns
        -------
        numpy.random.Generator
            Seeded from ``seed`` and ``spawn_key``.
        """
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
        tolerance 1e-12 at the end).

        Parameters
        ----------
        t : float or ndarray
            Time(s) [s].

        Returns
        -------
        bool or ndarray of bool
            Shaped as ``t``.
        """
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

    @property
    def initial_force(self) -> np.ndarray:
        """Drag on HO at rest of the air at t = 0, the mean wind plus the gust drawn for
        t = 0, shape (3,) [N]: the force the run's initial trim balances
        (``initial_wind_force``)."""
        return self.drag.force(np.asarray(self.N_v_mean_wind, dtype=float) + self._gust[0])

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``; the gusts themselves are regenerated from the seed.
        Returns
        -------
        dict of str to object
            ``type``, the fields, and the ``model`` and ``drag`` tables.
        """
        out = _plain_dict(self)
        out["model"] = self.model.to_dict()
        out["drag"] = self.drag.to_dict()
        return out


def _check_calibrated_mean_wind(model: CalibratedGaussMarkovTurbulence, N_v_mean: Vec3) -> None:
    """The calibration's convection speed and gust axis u must be the mean wind's."""
    v = np.asarray(N_v_mean, dtype=float)
    speed = float(np.linalg.norm(v))
    if abs(model.mean_wind_m_s - speed) > 1e-9 * max(speed, 1.0):
        raise ParameterError(
            "Turbulence.model.mean_wind_m_s",
            model.mean_wind_m_s,
            f"the speed of N_v_mean_wind ({speed:g} m/s), the calibration's convection speed",
        )
    if math.hypot(v[0], v[1]) > 1e-9 * speed:
        azimuth = math.atan2(v[1], v[0])
        off = math.remainder(model.heading_rad - azimuth, 2.0 * math.pi)
        if abs(off) > 1e-9:
            raise ParameterError(
                "Turbulence.model.heading_rad",
                model.heading_rad,
                f"the azimuth of N_v_mean_wind ({azimuth:.9g} rad): gust axis u along the wind",
            )


def initial_wind_force(wind: Disturbance) -> np.ndarray:
    """The force of the air on HO at rest at t = 0, shape (3,) [N]: the drag of the mean wind
    plus the gust at t = 0 of every ``Turbulence`` in ``wind`` (``Turbulence.initial_force``);
    zero for the force profiles (pulse, step, sine, constant), which a run meets as they
    come. A run starts in the trim that balances it (``sim.setup.start_point``).

    Parameters
    ----------
    wind : Disturbance
        The run's wind (a sum is summed part by part).

    Returns
    -------
    ndarray, shape (3,)
        The force along n1, n2, n3 [N].
    """
    if isinstance(wind, WindSum):
        parts = [initial_wind_force(part) for part in wind.components]
        return np.sum(parts, axis=0) + np.zeros(3)
    if isinstance(wind, Turbulence):
        return wind.initial_force
    return np.zeros(3)


def check_wind_covers(
    wind: Disturbance, duration: float, *, name: str = "wind", source: str | None = None
) -> None:
    """Refuse a turbulence whose gust grid ends before a run of ``duration`` [s] does.

    The one check for every path: the compiled engine would hold the last gust value for the
    rest of the run and the Python loop would stop with an error mid-run; ``Scenario``
    calls it on construction, the Gymnasium environment on every episode's wind.

    Parameters
    ----------
    wind : Disturbance
        The wind (a sum is checked part by part).
    duration : float
        The run's length [s].
    name : str, optional
        The field the error names (default ``"wind"``).
    source : str, optional
        Where the wind came from (a file), for the error message.

    Returns
    -------
    None

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
