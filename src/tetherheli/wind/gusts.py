"""Gust models: linear filters driven by white noise, sampled exactly on a time grid.

``GustModel`` (the contract: filters per gust axis, their variance, PSD and exact sampling),
``DrydenGust`` (MIL-F-8785C low-altitude Dryden model; it assumes forward flight) and
``GaussMarkovTurbulence`` (first-order Gauss-Markov gusts: white noise through K/(s + a) per
axis) generate gust *velocities* along the axes ``heading_axes`` gives. Their calibration
from published models is ``wind.calibration``; the disturbance that turns a gust series into
a force is ``wind.turbulence.Turbulence``.
"""

from __future__ import annotations

import functools
import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import scipy.linalg

from .._validation import check_number, check_vector
from ..errors import ParameterError
from ._common import PlainTable, Vec3, _set

__all__ = ["DrydenGust", "GaussMarkovTurbulence", "GustModel", "heading_axes"]

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


class GustModel(PlainTable, ABC):
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
