"""Actuators, sensors and the tether release in the closed loop (issue: beyond the paper)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tetherheli import ParameterError, load_scenario, simulate
from tetherheli.report.paper import sensing_scenario
from tetherheli.scenario.core import ActuatorSettings, paper_scenario
from tetherheli.sensing.config import SensorConfig
from tetherheli.sensing.sensors import hover_error_std

INF = np.inf
SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def test_defaults_leave_the_paper_unchanged():
    """Ideal actuators and perfect sensors give the paper's run bit for bit."""
    s = paper_scenario(1, "tethered")
    a = simulate(s)
    b = simulate(s.replace(actuators=ActuatorSettings(), sensors=SensorConfig(), seed=7))
    np.testing.assert_array_equal(a.states, b.states)
    assert "q1_est" not in a.extra


def _cyclic_limited(limit):
    return paper_scenario(1, "tethered").replace(
        actuators=ActuatorSettings(
            u_min=(-INF, -limit, -limit, -INF), u_max=(INF, limit, limit, INF)
        )
    )


def test_cyclic_saturation_eq40():
    """Eq 40: with the cyclic torque limited to 4 N m the applied tMR1, tMR2 never exceed
    it and the paper's run still completes; at 3 N m the saturated LQI loses the
    helicopter, and the run says so."""
    r = simulate(_cyclic_limited(4.0))
    assert r.ok
    assert np.abs(simulate(paper_scenario(1, "tethered")).inputs[:, 1:3]).max() > 4.0
    assert np.abs(r.inputs[:, 1:3]).max() <= 4.0 + 1e-12
    tight = simulate(_cyclic_limited(3.0))
    assert not tight.ok and "diverged" in tight.message
    # the tether lowers the cyclic authority the gust needs (measured by bisection: 3.37 N m
    # tethered, 4.31 N m free): at 4 N m the free helicopter is lost
    free = simulate(_cyclic_limited(4.0).replace(configuration="free"))
    assert not free.ok and "diverged" in free.message


def test_limit_below_hover_need_is_rejected():
    """A collective limit below the hover lift (148.66 N at 25 N tension): cannot hover."""
    s = paper_scenario(1, "tethered").replace(
        actuators=ActuatorSettings(u_max=(140.0, INF, INF, INF))
    )
    with pytest.raises(ParameterError, match="cannot hover"):
        simulate(s)


def test_actuator_lag_is_first_order():
    """A first-order lag tau u' = cmd - u, exact over a sample with the command held: after a
    step in the command at sample k0 the gap to it is e^{-(k - k0 + 1) dt / tau} of the step
    at sample k (analytic solution), on every input; without lag the step is applied at
    once. A custom controller commands the step, so nothing else moves the inputs."""
    from tetherheli.control.base import Command, Controller

    class StepCommand(Controller):
        def __init__(self, u0, du):
            self.u0, self.du = u0, du

        def reset(self) -> None:
            pass

        def step(self, t, measurement):
            return Command(inputs=self.u0 + (self.du if t >= 0.5 - 1e-9 else 0.0))

    tau, dt, k0 = 0.05, 0.01, 50
    free = paper_scenario(1, "free").replace(duration=1.0)
    u0 = simulate(free.replace(duration=0.01)).trim_input
    du = np.array([2.0, 0.2, -0.1, 0.5])
    lagged = simulate(
        free.replace(actuators=ActuatorSettings(time_constant=tau)), controller=StepCommand(u0, du)
    )
    ideal = simulate(free, controller=StepCommand(u0, du))
    np.testing.assert_array_equal(ideal.inputs[k0:], np.tile(u0 + du, (51, 1)))
    np.testing.assert_array_equal(lagged.inputs[:k0], np.tile(u0, (k0, 1)))
    k = np.arange(k0, 101)
    gap = (u0 + du) - lagged.inputs[k0:]
    expected = np.outer(np.exp(-(k - k0 + 1) * dt / tau), du)
    np.testing.assert_allclose(gap, expected, rtol=1e-9, atol=1e-12)


def test_reel_rate_limit():
    """The winch's reel rate stays within its limit (PI with anti-windup, eq 56)."""
    s = paper_scenario(1, "tethered").replace(actuators=ActuatorSettings(reel_rate_limit=0.002))
    r = simulate(s)
    assert r.ok and np.abs(r.reel_rate).max() <= 0.002 + 1e-15
    assert np.abs(simulate(paper_scenario(1, "tethered")).reel_rate).max() > 0.002


