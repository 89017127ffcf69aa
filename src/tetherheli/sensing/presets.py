"""Datasheet-class sensors (``SENSOR_PRESETS``): the ``SensorConfig`` fields each sets, with
the kind of source each number comes from; ``SensorConfig.from_presets`` and ``flown``, and a
scenario's ``[sensors] presets = [...]``, apply them. It is the one table of the GNSS
receivers: the white-noise ``SensorConfig.typical_gps`` and ``typical_rtk_gps`` are derived
from its ``consumer_gnss`` and ``rtk_gnss`` (``sensing.config.white_gnss``)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

__all__ = [
    "SENSOR_PRESETS",
]

_G0 = 9.80665  # standard gravity [m/s^2], for datasheet figures in g

#: Datasheet-class sensors, each the ``SensorConfig`` fields it sets (``from_presets``,
#: ``flown``; a scenario's ``[sensors] presets = [...]``). 1-sigma numbers; the kind of
#: source each comes from is given beside it.
SENSOR_PRESETS: Mapping[str, Mapping[str, Any]] = MappingProxyType(
    {
        # single-frequency consumer GNSS, u-blox M8 datasheet class (NEO-M8 data sheet,
        # UBX-15031086: 2.5 m CEP, velocity 0.05 m/s, up to 10 Hz): 2.5 m CEP horizontal
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
        # RTK GNSS (fixed solution), u-blox F9 datasheet class (ZED-F9P data sheet,
        # UBX-17051259: RTK 0.01 m + 1 ppm CEP, up to 20 Hz): 0.01 m + 1 ppm CEP
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
            "gyro_density": math.radians(0.014),
            "gyro_random_walk": 2e-6,
            "accel_density": 175e-6 * _G0,
            "accel_random_walk": 1e-4,
            "attitude_std": math.radians(0.5),
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
