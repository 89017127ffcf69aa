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
c3, f3 are the tether direction and the fuselage axis in N (docs/paper.md, "Frames, points,
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

Flown sensors
-------------
With every field below at 0 (the default) a sensor is white noise plus a constant bias at
every control sample, without delay: the legacy model (``SensorConfig.is_white``), bit for
bit. Otherwise, per sensor group (``SENSOR_GROUPS``, a group shares rate and latency):

- ``<group>_rate`` [Hz], ``<group>_latency`` [s]: the sensor samples every P control samples
  and each sample arrives L samples later; in between the controller holds the newest
  arrived one (``sample_schedule``; rule and refusals in ``SensorConfig.group_timing``). The
  engine keeps a small history ring of true channel values for this (``measure_sampled``).
- ``gps_outage = [t_start, t_end]`` [s]: GNSS samples taken in it are lost (the last one
  before it is held).
- ``gyro_density`` [rad/s/sqrt(Hz)]: white noise given as a density instead of ``gyro_std``
  (``SensorConfig.white_std``); ``gyro_random_walk`` [rad/s/sqrt(s)]: a bias random walk.
- ``gps_markov_sigma`` (3,) [m], ``gps_markov_tau`` [s]; ``altimeter_markov_sigma`` [m],
  ``altimeter_markov_tau`` [s]: first-order Gauss-Markov errors (``gauss_markov``).
- ``accel_density``, ``accel_random_walk``, ``accel_bias``: the accelerometer, which only the
  state estimator reads (``accelerometer_errors``, ``tetherheli.estimation``).

Every additive error is drawn up front into the noise table, discretised exactly at the
control step; a slow sensor reads row j of its sample j. ``SENSOR_PRESETS`` holds
datasheet-class sensors (consumer and RTK GNSS, MEMS IMU, barometric and laser altimeters,
joint encoders, load cell), ``SensorConfig.flown`` a full suite of them.

Analysis helpers: ``tether_position_estimate`` (vectorised Sec. IV-F position estimate) and
``hover_error_std`` (first-order predicted std of that estimate, to compare with a GPS's std).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from functools import cached_property
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
    "CHANNEL_GROUP",
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
    "N_GROUPS",
    "POSITION_SOURCES",
    "SENSOR_GROUPS",
    "SENSOR_PRESETS",
    "SOURCE_GPS",
    "SOURCE_TETHER",
    "SOURCE_TRUE",
    "SensorConfig",
    "accelerometer_errors",
    "gauss_markov",
    "group_samples",
    "hover_error_std",
    "measure",
    "measure_batch",
    "measure_sampled",
    "measured_channels",
    "noise_table",
    "random_walk",
    "ring_rows",
    "sample_schedule",
    "sensor_config_from_dict",
    "tether_position_estimate",
    "true_channels_into",
]

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")

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
    # time-correlated and density-specified errors (``flown`` sensors; all 0: white only)
    "gyro_density": ("scalar", True),
    "gyro_random_walk": ("scalar", True),
    "gps_markov_sigma": ("triple", True),
    "gps_markov_tau": ("scalar", True),
    "altimeter_markov_sigma": ("scalar", True),
    "altimeter_markov_tau": ("scalar", True),
    "accel_density": ("scalar", True),
    "accel_random_walk": ("scalar", True),
    "accel_bias": ("triple", False),
}

#: The sensors, each a group of noise channels sharing one sample rate and latency; the
#: ``<group>_rate`` [Hz] and ``<group>_latency`` [s] fields of ``SensorConfig`` time them.
SENSOR_GROUPS: tuple[str, ...] = (
    "load_cell",
    "encoder",
    "altimeter",
    "attitude",
    "gyro",
    "velocity",
    "gps",
    "winch_encoder",
)
N_GROUPS = len(SENSOR_GROUPS)
#: the group of every noise channel (``CH_*`` order)
CHANNEL_GROUP = np.array([0, 1, 1, 2, 3, 3, 3, 4, 4, 4, 5, 5, 5, 6, 6, 6, 7], dtype=np.int64)
G_GPS = SENSOR_GROUPS.index("gps")
G_ENCODER = SENSOR_GROUPS.index("encoder")
for _g in SENSOR_GROUPS:
    _NUMERIC_FIELDS[f"{_g}_rate"] = ("scalar", True)
    _NUMERIC_FIELDS[f"{_g}_latency"] = ("scalar", True)
#: fields whose nonzero value leaves the legacy model (white noise at every control sample)
_FLOWN_FIELDS = tuple(name for name in _NUMERIC_FIELDS if not name.endswith(("_std", "_bias")))
#: timing rounding tolerance: a period or latency within this many samples of an integer
_GRID_TOL = 1e-6


