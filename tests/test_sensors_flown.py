"""Sensors as they are flown (tetherheli.sensing): the exact discretisation of the
time-correlated errors against their analytic processes, white noise from a density against
the angle-random-walk definition, the sample-and-hold / latency schedule against its rule,
the engine's history ring against the NumPy replay, the presets and their validation, and
the GNSS outage that measures Sec. IV-F's claim in closed loop."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tetherheli.errors import ParameterError
from tetherheli.model.kernels import tethered_outputs
from tetherheli.report.paper import SENSING_RUNS, sensing_scenario
from tetherheli.runs import simulate
from tetherheli.runs.packing import sensor_noise, sensor_schedule
from tetherheli.scenario import load_scenario
from tetherheli.sensing.config import (
    CH_GPS,
    CH_GYRO,
    G_GPS,
    SENSOR_GROUPS,
    SensorConfig,
    sensor_config_from_dict,
)
from tetherheli.sensing.noise import gauss_markov, noise_table, random_walk
from tetherheli.sensing.presets import SENSOR_PRESETS
from tetherheli.sensing.schedules import group_samples, sample_schedule
from tetherheli.sensing.sensors import measured_channels, tether_position_estimate

DT = 0.01


# ---------------------------------------------------------------------------------------------
# error processes against their analytic statistics
# ---------------------------------------------------------------------------------------------
def test_gauss_markov_variance_and_autocorrelation():
    """First-order Gauss-Markov (Gelb, Applied Optimal Estimation, Table 3.4-1): stationary
    variance sigma^2 and autocorrelation sigma^2 exp(-|lag| / tau), over 20000 independent
    realizations (standard errors about 1 % and 0.007)."""
    rng = np.random.default_rng(3)
    sigma, tau, n = 1.5, 0.8, 301
    e = gauss_markov(sigma, tau, DT, rng.standard_normal((n, 20000)))
    for k in (0, 150, 300):
        assert e[k].var() == pytest.approx(sigma**2, rel=0.05)
    for lag in (10, 100, 300):
        rho = np.corrcoef(e[0], e[lag])[0, 1]
        assert rho == pytest.approx(math.exp(-lag * DT / tau), abs=0.03)


def test_random_walk_variance_grows_linearly():
    """A random walk of density K: b_0 = 0 and Var b(t) = K^2 t."""
    rng = np.random.default_rng(4)
    K = 2e-3
    b = random_walk(K, DT, rng.standard_normal((501, 20000)))
    assert np.all(b[0] == 0.0)
    for k in (100, 500):
        assert b[k].var() == pytest.approx(K**2 * k * DT, rel=0.05)


def test_gyro_density_is_angle_random_walk():
    """IEEE Std 952: white rate noise of density N integrates to an angle whose variance
    grows as N^2 t. A gyro at 50 Hz (period 2 at dt = 0.01 s) reads sigma = N sqrt(50) per
    sample; summing its samples over 1 s gives Var = N^2 x 1 s."""
    N = 0.014 * math.pi / 180.0
    config = SensorConfig(gyro_density=N, gyro_rate=50.0)
    assert config.white_std(DT)[CH_GYRO] == pytest.approx(N * math.sqrt(50.0), rel=1e-12)
    rng = np.random.default_rng(5)
    table = noise_table(config, 200 * 400 - 1, rng, dt=DT)
    held = table[::2, CH_GYRO].reshape(800, 50)  # the gyro's own samples, 1 s per row
    angle = held.sum(axis=1) * (2 * DT)
    assert angle.var() == pytest.approx(N**2 * 1.0, rel=0.2)


def test_noise_table_of_flown_gnss_has_its_variance():
    """The consumer GNSS preset: per-sample variance white^2 + Gauss-Markov sigma^2, and the
    sample-to-sample correlation of its error exp(-dt / tau) up to the white part."""
    config = SensorConfig.from_presets("consumer_gnss")
    tables = [noise_table(config, 0, np.random.default_rng(s), dt=DT) for s in range(4000)]
    first = np.array([t[0, CH_GPS : CH_GPS + 3] for t in tables])
    expected = np.array(config.gps_std) ** 2 + np.array(config.gps_markov_sigma) ** 2
    np.testing.assert_allclose(first.var(axis=0), expected, rtol=0.08)


def test_white_config_tables_unchanged():
    """The legacy model (white noise at every control sample) draws the same table with or
    without dt: the flown fields at 0 leave existing scenarios meaning what they meant."""
    config = SensorConfig.typical_gps()
    assert config.is_white and not config.is_timed
    a = noise_table(config, 50, np.random.default_rng(1))
    b = noise_table(config, 50, np.random.default_rng(1), dt=DT)
    np.testing.assert_array_equal(a, b)
    assert not SensorConfig.flown().is_white
    with pytest.raises(ParameterError, match="dt"):
        noise_table(SensorConfig.flown(), 5, np.random.default_rng(1))


# ---------------------------------------------------------------------------------------------
# sample rate, latency, outage
# ---------------------------------------------------------------------------------------------
def test_schedule_holds_and_delays_by_rule():
    """GNSS at 5 Hz with 0.15 s latency at dt = 0.01 s: at sample k it reports the sample
    20 floor((k - 15) / 20) (sample 0 before the first arrives); an outage [30, 50) s loses
    the samples taken in it, so the last one before it (2980) is held until 5000 + 15."""
    config = SensorConfig(gps_rate=5.0, gps_latency=0.15, gps_std=(1.0, 1.0, 1.0))
    n = 6000
    k = np.arange(n + 1)
    expected = np.where(k >= 15, 20 * ((k - 15) // 20), 0)
    np.testing.assert_array_equal(sample_schedule(config, DT, n)[:, G_GPS], expected)
    out = sample_schedule(replace(config, gps_outage=(30.0, 50.0)), DT, n)[:, G_GPS]
    inside = (k >= 3015) & (k < 5015)
    assert np.all(out[inside] == 2980)
    np.testing.assert_array_equal(out[~inside], expected[~inside])
    # the other sensors keep reading every sample
    other = [g for g in range(len(SENSOR_GROUPS)) if g != G_GPS]
    np.testing.assert_array_equal(sample_schedule(config, DT, n)[:, other], np.tile(k, (7, 1)).T)
    times, lag = group_samples(replace(config, gps_outage=(30.0, 50.0)), DT, n, "gps")
    assert lag == 15 and times[-1] == 5980 and not np.any((times >= 3000) & (times < 5000))


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"gps_rate": 3.0}, "sensors.gps_rate"),  # 1/(3 x 0.01) is not an integer
        ({"altimeter_latency": 0.015}, "sensors.altimeter_latency"),
    ],
)
def test_timing_off_the_control_grid_is_refused(kwargs, field):
    config = SensorConfig(**kwargs)
    with pytest.raises(ParameterError) as err:
        config.group_timing(DT)
    assert err.value.field == field
    text = "[sensors]\n" + "\n".join(f"{k} = {v}" for k, v in kwargs.items()) + "\n"
    with pytest.raises(ParameterError) as err:
        import tomllib

        from tetherheli.scenario.core import scenario_from_dict

        scenario_from_dict(tomllib.loads(text))
    assert err.value.field == field


def test_fast_sensors_read_every_sample():
    """A rate at or above the control rate (a 270 Hz lidar) gives period 1."""
    period, latency = SensorConfig(altimeter_rate=270.0).group_timing(DT)
    assert np.all(period == 1) and np.all(latency == 0)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"gps_markov_sigma": (1.0, 1.0, 1.0)}, "sensors.gps_markov_tau"),
        ({"gyro_std": 1e-3, "gyro_density": 1e-4}, "sensors.gyro_density"),
        ({"gps_outage": (5.0, 2.0)}, "sensors.gps_outage"),
        ({"gps_outage": (1.0,)}, "sensors.gps_outage"),
        ({"gps_rate": -5.0}, "sensors.gps_rate"),
    ],
)
def test_flown_fields_validated(kwargs, field):
    with pytest.raises(ParameterError) as err:
        SensorConfig(**kwargs)
    assert err.value.field == field


def test_presets_from_table_and_round_trip():
    """``[sensors] presets = [...]`` equals ``SensorConfig.from_presets``; to_dict maps back;
    an unknown preset is refused with its name."""
    names = ["consumer_gnss", "mems_imu", "laser_altimeter", "joint_encoders", "load_cell"]
    config = sensor_config_from_dict({"presets": names, "position_source": "tether"})
    assert config == SensorConfig.from_presets(*names, position_source="tether")
    assert sensor_config_from_dict(config.to_dict()) == config
    flown = SensorConfig.flown("gps", gnss="rtk", altimeter="barometric", gps_outage=(1.0, 2.0))
    assert sensor_config_from_dict(flown.to_dict()) == flown
    with pytest.raises(ParameterError) as err:
        sensor_config_from_dict({"presets": ["consumer_gps"]})
    assert err.value.field == "sensors.presets"
    # every preset sets only SensorConfig fields, and the encoder is a 14-bit quantiser
    for fields_ in SENSOR_PRESETS.values():
        SensorConfig(**fields_)
    assert SENSOR_PRESETS["joint_encoders"]["encoder_std"] == pytest.approx(
        2 * math.pi / 16384 / math.sqrt(12)
    )


def test_sensing_scenarios_shipped():
    """scenarios/sensing_*.toml equal the code's definitions (report.sensing_scenario)."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "scenarios"
    for key in SENSING_RUNS:
        assert load_scenario(root / f"sensing_{key}.toml") == sensing_scenario(key)


