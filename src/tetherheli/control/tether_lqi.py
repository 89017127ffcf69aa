"""An LQI designed on the *tethered* linearization, with the winch's reel rate as a fifth input.

The paper designs its LQI on the free helicopter (Sec. V-A) and leaves the tether to a
feed-forward (eq 55) and a tension PI (eq 56). Here the plant of eq 46 is the tethered model
linearized at Table V's trim (``model.linearization``: 13 states q4..u6 and LN, the tension
TC = KC (q9 - LN) of eq 28 inside A), with inputs u = [fMR3, tMR1, tMR2, fTR2, RC]
(RC = dLN/dt, eq 37). The integrators of eq 50 act on the paper's outputs [q1, q2, q3, q6];
the cost of eq 47 adds a weight on the tension deviation dTC = KC (dq9 - dLN), which is
not integrated (five inputs hold four integrated outputs; the tension is the spare degree of
freedom the weight prices):

    J = 1/2 sum( y_LQI' Qy y_LQI + q_T dTC^2 + u' Ru u ).

The gain is that of ``control.lqi`` (eqs 48-53) with Qx = C_LQI' Qy C_LQI + q_T c_T' c_T.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .._linalg import _discretize_zoh, solve_dare
from .._validation import trusted
from ..errors import DesignError, TetherheliError
from .lqi import LQIGain, _augment_lqi, _check_pd, _check_psd, _plant_arguments

__all__ = [
    "TetherLQIGain",
    "design_tether_lqi",
    "pack_gain",
    "tether_lqi_gain",
    "tethered_design",
]


@dataclass(frozen=True, eq=False)
class TetherLQIGain:
    """The tethered LQI (``design_tether_lqi``) with the free law flown after a release.

    Parameters
    ----------
    tethered : LQIGain
        K (5, 17) on [q4..u6, LN, z]; rows fMR3, tMR1, tMR2, fTR2, RC. Its ``Qy`` is the
        output weight on [y; z]; the tension weight is ``q_tension``.
    free : LQIGain
        The paper's K_LQI|F (4, 16), used once the tether is released.
    q_tension : float
        Weight on the tension deviation [1/N^2].
    """

    tethered: LQIGain
    free: LQIGain
    q_tension: float

    @property
    def K(self) -> np.ndarray:
        """The engine's packed gain (9, 17) (``layout.LAW_GAIN``, ``pack_gain``)."""
        return pack_gain(self.tethered.K, self.free.K)

    @property
    def spectral_radius(self) -> float:
        """Spectral radius of the tethered closed loop G_LQI - H_LQI K."""
        return self.tethered.spectral_radius


def pack_gain(K_tethered: np.ndarray, K_free: np.ndarray) -> np.ndarray:
    """(9, 17): rows 0-4 the tethered gain (5, 17), rows 5-8 the free gain (4, 16) with a zero
    LN column inserted at 12 (``layout.LAW_GAIN``).

    Parameters
    ----------
    K_tethered : ndarray, shape (5, 17)
        The tethered LQI's gain on [q4..u6, LN, z].
    K_free : ndarray, shape (4, 16)
        The free law's gain on [q4..u6, z].

    Returns
    -------
    ndarray, shape (9, 17)
        The packed gain the engine takes.
    """
    K = np.zeros((9, 17))
    K[:5] = K_tethered
    K[5:, :12] = K_free[:, :12]
    K[5:, 13:] = K_free[:, 12:]
    return K


