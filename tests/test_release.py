"""After the tether lets go (Sec. IV-C safety device): the paper controller switches to the
free configuration's trim input u0|F (Table IV), drops the feed-forward and the winch."""

from __future__ import annotations

import numpy as np
import pytest

from tetherheli import FreeHelicopter, TetheredHelicopter, simulate
from tetherheli.control.paper import PaperController
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import ActuatorSettings, Scenario, paper_scenario
from tetherheli.studies.release import altitude_excursion, release_comparison
from tetherheli.wind import Pulse


def _upward_pulse(duration: float = 40.0) -> Scenario:
    """A 20 N upward pulse (0.5-1.5 s) stretches the tether past 25.5 N: released at 0.96 s,
    then calm air."""
    return Scenario(
        name="release",
        duration=duration,
        wind=Pulse(0.5, 1.0, 20.0, (0.0, 0.0, 1.0)),
        actuators=ActuatorSettings(breaking_tension=25.5),
    )


def test_free_trim_differs_from_tethered_only_in_its_input():
    """Tables IV and V at q9 = 10 m: the same attitude, speeds and outputs (the tension acts
    along the shaft), inputs fMR3 123.7633 N against 148.6568 N: only u0 needs switching."""
    model = TetheredHelicopter()
    free, tethered = model.trim(0.0, 10.0), model.trim(25.0, 10.0)
    np.testing.assert_allclose(free.x[:12], tethered.x[:12], rtol=0, atol=1e-12)
    np.testing.assert_allclose(free.y, tethered.y, rtol=0, atol=1e-12)
    assert free.u[0] == pytest.approx(123.7633, abs=5e-5)  # Table IV
    assert tethered.u[0] == pytest.approx(148.6568, abs=5e-5)  # Table V
    setup = engine_setup(_upward_pulse())
    np.testing.assert_array_equal(setup.u0_free, free.u)


def test_release_in_paper_sim1_no_longer_climbs():
    """Paper simulation 1 with a 25.05 N breaking tension (released at 12.85 s): with u0|T kept
    the helicopter climbed about 2 m after the release; switched to u0|F it stays within 0.35 m
    (measured 2.051 m against 0.289 m, a dip: the collective drops by 25 N at once)."""
    s = paper_scenario(1, "tethered").replace(actuators=ActuatorSettings(breaking_tension=25.05))
    c = release_comparison(s)
    assert c.switched.release_time == c.kept.release_time == pytest.approx(12.85)
    assert altitude_excursion(c.kept) > 1.5
    assert altitude_excursion(c.switched) < 0.35
    # before the release the two controllers are the same law
    k = int(np.searchsorted(c.switched.time, c.switched.release_time))
    np.testing.assert_allclose(c.switched.states[:k], c.kept.states[:k], rtol=0, atol=1e-9)
    # from the release on, no feed-forward and no winch
    assert np.all(c.switched.feedforward[k:] == 0.0) and np.all(c.switched.reel_rate[k:] == 0.0)


def test_post_release_steady_state_is_the_free_trim():
    """Long after a release in calm air the helicopter hovers at the free trim computed by the
    Cartesian free model (model/trim.py, Table IV): inputs and attitude equal it."""
    r = simulate(_upward_pulse())
    assert r.ok and r.released
    free = FreeHelicopter().trim()
    np.testing.assert_allclose(r.inputs[-1], free.u, rtol=0, atol=1e-4)
    np.testing.assert_allclose(r.outputs[-1, :3], free.x[:3], rtol=0, atol=1e-4)
    np.testing.assert_allclose(r.states[-1, 0:3], free.x[3:6], rtol=0, atol=1e-5)


def test_release_is_one_law_in_compiled_python_and_gym_loops():
    """The compiled loop, the Python loop with ``PaperController`` and the Gymnasium
    environment (zero residual) fly the same post-release trajectory."""
    s = _upward_pulse(3.0)
    compiled = simulate(s)
    setup = engine_setup(s)
    t = setup.trim
    ctl = PaperController(
        setup.gain.K,
        t.x,
        t.y,
        t.u,
        setup.ctrl,
        setup.model.constants,
        free_trim_input=setup.u0_free,
    )
    python = simulate(s, controller=ctl)
    assert python.release_time == compiled.release_time
    np.testing.assert_allclose(python.states, compiled.states, rtol=0, atol=1e-9)
    gymnasium = pytest.importorskip("gymnasium")
    assert gymnasium is not None
    from tetherheli.envs.env import TetheredHoverEnv

    env = TetheredHoverEnv(s, wind=s.wind, max_episode_time=3.0)
    env.reset(seed=0)
    states, truncated = [env.state], False
    while not truncated:
        _, _, terminated, truncated, info = env.step(np.zeros(4, dtype=np.float32))
        assert not terminated
        states.append(env.state)
    assert info["tether_release"]["time"] == compiled.release_time
    np.testing.assert_allclose(np.array(states), compiled.states, rtol=0, atol=1e-12)