@dataclass(frozen=True)
class SensorConfig:
    """The controller's sensors: position source, noise standard deviations and biases.

    Every measurement is the true value plus white Gaussian noise of the given standard
    deviation (independent per sample and per channel) plus the constant bias. The standard
    deviations are *per control sample* (the noise is not scaled with the sample time). All
    defaults are zero with ``position_source="true"``: perfect sensors, the paper's
    assumption, so the paper's results are unchanged. All the fields from ``gyro_density`` on
    (rates [Hz], latencies [s]) are 0 / empty by default too: the legacy white model.

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
    gyro_density : float
        Gyro white noise as a density instead of ``gyro_std`` [rad/s/sqrt(Hz)]
        (``white_std``).
    gyro_random_walk : float
        Gyro bias random walk [rad/s/sqrt(s)].
    gps_markov_sigma : tuple of 3 floats
        Standard deviation of the GNSS's first-order Gauss-Markov error along n1, n2, n3 [m].
    gps_markov_tau : float
        Correlation time of that error [s]; > 0 when ``gps_markov_sigma`` is set.
    altimeter_markov_sigma : float
        Standard deviation of the altimeter's Gauss-Markov error [m].
    altimeter_markov_tau : float
        Correlation time of that error [s]; > 0 when ``altimeter_markov_sigma`` is set.
    accel_density : float
        Accelerometer white noise density [m/s^2/sqrt(Hz)] (read by the state estimator
        only, ``accelerometer_errors``).
    accel_random_walk : float
        Accelerometer bias random walk [m/s^2/sqrt(s)].
    accel_bias : tuple of 3 floats
        Constant accelerometer bias along n1, n2, n3 [m/s^2].
    gps_outage : sequence of 2 floats
        ``[t_start, t_end]`` [s]: GNSS samples taken in it are lost (the last one before it
        is held); empty: none.
    load_cell_rate : float
        sample rate of the load_cell sensor (0: every control sample)
    load_cell_latency : float
        delay of the load_cell sensor's output (0: none)
    encoder_rate : float
        sample rate of the encoder sensor (0: every control sample)
    encoder_latency : float
        delay of the encoder sensor's output (0: none)
    altimeter_rate : float
        sample rate of the altimeter sensor (0: every control sample)
    altimeter_latency : float
        delay of the altimeter sensor's output (0: none)
    attitude_rate : float
        sample rate of the attitude sensor (0: every control sample)
    attitude_latency : float
        delay of the attitude sensor's output (0: none)
    gyro_rate : float
        sample rate of the gyro sensor (0: every control sample)
    gyro_latency : float
        delay of the gyro sensor's output (0: none)
    velocity_rate : float
        sample rate of the velocity sensor (0: every control sample)
    velocity_latency : float
        delay of the velocity sensor's output (0: none)
    gps_rate : float
        sample rate of the gps sensor (0: every control sample)
    gps_latency : float
        delay of the gps sensor's output (0: none)
    winch_encoder_rate : float
        sample rate of the winch_encoder sensor (0: every control sample)
    winch_encoder_latency : float
        delay of the winch_encoder sensor's output (0: none)

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
    # --- sensors as they are flown (module docstring "Flown sensors"); 0: off -------------
    gyro_density: float = 0.0
    gyro_random_walk: float = 0.0
    gps_markov_sigma: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gps_markov_tau: float = 0.0
    altimeter_markov_sigma: float = 0.0
    altimeter_markov_tau: float = 0.0
    accel_density: float = 0.0
    accel_random_walk: float = 0.0
    accel_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gps_outage: tuple[float, ...] = ()
    load_cell_rate: float = 0.0
    load_cell_latency: float = 0.0
    encoder_rate: float = 0.0
    encoder_latency: float = 0.0
    altimeter_rate: float = 0.0
    altimeter_latency: float = 0.0
    attitude_rate: float = 0.0
    attitude_latency: float = 0.0
    gyro_rate: float = 0.0
    gyro_latency: float = 0.0
    velocity_rate: float = 0.0
    velocity_latency: float = 0.0
    gps_rate: float = 0.0
    gps_latency: float = 0.0
    winch_encoder_rate: float = 0.0
    winch_encoder_latency: float = 0.0

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
        if self.gyro_std > 0.0 and self.gyro_density > 0.0:
            raise ParameterError(
                f"{_SECTION}.gyro_density",
                self.gyro_density,
                "0 when gyro_std is set (one or the other)",
            )
        for name in ("gps", "altimeter"):
            sigma, tau = getattr(self, f"{name}_markov_sigma"), getattr(self, f"{name}_markov_tau")
            if np.any(np.asarray(sigma) > 0.0) and not tau > 0.0:
                raise ParameterError(
                    f"{_SECTION}.{name}_markov_tau", tau, f"> 0 s when {name}_markov_sigma is set"
                )
        outage = self.gps_outage
        allowed = "[] or [t_start, t_end] with 0 <= t_start < t_end [s]"
        if isinstance(outage, (str, bytes)) or not hasattr(outage, "__len__"):
            raise ParameterError(f"{_SECTION}.gps_outage", outage, allowed)
        if len(outage) != 0:
            values = check_vector(f"{_SECTION}.gps_outage", outage, 2, low=0.0, unit="[s]")
            if not values[0] < values[1]:
                raise ParameterError(f"{_SECTION}.gps_outage", list(outage), allowed)
            object.__setattr__(self, "gps_outage", tuple(values))
        else:
            object.__setattr__(self, "gps_outage", ())

    # --- presets ------------------------------------------------------------------------------
    @classmethod
    def perfect(cls) -> SensorConfig:
        """Perfect sensors and the true position: the paper's assumption (the default).

        Returns
        -------
        SensorConfig
            All stds and biases 0, ``position_source="true"``.
        """
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

        Returns
        -------
        SensorConfig
            The preset, position from the GPS.
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

        Returns
        -------
        SensorConfig
            The preset, position from the GPS.
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

        Returns
        -------
        SensorConfig
            The preset, position from the tether (tethered configuration only).
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

    @classmethod
    def from_presets(cls, *names: str, **fields_: Any) -> SensorConfig:
        """The sensors of ``SENSOR_PRESETS`` ``names`` (later ones win on shared fields), then
        ``fields_`` (e.g. ``position_source``, ``gps_outage``) on top.

        Parameters
        ----------
        *names : str
            Keys of ``SENSOR_PRESETS``.
        **fields_ : Any
            ``SensorConfig`` fields that override the presets.

        Returns
        -------
        SensorConfig
            The merged sensors.

        Raises
        ------
        ParameterError
            An unknown preset name.
        """
        merged: dict[str, Any] = {}
        for name in names:
            if name not in SENSOR_PRESETS:
                raise ParameterError(
                    f"{_SECTION}.presets", name, f"one of {sorted(SENSOR_PRESETS)}"
                )
            merged.update(SENSOR_PRESETS[name])
        merged.update(fields_)
        return cls(**merged)

    @classmethod
    def flown(
        cls,
        position_source: str = "gps",
        *,
        gnss: str = "consumer",
        altimeter: str = "laser",
        gps_outage: tuple[float, ...] = (),
    ) -> SensorConfig:
        """A full suite of sensors as they are flown (``SENSOR_PRESETS``): a GNSS receiver
        (``gnss`` "consumer" or "rtk"), the MEMS IMU, an altimeter (``altimeter`` "laser" or
        "barometric"), the ground-joint encoders, the load cell and the winch encoder; the
        controller's position from ``position_source``.

        Parameters
        ----------
        position_source : {"true", "gps", "tether"}
            Where the controller's position comes from.
        gnss : {"consumer", "rtk"}
            The GNSS receiver's preset.
        altimeter : {"laser", "barometric"}
            The altimeter's preset.
        gps_outage : tuple of 2 floats or ()
            ``(t_start, t_end)`` [s] of a GNSS outage; empty: none.

        Returns
        -------
        SensorConfig
            The suite.
        """
        if gnss not in ("consumer", "rtk"):
            raise ParameterError("gnss", gnss, "'consumer' or 'rtk'")
        if altimeter not in ("laser", "barometric"):
            raise ParameterError("altimeter", altimeter, "'laser' or 'barometric'")
        return cls.from_presets(
            f"{gnss}_gnss",
            "mems_imu",
            f"{altimeter}_altimeter",
            "joint_encoders",
            "load_cell",
            "winch_encoder",
            position_source=position_source,
            gps_outage=gps_outage,
        )

    # --- derived ------------------------------------------------------------------------------
    @property
    def source_code(self) -> int:
        """The integer code of ``position_source`` (``SOURCE_*``) for ``measure``."""
        return POSITION_SOURCES[self.position_source]

    @cached_property  # the config is frozen; a batch asks for it per run
    def is_perfect(self) -> bool:
        """True when every std and bias is zero, no sensor is timed, correlated or out, and
        the position source is ``"true"``: the measurement equals the true state and tension,
        so an engine may skip ``measure``."""
        return (
            self.position_source == "true"
            and not np.any(self.channel_std())
            and not np.any(self.channel_bias())
            and self.is_white
        )

    @cached_property  # the config is frozen; a batch asks for it per run
    def is_white(self) -> bool:
        """True for the legacy model: white noise plus constant bias at every control sample,
        no delay (every ``Flown sensors`` field of the module docstring at 0, no outage)."""
        return not self.gps_outage and not any(
            np.any(np.asarray(getattr(self, name))) for name in _FLOWN_FIELDS
        )

    @cached_property  # the config is frozen; a batch asks for it per run
    def is_timed(self) -> bool:
        """True when a sensor has its own rate or latency, or the GNSS an outage (the engine
        then holds and delays samples: ``sample_schedule``)."""
        return bool(self.gps_outage) or any(
            getattr(self, f"{g}_{what}") > 0.0
            for g in SENSOR_GROUPS
            for what in ("rate", "latency")
        )

    def group_timing(self, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """Sample period and latency of every sensor group (``SENSOR_GROUPS``) in control
        samples of ``dt`` [s], shape (N_GROUPS,) each, integers.

        Rule: a rate of 0 or at least the control rate 1/dt gives period 1 (the controller
        reads the newest sample at every control sample); a slower rate r must divide it,
        1/(r dt) an integer (e.g. 50, 25, 20, 10, 5, 1 Hz at dt = 0.01 s); a latency must be
        a multiple of dt. Anything else is refused (``ParameterError`` naming the field), so
        a scenario never means a timing it does not get.

        Parameters
        ----------
        dt : float
            Control sample time [s], > 0.

        Returns
        -------
        period, latency : numpy.ndarray of int64, shape (N_GROUPS,)
            Sample period and latency of each group, in control samples.
        """
        dt = check_number("control.dt", dt, low=0.0, low_open=True)
        period = np.ones(N_GROUPS, dtype=np.int64)
        latency = np.zeros(N_GROUPS, dtype=np.int64)
        for i, g in enumerate(SENSOR_GROUPS):
            rate, lag = getattr(self, f"{g}_rate"), getattr(self, f"{g}_latency")
            if rate > 0.0 and rate * dt < 1.0 - _GRID_TOL:
                p = 1.0 / (rate * dt)
                if abs(p - round(p)) > _GRID_TOL * p:
                    raise ParameterError(
                        f"{_SECTION}.{g}_rate",
                        rate,
                        f"0, >= 1/dt = {1.0 / dt:g} Hz, or a rate r with 1/(r dt) an integer "
                        f"(dt = {dt:g} s)",
                    )
                period[i] = round(p)
            n_lag = lag / dt
            if abs(n_lag - round(n_lag)) > _GRID_TOL * max(1.0, n_lag):
                raise ParameterError(
                    f"{_SECTION}.{g}_latency", lag, f"a multiple of control.dt = {dt:g} s"
                )
            latency[i] = round(n_lag)
        return period, latency

    def white_std(self, dt: float | None = None) -> np.ndarray:
        """Per-sample std of the white noise of every channel, shape (N_CHANNELS,):
        ``channel_std`` with the gyro's from ``gyro_density`` when that is set (needs
        ``dt``): sigma = N sqrt(f) with f the gyro's sample rate, min(gyro_rate, 1/dt) (the
        average over one sample of continuous white noise of density N, IEEE Std 952's
        angle-random-walk convention; a datasheet quoting N sqrt(bandwidth) with the
        bandwidth f/2 gives a std smaller by sqrt(2)).

        Parameters
        ----------
        dt : float or None
            Control sample time [s]; needed only when ``gyro_density`` is set.

        Returns
        -------
        numpy.ndarray, shape (N_CHANNELS,)
            Per-sample std of every channel, units per channel (``CHANNEL_NAMES``).
        """
        std = self.channel_std()
        if self.gyro_density > 0.0:
            if dt is None:
                raise ParameterError("dt", dt, "the control sample time [s] (gyro_density is set)")
            period = self.group_timing(dt)[0][SENSOR_GROUPS.index("gyro")]
            std[CH_GYRO : CH_GYRO + 3] = self.gyro_density / math.sqrt(period * dt)
        return std

    def channel_std(self) -> np.ndarray:
        """Noise standard deviation of every channel, shape (N_CHANNELS,), units per channel
        (see ``CHANNEL_NAMES``).

        Returns
        -------
        numpy.ndarray, shape (N_CHANNELS,)
            The stds, in ``CH_*`` order.
        """
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
        """Constant bias of every channel, shape (N_CHANNELS,), units per channel.

        Returns
        -------
        numpy.ndarray, shape (N_CHANNELS,)
            The biases, in ``CH_*`` order (0 for channels without a bias field).
        """
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

        Parameters
        ----------
        tethered : bool
            True for the tethered configuration, False for the free helicopter.
        """
        if not tethered and self.position_source == "tether":
            raise ParameterError(
                f"{_SECTION}.position_source",
                self.position_source,
                "'true' or 'gps' for the free configuration (no tether encoders)",
            )

    def to_dict(self) -> dict[str, Any]:
        """A TOML-friendly table (tuples as lists) that ``sensor_config_from_dict`` maps back
        to an equal object.

        Returns
        -------
        dict of str to Any
            Field name to value, tuples as lists.
        """
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            out[f.name] = list(value) if isinstance(value, tuple) else value
        return out


