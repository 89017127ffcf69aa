"""The compiled measurement: what every channel reads at a control sample (``measure``,
``measure_into``, ``measure_sampled`` with its history ring for slow and delayed sensors,
``measure_batch`` row-wise) and the controller's tethered-coordinate state estimate rebuilt
from it by the position source (``SensorConfig.position_source``: true, GPS or the tether,
Sec. IV-F, eqs 43-45); its NumPy replay after a run (``measured_channels``) and the analysis
of the tether route (``tether_position_estimate``, ``hover_error_std``). Channels, sources and
fields: ``sensing.config``."""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled
from .._validation import check_number
from ..errors import ParameterError
from ..model.kernels import (
    kinematics_dcm,
    kinematics_tether_angles,
    kinematics_tether_length,
    kinematics_tethered_HO,
)
from ..model.kinematics import tether_length_from_altitude, tethered_HO_position
from ..params import check_tether_length
from .config import (
    CH_ALTIMETER,
    CH_ATTITUDE,
    CH_ENCODER_Q7,
    CH_ENCODER_Q8,
    CH_GPS,
    CH_GYRO,
    CH_LOAD_CELL,
    CH_VELOCITY,
    CH_WINCH_ENCODER,
    CHANNEL_GROUP,
    N_CHANNELS,
    SOURCE_GPS,
    SOURCE_TETHER,
    SOURCE_TRUE,
    SensorConfig,
)

__all__ = [
    "hover_error_std",
    "measure",
    "measure_batch",
    "measure_into",
    "measure_sampled",
    "measured_channels",
    "tether_position_estimate",
    "true_channels_into",
]

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")


# --- compiled measurement -----------------------------------------------------------------------
@_jit
def measure(x_true, tension_true, noise_row, source_code, arm, x_est):
    """The controller's state and tension estimate at one sample (compiled); see
    ``measure_into``, which the closed loop calls with its own scratch array.

    Parameters
    ----------
    x_true, tension_true, noise_row, source_code, arm
        As for ``measure_into``.
    x_est : ndarray, shape (13,)
        Filled with the state estimate (as ``measure_into``).

    Returns
    -------
    float
        Measured tension [N].
    """
    return measure_into(x_true, tension_true, noise_row, source_code, arm, x_est, np.empty((4, 3)))


@_jit
def measure_into(x_true, tension_true, noise_row, source_code, arm, x_est, scratch):
    """The controller's state and tension estimate at one sample (compiled), allocation-free.

    Parameters
    ----------
    x_true : ndarray, shape (13,)
        True state [q4..q9, u1..u6, LN] (rad, m, m/s, rad/s, m).
    tension_true : float
        True tether tension TC [N] (0 for the free configuration).
    noise_row : ndarray, shape (N_CHANNELS,)
        Noise plus bias of this sample (a row of ``noise_table``).
    source_code : int
        ``SOURCE_TRUE``, ``SOURCE_GPS`` or ``SOURCE_TETHER``.
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).
    x_est : ndarray, shape (13,)
        Filled with the estimate: q4..q6 = true + attitude noise, u1..u3 = true + velocity
        noise, u4..u6 = true + gyro noise, LN = true + winch-encoder noise, and q7, q8, q9 from
        the position source (module docstring; the GPS and tether sources use the measured
        attitude).
    scratch : ndarray, shape (4, 3)
        Work space: row 0 the true HO, rows 1-3 the rotation N_R_F at the measured attitude.

    Returns
    -------
    float
        Measured tension, true + load-cell noise [N] (not clipped: it may be slightly
        negative near slack).
    """
    for i in range(3):
        x_est[i] = x_true[i] + noise_row[CH_ATTITUDE + i]
        x_est[6 + i] = x_true[6 + i] + noise_row[CH_VELOCITY + i]
        x_est[9 + i] = x_true[9 + i] + noise_row[CH_GYRO + i]
    x_est[12] = x_true[12] + noise_row[CH_WINCH_ENCODER]

    if source_code == SOURCE_TRUE:
        x_est[3] = x_true[3]
        x_est[4] = x_true[4]
        x_est[5] = x_true[5]
    elif source_code == SOURCE_GPS:
        # the true HO = q9 c3 - arm f3 (eqs 43-45), measured
        HO = scratch[0]
        kinematics_tethered_HO(x_true, arm, HO)
        _tether_from_gps(
            HO[0] + noise_row[CH_GPS],
            HO[1] + noise_row[CH_GPS + 1],
            HO[2] + noise_row[CH_GPS + 2],
            arm,
            x_est,
            scratch,
        )
    elif source_code == SOURCE_TETHER:
        # the altimeter sees the true altitude of HO (eq 45); q9 from eq 45 with the encoders'
        # q7, q8 and the measured attitude
        HO = scratch[0]
        kinematics_tethered_HO(x_true, arm, HO)
        x_est[3] = x_true[3] + noise_row[CH_ENCODER_Q7]
        x_est[4] = x_true[4] + noise_row[CH_ENCODER_Q8]
        x_est[5] = kinematics_tether_length(x_est, HO[2] + noise_row[CH_ALTIMETER], arm)
    else:
        raise ValueError("measure: unknown position source code")
    return tension_true + noise_row[CH_LOAD_CELL]


