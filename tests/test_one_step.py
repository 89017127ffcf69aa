"""Issue 10, items 1 and 3: one closed-loop sample step shared by every loop, and the packed
layouts and run statuses named in modules that import without Numba."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from tetherheli.control.paper import PaperController
from tetherheli.runs import simulate
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario import Scenario
from tetherheli.scenario.core import ActuatorSettings
from tetherheli.status import Status, status_message
from tetherheli.wind import Pulse, Step

# every actuator effect at once: saturation that binds during the pulse, a lag, the winch's
# rate and acceleration limits binding after the pulse, and a release by the safety device
# when the upward step loads the tether
ALL_ACTUATORS = Scenario(
    name="all_actuators",
    duration=20.0,
    wind=Pulse(5.0, 1.0, 20.0, (1.0, 0.0, 0.0)) + Step(12.0, 25.0, (0.0, 0.0, 1.0)),
    actuators=ActuatorSettings(
        u_min=(0.0, -5.0, -5.0, -30.0),
        u_max=(300.0, 5.0, 5.0, 30.0),
        time_constant=0.02,
        reel_rate_limit=0.5,
        reel_acceleration_limit=0.3,
        breaking_tension=40.0,
    ),
)


@pytest.fixture(scope="module")
def fixed_and_adaptive():
    return simulate(ALL_ACTUATORS), simulate(ALL_ACTUATORS, method="adaptive")


def test_fixed_step_equals_adaptive_with_every_actuator_active(fixed_and_adaptive):
    """The compiled RK4 loop and the adaptive DOP853 reference run the same sample step, so
    with saturation, lag, reel-rate and reel-acceleration limits and a tether release active
    they differ only by RK4's truncation error (before: 6.5e-4 m, as the Python loop lacked
    the winch's anti-windup)."""
    rk4, adaptive = fixed_and_adaptive
    assert rk4.ok and adaptive.ok
    assert rk4.released and adaptive.released
    assert rk4.release_time == adaptive.release_time
    # the limits really bind in this run
    assert np.max(np.abs(rk4.inputs[:, 1])) == pytest.approx(5.0)
    assert np.max(np.abs(np.diff(rk4.reel_rate[: int(12.0 / 0.01)]))) == pytest.approx(
        0.3 * 0.01, rel=1e-9
    )
    np.testing.assert_allclose(rk4.outputs[:, :3], adaptive.outputs[:, :3], rtol=0, atol=1e-6)
    np.testing.assert_allclose(rk4.tension, adaptive.tension, rtol=0, atol=1e-4)


def test_python_controller_loop_equals_the_compiled_loop(fixed_and_adaptive):
    """The paper's controller as a Python ``Controller`` (the Python loop's phases around it)
    gives the compiled loop's run to rounding, actuators and release included: the winch PI
    owns its anti-windup, and a release reaches the controller as Measurement.attached."""
    rk4, _ = fixed_and_adaptive
    setup = engine_setup(ALL_ACTUATORS)
    controller = PaperController(
        setup.gain.K,
        setup.trim.x,
        setup.trim.y,
        setup.trim.u,
        setup.ctrl,
        setup.model.constants,
        free_trim_input=setup.u0_free,  # after the release, as the engine (paper_sample)
    )
    python = simulate(ALL_ACTUATORS, controller=controller)
    assert python.release_time == rk4.release_time
    np.testing.assert_allclose(python.states, rk4.states, rtol=0, atol=1e-12)
    np.testing.assert_allclose(python.reel_rate, rk4.reel_rate, rtol=0, atol=1e-12)
    np.testing.assert_allclose(python.feedforward, rk4.feedforward, rtol=0, atol=1e-12)
    # the controller is reusable: reset() restores its settings after the release
    again = simulate(ALL_ACTUATORS, controller=controller)
    np.testing.assert_array_equal(again.states, python.states)


def test_statuses_carry_their_messages_and_import_without_numba():
    code = "import sys; import tetherheli.status, tetherheli.layout; print('numba' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"
    assert [s.value for s in Status] == list(range(14))  # 13: NOT_SETTLED (a landing)
    assert Status(0).message == "completed"
    assert [s for s in Status if s.is_success] == [Status.OK, Status.LANDED]
    assert status_message(Status.OK, 3.5) == "completed (tether released at t = 3.5 s)"
    assert "after the tether was released" in status_message(Status.GROUND, 3.5)