_RAD_PER_DEG_S = _DEG  # [rad/s] per [deg/s]
_G0 = 9.80665  # standard gravity [m/s^2], for datasheet figures in g

#: Datasheet-class sensors, each the ``SensorConfig`` fields it sets (``from_presets``,
#: ``flown``; a scenario's ``[sensors] presets = [...]``). 1-sigma numbers; the kind of
#: source each comes from is given beside it.
SENSOR_PRESETS: Mapping[str, Mapping[str, Any]] = MappingProxyType(
    {
        # single-frequency consumer GNSS, u-blox M8 datasheet class: 2.5 m CEP horizontal
        # (CEP = 1.18 sigma per axis: ~2.1 m), vertical about twice, Doppler velocity
        # 0.05 m/s, navigation rate up to 10 Hz, ~0.1-0.2 s from measurement to output. The
        # position error is mostly slow (satellite geometry, ionosphere, multipath):
        # Gauss-Markov 1.5 m (3 m vertical) with a 100 s correlation time, plus 0.2 m
        # (0.4 m) white receiver noise. The velocity is the IMU-aided navigation solution's
        # (0.05 m/s, at the control rate, no delay): with the raw 5 Hz, 0.15 s Doppler
        # velocity the paper's LQI loses simulation 1 (tests/test_sensors_flown.py).
        "consumer_gnss": {
            "gps_std": (0.2, 0.2, 0.4),
            "gps_markov_sigma": (1.5, 1.5, 3.0),
            "gps_markov_tau": 100.0,
            "gps_rate": 5.0,
            "gps_latency": 0.15,
            "velocity_std": 0.05,
        },
        # RTK GNSS (fixed solution), u-blox F9 datasheet class: 0.01 m + 1 ppm CEP
        # horizontal, about twice vertical, up to 20 Hz: Gauss-Markov 1 cm (2 cm) over 60 s
        # plus 5 mm (1 cm) white; velocity 0.02 m/s; 10 Hz, 50 ms latency.
        "rtk_gnss": {
            "gps_std": (0.005, 0.005, 0.01),
            "gps_markov_sigma": (0.01, 0.01, 0.02),
            "gps_markov_tau": 60.0,
            "gps_rate": 10.0,
            "gps_latency": 0.05,
            "velocity_std": 0.02,
        },
        # MEMS IMU, Bosch BMI088 datasheet class: gyro noise density 0.014 deg/s/sqrt(Hz),
        # accelerometer 175 ug/sqrt(Hz). Bias instability (Allan minimum, consumer MEMS,
        # a few deg/h and ~50 ug near 100 s) as a bias random walk K = B / sqrt(tau / 3):
        # 2e-6 rad/s/sqrt(s) and 1e-4 m/s^2/sqrt(s). Sampled at or above the control rate.
        # The attitude is the AHRS's output, 0.5 deg per axis (roll/pitch specification
        # of MEMS AHRS modules).
        "mems_imu": {
            "gyro_density": 0.014 * _RAD_PER_DEG_S,
            "gyro_random_walk": 2e-6,
            "accel_density": 175e-6 * _G0,
            "accel_random_walk": 1e-4,
            "attitude_std": 0.5 * _DEG,
        },
        # barometric altimeter, Bosch BMP388 datasheet class: relative accuracy +-0.08 hPa
        # (+-0.66 m) as a slow drift (Gauss-Markov 0.5 m over 300 s), 0.1 m white noise in
        # flight (rotor wash), 25 Hz, 40 ms filter delay.
        "barometric_altimeter": {
            "altimeter_std": 0.1,
            "altimeter_markov_sigma": 0.5,
            "altimeter_markov_tau": 300.0,
            "altimeter_rate": 25.0,
            "altimeter_latency": 0.04,
        },
        # laser altimeter over flat ground, Garmin LIDAR-Lite v3 datasheet class: +-2.5 cm
        # above 1 m; 50 Hz, 20 ms delay.
        "laser_altimeter": {
            "altimeter_std": 0.025,
            "altimeter_rate": 50.0,
            "altimeter_latency": 0.02,
        },
        # ground-joint encoders: 14-bit absolute optical encoders, quantisation
        # 2 pi / 2^14 rad, std LSB / sqrt(12) = 1.1e-4 rad; read at the control rate.
        "joint_encoders": {"encoder_std": 2.0 * math.pi / 2**14 / math.sqrt(12.0)},
        # load cell of 100 N range, accuracy class C3 (OIML R 60: 3000 verification
        # intervals): 100 N / 3000 = 0.033 N.
        "load_cell": {"load_cell_std": 100.0 / 3000.0},
        # winch drum encoder: about 1 mm of tether per count
        "winch_encoder": {"winch_encoder_std": 1e-3},
    }
)