@_jit_inline
def _tether_from_gps(h1, h2, h3, arm, x_est, scratch):
    """q7, q8, q9 of x_est from a measured HO (h1, h2, h3) and the measured attitude in
    x_est: P = HO + arm f3 (into scratch[0]), f3 the third column of N_R_F (Table I, into
    scratch[1:], (3, 3)), then the inverse of P = q9 c3 (eqs 27, 43-45,
    ``kinematics_tether_angles``)."""
    P, R = scratch[0], scratch[1:]
    kinematics_dcm(x_est, R)
    P[0] = h1 + arm * R[0, 2]
    P[1] = h2 + arm * R[1, 2]
    P[2] = h3 + arm * R[2, 2]
    kinematics_tether_angles(P, x_est[3:6])


@_jit
def true_channels_into(x_true, tension_true, arm, HO, out):
    """The true value of every noise channel (``CH_*`` order) into out (N_CHANNELS,): TC,
    q7, q8, altitude of HO, q4..q6, u4..u6, u1..u3, HO in N (eqs 43-45, into HO (3,)), LN.

    Parameters
    ----------
    x_true, tension_true, arm
        As for ``measure_into``.
    HO : ndarray, shape (3,)
        Filled with the true position of HO in N [m].
    out : ndarray, shape (N_CHANNELS,)
        Filled with the true channel values, units per channel (``CHANNEL_NAMES``).

    Returns
    -------
    None
        The results are written into ``HO`` and ``out``.
    """
    kinematics_tethered_HO(x_true, arm, HO)
    out[CH_LOAD_CELL] = tension_true
    out[CH_ENCODER_Q7] = x_true[3]
    out[CH_ENCODER_Q8] = x_true[4]
    out[CH_ALTIMETER] = HO[2]
    for i in range(3):
        out[CH_ATTITUDE + i] = x_true[i]
        out[CH_GYRO + i] = x_true[9 + i]
        out[CH_VELOCITY + i] = x_true[6 + i]
        out[CH_GPS + i] = HO[i]
    out[CH_WINCH_ENCODER] = x_true[12]


@_jit
def measure_sampled(x_true, tension_true, k, sensors, x_est):
    """The controller's state and tension estimate at control sample k with every sensor at
    its own rate and latency (compiled); ``sensors`` is ``runs.packing.sensor_tuple``'s
    (noise table, source code, arm, scratch (4, 3), schedule, ring).

    With an empty schedule this is ``measure_into`` with noise row k (white sensors, no
    delay: the legacy model, bit for bit). Otherwise the true channels of this sample are
    stored in row k mod H of the history ring (H = rows - 1; its last row is scratch) and
    channel c reads sample j = schedule[k, group of c] (``sample_schedule``): the true value
    stored at j plus noise row j. The position source then converts as ``measure_into``.

    Parameters
    ----------
    x_true, tension_true
        As for ``measure_into``.
    k : int
        Control sample index.
    sensors : tuple
        ``(noise (n + 1, N_CHANNELS), source_code, arm, scratch (4, 3), schedule, ring)``
        from ``runs.setup.sensor_tuple``.
    x_est : ndarray, shape (13,)
        Filled with the state estimate (as ``measure_into``).

    Returns
    -------
    float
        Measured tension [N].
    """
    noise, source_code, arm, scratch, schedule, ring = sensors
    if schedule.shape[0] == 0:
        return measure_into(x_true, tension_true, noise[k], source_code, arm, x_est, scratch)
    h = ring.shape[0] - 1
    true_channels_into(x_true, tension_true, arm, scratch[0], ring[k % h])
    m = ring[h]
    for c in range(N_CHANNELS):
        j = schedule[k, CHANNEL_GROUP[c]]
        m[c] = ring[j % h, c] + noise[j, c]
    for i in range(3):
        x_est[i] = m[CH_ATTITUDE + i]
        x_est[6 + i] = m[CH_VELOCITY + i]
        x_est[9 + i] = m[CH_GYRO + i]
    x_est[12] = m[CH_WINCH_ENCODER]
    if source_code == SOURCE_TRUE:
        x_est[3] = x_true[3]
        x_est[4] = x_true[4]
        x_est[5] = x_true[5]
    elif source_code == SOURCE_GPS:
        _tether_from_gps(m[CH_GPS], m[CH_GPS + 1], m[CH_GPS + 2], arm, x_est, scratch)
    elif source_code == SOURCE_TETHER:
        x_est[3] = m[CH_ENCODER_Q7]
        x_est[4] = m[CH_ENCODER_Q8]
        x_est[5] = kinematics_tether_length(x_est, m[CH_ALTIMETER], arm)
    else:
        raise ValueError("measure: unknown position source code")
    return m[CH_LOAD_CELL]


