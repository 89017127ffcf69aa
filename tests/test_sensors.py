"""Tests of tetherheli.sensing: the measurement model, the tether as a position sensor
(Sec. IV-F, eqs 43-45), its predicted accuracy, the noise tables and the strict configuration."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tetherheli import Params, TetheredHelicopter
from tetherheli.errors import ParameterError
from tetherheli.sensing.config import (
    CH_ALTIMETER,
    CH_ATTITUDE,
    CH_ENCODER_Q7,
    CH_ENCODER_Q8,
    CH_GPS,
    CH_GYRO,
    CH_LOAD_CELL,
    CH_VELOCITY,
    CH_WINCH_ENCODER,
    CHANNEL_NAMES,
    N_CHANNELS,
    POSITION_SOURCES,
    SOURCE_GPS,
    SOURCE_TETHER,
    SOURCE_TRUE,
    SensorConfig,
    sensor_config_from_dict,
)
from tetherheli.sensing.noise import noise_table
from tetherheli.sensing.sensors import (
    hover_error_std,
    measure,
    measure_batch,
    tether_position_estimate,
)

ARM = Params.paper().helicopter.tether_arm
SOURCES = (SOURCE_TRUE, SOURCE_GPS, SOURCE_TETHER)


@pytest.fixture(scope="module")
def trim_state() -> np.ndarray:
    """Tethered hover at TC = 25 N (Table V)."""
    return TetheredHelicopter().trim(25.0).x.copy()


@pytest.fixture(scope="module")
def generic_state(trim_state: np.ndarray) -> np.ndarray:
    """The Table V hover perturbed to a generic state: every angle and speed nonzero."""
    x = trim_state.copy()
    x[:6] += [0.05, -0.07, 0.3, 0.12, -0.09, 0.4]  # q4..q9
    x[6:12] = [0.3, -0.2, 0.1, 0.05, -0.04, 0.02]  # u1..u6
    x[12] += 0.1  # LN
    return x


def ho_position(x: np.ndarray, arm: float = ARM) -> np.ndarray:
    """Eqs 43-45 (with the eq-43 fix): HO = q9 c3 - arm f3 of states (..., 13) (test oracle)."""
    q4, q5, q7, q8, q9 = x[..., 0], x[..., 1], x[..., 3], x[..., 4], x[..., 5]
    return np.stack(
        [
            q9 * np.sin(q8) - arm * np.sin(q5),
            -q9 * np.sin(q7) * np.cos(q8) + arm * np.sin(q4) * np.cos(q5),
            q9 * np.cos(q7) * np.cos(q8) - arm * np.cos(q4) * np.cos(q5),
        ],
        axis=-1,
    )


def run_measure(x, tension, row, source):
    x_est = np.empty(13)
    t_est = measure(x, tension, row, source, ARM, x_est)
    return x_est, t_est


# ---------------------------------------------------------------------------------------------
# the measurement function
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("source", SOURCES)
def test_zero_noise_returns_true_state(generic_state, source):
    """Perfect sensors leave the paper's controller input unchanged (Sec. V): every source
    returns the true state and tension; q7..q9 rebuilt by eqs 43-45 agree to rounding."""
    x_est, t_est = run_measure(generic_state, 23.5, np.zeros(N_CHANNELS), source)
    assert t_est == 23.5
    keep = [0, 1, 2, 6, 7, 8, 9, 10, 11, 12]
    np.testing.assert_array_equal(x_est[keep], generic_state[keep])
    if source == SOURCE_TRUE:
        np.testing.assert_array_equal(x_est, generic_state)
    else:
        np.testing.assert_allclose(x_est[3:6], generic_state[3:6], rtol=0, atol=1e-12)


def test_noise_adds_to_direct_channels(generic_state, rng):
    """Attitude, gyro, velocity, winch encoder and load cell are true + noise (Sec. IV-D)."""
    row = rng.standard_normal(N_CHANNELS)
    x_est, t_est = run_measure(generic_state, 25.0, row, SOURCE_TRUE)
    assert t_est == 25.0 + row[CH_LOAD_CELL]
    np.testing.assert_array_equal(
        x_est[0:3], generic_state[0:3] + row[CH_ATTITUDE : CH_ATTITUDE + 3]
    )
    np.testing.assert_array_equal(
        x_est[6:9], generic_state[6:9] + row[CH_VELOCITY : CH_VELOCITY + 3]
    )
    np.testing.assert_array_equal(x_est[9:12], generic_state[9:12] + row[CH_GYRO : CH_GYRO + 3])
    assert x_est[12] == generic_state[12] + row[CH_WINCH_ENCODER]
    np.testing.assert_array_equal(x_est[3:6], generic_state[3:6])


def test_tether_source_reproduces_eqs_43_45(generic_state, rng):
    """Sec. IV-F: encoders q7, q8, altimeter and IMU attitude give HO by eqs 43-45; the
    estimate's q7, q8 are the encoder readings and its altitude is the altimeter reading."""
    row = 0.01 * rng.standard_normal(N_CHANNELS)
    x_est, _ = run_measure(generic_state, 25.0, row, SOURCE_TETHER)
    assert x_est[3] == generic_state[3] + row[CH_ENCODER_Q7]
    assert x_est[4] == generic_state[4] + row[CH_ENCODER_Q8]
    altitude = ho_position(generic_state)[2] + row[CH_ALTIMETER]
    ho_est = ho_position(x_est)
    assert ho_est[2] == pytest.approx(altitude, abs=1e-12)
    expected = tether_position_estimate(x_est[3], x_est[4], altitude, x_est[0], x_est[1], ARM)
    np.testing.assert_allclose(ho_est, expected[0], rtol=0, atol=1e-12)
    # without noise, the vectorised estimate is the true HO of eqs 43-45
    x = generic_state
    exact = tether_position_estimate(x[3], x[4], ho_position(x)[2], x[0], x[1], ARM)
    np.testing.assert_allclose(exact[0], ho_position(x), rtol=0, atol=1e-12)


