"""Sensor models: what the controller measures instead of the true state and tension.

The paper's controller (Sec. V) reads the full state and the tether tension. Real helicopters
measure them: an IMU (attitude, body rates), a GPS or the tether itself (position), a load
cell (tension, Sec. IV-D) and the winch drum's encoder (natural length LN). This module models
those sensors as the true value plus white Gaussian noise plus a constant bias, and rebuilds
the controller's tethered-coordinate state estimate from the measurements.

Position sources (``SensorConfig.position_source``)
--------------------------------------------------
``"true"``
    The controller gets the true q7, q8, q9 (the paper's assumption).
``"gps"``
    A GPS-like sensor measures the position of HO in N; the estimate of the attachment point
    P = HO + arm f3 uses the *measured* attitude, then q9 = |P|, q8 = asin(P1 / q9),
    q7 = atan2(-P2, P3) (the inverse of c3 = [s8, -s7 c8, c7 c8], eqs 43-45).
``"tether"``
    Sec. IV-F, "tether as sensing device": the two optical encoders of the ground joint measure
    q7, q8, a high-precision altimeter the altitude q3 of HO, and the IMU the attitude; with q9
    unknown, eq 45 fixes it: q9 = (q3 + arm c4 c5) / (c7 c8). There are no encoders on a free
    helicopter, so this source is invalid for the free configuration
    (``SensorConfig.check_configuration``).

Here arm = dO-P,3 - dO-HO,3 (``HelicopterParams.tether_arm``, -0.2046 m for Table II), and
c3, f3 are the tether direction and the fuselage axis in N (SPEC "Frames, points,
coordinates").

Noise channels
--------------
Every control sample uses one row of ``N_CHANNELS`` numbers (noise plus bias), in the order
of the ``CH_*`` indices:

====  ==================  ======  =====================================
col   constant            unit    what
====  ==================  ======  =====================================
0     CH_LOAD_CELL        N       tether tension TC (load cell)
1     CH_ENCODER_Q7       rad     ground-joint encoder, q7
2     CH_ENCODER_Q8       rad     ground-joint encoder, q8
3     CH_ALTIMETER        m       altitude of HO, q3
4-6   CH_ATTITUDE         rad     attitude q4, q5, q6 (IMU / AHRS)
7-9   CH_GYRO             rad/s   body rates u4, u5, u6 (gyroscopes)
10-12 CH_VELOCITY         m/s     velocity of HO in N, u1, u2, u3
13-15 CH_GPS              m       position of HO in N, q1, q2, q3 (GPS)
16    CH_WINCH_ENCODER    m       winch natural length LN (drum encoder)
====  ==================  ======  =====================================

``noise_table`` draws the rows for a whole run up front (so the compiled engine only adds a
row per sample and runs are reproducible from a seed); ``measure`` is the compiled measurement
function the engine calls at every sample.

Analysis helpers: ``tether_position_estimate`` (vectorised Sec. IV-F position estimate) and
``hover_error_std`` (first-order predicted std of that estimate, to compare with a GPS's std).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from ._compile import compiled
from ._validation import check_integer, check_number, check_vector
from .errors import ParameterError
from .model.kernels import kinematics_dcm, kinematics_tether_length, kinematics_tethered_HO
from .model.kinematics import tether_length_from_altitude, tethered_HO_position
from .params import check_tether_length

__all__ = [
    "CHANNEL_NAMES",
    "CH_ALTIMETER",
    "CH_ATTITUDE",
    "CH_ENCODER_Q7",
    "CH_ENCODER_Q8",
    "CH_GPS",
    "CH_GYRO",
    "CH_LOAD_CELL",
    "CH_VELOCITY",
    "CH_WINCH_ENCODER",
    "N_CHANNELS",
    "POSITION_SOURCES",
    "SOURCE_GPS",
    "SOURCE_TETHER",
    "SOURCE_TRUE",
    "SensorConfig",
    "hover_error_std",
    "measure",
    "measure_batch",
    "noise_table",
    "sensor_config_from_dict",
    "tether_position_estimate",
]

_jit = compiled(error_model="numpy")

# --- noise channels: columns of a noise row ---------------------------------------------------
CH_LOAD_CELL = 0  # [N]
CH_ENCODER_Q7 = 1  # [rad]
CH_ENCODER_Q8 = 2  # [rad]
CH_ALTIMETER = 3  # [m]
CH_ATTITUDE = 4  # [rad], 3 columns: q4, q5, q6
CH_GYRO = 7  # [rad/s], 3 columns: u4, u5, u6
CH_VELOCITY = 10  # [m/s], 3 columns: u1, u2, u3
CH_GPS = 13  # [m], 3 columns: HO along n1, n2, n3
CH_WINCH_ENCODER = 16  # [m]
N_CHANNELS = 17

#: Label of every column of a noise row (unit in brackets).
CHANNEL_NAMES: tuple[str, ...] = (
    "load_cell [N]",
    "encoder_q7 [rad]",
    "encoder_q8 [rad]",
    "altimeter [m]",
    "attitude_q4 [rad]",
    "attitude_q5 [rad]",
    "attitude_q6 [rad]",
    "gyro_u4 [rad/s]",
    "gyro_u5 [rad/s]",
    "gyro_u6 [rad/s]",
    "velocity_u1 [m/s]",
    "velocity_u2 [m/s]",
    "velocity_u3 [m/s]",
    "gps_q1 [m]",
    "gps_q2 [m]",
    "gps_q3 [m]",
    "winch_encoder [m]",
)

# --- position sources -------------------------------------------------------------------------
SOURCE_TRUE = 0
SOURCE_GPS = 1
SOURCE_TETHER = 2

#: ``SensorConfig.position_source`` -> the integer code ``measure`` takes (read-only).
POSITION_SOURCES: Mapping[str, int] = MappingProxyType(
    {"true": SOURCE_TRUE, "gps": SOURCE_GPS, "tether": SOURCE_TETHER}
)

_SECTION = "sensors"
_DEG = math.pi / 180.0


#: field name -> (kind, nonnegative); kind "scalar" or "triple". Drives validation.
_NUMERIC_FIELDS: dict[str, tuple[str, bool]] = {
    "load_cell_std": ("scalar", True),
    "load_cell_bias": ("scalar", False),
    "encoder_std": ("scalar", True),
    "altimeter_std": ("scalar", True),
    "altimeter_bias": ("scalar", False),
    "attitude_std": ("scalar", True),
    "attitude_bias": ("triple", False),
    "gyro_std": ("scalar", True),
    "velocity_std": ("scalar", True),
    "gps_std": ("triple", True),
    "gps_bias": ("triple", False),
    "winch_encoder_std": ("scalar", True),
}


@dataclass(frozen=True)
class SensorConfig:
    """The controller's sensors: position source, noise standard deviations and biases.

    Every measurement is the true value plus white Gaussian noise of the given standard
    deviation (independent per sample and per channel) plus the constant bias. The standard
    deviations are *per control sample* (the noise is not scaled with the sample time). All
    defaults are zero with ``position_source="true"``: perfect sensors, the paper's
    assumption, so the paper's results are unchanged.

    Parameters
    ----------
    position_source : {"true", "gps", "tether"}
        Where the controller's position (q7, q8, q9) comes from; see the module docstring.
        ``"tether"`` needs the tethered configuration.
    load_cell_std, load_cell_bias : float
        Tether tension TC measured by the load cell (Sec. IV-D) [N].
    encoder_std : float
        Optical encoders of the ground universal joint, q7 and q8 (Sec. IV-D, IV-F) [rad].
    altimeter_std, altimeter_bias : float
        High-precision altimeter measuring the altitude q3 of HO (Sec. IV-F) [m].
    attitude_std : float
        IMU / AHRS attitude q4, q5, q6, each axis [rad].
    attitude_bias : tuple of 3 floats
        Constant attitude errors on q4, q5, q6 [rad].
    gyro_std : float
        Gyroscopes, body rates u4, u5, u6, each axis [rad/s].
    velocity_std : float
        Velocity of HO in N, u1, u2, u3, each axis [m/s].
    gps_std, gps_bias : tuple of 3 floats
        GPS position of HO along n1, n2, n3 [m] (used by ``position_source="gps"``).
    winch_encoder_std : float
        Drum encoder of the winch, natural length LN [m].

    Raises
    ------
    ParameterError
        A std that is negative or not finite, a bias that is not finite, a tuple without 3
        entries, an unknown ``position_source``; the one-line message names the field.
    """

    position_source: str = "true"
    load_cell_std: float = 0.0
    load_cell_bias: float = 0.0
    encoder_std: float = 0.0
    altimeter_std: float = 0.0
    altimeter_bias: float = 0.0
    attitude_std: float = 0.0
    attitude_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gyro_std: float = 0.0
    velocity_std: float = 0.0
    gps_std: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gps_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)
    winch_encoder_std: float = 0.0

    def __post_init__(self) -> None:
        source = self.position_source
        if not isinstance(source, str) or source not in POSITION_SOURCES:
            raise ParameterError(
                f"{_SECTION}.position_source", source, f"one of {sorted(POSITION_SOURCES)}"
            )
        for name, (kind, nonnegative) in _NUMERIC_FIELDS.items():
            value, low = getattr(self, name), 0.0 if nonnegative else None
            if kind == "scalar":
                checked: object = check_number(f"{_SECTION}.{name}", value, low=low)
            else:
                checked = check_vector(f"{_SECTION}.{name}", value, 3, low=low, unit="[n1, n2, n3]")
            object.__setattr__(self, name, checked)

    # --- presets ------------------------------------------------------------------------------
    @classmethod
    def perfect(cls) -> SensorConfig:
        """Perfect sensors and the true position: the paper's assumption (the default)."""
        return cls()

    @classmethod
    def typical_gps(cls) -> SensorConfig:
        """A consumer-grade GPS receiver with a MEMS IMU, position from the GPS.

        Numbers (1-sigma, per control sample):

        - GPS position (1.5, 1.5, 3.0) m: single-frequency consumer GNSS (u-blox M8/M9
          class) reaches about 1.5-2.5 m CEP horizontally in open sky; the vertical error is
          about twice the horizontal one because all satellites lie above the horizon.
        - velocity 0.1 m/s: Doppler velocity of the same receivers (0.05-0.1 m/s specified).
        - attitude 0.5 deg (8.7e-3 rad): a MEMS AHRS's roll/pitch accuracy (0.2-0.5 deg;
          heading is usually worse, about 1 deg, kept at 0.5 deg for one number per axis).
        - gyro 2e-3 rad/s (0.11 deg/s): MEMS rate noise density of about 0.01 deg/s/sqrt(Hz)
          over a 50 Hz bandwidth (0.01 s sampling).
        - load cell 0.1 N (0.4 % of Tref = 25 N): an S-beam load cell of about 100 N range
          with 0.02-0.05 % FS error plus amplifier noise.
        - winch drum encoder 1e-3 m: an encoder with about 1 mm of tether per count.

        No biases (a GPS bias of a few metres is common; set ``gps_bias`` to study it).
        For RTK-corrected GNSS see ``typical_rtk_gps``.
        """
        return cls(
            position_source="gps",
            load_cell_std=0.1,
            attitude_std=0.5 * _DEG,
            gyro_std=2e-3,
            velocity_std=0.1,
            gps_std=(1.5, 1.5, 3.0),
            winch_encoder_std=1e-3,
        )

    @classmethod
    def typical_rtk_gps(cls) -> SensorConfig:
        """As ``typical_gps`` with an RTK-corrected receiver (fixed solution).

        RTK GNSS gives about 0.01 m + 1 ppm horizontally and twice that vertically; we take
        (0.02, 0.02, 0.04) m and 0.02 m/s velocity. It needs a base station and a radio link,
        and it loses the fixed solution under multipath or occlusion, the "typical
        degradation factors of GPS systems" of Sec. IV-F.
        """
        return replace(cls.typical_gps(), velocity_std=0.02, gps_std=(0.02, 0.02, 0.04))

    @classmethod
    def typical_tether(cls) -> SensorConfig:
        """The tether as a sensor (Sec. IV-F): encoders + altimeter + IMU attitude.

        Numbers (1-sigma, per control sample):

        - ground-joint encoders 0.1 deg (1.75e-3 rad): optical incremental encoders of
          2000-4000 counts per revolution resolve 0.09-0.18 deg; at q9 = 10 m this is
          about 1.7 cm of horizontal position.
        - altimeter 0.05 m: the paper's "altimeter of high precision"; a laser rangefinder
          (LIDAR-Lite class, +-2.5 cm above 1 m) over flat ground; a barometer alone would be
          about 0.1-0.5 m and drift.
        - attitude 0.5 deg (8.7e-3 rad): the same MEMS AHRS as ``typical_gps``; it enters the
          position through the lever arm of HO about P (0.2 m), about 2 mm.
        - load cell, gyro, winch encoder: as ``typical_gps``.
        - velocity 0.1 m/s: Sec. IV-F gives no velocity sensor; we assume a filtered estimate
          as good as the GPS's Doppler velocity, so the two presets differ in position only.

        ``hover_error_std`` gives the resulting position error (about 1.7 cm horizontal and
        5 cm vertical at the paper's hover, against 1.5 m and 3 m for ``typical_gps``).
        """
        return cls(
            position_source="tether",
            load_cell_std=0.1,
            encoder_std=0.1 * _DEG,
            altimeter_std=0.05,
            attitude_std=0.5 * _DEG,
            gyro_std=2e-3,
            velocity_std=0.1,
            winch_encoder_std=1e-3,
        )

    # --- derived ------------------------------------------------------------------------------
    @property
    def source_code(self) -> int:
        """The integer code of ``position_source`` (``SOURCE_*``) for ``measure``."""
        return POSITION_SOURCES[self.position_source]

    @property
    def is_perfect(self) -> bool:
        """True when every std and bias is zero and the position source is ``"true"``: the
        measurement equals the true state and tension, so an engine may skip ``measure``."""
        return (
            self.position_source == "true"
            and not np.any(self.channel_std())
            and not np.any(self.channel_bias())
        )

    def channel_std(self) -> np.ndarray:
        """Noise standard deviation of every channel, shape (N_CHANNELS,), units per channel
        (see ``CHANNEL_NAMES``)."""
        std = np.zeros(N_CHANNELS)
        std[CH_LOAD_CELL] = self.load_cell_std
        std[CH_ENCODER_Q7] = self.encoder_std
        std[CH_ENCODER_Q8] = self.encoder_std
        std[CH_ALTIMETER] = self.altimeter_std
        std[CH_ATTITUDE : CH_ATTITUDE + 3] = self.attitude_std
        std[CH_GYRO : CH_GYRO + 3] = self.gyro_std
        std[CH_VELOCITY : CH_VELOCITY + 3] = self.velocity_std
        std[CH_GPS : CH_GPS + 3] = self.gps_std
        std[CH_WINCH_ENCODER] = self.winch_encoder_std
        return std

    def channel_bias(self) -> np.ndarray:
        """Constant bias of every channel, shape (N_CHANNELS,), units per channel."""
        bias = np.zeros(N_CHANNELS)
        bias[CH_LOAD_CELL] = self.load_cell_bias
        bias[CH_ALTIMETER] = self.altimeter_bias
        bias[CH_ATTITUDE : CH_ATTITUDE + 3] = self.attitude_bias
        bias[CH_GPS : CH_GPS + 3] = self.gps_bias
        return bias

    def check_configuration(self, *, tethered: bool) -> None:
        """Raise ``ParameterError`` if the position source does not exist on the configuration.

        ``"tether"`` needs the ground-joint encoders, which the free helicopter lacks (its
        q7, q8, q9 are virtual).
        """
        if not tethered and self.position_source == "tether":
            raise ParameterError(
                f"{_SECTION}.position_source",
                self.position_source,
                "'true' or 'gps' for the free configuration (no tether encoders)",
            )

    def to_dict(self) -> dict[str, Any]:
        """A TOML-friendly table (tuples as lists) that ``sensor_config_from_dict`` maps back
        to an equal object."""
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            out[f.name] = list(value) if isinstance(value, tuple) else value
        return out


