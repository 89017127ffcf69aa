"""The constrained linear MPC's design (flown by ``control.mpc.MPCController``): its plant,
steady-state target, condensed prediction and cost, from explicit numbers.

Plant. The tethered linearization at Table V's trim (``tether_lqi.tethered_design``: 13
states q4..q9, u1..u6, LN; inputs u = [fMR3, tMR1, tMR2, fTR2, RC]; the tension row
dTC = KC (dq9 - dLN) of eq 28), ZOH-discretised (eq 46), with the wind force on HO as an
input disturbance d (3,) [N] (``LinearModel.E_wind``):

    x_{k+1} = G x_k + H u_k + H_d d_k,    d_{k+1} = d_k.

On the free configuration the same on the free linearization (12 states, 4 inputs, no
tension). The paper's integrators (eq 50), z_{k+1} = z_k + dt (r - y_k), augment the state
as in ``lqi.augment_lqi``: xi = [x; z].

Target. A disturbance estimate d_hat (``control.mpc``: offset-free) enters as a steady-state
target (x_s, u_s): (I - G) x_s - H u_s = H_d d_hat, C x_s = 0, with the least
u_s' Ru u_s + q_T (c_T' x_s)^2 (the tension, the spare degree of freedom of five inputs and
four outputs, priced as in the cost). The MPC then regulates dxi = [x - x_s; z],
du = u - u_s, whose dynamics are exactly the LQI's augmented ones (G_LQI, H_LQI).

Cost (the tethered LQI's, ``tether_lqi.design_tether_lqi``), over the horizon N:

    J = sum_{j<N} (dxi_j' Qx dxi_j + du_j' Ru du_j) + dxi_N' P dxi_N + w sum_j (s_j + s_j^2),

Qx = C_LQI' Qy C_LQI + q_T c_T c_T', P the DARE's solution of the same weights, so the
unconstrained MPC equals the infinite-horizon LQ law (the tethered LQI's gain); the slacks
s_j soften the tension bounds (``control.mpc``: constraints).

Formulation: condensed. The states are eliminated (xi_j = Phi_j xi_0 + Gamma_j U), leaving
N m inputs and N slacks: with the default N = 10 that is 60 variables against 230 for the
sparse form, a dense Hessian of 50 x 50 (condition number about 2.3) that OSQP factorises
once. The horizon is short (0.1 s at dt = 10 ms) so the condensed prediction of the
open-loop unstable hover stays well conditioned; a longer one also costs more per OSQP
iteration (the dense block grows as N^2) and, on the paper's runs, did not fly better
(N = 20 against N = 10: see ``benchmarks/bench_mpc.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import sparse

from .._linalg import _discretize_zoh, solve_dare
from ..errors import DesignError, TetherheliError
from ..sensing.config import _checked_dt
from .lqi import _augment_lqi, _check_pd, _check_psd, _plant_arguments
from .observer import DisturbanceKalman, _measurement_covariance

__all__ = [
    "MPCDesign",
    "design_mpc",
    "design_mpc_kalman",
    "hover_design",
    "mpc_plant",
    "mpc_sample_seconds",
]


@dataclass(frozen=True, eq=False)
class MPCDesign:
    """The MPC's condensed prediction and cost (``design_mpc``).

    Parameters
    ----------
    G_aug, H_aug : ndarray, shapes (na, na), (na, m)
        The LQI-augmented plant (eqs 51-53), na = n + 4.
    Qx, Ru, P : ndarray
        Stage weights on xi (na, na) and u (m, m), terminal weight (na, na).
    K : ndarray, shape (m, na)
        The unconstrained first move's gain, du_0 = -K dxi_0 (the LQ law when P is the DARE's).
    Sx, Su : ndarray, shapes (N na, na), (N na, N m)
        Predictions xi_1..xi_N = Sx xi_0 + Su U.
    hessian, linear : ndarray, shapes (N m, N m), (N m, na)
        J = U' hessian U + 2 xi_0' linear' U + const.
    c_aug : ndarray, shape (na,), or None
        The tension deviation's row on xi [N per unit] (None: free configuration).
    Hd : ndarray, shape (n, 3)
        The wind force's discrete input matrix.
    target : ndarray, shape (n + m, 3)
        (x_s, u_s) = target d for a disturbance d [N].
    """

    G_aug: np.ndarray
    H_aug: np.ndarray
    Qx: np.ndarray
    Ru: np.ndarray
    P: np.ndarray
    K: np.ndarray
    Sx: np.ndarray
    Su: np.ndarray
    hessian: np.ndarray
    linear: np.ndarray
    c_aug: np.ndarray | None
    Hd: np.ndarray
    target: np.ndarray

    @property
    def horizon(self) -> int:
        """N, samples."""
        return self.Su.shape[1] // self.Ru.shape[0]

    @property
    def n_inputs(self) -> int:
        """m: 5 tethered (rotor inputs and reel rate), 4 free."""
        return self.Ru.shape[0]

    @property
    def n_states(self) -> int:
        """n: the plant's states (13 tethered, 12 free), without the integrators."""
        return self.G_aug.shape[0] - 4