# ---------------------------------------------------------------------------------------------
# the engine's history ring against the NumPy replay; closed loop
# ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def flown_runs():
    """Shortened shipped runs: GNSS at 5 Hz / 0.15 s, laser altimeter at 50 Hz / 0.02 s."""
    runs = {}
    for key in ("gps", "tether"):
        s = sensing_scenario(key).replace(duration=14.0)
        runs[key] = (s, simulate(s))
    return runs


def test_engine_hold_and_latency_equal_replay(flown_runs):
    """The compiled engine's controller saw exactly what ``measured_channels`` replays from
    the recorded states, noise table and schedule: the GNSS position (held for 20 samples,
    0.15 s late) and the tether's position from encoders, delayed altimeter and attitude."""
    s, r = flown_runs["gps"]
    arm = s.params.helicopter.tether_arm
    schedule = sensor_schedule(s.sensors, s.control.dt, s.n_samples)
    m = measured_channels(r.states, r.tension, sensor_noise(s), schedule, arm)
    est = np.column_stack([r.extra[f"q{i}_est"] for i in (1, 2, 3)])
    np.testing.assert_allclose(est, m[:, CH_GPS : CH_GPS + 3], rtol=0, atol=1e-9)
    # held between fixes (up to the round-off of the attitude's way through q7, q8, q9)
    steps = np.flatnonzero(np.any(np.abs(np.diff(est, axis=0)) > 1e-9, axis=1)) + 1
    np.testing.assert_array_equal(steps, np.arange(35, r.time.size, 20))  # 20 k + 15
    s, r = flown_runs["tether"]
    m = measured_channels(r.states, r.tension, sensor_noise(s), sensor_schedule(
        s.sensors, s.control.dt, s.n_samples), arm)  # fmt: skip
    pos = tether_position_estimate(m[:, 1], m[:, 2], m[:, 3], m[:, 4], m[:, 5], arm)
    est = np.column_stack([r.extra[f"q{i}_est"] for i in (1, 2, 3)])
    np.testing.assert_allclose(est, pos, rtol=0, atol=1e-9)