def test_gps_source_round_trip(generic_state, rng):
    """A GPS reading of HO, converted to q7, q8, q9 with the measured attitude (inverse of
    eqs 43-45), gives back exactly that reading through eqs 43-45."""
    row = rng.standard_normal(N_CHANNELS)
    row[CH_ATTITUDE : CH_ATTITUDE + 3] *= 0.02
    x_est, _ = run_measure(generic_state, 25.0, row, SOURCE_GPS)
    gps = ho_position(generic_state) + row[CH_GPS : CH_GPS + 3]
    np.testing.assert_allclose(ho_position(x_est), gps, rtol=0, atol=1e-12)
    assert x_est[5] > 0 and abs(x_est[4]) < math.pi / 2


def test_measure_batch_equals_single_calls(generic_state, rng):
    """A batch of n measurements equals n single ``measure`` calls."""
    n = 5
    xs = np.tile(generic_state, (n, 1))
    noise = 0.01 * rng.standard_normal((n, N_CHANNELS))
    x_est, t_est = np.empty((n, 13)), np.empty(n)
    measure_batch(xs, np.full(n, 25.0), noise, SOURCE_TETHER, ARM, x_est, t_est)
    for k in range(n):
        xk, tk = run_measure(xs[k], 25.0, noise[k], SOURCE_TETHER)
        np.testing.assert_array_equal(x_est[k], xk)
        assert t_est[k] == tk


# ---------------------------------------------------------------------------------------------
# predicted accuracy of the tether as a sensor (Sec. IV-F) against Monte Carlo
# ---------------------------------------------------------------------------------------------
def monte_carlo_ho_std(config, x, rng, n=20000):
    """Std of HO (eqs 43-45 on the estimated states) over n noise draws at one true state."""
    noise = noise_table(config, n - 1, rng)
    x_est, t_est = np.empty((n, 13)), np.empty(n)
    xs = np.tile(x, (n, 1))
    measure_batch(xs, np.full(n, 25.0), noise, config.source_code, ARM, x_est, t_est)
    return ho_position(x_est).std(axis=0, ddof=1)