def design_mpc(
    G: np.ndarray,
    H: np.ndarray,
    C: np.ndarray,
    Hd: np.ndarray,
    dt: float,
    *,
    Qy: np.ndarray,
    Ru: np.ndarray,
    horizon: int,
    c_tension: np.ndarray | None = None,
    q_tension: float = 0.0,
    terminal: np.ndarray | None = None,
) -> MPCDesign:
    """The condensed MPC of the module docstring on the discrete plant (G, H, C).

    Parameters
    ----------
    G, H, C : ndarray, shapes (n, n), (n, m), (4, n)
        Discrete plant and the integrated outputs (eqs 46, 50).
    Hd : ndarray, shape (n, 3)
        Discrete input matrix of the wind force on HO [per N].
    dt : float
        Sample time [s].
    Qy : ndarray, shape (8, 8)
        Weight on [y; z] (eq 47).
    Ru : ndarray, shape (m, m)
        Input weight, positive definite.
    horizon : int
        N >= 1 samples.
    c_tension : ndarray, shape (n,), optional
        The tension deviation's row (tethered; None: free).
    q_tension : float, optional
        Weight on the tension deviation [1/N^2].
    terminal : ndarray, shape (n + 4, n + 4), optional
        Terminal weight; default the DARE's solution of the same weights (infinite horizon).

    Returns
    -------
    MPCDesign
    """
    G_a, H_a, C_a = _augment_lqi(*_plant_arguments(G, H, C, dt))
    _check_psd("Qy", Qy)
    _check_pd("Ru", Ru)
    if not (isinstance(horizon, int) and horizon >= 1):
        raise TetherheliError(f"horizon = {horizon!r}; allowed: an integer >= 1 [samples]")
    if terminal is not None:
        terminal = np.asarray(terminal, dtype=float)
        _check_psd("terminal", terminal)
    return _design_mpc(
        G, H, C, Hd, G_a, H_a, C_a, Qy=Qy, Ru=Ru, horizon=horizon, c_tension=c_tension,
        q_tension=q_tension, terminal=terminal,
    )  # fmt: skip


