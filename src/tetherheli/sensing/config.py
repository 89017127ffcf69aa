"""Sensor configuration: what the controller measures instead of the true state and tension.

The paper's controller (Sec. V) reads the full state and the tether tension. Real helicopters
measure them: an IMU (attitude, body rates), a GPS or the tether itself (position), a load
cell (tension, Sec. IV-D) and the winch drum's encoder (natural length LN). The ``sensing``
package models those sensors as the true value plus noise plus a bias, and rebuilds the
controller's tethered-coordinate state estimate from the measurements. This module holds
the configuration (``SensorConfig``, the channels, groups and position sources);
``presets`` the datasheet-class sensors, ``noise`` the noise table, ``schedules`` the
sample schedule of slow and delayed sensors, ``sensors`` the compiled measurement and
``estimation`` the position filter flown after a run.

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

``noise.noise_table`` draws the rows for a whole run up front (so the compiled engine only
adds a row per sample and runs are reproducible from a seed); ``sensing.sensors.measure`` is the
compiled measurement function the engine calls at every sample.

Flown sensors
-------------
With every field below at 0 (the default) a sensor is white noise plus a constant bias at
every control sample, without delay: the legacy model (``SensorConfig.is_white``), bit for
bit. Otherwise, per sensor group (``SENSOR_GROUPS``, a group shares rate and latency):

- ``<group>_rate`` [Hz], ``<group>_latency`` [s]: the sensor samples every P control samples
  and each sample arrives L samples later; in between the controller holds the newest
  arrived one (``schedules.sample_schedule``; rule and refusals in
  ``SensorConfig.group_timing``). The engine keeps a small history ring of true channel
  values for this (``sensing.sensors.measure_sampled``).
- ``gps_outage = [t_start, t_end]`` [s]: GNSS samples taken in it are lost (the last one
  before it is held).
- ``gyro_density`` [rad/s/sqrt(Hz)]: white noise given as a density instead of ``gyro_std``
  (``SensorConfig.white_std``); ``gyro_random_walk`` [rad/s/sqrt(s)]: a bias random walk.
- ``gps_markov_sigma`` (3,) [m], ``gps_markov_tau`` [s]; ``altimeter_markov_sigma`` [m],
  ``altimeter_markov_tau`` [s]: first-order Gauss-Markov errors (``noise.gauss_markov``).
- ``accel_density``, ``accel_random_walk``, ``accel_bias``: the accelerometer, which only the
  state estimator reads (``noise.accelerometer_errors``, ``estimation``).

Every additive error is drawn up front into the noise table, discretised exactly at the
control step; a slow sensor reads row j of its sample j. ``presets.SENSOR_PRESETS`` holds
datasheet-class sensors (consumer and RTK GNSS, MEMS IMU, barometric and laser altimeters,
joint encoders, load cell), ``SensorConfig.flown`` a full suite of them.

Analysis helpers (in ``sensors``): ``tether_position_estimate`` (vectorised Sec. IV-F
position estimate) and ``hover_error_std`` (first-order predicted std of that estimate, to
compare with a GPS's std).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from functools import cached_property
from types import MappingProxyType
from typing import Any

import numpy as np

from .._validation import check_number, check_vector
from ..errors import ParameterError
from .presets import SENSOR_PRESETS

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
    "G_ENCODER",
    "G_GPS",
    "N_CHANNELS",
    "N_GROUPS",
    "POSITION_SOURCES",
    "SENSOR_GROUPS",
    "SOURCE_GPS",
    "SOURCE_TETHER",
    "SOURCE_TRUE",
    "SensorConfig",
    "sensor_config_from_dict",
    "white_gnss",
]

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


def white_gnss(name: str) -> dict[str, Any]:
    """A GNSS receiver of ``SENSOR_PRESETS`` as white noise at every control sample (the
    ``typical_*`` presets): its whole position error, the white and the Gauss-Markov parts
    summed in quadrature (their stationary variances add), and its velocity std.

    Parameters
    ----------
    name : str
        A GNSS preset of ``SENSOR_PRESETS`` ("consumer_gnss", "rtk_gnss").

    Returns
    -------
    dict of str to object
        ``gps_std`` (3,) [m] and ``velocity_std`` [m/s], ``SensorConfig`` fields.
    """
    g = SENSOR_PRESETS[name]
    white, markov = g["gps_std"], g["gps_markov_sigma"]
    return {
        "gps_std": tuple(math.hypot(w, m) for w, m in zip(white, markov, strict=True)),
        "velocity_std": g["velocity_std"],
    }


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
    load_cell_rate, encoder_rate, altimeter_rate, attitude_rate : float
        Sample rate of each sensor group (``SENSOR_GROUPS``) [Hz]; 0: every control sample.
    gyro_rate, velocity_rate, gps_rate, winch_encoder_rate : float
        The same, for the other groups.
    load_cell_latency, encoder_latency, altimeter_latency, attitude_latency : float
        Delay of each group's output [s]; 0: none.
    gyro_latency, velocity_latency, gps_latency, winch_encoder_latency : float
        The same, for the other groups.

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
        """A consumer-grade GPS receiver with a MEMS IMU, position from the GPS: white noise
        at every control sample (no rate, latency or correlation).

        Numbers (1-sigma, per control sample):

        - GPS position and velocity: the receiver of ``SENSOR_PRESETS["consumer_gnss"]``
          (the one GNSS table, with its sources), its whole position error as white noise
          (``white_gnss``: the white and the Gauss-Markov parts in quadrature, about
          (1.51, 1.51, 3.03) m) and its velocity std (0.05 m/s).
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
            winch_encoder_std=1e-3,
            **white_gnss("consumer_gnss"),
        )

    @classmethod
    def typical_rtk_gps(cls) -> SensorConfig:
        """As ``typical_gps`` with an RTK-corrected receiver (fixed solution).

        The receiver of ``SENSOR_PRESETS["rtk_gnss"]`` as white noise (``white_gnss``: about
        (0.011, 0.011, 0.022) m and 0.02 m/s): RTK GNSS gives about 0.01 m + 1 ppm
        horizontally and twice that vertically. It needs a base station and a radio link,
        and it loses the fixed solution under multipath or occlusion, the "typical
        degradation factors of GPS systems" of Sec. IV-F.

        Returns
        -------
        SensorConfig
            The preset, position from the GPS.
        """
        return replace(cls.typical_gps(), **white_gnss("rtk_gnss"))

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
        - velocity 0.05 m/s: Sec. IV-F gives no velocity sensor; we assume a filtered
          estimate as good as the GNSS receiver's velocity (``consumer_gnss``'s, as
          ``typical_gps``), so the two presets differ in position only.

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
            velocity_std=white_gnss("consumer_gnss")["velocity_std"],
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
        return self._group_timing(_checked_dt(dt))

    def _group_timing(self, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """``group_timing`` of a sample time already checked (a scenario's ``control.dt``);
        the rates and latencies are still put on its grid (refused off it)."""
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
        if self.gyro_density > 0.0:
            if dt is None:
                raise ParameterError("dt", dt, "the control sample time [s] (gyro_density is set)")
            dt = _checked_dt(dt)
        return self._white_std(dt)

    def _white_std(self, dt: float | None) -> np.ndarray:
        """``white_std`` of a sample time already checked (a scenario's ``control.dt``)."""
        std = self.channel_std()
        if self.gyro_density > 0.0:
            period = self._group_timing(dt)[0][SENSOR_GROUPS.index("gyro")]  # type: ignore[arg-type]
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


def _checked_dt(dt: Any) -> float:
    """A control sample time given to a public method (``group_timing``, ``white_std``)."""
    return check_number("control.dt", dt, low=0.0, low_open=True)


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