@pytest.mark.parametrize("where", ["trim", "generic"])
def test_encoder_noise_matches_predicted_horizontal_std(trim_state, generic_state, where, rng):
    """Sec. IV-F: with encoder noise only, the Monte Carlo std of the tether-based HO
    position matches the first-order prediction (about q9 sigma_enc horizontally)."""
    x = trim_state if where == "trim" else generic_state
    config = SensorConfig(position_source="tether", encoder_std=math.radians(0.1))
    predicted = hover_error_std(config, x[5], ARM, x[0], q5=x[1], q7=x[3], q8=x[4])
    measured = monte_carlo_ho_std(config, x, rng)
    np.testing.assert_allclose(measured[:2], predicted[:2], rtol=0.03)
    assert predicted[2] == 0.0 and measured[2] < 1e-9
    if where == "trim":
        assert predicted[0] == pytest.approx(10.0 * math.radians(0.1), rel=1e-12)


def test_altimeter_noise_matches_predicted_vertical_std(trim_state, rng):
    """Sec. IV-F: the altimeter fixes the altitude, so the vertical error is the altimeter's
    (and at hover, q7 = q8 = 0, it does not leak into the horizontal position)."""
    config = SensorConfig(position_source="tether", altimeter_std=0.05)
    predicted = hover_error_std(config, trim_state[5], ARM, trim_state[0])
    measured = monte_carlo_ho_std(config, trim_state, rng)
    assert predicted[2] == pytest.approx(0.05, rel=1e-12)
    assert measured[2] == pytest.approx(predicted[2], rel=0.03)
    np.testing.assert_allclose(measured[:2], 0.0, atol=1e-12)


def test_all_tether_noise_matches_prediction_at_generic_state(generic_state, rng):
    """Sec. IV-F with the ``typical_tether`` preset (encoders, altimeter, attitude) at a
    generic state: every axis of the Monte Carlo std within 3 % of the prediction."""
    config = SensorConfig.typical_tether()
    x = generic_state
    predicted = hover_error_std(config, x[5], ARM, x[0], q5=x[1], q7=x[3], q8=x[4])
    measured = monte_carlo_ho_std(config, x, rng)
    np.testing.assert_allclose(measured, predicted, rtol=0.03)


def test_hover_error_jacobian_against_finite_differences(generic_state):
    """The linearisation behind ``hover_error_std`` equals central differences of the
    estimate of Sec. IV-F (eqs 43-45), one noise source at a time."""
    x = generic_state
    # estimate inputs: [q7, q8, altitude, q4, q5]
    base = np.array([x[3], x[4], ho_position(x)[2], x[0], x[1]])
    h = 1e-6
    for field, cols in [("encoder_std", [0, 1]), ("altimeter_std", [2]), ("attitude_std", [3, 4])]:
        fd_sq = np.zeros(3)
        for c in cols:
            plus, minus = base.copy(), base.copy()
            plus[c] += h
            minus[c] -= h
            d = tether_position_estimate(*plus, ARM) - tether_position_estimate(*minus, ARM)
            fd_sq += (d[0] / (2 * h)) ** 2
        config = SensorConfig(**{field: 1.0})
        predicted = hover_error_std(config, x[5], ARM, x[0], q5=x[1], q7=x[3], q8=x[4])
        np.testing.assert_allclose(predicted, np.sqrt(fd_sq), rtol=1e-6, atol=1e-8)


def test_typical_presets_compare_tether_with_gps():
    """Sec. IV-F's claim in numbers: at the paper's hover (q9 = 10 m, Table V) the tether's
    position error is centimetres, a consumer GPS's metres."""
    tether = hover_error_std(SensorConfig.typical_tether())
    assert np.all(tether[:2] < 0.02) and tether[2] == pytest.approx(0.05)
    assert np.all(tether < 0.1 * np.array(SensorConfig.typical_gps().gps_std))


