"""Discrete-time LQI position controller of the helicopter (paper Sec. V-A, eqs 46-53).

The plant is the ZOH-discretised linearisation about hover (eq 46),

    x_{k+1} = G x_k + H u_k,    y_k = C x_k,

with x (n,), u (m,), y (p,) deviations from trim. The integrators of eq 50 are

    z_{k+1} = z_k + dt (r_k - y_k),

so the augmented system of eqs 51-53 is

    [x; z]_{k+1} = G_LQI [x; z]_k + H_LQI u_k,
    G_LQI = [[G, 0], [T, I_p]],  T = -dt C,   H_LQI = [[H], [0]],
    y_LQI = C_LQI [x; z],        C_LQI = [[C, 0], [0, I_p]].

The gain minimises J = 1/2 sum(y_LQI' Qy y_LQI + u' Ru u) (eq 47): with
Qx = C_LQI' Qy C_LQI, P solves the DARE of eq 49 on (G_LQI, H_LQI) and
K = (Ru + H_LQI' P H_LQI)^{-1} H_LQI' P G_LQI (eq 48). The control law is
u_k = -K [x_k; z_k] = -Kx x_k - Kz z_k.

Note: python-control's ``dlqr(..., integral_action=M)`` augments with
z_{k+1} = z_k + M x_k; the paper's form is recovered with M = -dt C (see
tests/test_lqi.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .._linalg import check_dt, discretize_zoh, real_matrix, solve_dare
from .._validation import trusted
from ..errors import DesignError, TetherheliError

__all__ = [
    "PAPER_QY",
    "PAPER_RU",
    "LQIGain",
    "augment_lqi",
    "design_lqi",
    "discretize_zoh",
]

PAPER_QY: np.ndarray = np.diag([1.0, 1.0, 1.0, 1.0, 10.0, 10.0, 10.0, 10.0])
"""The paper's output weight Qy (Sec. V-A, after eq 53), (8, 8): 1 on the outputs
[q1, q2, q3, q6] and 10 on their four integrators."""
PAPER_QY.setflags(write=False)

PAPER_RU: np.ndarray = np.eye(4)
"""The paper's input weight Ru = I4 (Sec. V-A, after eq 53), (4, 4), on the inputs
[fMR,3, tMR,1, tMR,2, fTR,2]."""
PAPER_RU.setflags(write=False)


# --------------------------------------------------------------------------------------------
# validation helpers (one-line ValueErrors naming the argument)
# --------------------------------------------------------------------------------------------


def _check_symmetric(name: str, M: np.ndarray) -> None:
    scale = max(1.0, float(np.max(np.abs(M))))
    if not np.allclose(M, M.T, rtol=0.0, atol=1e-12 * scale):
        raise TetherheliError(f"{name} is not symmetric; allowed: a symmetric matrix")


def _check_psd(name: str, M: np.ndarray) -> None:
    _check_symmetric(name, M)
    eig = np.linalg.eigvalsh(M)
    if eig[0] < -1e-12 * max(1.0, float(np.max(np.abs(eig)))):
        raise TetherheliError(
            f"{name} has eigenvalue {eig[0]:.3g} < 0; allowed: symmetric positive semidefinite"
        )


def _check_pd(name: str, M: np.ndarray) -> None:
    _check_symmetric(name, M)
    try:
        np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        eig = np.linalg.eigvalsh(M)
        raise TetherheliError(
            f"{name} has eigenvalue {eig[0]:.3g} <= 0; allowed: symmetric positive definite"
        ) from None


# --------------------------------------------------------------------------------------------
# discretisation and augmentation
# --------------------------------------------------------------------------------------------


def augment_lqi(
    G: ArrayLike, H: ArrayLike, C: ArrayLike, dt: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The LQI-augmented system of eqs 51-53.

    Parameters
    ----------
    G : array_like, shape (n, n)
        Discrete state matrix of eq 46.
    H : array_like, shape (n, m)
        Discrete input matrix of eq 46.
    C : array_like, shape (p, n)
        Output matrix of eq 46.
    dt : float
        Sample time [s] of the forward-Euler integrators of eq 50.

    Returns
    -------
    G_lqi : ndarray, shape (n + p, n + p)
        [[G, 0], [T, I_p]] with T = -dt C (eq 53).
    H_lqi : ndarray, shape (n + p, m)
        [[H], [0]] (eq 53).
    C_lqi : ndarray, shape (2 p, n + p)
        [[C, 0], [0, I_p]] (eq 53).
    """
    return _augment_lqi(*_plant_arguments(G, H, C, dt))