def _design_mpc(
    G, H, C, Hd, G_a, H_a, C_a, *, Qy, Ru, horizon, c_tension, q_tension, terminal
) -> MPCDesign:  # fmt: skip
    """``design_mpc`` on the augmented system (``lqi._augment_lqi``) with weights and a
    horizon already checked (a run's set-up: the scenario's positive diagonals)."""
    n, m = H.shape
    na = n + 4
    c_aug = None
    Qx = C_a.T @ Qy @ C_a
    if c_tension is not None:
        c_aug = np.zeros(na)
        c_aug[:n] = c_tension
        Qx = Qx + q_tension * np.outer(c_aug, c_aug)
    if terminal is None:
        try:
            P = solve_dare(G_a, H_a, Qx, Ru)
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise DesignError(
                f"no stabilising solution of the MPC's terminal DARE: {exc}"
            ) from None
        P = 0.5 * (P + P.T)
    else:
        P = terminal
    N = horizon
    Sx = np.zeros((N * na, na))
    Su = np.zeros((N * na, N * m))
    power = np.eye(na)
    for j in range(N):  # xi_{j+1} = G_a xi_j + H_a u_j
        power = G_a @ power
        Sx[j * na : (j + 1) * na] = power
        if j == 0:
            Su[:na, :m] = H_a
        else:
            Su[j * na : (j + 1) * na] = G_a @ Su[(j - 1) * na : j * na]
            Su[j * na : (j + 1) * na, j * m : (j + 1) * m] = H_a
    Qbar = sparse.block_diag([Qx] * (N - 1) + [P]).toarray()
    hessian = Su.T @ Qbar @ Su + np.kron(np.eye(N), Ru)
    hessian = 0.5 * (hessian + hessian.T)
    linear = Su.T @ Qbar @ Sx
    K = np.linalg.solve(hessian, linear)[:m]
    target = _target_map(G, H, C, Hd, Ru, c_tension, q_tension)
    return MPCDesign(G_a, H_a, Qx, Ru, P, K, Sx, Su, hessian, linear, c_aug, Hd, target)


def _target_map(G, H, C, Hd, Ru, c_tension, q_tension):
    """(n + m, 3): the steady state and input (x_s, u_s) of a constant disturbance d with the
    outputs at their references, least u_s' Ru u_s + q_T (c_T' x_s)^2: the KKT system of
    min 1/2 v' W v s.t. E v = b, v = (x_s, u_s), E = [[I - G, -H], [C, 0]], b = [Hd d; 0]."""
    n, m = H.shape
    W = np.zeros((n + m, n + m))
    W[n:, n:] = Ru
    if c_tension is not None:
        W[:n, :n] = q_tension * np.outer(c_tension, c_tension)
    E = np.block([[np.eye(n) - G, -H], [C, np.zeros((C.shape[0], m))]])
    kkt = np.block([[W, E.T], [E, np.zeros((E.shape[0], E.shape[0]))]])
    rhs = np.zeros((kkt.shape[0], Hd.shape[1]))
    rhs[n + m : n + m + n] = Hd
    try:
        sol = np.linalg.solve(kkt, rhs)
    except np.linalg.LinAlgError:
        raise TetherheliError("the MPC's steady-state target has no unique solution") from None
    return sol[: n + m]


def mpc_plant(params, configuration: str, T_ref: float, q9: float, dt: float) -> tuple:
    """The MPC's design plant: (G, H, C, Hd, c_tension) at the hover trim, ZOH at dt [s].

    Parameters
    ----------
    params : Params
        Model parameters.
    configuration : {"tethered", "free"}
        Tethered: ``tether_lqi.tethered_design`` (13 states, 5 inputs, tension row); free:
        the linearization at TC = 0 on q4..u6 (12 states, 4 inputs; c_tension None).
    T_ref : float
        Trim tension [N] (tethered).
    q9 : float
        Tether length at trim [m].
    dt : float
        Sample time [s].

    Returns
    -------
    tuple
        G (n, n), H (n, m), C (4, n), Hd (n, 3) [per N], c_tension (n,) or None.
    """
    T_ref, q9 = _trim_arguments(params, configuration, T_ref, q9)
    return _mpc_plant(params, configuration, T_ref, q9, float(dt))


def _trim_arguments(params, configuration: str, T_ref: object, q9: object) -> tuple[float, float]:
    """The design trim's tension and length checked (``model.trim.check_trim_arguments``;
    free: the trim at TC = 0, ``T_ref`` unused)."""
    from ..model.trim import check_trim_arguments

    if configuration == "tethered":
        return check_trim_arguments(params, T_ref, q9)
    return float(T_ref), check_trim_arguments(params, 0.0, q9)[1]  # type: ignore[arg-type]