# ---------------------------------------------------------------------------------------------
# noise tables
# ---------------------------------------------------------------------------------------------
def test_noise_table_equal_seeds_equal_tables():
    """Explicit generators: equal seeds give equal tables, other seeds other tables."""
    config = SensorConfig.typical_gps()
    a = noise_table(config, 50, np.random.default_rng(7))
    b = noise_table(config, 50, np.random.default_rng(7))
    c = noise_table(config, 50, np.random.default_rng(8))
    assert a.shape == (51, N_CHANNELS) and a.flags.c_contiguous
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_noise_table_common_random_numbers():
    """Turning one sensor's noise on leaves the other channels' draws unchanged."""
    base = SensorConfig(gyro_std=0.01)
    more = SensorConfig(gyro_std=0.01, encoder_std=0.002)
    a = noise_table(base, 20, np.random.default_rng(3))
    b = noise_table(more, 20, np.random.default_rng(3))
    np.testing.assert_array_equal(a[:, CH_GYRO : CH_GYRO + 3], b[:, CH_GYRO : CH_GYRO + 3])
    assert np.all(a[:, CH_ENCODER_Q7] == 0.0) and np.all(b[:, CH_ENCODER_Q7] != 0.0)


def test_noise_table_statistics_as_configured(rng):
    """Column means are the biases and column stds the configured stds."""
    config = SensorConfig(
        load_cell_std=0.1, load_cell_bias=0.5, encoder_std=2e-3, altimeter_std=0.05,
        altimeter_bias=-0.2, attitude_std=0.01, attitude_bias=(0.01, -0.02, 0.03),
        gyro_std=0.002, velocity_std=0.1, gps_std=(1.5, 1.5, 3.0), gps_bias=(1.0, -2.0, 0.5),
        winch_encoder_std=1e-3,
    )  # fmt: skip
    n = 40000
    table = noise_table(config, n - 1, rng)
    std, bias = config.channel_std(), config.channel_bias()
    np.testing.assert_allclose(table.std(axis=0, ddof=1), std, rtol=0.03)
    # means within 5 standard errors of the biases
    assert np.all(np.abs(table.mean(axis=0) - bias) <= 5 * std / math.sqrt(n) + 1e-15)
    assert std[CH_ENCODER_Q8] == 2e-3 and std[CH_GPS + 2] == 3.0
    assert bias[CH_ATTITUDE + 2] == 0.03 and bias[CH_ALTIMETER] == -0.2
    assert len(CHANNEL_NAMES) == N_CHANNELS


def test_noise_table_perfect_is_zero():
    """The default (perfect) sensors give an all-zero table: the paper's results unchanged."""
    table = noise_table(SensorConfig(), 10, np.random.default_rng(0))
    np.testing.assert_array_equal(table, 0.0)
    assert SensorConfig().is_perfect and not SensorConfig.typical_tether().is_perfect


@pytest.mark.parametrize("bad", [-1, 1.5, True])
def test_noise_table_rejects_bad_sample_count(bad):
    with pytest.raises(ParameterError, match="n_samples"):
        noise_table(SensorConfig(), bad, np.random.default_rng(0))


def test_noise_table_requires_generator():
    with pytest.raises(ParameterError, match="rng"):
        noise_table(SensorConfig(), 3, 42)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------