def measured_channels(
    x_true: np.ndarray,
    tension_true: np.ndarray,
    noise: np.ndarray,
    schedule: np.ndarray,
    arm: float,
) -> np.ndarray:
    """What every channel read at every sample of a recorded run, shape (n, N_CHANNELS): the
    replay of ``measure_sampled`` in NumPy (true values from the recorded states (n, 13) and
    tension (n,), noise rows and schedule as the run used; an empty schedule reads sample k
    at k). Used to feed a state estimator after a run (``tetherheli.sensing.estimation``).

    Parameters
    ----------
    x_true : numpy.ndarray, shape (n, 13)
        Recorded true states (``layout.py`` order).
    tension_true : numpy.ndarray, shape (n,)
        Recorded true tension TC [N].
    noise : numpy.ndarray, shape (>= n, N_CHANNELS)
        The run's noise table (``noise_table``).
    schedule : numpy.ndarray of int, shape (>= n, N_GROUPS) or (0, N_GROUPS)
        The run's ``sample_schedule``.
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).

    Returns
    -------
    numpy.ndarray, shape (n, N_CHANNELS)
        Measured value of every channel (``CH_*`` order) at every sample, units per channel.
    """
    n = x_true.shape[0]
    q4, q5, q7, q8, q9 = (x_true[:, i] for i in (0, 1, 3, 4, 5))
    HO = tethered_HO_position(q4, q5, q7, q8, q9, arm)
    raw = np.empty((n, N_CHANNELS))
    raw[:, CH_LOAD_CELL] = tension_true
    raw[:, CH_ENCODER_Q7], raw[:, CH_ENCODER_Q8] = q7, q8
    raw[:, CH_ALTIMETER] = HO[:, 2]
    raw[:, CH_ATTITUDE : CH_ATTITUDE + 3] = x_true[:, 0:3]
    raw[:, CH_GYRO : CH_GYRO + 3] = x_true[:, 9:12]
    raw[:, CH_VELOCITY : CH_VELOCITY + 3] = x_true[:, 6:9]
    raw[:, CH_GPS : CH_GPS + 3] = HO
    raw[:, CH_WINCH_ENCODER] = x_true[:, 12]
    if schedule.shape[0] == 0:
        j = np.broadcast_to(np.arange(n)[:, None], (n, N_CHANNELS))
    else:
        j = schedule[:n][:, CHANNEL_GROUP]
    cols = np.arange(N_CHANNELS)[None, :]
    return raw[j, cols] + noise[j, cols]


@_jit
def measure_batch(x_true, tension_true, noise, source_code, arm, x_est, tension_est):
    """Row-wise ``measure``: x_true (n, 13), tension_true (n,), noise (n, N_CHANNELS); fills
    x_est (n, 13) and tension_est (n,) (for Monte Carlo analysis of the estimates).

    Parameters
    ----------
    x_true : ndarray, shape (n, 13)
        True states, one per row.
    tension_true : ndarray, shape (n,)
        True tension TC [N].
    noise : ndarray, shape (n, N_CHANNELS)
        Noise rows (``noise_table``).
    source_code : int
        ``SOURCE_TRUE``, ``SOURCE_GPS`` or ``SOURCE_TETHER``.
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).
    x_est : ndarray, shape (n, 13)
        Filled with the state estimates.
    tension_est : ndarray, shape (n,)
        Filled with the measured tensions [N].

    Returns
    -------
    None
        The results are written into ``x_est`` and ``tension_est``.
    """
    scratch = np.empty((4, 3))
    for k in range(x_true.shape[0]):
        tension_est[k] = measure_into(
            x_true[k], tension_true[k], noise[k], source_code, arm, x_est[k], scratch
        )