def test_reel_acceleration_limit():
    """The winch's acceleration limit: the reel rate changes by at most a dt per sample and
    a loose limit changes nothing. The paper's PI asks for up to 0.33 m/s^2; at 0.3 m/s^2 the
    limit binds and the tension still stays within 25 +- 0.2 N; at 0.03 m/s^2 the slew-limited
    loop limit-cycles (measured 20-32 N), which the run reports faithfully."""
    base = paper_scenario(1, "tethered")
    ideal = simulate(base)
    assert 0.3 < np.abs(np.diff(ideal.reel_rate)).max() / 0.01 < 0.4
    for a, band in ((0.3, 0.2), (0.03, 10.0)):
        r = simulate(base.replace(actuators=ActuatorSettings(reel_acceleration_limit=a)))
        assert r.ok
        assert np.abs(np.diff(r.reel_rate)).max() <= a * 0.01 * (1 + 1e-12)
        assert np.abs(r.tension - 25.0).max() < band
    assert np.abs(r.tension - 25.0).max() > 5.0  # 0.03 m/s^2: the loop limit-cycles
    loose = simulate(base.replace(actuators=ActuatorSettings(reel_acceleration_limit=1e6)))
    np.testing.assert_array_equal(loose.states, ideal.states)


def test_tether_release_above_breaking_tension():
    """Sec. IV-C safety device: above the breaking tension the tether is released, the
    tension is zero from then on and the helicopter flies on, free."""
    s = paper_scenario(1, "tethered").replace(actuators=ActuatorSettings(breaking_tension=25.05))
    r = simulate(s)
    assert r.ok
    k = np.argmax(r.tension == 0.0)
    assert 10.0 <= r.time[k] <= 15.0  # during the pulse response
    assert np.all(r.tension[k:] == 0.0) and np.all(r.reel_rate[k:] == 0.0)


def test_tether_as_sensor_error_matches_prediction():
    """Sec. IV-F: the controller's position estimate from encoders + altimeter + attitude
    errs by about the first-order prediction (hover_error_std); a consumer GPS by ~1.5 m.
    White sensors at the control rate (the ``typical_*`` presets; the shipped sensing
    scenarios fly the sensors as they are flown, tests/test_sensors_flown.py)."""

    def white(config: SensorConfig):
        return paper_scenario(1, "tethered").replace(sensors=config, seed=1)

    r = simulate(white(SensorConfig.typical_tether()))
    g = simulate(white(SensorConfig.typical_gps()))
    assert r.ok and g.ok
    err = np.column_stack([r.extra[f"q{i}_est"] for i in (1, 2, 3)]) - r.outputs[:, :3]
    predicted = hover_error_std(
        SensorConfig.typical_tether(),
        q9=10.0,
        arm=r.configuration["params"]["helicopter"]["d_O_P3"] + 0.0954049,
        q4=r.trim_state[0],
    )
    np.testing.assert_allclose(err.std(axis=0), predicted, rtol=0.15)
    gerr = np.column_stack([g.extra[f"q{i}_est"] for i in (1, 2, 3)]) - g.outputs[:, :3]
    assert 1.3 < gerr[:, 0].std() < 1.7
    # fed by the tether the hover is steadier than fed by the GPS
    dev = lambda x: np.sqrt(np.mean((x.outputs[:, 1] - x.trim_output[1]) ** 2))  # noqa: E731
    assert dev(r) < 0.6 * dev(g)


def test_sensing_scenarios_shipped():
    """scenarios/sensing_{gps,tether}.toml equal the code's definitions."""
    for source in ("gps", "tether"):
        assert load_scenario(SCENARIOS / f"sensing_{source}.toml") == sensing_scenario(source)


def test_sensor_noise_reproducible_by_seed():
    s = sensing_scenario("tether")
    a, b = simulate(s), simulate(s)
    np.testing.assert_array_equal(a.states, b.states)
    c = simulate(s.replace(seed=2))
    assert not np.array_equal(a.states, c.states)


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("[actuators]\nu_max = [1, 2]\n", "actuators.u_max"),
        ("[actuators]\ntime_constant = -1.0\n", "actuators.time_constant"),
        ("[actuators]\nbreaking_tension = 0.0\n", "actuators.breaking_tension"),
        ("[actuators]\nreel_acceleration_limit = -2.0\n", "actuators.reel_acceleration_limit"),
        ("[actuators]\nspeed = 1.0\n", "actuators.speed"),
        ("[sensors]\nencoder_std = -1.0\n", "encoder_std"),
        ("configuration = 'free'\n[sensors]\nposition_source = 'tether'\n", "position_source"),
        ("seed = -3\n", "seed"),
    ],
)
def test_bad_realism_settings(tmp_path, text, key):
    f = tmp_path / "bad.toml"
    f.write_text("duration = 2.0\n" + text)
    with pytest.raises(ParameterError) as err:
        load_scenario(f)
    assert key in str(err.value) and str(f) in str(err.value)