# configuration: validation, presets, round trip
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"encoder_std": -1e-3}, "sensors.encoder_std"),
        ({"load_cell_std": math.nan}, "sensors.load_cell_std"),
        ({"altimeter_bias": math.inf}, "sensors.altimeter_bias"),
        ({"gps_std": (1.0, -1.0, 1.0)}, "sensors.gps_std"),
        ({"gps_bias": (1.0, 2.0)}, "sensors.gps_bias"),
        ({"attitude_bias": (0.0, math.nan, 0.0)}, "sensors.attitude_bias"),
        ({"gyro_std": "0.1"}, "sensors.gyro_std"),
        ({"velocity_std": True}, "sensors.velocity_std"),
        ({"position_source": "lidar"}, "sensors.position_source"),
    ],
)
def test_config_validation(kwargs, field):
    """Invalid fields raise one-line ParameterErrors naming the field."""
    with pytest.raises(ParameterError) as info:
        SensorConfig(**kwargs)
    assert info.value.field == field
    assert "\n" not in str(info.value)


def test_from_dict_unknown_key_and_source():
    """The loader is strict: an unknown key is named, with the file it came from."""
    with pytest.raises(ParameterError, match=r"run\.toml: sensors\.gps_sigma") as info:
        sensor_config_from_dict({"gps_sigma": 1.0}, source="run.toml")
    assert info.value.field == "sensors.gps_sigma"
    with pytest.raises(ParameterError, match=r"run\.toml: sensors\.encoder_std"):
        sensor_config_from_dict({"encoder_std": -1.0}, source="run.toml")
    with pytest.raises(ParameterError, match="sensors"):
        sensor_config_from_dict([1, 2])  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "preset",
    [
        SensorConfig.perfect,
        SensorConfig.typical_gps,
        SensorConfig.typical_rtk_gps,
        SensorConfig.typical_tether,
    ],
)
def test_to_dict_round_trip(preset):
    """to_dict -> sensor_config_from_dict gives an equal configuration (TOML-friendly)."""
    config = preset()
    table = config.to_dict()
    assert all(isinstance(v, (str, float, list)) for v in table.values())
    assert sensor_config_from_dict(table) == config
    assert POSITION_SOURCES[config.position_source] == config.source_code


def test_presets_numbers():
    """The documented preset numbers: consumer GPS about 1.5 / 3 m (the ``consumer_gnss``
    receiver of SENSOR_PRESETS, its white 0.2 / 0.4 m and Gauss-Markov 1.5 / 3 m in
    quadrature), RTK about 1 / 2 cm, velocity 0.05 m/s for the GPS and the tether, encoders
    0.1 deg, altimeter 5 cm, attitude 0.5 deg."""
    gps, tether = SensorConfig.typical_gps(), SensorConfig.typical_tether()
    rtk = SensorConfig.typical_rtk_gps()
    assert gps.position_source == "gps"
    np.testing.assert_allclose(gps.gps_std, [1.5133, 1.5133, 3.0266], rtol=1e-4)
    np.testing.assert_allclose(rtk.gps_std, [0.01118, 0.01118, 0.02236], rtol=1e-3)
    assert gps.velocity_std == tether.velocity_std == 0.05 and rtk.velocity_std == 0.02
    assert tether.position_source == "tether"
    assert tether.encoder_std == pytest.approx(1.745e-3, rel=1e-3)
    assert tether.altimeter_std == 0.05
    assert tether.attitude_std == pytest.approx(math.radians(0.5))


def test_tether_source_needs_tethered_configuration():
    """Sec. IV-F: the encoders sit on the tether's ground joint; the free helicopter has none."""
    SensorConfig.typical_tether().check_configuration(tethered=True)
    SensorConfig.typical_gps().check_configuration(tethered=False)
    with pytest.raises(ParameterError, match=r"sensors\.position_source"):
        SensorConfig.typical_tether().check_configuration(tethered=False)


def test_hover_error_std_validation():
    with pytest.raises(ParameterError, match="q9"):
        hover_error_std(SensorConfig(), q9=0.0)
    with pytest.raises(ParameterError, match="q4"):
        hover_error_std(SensorConfig(), q4=math.nan)


def test_measure_rejects_unknown_source_code(generic_state):
    """Only the three ``SOURCE_*`` codes are valid position sources."""
    with pytest.raises(ValueError, match="unknown position source"):
        run_measure(generic_state, 25.0, np.zeros(N_CHANNELS), 7)
