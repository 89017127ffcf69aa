"""Sensing: what the controller measures instead of the true state and tension.

``config``
    ``SensorConfig`` (noise, biases, rates, latencies, correlated errors, the position
    source), the noise channels ``CH_*``, the sensor groups and ``sensor_config_from_dict``;
``presets``
    ``SENSOR_PRESETS``, datasheet-class sensors;
``noise``
    ``noise_table`` (the run's noise rows, drawn up front), ``gauss_markov``, ``random_walk``,
    ``accelerometer_errors``;
``schedules``
    ``sample_schedule``, ``group_samples``, ``ring_rows``: when slow and delayed sensors report;
``sensors``
    the compiled measurement (``measure``, ``measure_sampled``, ...), its NumPy replay and the
    tether route's analysis (``tether_position_estimate``, ``hover_error_std``);
``estimation``
    the position Kalman filter (``position_filter``, ``run_filter``) and the chi-square
    consistency tests (``ConsistencyTest``); ``studies.estimation`` flies them on a run's
    records.

The names below load on first use (PEP 562): ``from tetherheli.sensing import SensorConfig``
does not import the compiled measurement.
"""

from __future__ import annotations

from .._lazy import lazy_getattr

_HOMES = {
    **dict.fromkeys(
        (
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
        ),
        ".config",
    ),
    **dict.fromkeys(
        ("SENSOR_PRESETS",),
        ".presets",
    ),
    **dict.fromkeys(
        (
            "accelerometer_errors",
            "gauss_markov",
            "noise_table",
            "random_walk",
        ),
        ".noise",
    ),
    **dict.fromkeys(
        (
            "group_samples",
            "ring_rows",
            "sample_schedule",
        ),
        ".schedules",
    ),
    **dict.fromkeys(
        (
            "hover_error_std",
            "measure",
            "measure_batch",
            "measure_into",
            "measure_sampled",
            "measured_channels",
            "tether_position_estimate",
            "true_channels_into",
        ),
        ".sensors",
    ),
    **dict.fromkeys(
        (
            "ConsistencyTest",
            "EstimateResult",
            "FUSIONS",
            "Fixes",
            "KalmanConsistency",
            "PositionFilter",
            "chi2_mean_band",
            "estimate_run",
            "kalman_consistency",
            "normalized_squares",
            "position_filter",
            "run_filter",
        ),
        ".estimation",
    ),
}

__all__ = sorted(_HOMES)

__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