@lru_cache(maxsize=16)
def _mpc_plant(params, configuration: str, T_ref: float, q9: float, dt: float) -> tuple:
    """``mpc_plant`` of a trim tension and length already checked (a run's set-up), cached."""
    from ..model import TetheredHelicopter
    from ..model.linearization import _linearize
    from ..model.trim import _hover_trim
    from ..names import TETHERED_STATE, WIND
    from .tether_lqi import _tethered_design

    model = TetheredHelicopter(params)
    if configuration == "tethered":
        G, H, C, c_t = _tethered_design(params, T_ref, q9, dt)
        lin = _linearize(model, _hover_trim(params, T_ref, q9))
    else:
        lin = _linearize(model, _hover_trim(params, 0.0, q9)).select(TETHERED_STATE[:12])
        G, H = _discretize_zoh(lin.A, lin.B, dt)
        C, c_t = lin.C, None
    Hd = _discretize_zoh(lin.A, lin.input_matrix(WIND), dt)[1]
    return G, H, C, Hd, c_t


@lru_cache(maxsize=16)
def _hover_design(params, configuration, T_ref, q9, dt, Qy, Ru, q_tension, horizon):
    """``hover_design`` of a trim tension and length already checked (a run's set-up from its
    ``Scenario``), cached; ``Qy``, ``Ru``: tuples."""
    G, H, C, Hd, c_t = _mpc_plant(params, configuration, float(T_ref), float(q9), float(dt))
    m = H.shape[1]
    G_a, H_a, C_a = _augment_lqi(G, H, C, dt)  # the scenario's dt, weights and horizon
    return _design_mpc(
        G, H, C, Hd, G_a, H_a, C_a, Qy=np.diag(Qy), Ru=np.diag(Ru[:m]), horizon=horizon,
        c_tension=c_t, q_tension=q_tension, terminal=None,
    )  # fmt: skip


#: Seconds per control sample of the MPC: Python's loop and OSQP's set-up, and the QP's
#: condensed Hessian of (horizon x inputs)^2 entries; 0.37 s at horizon = 400 (measured
#: on the paper's tethered run).
_SAMPLE_BASE_S = 5e-4
_SAMPLE_AT_400_S = 0.37


def mpc_sample_seconds(horizon: int) -> float:
    """The estimated compute time of one MPC sample at ``horizon`` [s] (the QP's size grows
    with the horizon; OSQP's work with its square).

    Parameters
    ----------
    horizon : int
        ``[control.mpc] horizon`` [samples].

    Returns
    -------
    float
        Seconds per control sample.
    """
    return _SAMPLE_BASE_S + _SAMPLE_AT_400_S * (horizon / 400.0) ** 2


def hover_design(
    params,
    configuration: str,
    T_ref: float,
    q9: float,
    dt: float,
    *,
    Qy: tuple[float, ...],
    Ru: tuple[float, ...],
    q_tension: float,
    horizon: int,
) -> MPCDesign:
    """The MPC's design at the hover trim (``mpc_plant``, ``design_mpc`` with diagonal
    weights), cached per set of arguments (a Monte Carlo designs the same model many times).

    Parameters
    ----------
    params : Params
        The parameters of the design model.
    configuration : {"tethered", "free"}
        The configuration (``mpc_plant``).
    T_ref : float
        Trim tension [N] of the design model (0 for the free configuration).
    q9 : float
        Tether length at trim [m].
    dt : float
        Sample time [s].
    Qy : tuple of float, length 8
        Diagonal of the weight on [y; z] (eq 47).
    Ru : tuple of float, length >= m
        Diagonal of the input weight; its first m entries are used (4 free, 5 tethered).
    q_tension : float
        Weight on the tension deviation [1/N^2].
    horizon : int
        N >= 1 samples.

    Returns
    -------
    MPCDesign

    Raises
    ------
    DesignError
        The weights admit no stabilising design.
    """
    T_ref, q9 = _trim_arguments(params, configuration, T_ref, q9)
    return _hover_design(
        params, configuration, T_ref, q9, dt, tuple(Qy), tuple(Ru), q_tension, horizon
    )