def sensor_config_from_dict(d: Mapping[str, Any], *, source: str | None = None) -> SensorConfig:
    """Build a ``SensorConfig`` from a table, strictly.

    Parameters
    ----------
    d : mapping
        ``field = value`` pairs of ``SensorConfig`` (missing fields keep their defaults),
        e.g. ``{"position_source": "tether", "encoder_std": 1.7e-3}``, and optionally
        ``presets``, a list of ``SENSOR_PRESETS`` names applied first (the other keys
        override them), e.g. ``{"presets": ["consumer_gnss", "mems_imu"]}``.
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
        if key not in known and key != "presets":
            raise ParameterError(
                f"{_SECTION}.{key}", d[key], f"'presets' or one of {known}", source=source
            )
    table = dict(d)
    presets = table.pop("presets", [])
    if isinstance(presets, str) or not isinstance(presets, (list, tuple)):
        raise ParameterError(
            f"{_SECTION}.presets", presets, f"a list of {sorted(SENSOR_PRESETS)}", source=source
        )
    try:
        return SensorConfig.from_presets(*presets, **table)
    except ParameterError as exc:
        raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None


def noise_table(
    config: SensorConfig, n_samples: int, rng: np.random.Generator, *, dt: float | None = None
) -> np.ndarray:
    """Noise plus bias of every channel for a run of ``n_samples`` control samples.

    The draw order is fixed: one ``rng.standard_normal((n_samples + 1, N_CHANNELS))`` call,
    filled row by row (sample 0 channels 0..16, then sample 1, ...), then scaled column-wise
    by ``config.white_std(dt)`` and shifted by ``config.channel_bias()``. Channels with zero
    std consume their draws too, so equal seeds give equal tables, and switching one sensor's
    noise on or off leaves the other channels' noise unchanged (common random numbers).

    Flown sensors (``config.is_white`` False) add their time-correlated errors, discretised
    exactly at the control step ``dt`` from a second block of the same shape drawn next:
    the GNSS and altimeter Gauss-Markov errors (``gauss_markov``, stationary from sample 0)
    and the gyro bias random walk (``random_walk``, 0 at sample 0). A sensor slower than the
    control holds row j of its sample j, so every row is a sample of the continuous process.

    Parameters
    ----------
    config : SensorConfig
        The sensors.
    n_samples : int
        Number of control samples of the run (>= 0); rows are t_k = k dt, k = 0..n_samples.
    rng : numpy.random.Generator
        The run's generator (e.g. from ``SeedSequence.spawn``).
    dt : float or None
        Control sample time [s]; needed when ``config`` has flown sensors or a gyro density.

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
    if config.is_white:
        return np.ascontiguousarray(z * config.channel_std() + config.channel_bias())
    if dt is None:
        raise ParameterError("dt", dt, "the control sample time [s] (flown sensors are set)")
    table = z * config.white_std(dt) + config.channel_bias()
    w = rng.standard_normal(z.shape)
    gps = slice(CH_GPS, CH_GPS + 3)
    if np.any(np.asarray(config.gps_markov_sigma) > 0.0):
        table[:, gps] += gauss_markov(config.gps_markov_sigma, config.gps_markov_tau, dt, w[:, gps])
    if config.altimeter_markov_sigma > 0.0:
        alt = slice(CH_ALTIMETER, CH_ALTIMETER + 1)
        table[:, alt] += gauss_markov(
            config.altimeter_markov_sigma, config.altimeter_markov_tau, dt, w[:, alt]
        )
    if config.gyro_random_walk > 0.0:
        gyro = slice(CH_GYRO, CH_GYRO + 3)
        table[:, gyro] += random_walk(config.gyro_random_walk, dt, w[:, gyro])
    return np.ascontiguousarray(table)