def sensor_config_from_dict(d: Mapping[str, Any], *, source: str | None = None) -> SensorConfig:
    """Build a ``SensorConfig`` from a table, strictly.

    Parameters
    ----------
    d : mapping
        ``field = value`` pairs of ``SensorConfig`` (missing fields keep their defaults),
        e.g. ``{"position_source": "tether", "encoder_std": 1.7e-3}``.
    source : str, optional
        Where the table came from (a file name), put in front of error messages.

    Returns
    -------
    SensorConfig

    Raises
    ------
    ParameterError
        ``d`` is not a table, a key is unknown (named as ``sensors.<key>``) or a value is
        invalid.
    """
    if not isinstance(d, Mapping):
        raise ParameterError(_SECTION, d, "a table of field = value", source=source)
    known = [f.name for f in fields(SensorConfig)]
    for key in d:
        if key not in known:
            raise ParameterError(f"{_SECTION}.{key}", d[key], f"one of {known}", source=source)
    try:
        return SensorConfig(**dict(d))
    except ParameterError as exc:
        raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None


def noise_table(config: SensorConfig, n_samples: int, rng: np.random.Generator) -> np.ndarray:
    """Noise plus bias of every channel for a run of ``n_samples`` control samples.

    The draw order is fixed: one ``rng.standard_normal((n_samples + 1, N_CHANNELS))`` call,
    filled row by row (sample 0 channels 0..16, then sample 1, ...), then scaled column-wise
    by ``config.channel_std()`` and shifted by ``config.channel_bias()``. Channels with zero
    std consume their draws too, so equal seeds give equal tables, and switching one sensor's
    noise on or off leaves the other channels' noise unchanged (common random numbers).

    Parameters
    ----------
    config : SensorConfig
    n_samples : int
        Number of control samples of the run (>= 0); rows are t_k = k dt, k = 0..n_samples.
    rng : numpy.random.Generator
        The run's generator (e.g. from ``SeedSequence.spawn``).

    Returns
    -------
    ndarray, shape (n_samples + 1, N_CHANNELS)
        Row k is what ``measure`` adds at sample k; units per channel (``CHANNEL_NAMES``).
    """
    if not isinstance(config, SensorConfig):
        raise ParameterError("config", config, "a SensorConfig")
    n_samples = check_integer("n_samples", n_samples, low=0)
    if not isinstance(rng, np.random.Generator):
        raise ParameterError("rng", rng, "a numpy.random.Generator")
    z = rng.standard_normal((int(n_samples) + 1, N_CHANNELS))
    return np.ascontiguousarray(z * config.channel_std() + config.channel_bias())