def _plant_arguments(
    G: ArrayLike, H: ArrayLike, C: ArrayLike, dt: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The discrete plant (G, H, C) and sample time of a design's arguments checked: finite
    float copies of matching shapes, dt a finite number > 0 [s] (one-line errors naming the
    argument)."""
    dt = check_dt(dt)
    G = real_matrix("G", G, (None, None))
    n = G.shape[0]
    if G.shape[1] != n:
        raise TetherheliError(f"G has shape {G.shape}; allowed: square (n, n)")
    return G, real_matrix("H", H, (n, None)), real_matrix("C", C, (None, n)), dt


def _augment_lqi(
    G: np.ndarray, H: np.ndarray, C: np.ndarray, dt: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``augment_lqi`` of finite float arrays of matching shapes and a checked dt (a run's
    set-up: its plant from the checked model, its dt from the checked scenario)."""
    n, m = H.shape
    p = C.shape[0]
    G_lqi = np.zeros((n + p, n + p))
    G_lqi[:n, :n] = G
    G_lqi[n:, :n] = -dt * C
    G_lqi[n:, n:] = np.eye(p)
    H_lqi = np.zeros((n + p, m))
    H_lqi[:n] = H
    C_lqi = np.zeros((2 * p, n + p))
    C_lqi[:p, :n] = C
    C_lqi[p:, n:] = np.eye(p)
    return G_lqi, H_lqi, C_lqi


# --------------------------------------------------------------------------------------------
# the gain
# --------------------------------------------------------------------------------------------


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class LQIGain:
    """An LQI gain K_LQI of eqs 48-53 with the data it was designed from.

    The control law is u_k = -K [x_k; z_k] = -Kx x_k - Kz z_k, with the integrators updated by
    eq 50, z_{k+1} = z_k + dt (r_k - y_k). All arrays are read-only copies.

    Parameters
    ----------
    K : ndarray, shape (m, n + p)
        The gain K_LQI [input unit / state unit].
    dt : float
        Sample time [s].
    Qy : ndarray, shape (2 p, 2 p)
        Output weight of eq 47 on y_LQI = [y; z].
    Ru : ndarray, shape (m, m)
        Input weight of eq 47.
    P : ndarray, shape (n + p, n + p)
        Stabilising solution of the DARE (eq 49) on the augmented system.
    G_lqi : ndarray, shape (n + p, n + p)
        Augmented state matrix of eq 53.
    H_lqi : ndarray, shape (n + p, m)
        Augmented input matrix of eq 53.
    """

    K: np.ndarray
    dt: float
    Qy: np.ndarray
    Ru: np.ndarray
    P: np.ndarray
    G_lqi: np.ndarray
    H_lqi: np.ndarray

    def __post_init__(self) -> None:
        self._derive()
        object.__setattr__(self, "dt", check_dt(self.dt))
        if self.K.ndim != 2:
            raise TetherheliError(f"LQIGain: K has shape {self.K.shape}; allowed: (m, n + p)")
        m, nz = self.K.shape
        p2 = self.Qy.shape[0]
        expected = {
            "Qy": (p2, p2),
            "Ru": (m, m),
            "P": (nz, nz),
            "G_lqi": (nz, nz),
            "H_lqi": (nz, m),
        }
        for name, shape in expected.items():
            if getattr(self, name).shape != shape:
                raise TetherheliError(
                    f"LQIGain: {name} has shape {getattr(self, name).shape}; "
                    f"allowed: {shape} to fit K {self.K.shape}"
                )
        if p2 % 2 or not 0 < p2 // 2 < nz:
            raise TetherheliError(
                f"LQIGain: Qy has shape {self.Qy.shape}; allowed: (2 p, 2 p) with 0 < p < {nz}"
            )

    def _derive(self) -> None:
        # read-only copies of the arrays (also of a ``trusted`` build: a design's own gain)
        for name in ("K", "Qy", "Ru", "P", "G_lqi", "H_lqi"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))

    # sizes ------------------------------------------------------------------------------------
    @property
    def m(self) -> int:
        """Number of inputs m."""
        return int(self.K.shape[0])

    @property
    def p(self) -> int:
        """Number of outputs (and integrators) p."""
        return int(self.Qy.shape[0] // 2)

    @property
    def n(self) -> int:
        """Number of plant states n."""
        return int(self.K.shape[1] - self.p)

    # gain blocks ------------------------------------------------------------------------------
    @property
    def Kx(self) -> np.ndarray:
        """State block of K, shape (m, n)."""
        return self.K[:, : self.n]

    @property
    def Kz(self) -> np.ndarray:
        """Integrator block of K, shape (m, p)."""
        return self.K[:, self.n :]

    # closed loop ------------------------------------------------------------------------------
    @property
    def closed_loop(self) -> np.ndarray:
        """Discrete closed-loop matrix G_LQI - H_LQI K, shape (n + p, n + p)."""
        return self.G_lqi - self.H_lqi @ self.K

    @property
    def spectral_radius(self) -> float:
        """Spectral radius of G_LQI - H_LQI K (< 1 for a stabilising gain)."""
        return float(np.max(np.abs(np.linalg.eigvals(self.closed_loop))))

    # use --------------------------------------------------------------------------------------
    def control(self, x: ArrayLike, z: ArrayLike) -> np.ndarray:
        """The LQI input deviation u_k = -Kx x_k - Kz z_k, shape (m,).

        Parameters
        ----------
        x : array_like, shape (n,)
            Plant state deviation from trim.
        z : array_like, shape (p,)
            Integrator state of eq 50.

        Returns
        -------
        ndarray, shape (m,)
            The input deviation from trim [input unit].
        """
        return -(self.Kx @ np.asarray(x, dtype=float)) - self.Kz @ np.asarray(z, dtype=float)

    def integrate(self, z: ArrayLike, r: ArrayLike, y: ArrayLike) -> np.ndarray:
        """The next integrator state z_{k+1} = z_k + dt (r_k - y_k) (eq 50), shape (p,).

        Parameters
        ----------
        z : array_like, shape (p,)
            Integrator state at sample k [output unit s].
        r : array_like, shape (p,)
            Reference deviation at sample k [output unit].
        y : array_like, shape (p,)
            Output deviation at sample k [output unit].

        Returns
        -------
        ndarray, shape (p,)
            z_{k+1} [output unit s].
        """
        z = np.asarray(z, dtype=float)
        return z + self.dt * (np.asarray(r, dtype=float) - np.asarray(y, dtype=float))

    def as_dict(self) -> dict[str, Any]:
        """A JSON-friendly record: sizes, dt, Qy, Ru, K, and the closed-loop spectral radius.

        Returns
        -------
        dict of str to object
            Keys ``n``, ``m``, ``p`` (int), ``dt`` [s], ``Qy``, ``Ru``, ``K`` (nested lists)
            and ``spectral_radius`` (float).
        """
        return {
            "n": self.n,
            "m": self.m,
            "p": self.p,
            "dt": self.dt,
            "Qy": self.Qy.tolist(),
            "Ru": self.Ru.tolist(),
            "K": self.K.tolist(),
            "spectral_radius": self.spectral_radius,
        }


def design_lqi(
    G: ArrayLike,
    H: ArrayLike,
    C: ArrayLike,
    dt: float,
    *,
    Qy: ArrayLike | None = None,
    Ru: ArrayLike | None = None,
) -> LQIGain:
    """Design the paper's LQI gain (eqs 47-53).

    Builds the augmented system of eq 53, weights Qx = C_LQI' Qy C_LQI, solves the DARE of
    eq 49 with :func:`scipy.linalg.solve_discrete_are`, and forms
    K = (Ru + H_LQI' P H_LQI)^{-1} H_LQI' P G_LQI (eq 48).

    Parameters
    ----------
    G : array_like, shape (n, n)
        Discrete state matrix of eq 46 (e.g. from :func:`discretize_zoh`).
    H : array_like, shape (n, m)
        Discrete input matrix of eq 46.
    C : array_like, shape (p, n)
        Output matrix of eq 46.
    dt : float
        Sample time [s]; also the step of the integrators of eq 50.
    Qy : array_like, shape (2 p, 2 p), optional
        Symmetric positive semidefinite weight on y_LQI = [y; z]. Defaults to
        :data:`PAPER_QY` when p = 4; required otherwise.
    Ru : array_like, shape (m, m), optional
        Symmetric positive definite input weight. Defaults to :data:`PAPER_RU` when m = 4;
        required otherwise.

    Returns
    -------
    LQIGain
        The gain K (m, n + p) with its design data.

    Raises
    ------
    ValueError
        On a bad argument (shape, non-finite entries, dt, Qy not PSD, Ru not PD), or when no
        stabilising DARE solution exists (e.g. (G_LQI, H_LQI) not stabilisable, or a mode on
        the unit circle unobservable from Qx).
    """
    G, H, C, dt = _plant_arguments(G, H, C, dt)
    G_lqi, H_lqi, C_lqi = _augment_lqi(G, H, C, dt)
    m = H_lqi.shape[1]
    p = C_lqi.shape[0] // 2
    if Qy is None:
        if p != PAPER_QY.shape[0] // 2:
            raise TetherheliError(f"Qy is required when p = {p} (the paper's default needs p = 4)")
        Qy = PAPER_QY
    if Ru is None:
        if m != PAPER_RU.shape[0]:
            raise TetherheliError(f"Ru is required when m = {m} (the paper's default needs m = 4)")
        Ru = PAPER_RU
    Qy = real_matrix("Qy", Qy, (2 * p, 2 * p))
    Ru = real_matrix("Ru", Ru, (m, m))
    _check_psd("Qy", Qy)
    _check_pd("Ru", Ru)
    return _design_lqi(G_lqi, H_lqi, C_lqi, dt, 0.5 * (Qy + Qy.T), 0.5 * (Ru + Ru.T))


def _design_lqi(
    G_lqi: np.ndarray,
    H_lqi: np.ndarray,
    C_lqi: np.ndarray,
    dt: float,
    Qy: np.ndarray,
    Ru: np.ndarray,
) -> LQIGain:
    """``design_lqi`` on the augmented system (``_augment_lqi``) with symmetric weights
    already checked (Qy positive semidefinite, Ru positive definite: a run's set-up, whose
    weights are the checked scenario's positive diagonals); raises ``DesignError`` as it
    does."""
    Qx = C_lqi.T @ Qy @ C_lqi  # eq 49's Qx = C' Qy C on the augmented system

    try:
        P = solve_dare(G_lqi, H_lqi, Qx, Ru)
    except (np.linalg.LinAlgError, ValueError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DesignError(
            f"no stabilising solution of the LQI Riccati equation (eq 49): {msg}; "
            "check that (G_LQI, H_LQI) is stabilisable and Qx detectable"
        ) from None
    if not np.all(np.isfinite(P)):
        raise DesignError("the LQI Riccati solution (eq 49) is not finite")
    P = 0.5 * (P + P.T)
    K = np.linalg.solve(Ru + H_lqi.T @ P @ H_lqi, H_lqi.T @ P @ G_lqi)  # eq 48
    gain = trusted(LQIGain, K=K, dt=dt, Qy=Qy, Ru=Ru, P=P, G_lqi=G_lqi, H_lqi=H_lqi)
    rho = gain.spectral_radius
    if not rho < 1.0:
        raise DesignError(
            f"the LQI closed loop G_LQI - H_LQI K has spectral radius {rho:.6g} >= 1; "
            "check that (G_LQI, H_LQI) is stabilisable and Qx detectable"
        )
    return gain