def gauss_markov(sigma: Any, tau: float, dt: float, w: np.ndarray) -> np.ndarray:
    """A first-order Gauss-Markov process sampled at dt, exactly: e_0 = sigma w_0,
    e_k = phi e_{k-1} + sigma sqrt(1 - phi^2) w_k with phi = exp(-dt / tau).

    It is the sampled solution of de/dt = -e / tau + noise of intensity 2 sigma^2 / tau:
    stationary, variance sigma^2, autocorrelation sigma^2 exp(-|lag| / tau) (Gelb, *Applied
    Optimal Estimation*, Table 3.4-1).

    Parameters
    ----------
    sigma : float or array_like, shape (m,)
        Stationary standard deviation of each column (any unit).
    tau : float
        Correlation time [s], > 0.
    dt : float
        Sample time [s].
    w : numpy.ndarray, shape (n, m)
        Standard normal draws.

    Returns
    -------
    numpy.ndarray, shape (n, m)
        The process at samples 0..n-1, in the unit of ``sigma``.
    """
    from scipy.signal import lfilter

    phi = math.exp(-dt / tau)
    sigma = np.broadcast_to(np.asarray(sigma, dtype=float), (w.shape[1],))
    e = np.empty_like(w)
    e[0] = sigma * w[0]
    if w.shape[0] > 1:
        drive = w[1:] * (sigma * math.sqrt(1.0 - phi * phi))
        e[1:] = lfilter([1.0], [1.0, -phi], drive, axis=0, zi=(phi * e[0])[None, :])[0]
    return e