def design_tether_lqi(
    G: np.ndarray,
    H: np.ndarray,
    C: np.ndarray,
    c_tension: np.ndarray,
    dt: float,
    *,
    Qy: np.ndarray,
    q_tension: float,
    Ru: np.ndarray,
) -> LQIGain:
    """The LQI gain on (G, H, C) with an extra, non-integrated tension weight.

    Parameters
    ----------
    G, H : ndarray, shapes (n, n), (n, m)
        Discrete tethered plant (eq 46) with the reel rate among the inputs.
    C : ndarray, shape (p, n)
        The integrated outputs (eq 50).
    c_tension : ndarray, shape (n,)
        The tension deviation's row, dTC = c_tension' dx [N].
    dt : float
        Sample time [s].
    Qy : ndarray, shape (2 p, 2 p)
        Weight on [y; z] (eq 47), positive semidefinite.
    q_tension : float
        Weight on dTC^2 [1/N^2], >= 0.
    Ru : ndarray, shape (m, m)
        Input weight, positive definite.

    Returns
    -------
    LQIGain
        K (m, n + p) = (Ru + H' P H)^{-1} H' P G on the augmented system (eqs 48-53).
    """
    G, H, C, dt = _plant_arguments(G, H, C, dt)
    G_lqi, H_lqi, C_lqi = _augment_lqi(G, H, C, dt)
    _check_psd("Qy", Qy)
    _check_pd("Ru", Ru)
    if not (np.isfinite(q_tension) and q_tension >= 0):
        raise TetherheliError(f"q_tension = {q_tension}; allowed: a weight >= 0 [1/N^2]")
    return _design_tether_lqi(G_lqi, H_lqi, C_lqi, c_tension, dt, Qy, q_tension, Ru)