def design_mpc_kalman(
    params,
    configuration: str,
    T_ref: float,
    q9: float,
    dt: float,
    *,
    sensors,
    x_trim: np.ndarray,
    tension_ref: float,
    tether_arm: float,
    load_cell: bool,
    tension_std: float,
    force_std: float,
    force_rate: float,
    input_std: np.ndarray,
    coordinate_std: float,
    force_accel: float,
    tether_angle_std: float,
) -> DisturbanceKalman:
    """The MPC's steady-state Kalman filter (``observer.DisturbanceKalman``) on the design
    plant (``mpc_plant``) with the sensors' measurement noise
    (``observer.measurement_covariance``).

    Parameters
    ----------
    params : Params
        The parameters of the design model.
    configuration : {"tethered", "free"}
        The configuration (``mpc_plant``).
    T_ref : float
        Trim tension [N] of the design model (0 for the free configuration).
    q9 : float
        Tether length at trim [m].
    dt : float
        Sample time [s].
    sensors : SensorConfig
        The run's sensors (their noise sets R).
    x_trim : ndarray, shape (13,)
        The run's trim state (where R is evaluated).
    tension_ref : float
        The run's reference tension [N] (0 for the free configuration).
    tether_arm : float
        dO-P,3 - dO-HO,3 of the run's helicopter [m].
    load_cell : bool
        Whether the load cell's tension is a measurement (eq 28's tension as the design
        model knows it; not with the lumped tether).
    tension_std : float
        Std of eq 28's tension model error added to the load cell's variance [N].
    force_std : float
        Std of the white force on HO per sample [N] (``DisturbanceKalman.design``).
    force_rate : float
        Density of the wind force's random walk [N/sqrt(s)].
    input_std : ndarray, shape (m,)
        Std of a white error of each input per sample, units of the inputs.
    coordinate_std : float
        Std of a white error per sample of each coordinate q4..q9 [rad, m].
    force_accel : float
        Density of the random walk of the wind force's rate [N/s^1.5] (0: no rate state).
    tether_angle_std : float
        The coordinate error of the tether's angles q7, q8 [rad].

    Returns
    -------
    DisturbanceKalman
        The filter.
    """
    T_ref, q9 = _trim_arguments(params, configuration, T_ref, q9)
    return _design_mpc_kalman(
        params, configuration, T_ref, q9, _checked_dt(dt), sensors=sensors, x_trim=x_trim,
        tension_ref=tension_ref, tether_arm=tether_arm, load_cell=load_cell,
        tension_std=tension_std, force_std=force_std, force_rate=force_rate,
        input_std=input_std, coordinate_std=coordinate_std, force_accel=force_accel,
        tether_angle_std=tether_angle_std,
    )  # fmt: skip


def _design_mpc_kalman(
    params, configuration: str, T_ref: float, q9: float, dt: float, *, sensors,
    x_trim: np.ndarray, tension_ref: float, tether_arm: float, load_cell: bool,
    tension_std: float, force_std: float, force_rate: float, input_std: np.ndarray,
    coordinate_std: float, force_accel: float, tether_angle_std: float | None,
) -> DisturbanceKalman:  # fmt: skip
    """``design_mpc_kalman`` of a trim and sample time already checked (a run's set-up from
    its ``Scenario``)."""
    G, H, _, Hd, c_t = _mpc_plant(params, configuration, T_ref, q9, dt)
    R = _measurement_covariance(
        sensors, x_trim, tension_ref, tether_arm, dt, states=G.shape[0], load_cell=load_cell
    )
    if load_cell:  # eq 28 as the design model knows it
        R[-1, -1] += tension_std**2
    return DisturbanceKalman.design(
        G, H, Hd, c_t if load_cell else None, R, dt, force_std=force_std,
        force_rate=force_rate, input_std=np.asarray(input_std),
        coordinate_std=coordinate_std, force_accel=force_accel,
        tether_angle_std=tether_angle_std,
    )  # fmt: skip