def random_walk(density: float, dt: float, w: np.ndarray) -> np.ndarray:
    """A random walk sampled at dt: b_0 = 0, b_k = b_{k-1} + density sqrt(dt) w_k, i.e. white
    noise of density ``density`` integrated (a rate random walk for a gyro, rad/s/sqrt(s));
    variance density^2 k dt at sample k.

    Parameters
    ----------
    density : float
        Density of the integrated white noise [unit/sqrt(s)].
    dt : float
        Sample time [s].
    w : numpy.ndarray, shape (n, m)
        Standard normal draws (row 0 is not used: b_0 = 0).

    Returns
    -------
    numpy.ndarray, shape (n, m)
        The walk at samples 0..n-1 [unit of ``density`` times sqrt(s)].
    """
    b = np.cumsum(w * (density * math.sqrt(dt)), axis=0)
    b -= b[0]
    return b


def accelerometer_errors(
    config: SensorConfig, n_samples: int, rng: np.random.Generator, dt: float
) -> np.ndarray:
    """The accelerometer's errors along n1, n2, n3 for the state estimator, shape
    (n_samples + 1, 3) [m/s^2]: white noise of density ``accel_density`` at the control rate
    (sigma = N / sqrt(dt), as ``white_std``), a bias random walk ``accel_random_walk``
    (``random_walk``) and the constant ``accel_bias``. Drawn as one (n + 1, 6) block.

    Parameters
    ----------
    config : SensorConfig
        The sensors (``accel_density``, ``accel_random_walk``, ``accel_bias``).
    n_samples : int
        Number of control samples of the run, >= 0.
    rng : numpy.random.Generator
        The generator the block is drawn from.
    dt : float
        Control sample time [s].

    Returns
    -------
    numpy.ndarray, shape (n_samples + 1, 3)
        Row k: the accelerometer error at sample k [m/s^2].
    """
    n_samples = check_integer("n_samples", n_samples, low=0)
    w = rng.standard_normal((n_samples + 1, 6))
    out = w[:, :3] * (config.accel_density / math.sqrt(dt)) + np.asarray(config.accel_bias)
    if config.accel_random_walk > 0.0:
        out += random_walk(config.accel_random_walk, dt, w[:, 3:])
    return out