def test_python_loop_and_environment_share_the_sensors(flown_runs):
    """The Python loop (``simulate`` with a ``PaperController``) and a zero-residual
    Gymnasium episode with the run's noise table fly the same states as the compiled loop
    (one ``sense`` phase, one sensor tuple from ``runs.setup``)."""
    from tetherheli.control.paper import PaperController
    from tetherheli.envs.env import TetheredHoverEnv
    from tetherheli.runs.setup import engine_setup

    s, r = flown_runs["tether"]
    s = s.replace(duration=3.0)
    r = simulate(s)
    setup = engine_setup(s)
    t = setup.trim
    ctl = PaperController(setup.gain.K, t.x, t.y, t.u, setup.ctrl, setup.model.constants)
    py = simulate(s, controller=ctl)
    np.testing.assert_allclose(py.states, r.states, rtol=0, atol=1e-9)
    # the episodes' noise is seeded by reset (a scenario's seed of noisy sensors is refused)
    env = TetheredHoverEnv(s.replace(seed=0), wind=s.wind, max_episode_time=s.duration)
    env.reset(seed=0)
    env._noise = sensor_noise(s)
    env._observe(env._tension())
    states, truncated = [env.state], False
    while not truncated:
        _, _, terminated, truncated, _ = env.step(np.zeros(4, dtype=np.float32))
        assert not terminated
        states.append(env.state)
    np.testing.assert_allclose(np.array(states), r.states, rtol=0, atol=1e-12)
    y = np.empty(4)
    tethered_outputs(env.state, setup.model.constants, y)
    assert np.all(np.isfinite(y))


