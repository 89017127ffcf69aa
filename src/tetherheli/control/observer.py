"""The MPC's state and wind-force estimator on the scenario's sensors: a steady-state Kalman
filter of the design model augmented with the wind force on HO (an input disturbance).

Model (``mpc_plant``; deviations from the hover trim, sample time dt, ZOH):

    x_{k+1} = G x_k + H (u_k + a_k) + Hd (d_k + w_k) + [c_k; 0],    d_{k+1} = d_k + v_k,

w (3,) white [N], std ``force_std`` per axis: the force the linear model misses over a sample
(unmodelled dynamics, linearization error, a lumped tether's waves, the gusts' fast part); a
(m,) white, std ``input_std``: the inputs' error (actuator lag and saturation, the rotor's
model error); c (6,) white on the coordinates q4..q9, std ``coordinate_std``: the
linearized kinematics' error (``tether_angle_std`` on the tether's angles q7, q8); v
(3,) white, std ``force_rate`` sqrt(dt) per axis [N]: the wind force as a random walk of
density ``force_rate`` [N/sqrt(s)]. With ``force_accel`` > 0 the force also has a rate r
(3,) [N/s], a random walk of density ``force_accel`` [N/s^1.5]:

    d_{k+1} = d_k + dt r_k + v_k,    r_{k+1} = r_k + a_k,    Var a = force_accel^2 dt,

a force that follows a ramp or a sine without lag and a step as fast as its noise lets it
(a random-walk force alone lags a 12.6 N/s sine and a 20 N pulse by several of its sigmas:
mean NEES 40 for 16 states on the shipped pulse-and-sine runs,
``studies.estimation.kalman_consistency``).
Measurements, every sample: the controller's measured
state (``sensing.sensors.measure_sampled``: 13 tethered or free-configuration channels) and, on the
tethered configuration, the load cell,

    m_k = [x_k; c_T' x_k] + e_k,    Cov e = R = J S J',

(the load cell's row only with the massless tether, whose tension eq 28 gives from the state;
a lumped chain's load cell reads its ground end, which the design model does not describe),

with J the Jacobian of ``sensing.sensors.measure`` (the measured state and tension) with respect to
the sensors' noise channels at the trim (central differences: the measurement is nonlinear
only through the attitude's rotation of the GNSS fix and the tether geometry) and S the
channels' per-sample variances (``measurement_covariance``). The filter's gain is the
steady-state one (the filter DARE, ``scipy.linalg.solve_discrete_are`` on the transposed
pair), so a sample costs two small matrix products.

R is the linearization's: a consumer GNSS's metres of error at 10 m of tether bend the angles
q7, q8 enough that their std is about 20 % above R's (``tests/test_observer.py``). What the
filter does not model, and so treats as noise: a sensor's hold between its samples
(its variance is multiplied by its period in samples: a value read p times carries the
information of one read) and its latency (a GNSS fix 0.15 s old differs from the present
position by the distance flown meanwhile, centimetres in hover against its metres of error),
the Gauss-Markov drifts (their stationary variance is added as if white), the gyro's and
accelerometer's random-walk biases, and constant biases.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_discrete_are

from ..errors import TetherheliError
from ..sensing.config import (
    CH_ALTIMETER,
    CH_GPS,
    CHANNEL_GROUP,
    N_CHANNELS,
    SensorConfig,
    _checked_dt,
)
from ..sensing.sensors import measure

__all__ = [
    "DisturbanceKalman",
    "measurement_covariance",
    "steady_state_kalman",
]

#: the smallest measurement variance the filter assumes, relative to 1 in each channel's
#: unit: a perfect channel (no noise configured) is read as exact to 1e-6 m, rad, m/s or N,
#: which keeps the filter's Riccati equation well posed
VARIANCE_FLOOR = 1e-12


def measurement_covariance(
    sensors: SensorConfig,
    x_trim: np.ndarray,
    tension: float,
    arm: float,
    dt: float,
    *,
    states: int,
    load_cell: bool,
) -> np.ndarray:
    """R: the covariance of the measured state (and, tethered, the load cell's tension) about
    the trim, by linear propagation of the sensors' per-channel noise through
    ``sensing.sensors.measure`` (module docstring).

    Parameters
    ----------
    sensors : SensorConfig
        The scenario's sensors (``position_source`` and the noise fields).
    x_trim : ndarray, shape (13,)
        The trim state [q4..q9, u1..u6, LN].
    tension : float
        The trim tension [N] (0 on the free configuration).
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).
    dt : float
        Control sample time [s] (the gyro's per-sample noise and the sensors' periods).
    states : int
        The measured states: 13 tethered [q4..q9, u1..u6, LN], 12 free (q4..u6).
    load_cell : bool
        Whether the load cell's tension is a measurement too (after the states).

    Returns
    -------
    ndarray, shape (p, p)
        R in the units of the state and N, p = ``states`` (+ 1 with the load cell); at least
        ``VARIANCE_FLOOR`` on the diagonal.
    """
    return _measurement_covariance(
        sensors, x_trim, tension, arm, _checked_dt(dt), states=states, load_cell=load_cell
    )


def _measurement_covariance(
    sensors: SensorConfig,
    x_trim: np.ndarray,
    tension: float,
    arm: float,
    dt: float,
    *,
    states: int,
    load_cell: bool,
) -> np.ndarray:
    """``measurement_covariance`` of a sample time already checked (a run's set-up)."""
    variance = sensors._white_std(dt) ** 2
    variance[CH_GPS : CH_GPS + 3] += np.asarray(sensors.gps_markov_sigma, dtype=float) ** 2
    variance[CH_ALTIMETER] += sensors.altimeter_markov_sigma**2
    period = sensors._group_timing(dt)[0]
    variance *= period[CHANNEL_GROUP]
    x_trim = np.ascontiguousarray(x_trim, dtype=float)
    source = sensors.source_code
    J = np.zeros((14, N_CHANNELS))
    step = 1e-6
    plus, minus = np.empty(13), np.empty(13)
    for c in range(N_CHANNELS):
        noise = np.zeros(N_CHANNELS)
        noise[c] = step
        t_plus = measure(x_trim, float(tension), noise, source, float(arm), plus)
        noise[c] = -step
        t_minus = measure(x_trim, float(tension), noise, source, float(arm), minus)
        J[:13, c] = (plus - minus) / (2.0 * step)
        J[13, c] = (t_plus - t_minus) / (2.0 * step)
    rows = list(range(states)) + ([13] if load_cell else [])
    J = J[rows]
    R = (J * variance) @ J.T
    R = 0.5 * (R + R.T)
    R[np.diag_indices_from(R)] = np.maximum(np.diag(R), VARIANCE_FLOOR)
    return R


def steady_state_kalman(
    A: np.ndarray, C: np.ndarray, Q: np.ndarray, R: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The steady-state Kalman filter of x+ = A x + w, m = C x + e (Cov w = Q, Cov e = R):
    the predicted covariance P from the filter DARE and the update gain L = P C' (C P C' +
    R)^-1 (the estimate after a measurement is x = x_pred + L (m - C x_pred)).

    Parameters
    ----------
    A, C : ndarray, shapes (n, n), (p, n)
        Transition and measurement matrices.
    Q, R : ndarray, shapes (n, n), (p, p)
        Process and measurement noise covariances (R positive definite).

    Returns
    -------
    P, L : ndarray, shapes (n, n), (n, p)
        Predicted (a priori) covariance and update gain.

    Raises
    ------
    TetherheliError
        The pair (A, C) is not detectable or the DARE has no stabilising solution.
    """
    try:
        P = solve_discrete_are(A.T, C.T, Q, R)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise TetherheliError(
            f"no stabilising solution of the Kalman filter's DARE: {exc}"
        ) from None
    P = 0.5 * (P + P.T)
    L = np.linalg.solve(C @ P @ C.T + R, C @ P).T
    return P, L


@dataclass
class DisturbanceKalman:
    """The filter of the module docstring, run by the MPC every sample.

    Parameters
    ----------
    A, B, C : ndarray
        The augmented model s = [x; d(; r)]: (ns, ns), (ns, m), (p, ns), ns = n + 3 (n + 6
        with the force's rate r, ``force_accel`` > 0).
    L : ndarray, shape (ns, p)
        The steady-state update gain (``steady_state_kalman``).
    P : ndarray, shape (ns, ns)
        The predicted (a priori) covariance.
    R : ndarray, shape (p, p)
        The measurement covariance the filter was designed with.
    force_states : int
        The disturbance's states after x: 3 (the force d) or 6 (d and its rate r).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    L: np.ndarray
    P: np.ndarray
    R: np.ndarray
    force_states: int = 3

    @classmethod
    def design(
        cls,
        G: np.ndarray,
        H: np.ndarray,
        Hd: np.ndarray,
        c_tension: np.ndarray | None,
        R: np.ndarray,
        dt: float,
        *,
        force_std: float,
        force_rate: float,
        input_std: np.ndarray,
        coordinate_std: float,
        force_accel: float = 0.0,
        tether_angle_std: float | None = None,
    ) -> DisturbanceKalman:
        """The filter on the discrete design model (G, H, Hd) and the measurement noise R.

        Parameters
        ----------
        G, H, Hd : ndarray, shapes (n, n), (n, m), (n, 3)
            The MPC's discrete plant and the wind force's input matrix [per N].
        c_tension : ndarray, shape (n,), or None
            The tension deviation's row when the load cell is a measurement (None: it is not).
        R : ndarray, shape (p, p)
            Measurement covariance (``measurement_covariance``), p = n (+ 1 tethered).
        dt : float
            Sample time [s].
        force_std : float
            Std of the white force w on HO per sample [N], > 0.
        force_rate : float
            Density of the wind force's random walk [N/sqrt(s)], > 0.
        input_std : ndarray, shape (m,)
            Std of a white error of each input per sample (the actuators' error and the
            inputs' model error; it reaches every state the inputs move, among them the yaw
            and the winch's length, which the wind force does not), units of the inputs.
        coordinate_std : float
            Std of a white error per sample of each coordinate q4..q9 [rad, m]: the
            linearized kinematics' error (e.g. the yaw rate's dependence on roll and pitch,
            eq 13), which otherwise accumulates in an estimate that trusts the model's
            integration of the measured rates over the measured angles.
        force_accel : float, optional
            Density of the random walk of the wind force's rate r [N/s^1.5], >= 0: with it
            the force is d_{k+1} = d_k + dt r_k + v_k, r_{k+1} = r_k + a_k (Var a = force_accel^2
            dt per axis), a model that follows a ramp or a sine without lag; 0 (the default):
            no rate state, d a random walk.
        tether_angle_std : float, optional
            The coordinate error of the tether's angles q7, q8 [rad] when it differs from
            ``coordinate_std`` (their kinematics is the velocity's integral, which the
            linearization keeps; the attitude's eq 13 it does not); None: ``coordinate_std``.

        Returns
        -------
        DisturbanceKalman
        """
        n, m = H.shape
        nf = 6 if force_accel > 0.0 else 3
        F = np.eye(nf)
        if nf == 6:
            F[:3, 3:] = dt * np.eye(3)
        Hf = np.hstack([Hd, np.zeros((n, nf - 3))])
        A = np.block([[G, Hf], [np.zeros((nf, n)), F]])
        B = np.vstack([H, np.zeros((nf, m))])
        C = np.hstack([np.eye(n), np.zeros((n, nf))])
        if c_tension is not None:
            C = np.vstack([C, np.concatenate([c_tension, np.zeros(nf)])])
        if R.shape != (C.shape[0], C.shape[0]):
            raise TetherheliError(f"R has shape {R.shape}; allowed: {(C.shape[0],) * 2}")
        Gw = np.vstack([Hd, np.zeros((nf, 3))])
        input_std = np.asarray(input_std, dtype=float)[:m]
        Q = force_std**2 * (Gw @ Gw.T)
        Q[:n, :n] += (H * input_std**2) @ H.T
        Q[:6, :6] += coordinate_std**2 * np.eye(6)
        if tether_angle_std is not None and n > 12:  # q7, q8: the tethered model's
            Q[3:5, 3:5] += (tether_angle_std**2 - coordinate_std**2) * np.eye(2)
        Q[n : n + 3, n : n + 3] += force_rate**2 * dt * np.eye(3)
        if nf == 6:
            Q[n + 3 :, n + 3 :] += force_accel**2 * dt * np.eye(3)
        P, L = steady_state_kalman(A, C, Q, R)
        return cls(A, B, C, L, P, np.array(R, dtype=float), nf)

    @property
    def posterior(self) -> np.ndarray:
        """The covariance of the estimate after a sample's measurements, (ns, ns): (I - L C)
        P (I - L C)' + L R L' (Joseph's form; P's with the steady gain)."""
        IKC = np.eye(self.A.shape[0]) - self.L @ self.C
        out = IKC @ self.P @ IKC.T + self.L @ self.R @ self.L.T
        return 0.5 * (out + out.T)

    @property
    def innovation_covariance(self) -> np.ndarray:
        """S = C P C' + R (p, p): the covariance of a sample's innovation m - C s_pred."""
        S = self.C @ self.P @ self.C.T + self.R
        return 0.5 * (S + S.T)

    @property
    def n_states(self) -> int:
        """n: the plant's states (the disturbance's ``force_states`` not counted)."""
        return self.A.shape[0] - self.force_states

    def start(self, d_init: np.ndarray, measured: np.ndarray) -> np.ndarray:
        """The estimate at the first sample: the prior [0; d_init] (a run starts at its trim,
        in the wind of its start) corrected by the first measurements with the steady gain,
        so that a first GNSS fix metres off moves the estimate by the gain's share only.

        Parameters
        ----------
        d_init : ndarray, shape (3,)
            The wind force at the start [N].
        measured : ndarray, shape (p,)
            The first sample's measurements (state deviation and, with the load cell, the
            tension's).

        Returns
        -------
        ndarray, shape (ns,)
        """
        prior = np.zeros(self.A.shape[0])
        prior[self.n_states : self.n_states + 3] = d_init
        return prior + self.L @ (measured - self.C @ prior)

    def update(self, s: np.ndarray, u_prev: np.ndarray, measured: np.ndarray) -> np.ndarray:
        """One sample: predict from the estimate s and the input u_prev applied since, then
        correct with ``measured`` (the state deviation and, tethered, the tension's).

        Parameters
        ----------
        s : ndarray, shape (ns,)
            The previous sample's estimate.
        u_prev : ndarray, shape (m,)
            The input (deviation) applied over the previous sample.
        measured : ndarray, shape (p,)
            This sample's measurements.

        Returns
        -------
        ndarray, shape (ns,)
            The estimate [x; d(; r)].
        """
        return self.step(s, u_prev, measured)[0]

    def step(
        self, s: np.ndarray, u_prev: np.ndarray, measured: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """``update`` that also returns the innovation (for its NIS, with
        ``innovation_covariance``).

        Parameters
        ----------
        s : ndarray, shape (ns,)
            The previous sample's estimate.
        u_prev : ndarray, shape (m,)
            The input (deviation) applied over the previous sample.
        measured : ndarray, shape (p,)
            This sample's measurements.

        Returns
        -------
        estimate : ndarray, shape (ns,)
            The estimate [x; d(; r)].
        innovation : ndarray, shape (p,)
            measured - C s_pred.
        """
        pred = self.A @ s + self.B @ u_prev
        innovation = measured - self.C @ pred
        return pred + self.L @ innovation, innovation