def sample_schedule(config: SensorConfig, dt: float, n_samples: int) -> np.ndarray:
    """Which sample every sensor group reports at every control sample, shape
    (n_samples + 1, N_GROUPS), int64; (0, N_GROUPS) for untimed sensors (``is_timed``).

    Sensor group g samples at the control samples j = 0, P, 2P, ... (period P, ``group_timing``),
    except GNSS samples with j dt in ``gps_outage`` = [t_start, t_end), which are lost; sample
    j arrives L samples later (latency L). At control sample k the sensor reports its newest
    arrived sample (zero-order hold): the largest valid j <= k - L. Before the first one
    arrives (k < L) it reports sample 0, as a sensor that has been reading the trim since
    before t = 0. The measurement at k is then the true value of sample j plus row j of the
    noise table.

    Parameters
    ----------
    config : SensorConfig
        The sensors (rates, latencies, ``gps_outage``).
    dt : float
        Control sample time [s].
    n_samples : int
        Number of control samples of the run, >= 0.

    Returns
    -------
    numpy.ndarray of int64, shape (n_samples + 1, N_GROUPS) or (0, N_GROUPS)
        Row k, column g: the sample index j group g reports at control sample k; no rows for
        untimed sensors.
    """
    n_samples = check_integer("n_samples", n_samples, low=0)
    if not config.is_timed:
        return np.zeros((0, N_GROUPS), dtype=np.int64)
    period, latency = config.group_timing(dt)
    k = np.arange(n_samples + 1)
    out = np.empty((n_samples + 1, N_GROUPS), dtype=np.int64)
    for g in range(N_GROUPS):
        newest = np.maximum.accumulate(np.where(_valid_samples(config, dt, k, g, period[g]), k, 0))
        out[:, g] = newest[np.maximum(k - latency[g], 0)]
    return out


def _valid_samples(
    config: SensorConfig, dt: float, k: np.ndarray, g: int, period: int
) -> np.ndarray:
    valid = k % period == 0
    if g == G_GPS and config.gps_outage:
        t0, t1 = config.gps_outage
        lo, hi = math.ceil(t0 / dt - _GRID_TOL), math.ceil(t1 / dt - _GRID_TOL)
        valid &= (k < lo) | (k >= hi)
    return valid