def _design_tether_lqi(
    G_lqi: np.ndarray,
    H_lqi: np.ndarray,
    C_lqi: np.ndarray,
    c_tension: np.ndarray,
    dt: float,
    Qy: np.ndarray,
    q_tension: float,
    Ru: np.ndarray,
) -> LQIGain:
    """``design_tether_lqi`` on the augmented system (``lqi._augment_lqi``) with weights
    already checked (a run's set-up: the scenario's positive diagonals and q_tension >= 0)."""
    c_aug = np.zeros(G_lqi.shape[0])
    c_aug[: H_lqi.shape[0] - C_lqi.shape[0] // 2] = c_tension  # the plant's n states
    Qx = C_lqi.T @ Qy @ C_lqi + q_tension * np.outer(c_aug, c_aug)
    try:
        P = solve_dare(G_lqi, H_lqi, Qx, Ru)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise DesignError(
            f"no stabilising solution of the tethered LQI's Riccati equation (eq 49): {exc}"
        ) from None
    P = 0.5 * (P + P.T)
    K = np.linalg.solve(Ru + H_lqi.T @ P @ H_lqi, H_lqi.T @ P @ G_lqi)
    gain = trusted(LQIGain, K=K, dt=dt, Qy=Qy, Ru=Ru, P=P, G_lqi=G_lqi, H_lqi=H_lqi)
    if not gain.spectral_radius < 1.0:
        raise DesignError(
            f"the tethered LQI's closed loop has spectral radius {gain.spectral_radius:.6g} >= 1"
        )
    return gain


def tethered_design(params, T_ref: float, q9: float, dt: float):
    """The tethered plant the LQI is designed on: (G, H, C, c_tension) at Table V's trim
    (tension T_ref [N], tether length q9 [m]), ZOH-discretised at dt [s] (eq 46), inputs
    [fMR3, tMR1, tMR2, fTR2, RC].

    Cached per (params, T_ref, q9, dt); the returned arrays are read-only.

    Parameters
    ----------
    params : Params
        The model parameters (helicopter, tether, tension control).
    T_ref : float
        Trim tension [N] (Table V's trim is at the reference tension, eq 40).
    q9 : float
        Trim tether length q9 [m].
    dt : float
        Sample time [s] of the zero-order hold (eq 46).

    Returns
    -------
    G : ndarray, shape (13, 13)
        Discrete state matrix on [q4..q9, u1..u6, LN].
    H : ndarray, shape (13, 5)
        Discrete input matrix; columns fMR3 [N], tMR1, tMR2 [N m], fTR2 [N], RC [m/s].
    C : ndarray, shape (4, 13)
        The outputs [q1, q2, q3, q6] linearized at trim (eq 50's integrated outputs).
    c_tension : ndarray, shape (13,)
        The tension deviation's row, dTC = KC (dq9 - dLN) (eq 28; the rope's law:
        ``TetherParams.stiffness``) [N per state unit].
    """
    from ..model.trim import check_trim_arguments

    T_ref, q9 = check_trim_arguments(params, T_ref, q9)
    return _tethered_design(params, T_ref, q9, float(dt))


@lru_cache(maxsize=32)
def _tethered_design(params, T_ref: float, q9: float, dt: float):
    """``tethered_design`` of a trim tension and length already checked (a run's set-up)."""
    from ..model import TetheredHelicopter
    from ..model.linearization import _linearize
    from ..model.trim import _hover_trim
    from ..names import INPUT, REEL_RATE

    model = TetheredHelicopter(params)
    trim = _hover_trim(params, T_ref, q9)
    if not trim.tension > 0.0:
        raise TetherheliError(
            f"the tethered LQI needs a taut tether at trim; tension {trim.tension:g} N"
        )
    lin = _linearize(model, trim)
    B = lin.input_matrix((*INPUT, REEL_RATE))
    G, H = _discretize_zoh(lin.A, B, dt)
    dT_dq9, dT_dLN = params.tether.stiffness(trim.x[5], trim.x[12])  # eq 28: (KC, -KC)
    c_t = np.zeros(lin.A.shape[0])
    c_t[lin.state_names.index("q9")] = dT_dq9
    c_t[lin.state_names.index("LN")] = dT_dLN
    for a in (G, H, lin.C, c_t):
        a.setflags(write=False)
    return G, H, lin.C, c_t


def tether_lqi_gain(
    params,
    T_ref: float,
    q9: float,
    dt: float,
    Qy: tuple,
    q_tension: float,
    Ru: tuple,
    free: LQIGain,
) -> TetherLQIGain:
    """``design_tether_lqi`` on ``tethered_design(params, T_ref, q9, dt)`` with diagonal
    weights Qy (8,) and Ru (5,) (tuples), paired with the free law ``free``; cached, as
    ``runs.start.paper_gain`` is (a batch's runs share it).

    Parameters
    ----------
    params : Params
        The model parameters.
    T_ref : float
        Trim tension [N].
    q9 : float
        Trim tether length q9 [m].
    dt : float
        Sample time [s].
    Qy : tuple of float, length 8
        Diagonal of the output weight on [y; z] (eq 47).
    q_tension : float
        Weight on the tension deviation dTC^2 [1/N^2], >= 0.
    Ru : tuple of float, length 5
        Diagonal of the input weight on [fMR3, tMR1, tMR2, fTR2, RC], > 0.
    free : LQIGain
        The free law K_LQI|F (4, 16) flown after a release.

    Returns
    -------
    TetherLQIGain
        The tethered gain (5, 17) with ``free`` and ``q_tension``.
    """
    from ..model.trim import check_trim_arguments

    T_ref, q9 = check_trim_arguments(params, T_ref, q9)
    return _tether_lqi_gain(params, T_ref, q9, dt, Qy, q_tension, Ru, free)


@lru_cache(maxsize=64)
def _tether_lqi_gain(
    params,
    T_ref: float,
    q9: float,
    dt: float,
    Qy: tuple,
    q_tension: float,
    Ru: tuple,
    free: LQIGain,
) -> TetherLQIGain:
    """``tether_lqi_gain`` of a trim tension and length already checked (a run's set-up
    from its ``Scenario``), cached."""
    G, H, C, c_t = _tethered_design(params, T_ref, q9, float(dt))
    G_lqi, H_lqi, C_lqi = _augment_lqi(G, H, C, dt)  # the scenario's dt and weights
    gain = _design_tether_lqi(
        G_lqi, H_lqi, C_lqi, c_t, dt, np.diag(Qy), float(q_tension), np.diag(Ru)
    )
    return TetherLQIGain(gain, free, float(q_tension))