def test_raw_gnss_doppler_velocity_loses_the_paper_lqi():
    """A finding the presets respect: fed the receiver's raw Doppler velocity (5 Hz, 0.15 s
    late) the paper's LQI loses simulation 1; at the control rate without delay (an
    IMU-aided velocity, the presets' choice) it completes."""
    s = sensing_scenario("tether").replace(duration=20.0)
    late = s.replace(sensors=replace(s.sensors, velocity_rate=5.0, velocity_latency=0.15))
    assert simulate(s).ok
    assert not simulate(late).ok


def test_gnss_outage_loses_gnss_flight_not_tether_flight():
    """Sec. IV-F, "not affected by typical degradation factors of GPS", measured: 20 s
    without GNSS fixes (30-50 s), the helicopter flown on the held GNSS position is lost,
    while the one flown on the tether flies exactly as without the outage (the GNSS is not
    in its loop)."""
    gps = simulate(sensing_scenario("gps_outage"))
    assert not gps.ok and gps.end_time > 30.0
    tether = simulate(sensing_scenario("tether_outage"))
    clean = simulate(sensing_scenario("tether"))
    assert tether.ok
    np.testing.assert_array_equal(tether.states, clean.states)


# ---------------------------------------------------------------------------------------------
# the command: scenario files as arguments, the time series' format
# ---------------------------------------------------------------------------------------------
def test_sensing_command_takes_files_as_arguments_and_parquet(tmp_path, capsys):
    """``tetherheli sensing A.toml B.toml --format parquet --out DIR`` (scenario files as
    arguments, as every command takes them; ``--scenario`` was the only spelling): each run's
    time series is ``<name>.parquet``, read back equal to the CSV of the same run. The old
    ``--scenario FILE`` still flies the file, with one deprecation line on stderr."""
    from tetherheli.cli import main
    from tetherheli.results import load_result

    files = []
    for key in ("gps", "tether"):
        path = tmp_path / f"{key}.toml"
        path.write_text(sensing_scenario(key).replace(duration=2.0).to_toml())
        files.append(str(path))
    assert (
        main(["sensing", *files, "--quiet", "--format", "parquet", "--out", str(tmp_path / "p")])
        == 0
    )
    assert main(["sensing", "--quiet", "--scenario", files[0], "--out", str(tmp_path / "c")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--scenario" in err[0] and "deprecated" in err[0], err
    name = sensing_scenario("gps").name
    written = {p.name for p in (tmp_path / "p").iterdir()}
    assert {f"{sensing_scenario(k).name}.parquet" for k in ("gps", "tether")} <= written
    assert not any(n.endswith(".csv") for n in written)
    from_parquet = load_result(tmp_path / "p", name)
    from_csv = load_result(tmp_path / "c", name)
    np.testing.assert_array_equal(from_parquet.time, from_csv.time)
    np.testing.assert_array_equal(from_parquet.outputs, from_csv.outputs)