def group_samples(
    config: SensorConfig, dt: float, n_samples: int, group: str
) -> tuple[np.ndarray, int]:
    """The samples a sensor group delivers in a run: (sample indices j, latency L in samples);
    sample j reaches the user at j + L (only those with j + L <= n_samples are returned).
    Same rule as ``sample_schedule``.

    Parameters
    ----------
    config : SensorConfig
        The sensors.
    dt : float
        Control sample time [s].
    n_samples : int
        Number of control samples of the run.
    group : str
        One of ``SENSOR_GROUPS``.

    Returns
    -------
    samples : numpy.ndarray of int, shape (m,)
        Control sample indices j at which the group samples (outage samples removed).
    latency : int
        Latency L in control samples.

    Raises
    ------
    ParameterError
        An unknown ``group`` or a rate/latency off the control grid.
    """
    if group not in SENSOR_GROUPS:
        raise ParameterError("group", group, f"one of {SENSOR_GROUPS}")
    g = SENSOR_GROUPS.index(group)
    period, latency = config.group_timing(dt)
    k = np.arange(n_samples + 1 - latency[g])
    return k[_valid_samples(config, dt, k, g, period[g])], int(latency[g])


def ring_rows(schedule: np.ndarray) -> int:
    """Rows of the history ring ``measure_sampled`` needs for ``schedule``: the oldest sample
    ever reported, counted back from the current one, plus one (1 for an empty schedule).

    Parameters
    ----------
    schedule : numpy.ndarray of int, shape (n + 1, N_GROUPS) or (0, N_GROUPS)
        ``sample_schedule``'s output.

    Returns
    -------
    int
        Number of ring rows, >= 1.
    """
    if schedule.shape[0] == 0:
        return 1
    return int((np.arange(schedule.shape[0])[:, None] - schedule).max()) + 1


# --- compiled measurement -----------------------------------------------------------------------
@_jit
def measure(x_true, tension_true, noise_row, source_code, arm, x_est):
    """The controller's state and tension estimate at one sample (compiled); see
    ``measure_into``, which the closed loop calls with its own scratch array.

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
            scratch[1:],
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
def _tether_from_gps(h1, h2, h3, arm, x_est, R):
    """q7, q8, q9 of x_est from a measured HO (h1, h2, h3) and the measured attitude in
    x_est: P = HO + arm f3, f3 the third column of N_R_F (Table I, into R (3, 3)), then the
    inverse of c3 = [s8, -s7 c8, c7 c8] (eqs 43-45)."""
    kinematics_dcm(x_est, R)
    p1 = h1 + arm * R[0, 2]
    p2 = h2 + arm * R[1, 2]
    p3 = h3 + arm * R[2, 2]
    q9m = math.sqrt(p1 * p1 + p2 * p2 + p3 * p3)
    ratio = p1 / q9m
    if ratio > 1.0:
        ratio = 1.0
    elif ratio < -1.0:
        ratio = -1.0
    x_est[3] = math.atan2(-p2, p3)
    x_est[4] = math.asin(ratio)
    x_est[5] = q9m


@_jit
def true_channels_into(x_true, tension_true, arm, HO, out):
    """The true value of every noise channel (``CH_*`` order) into out (N_CHANNELS,): TC,
    q7, q8, altitude of HO, q4..q6, u4..u6, u1..u3, HO in N (eqs 43-45, into HO (3,)), LN.

    Parameters
    ----------
    x_true : ndarray, shape (13,)
        True state [q4..q9, u1..u6, LN] (rad, m, m/s, rad/s, m).
    tension_true : float
        True tether tension TC [N] (0 for the free configuration).
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).
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
    its own rate and latency (compiled); ``sensors`` is ``sim.setup.sensor_tuple``'s
    (noise table, source code, arm, scratch (4, 3), schedule, ring).

    With an empty schedule this is ``measure_into`` with noise row k (white sensors, no
    delay: the legacy model, bit for bit). Otherwise the true channels of this sample are
    stored in row k mod H of the history ring (H = rows - 1; its last row is scratch) and
    channel c reads sample j = schedule[k, group of c] (``sample_schedule``): the true value
    stored at j plus noise row j. The position source then converts as ``measure_into``.

    Parameters
    ----------
    x_true : ndarray, shape (13,)
        True state [q4..q9, u1..u6, LN] (rad, m, m/s, rad/s, m).
    tension_true : float
        True tether tension TC [N] (0 for the free configuration).
    k : int
        Control sample index.
    sensors : tuple
        ``(noise (n + 1, N_CHANNELS), source_code, arm, scratch (4, 3), schedule, ring)``
        from ``sim.setup.sensor_tuple``.
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
        _tether_from_gps(m[CH_GPS], m[CH_GPS + 1], m[CH_GPS + 2], arm, x_est, scratch[1:])
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
    at k). Used to feed a state estimator after a run (``tetherheli.estimation``).

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