# --- compiled measurement -----------------------------------------------------------------------
@_jit
def measure(x_true, tension_true, noise_row, source_code, arm, x_est):
    """The controller's state and tension estimate at one sample (compiled); see
    ``measure_into``, which the closed loop calls with its own scratch array."""
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
        # the true HO = q9 c3 - arm f3 (eqs 43-45), measured; then P = HO_meas + arm f3 with
        # f3 the third column of N_R_F at the measured attitude (Table I)
        HO, R = scratch[0], scratch[1:]
        kinematics_tethered_HO(x_true, arm, HO)
        kinematics_dcm(x_est, R)
        p1 = HO[0] + noise_row[CH_GPS] + arm * R[0, 2]
        p2 = HO[1] + noise_row[CH_GPS + 1] + arm * R[1, 2]
        p3 = HO[2] + noise_row[CH_GPS + 2] + arm * R[2, 2]
        q9m = math.sqrt(p1 * p1 + p2 * p2 + p3 * p3)
        ratio = p1 / q9m
        if ratio > 1.0:
            ratio = 1.0
        elif ratio < -1.0:
            ratio = -1.0
        x_est[3] = math.atan2(-p2, p3)
        x_est[4] = math.asin(ratio)
        x_est[5] = q9m
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


@_jit
def measure_batch(x_true, tension_true, noise, source_code, arm, x_est, tension_est):
    """Row-wise ``measure``: x_true (n, 13), tension_true (n,), noise (n, N_CHANNELS); fills
    x_est (n, 13) and tension_est (n,) (for Monte Carlo analysis of the estimates)."""
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