# --- analysis helpers (numpy) -------------------------------------------------------------------
def tether_position_estimate(
    q7: np.ndarray | float,
    q8: np.ndarray | float,
    altitude: np.ndarray | float,
    q4: np.ndarray | float,
    q5: np.ndarray | float,
    arm: float,
) -> np.ndarray:
    """Position of HO in N from the tether's sensors (Sec. IV-F, eqs 43-45).

    q9 = (altitude + arm c4 c5) / (c7 c8), then HO = q9 c3 - arm f3 with
    c3 = [s8, -s7 c8, c7 c8] and f3 = [s5, -s4 c5, c4 c5].

    Parameters
    ----------
    q7, q8 : array_like, shape (n,) or scalar
        Ground-joint encoder angles [rad].
    altitude : array_like, shape (n,) or scalar
        Altimeter reading, the altitude q3 of HO [m].
    q4, q5 : array_like, shape (n,) or scalar
        IMU roll and pitch [rad].
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).

    Returns
    -------
    ndarray, shape (n, 3)
        [q1, q2, q3] of HO in N [m]; the inputs broadcast together (scalars give n = 1).
    """
    q7, q8, h, q4, q5 = (
        np.atleast_1d(np.asarray(a, dtype=float)) for a in (q7, q8, altitude, q4, q5)
    )
    q9 = tether_length_from_altitude(h, q4, q5, q7, q8, arm)
    return tethered_HO_position(q4, q5, q7, q8, q9, arm)


def _tether_estimate_jacobian(
    q4: float, q5: float, q7: float, q8: float, q9: float, arm: float
) -> np.ndarray:
    """d(HO estimate)/d[q7, q8, altitude, q4, q5], shape (3, 5), at the true state."""
    s4, c4 = math.sin(q4), math.cos(q4)
    s5, c5 = math.sin(q5), math.cos(q5)
    s7, c7 = math.sin(q7), math.cos(q7)
    s8, c8 = math.sin(q8), math.cos(q8)
    z = q9 * c7 * c8  # height of P = altitude + arm c4 c5
    t7, t8 = s7 / c7, s8 / c8
    jac = np.zeros((3, 5))
    # HO1 = z t8 / c7 - arm s5
    jac[0] = [z * t8 * t7 / c7, z / (c7 * c8 * c8), t8 / c7, -arm * s4 * c5 * t8 / c7,
              -arm * c4 * s5 * t8 / c7 - arm * c5]  # fmt: skip
    # HO2 = -z t7 + arm s4 c5
    jac[1] = [-z / (c7 * c7), 0.0, -t7, arm * s4 * c5 * t7 + arm * c4 * c5,
              arm * c4 * s5 * t7 - arm * s4 * s5]  # fmt: skip
    # HO3 = altitude
    jac[2] = [0.0, 0.0, 1.0, 0.0, 0.0]
    return jac


def hover_error_std(
    config: SensorConfig,
    q9: float = 10.0,
    arm: float = -0.2046,
    q4: float = 0.0923,
    *,
    q5: float = 0.0,
    q7: float = 0.0,
    q8: float = 0.0,
) -> np.ndarray:
    """First-order predicted std of the tether-based position estimate of HO (Sec. IV-F).

    The estimate ``tether_position_estimate`` is linearised about the true state; with
    independent noises on q7, q8 (``encoder_std``), the altitude (``altimeter_std``) and q4,
    q5 (``attitude_std``), std_i = sqrt(sum_j (J_ij sigma_j)^2). At hover (q5 = q7 = q8 = 0):
    std_1 = sqrt((q9 sigma_enc)^2 + (arm sigma_att)^2),
    std_2 = sqrt((q9 sigma_enc)^2 + (arm c4 sigma_att)^2), std_3 = sigma_alt.
    Biases are not included. Compare with ``config.gps_std`` for a GPS.

    Parameters
    ----------
    config : SensorConfig
        Its ``encoder_std``, ``altimeter_std`` and ``attitude_std`` are used.
    q9 : float
        Tether length [m] (in ``params.TETHER_LENGTH_RANGE``); 10 m at the paper's trim
        (Table V).
    arm : float
        dO-P,3 - dO-HO,3 [m]; -0.2046 m for Table II.
    q4 : float
        Roll [rad]; 0.0923 rad at the paper's tethered trim (Table V).
    q5, q7, q8 : float, keyword-only
        Pitch and tether angles [rad] of the state (0 at trim); |q7|, |q8| < 90 deg.

    Returns
    -------
    ndarray, shape (3,)
        Predicted std of the HO position error along n1, n2, n3 [m].
    """
    if not isinstance(config, SensorConfig):
        raise ParameterError("config", config, "a SensorConfig")
    values = {"q9": q9, "arm": arm, "q4": q4, "q5": q5, "q7": q7, "q8": q8}
    q4, q5, q7, q8, arm = (
        check_number(name, values[name]) for name in ("q4", "q5", "q7", "q8", "arm")
    )
    q9 = check_tether_length(q9, "q9")
    if math.cos(q7) * math.cos(q8) <= 1e-9:
        raise ParameterError("q7, q8", (q7, q8), "angles with cos q7 cos q8 > 0")
    jac = _tether_estimate_jacobian(q4, q5, q7, q8, q9, arm)
    sigma = np.array(
        [
            config.encoder_std,
            config.encoder_std,
            config.altimeter_std,
            config.attitude_std,
            config.attitude_std,
        ]
    )
    return np.sqrt(((jac * sigma) ** 2).sum(axis=1))
