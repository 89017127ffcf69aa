"""The SE(3) controller (Lee, Leok and McClamroch, CDC 2010) against RotorPy 3.0.0's
``SE3Control``, closed loops flown by both, and the tether feed-forward."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

from tests.test_multirotor import ROTORPY_MODULES
from tetherheli import layout as L
from tetherheli.control.se3 import SE3Controller
from tetherheli.errors import ParameterError
from tetherheli.model.multirotor import MULTIROTOR_PRESETS, Multirotor

rotorpy_only = pytest.mark.extra("validation", "rotorpy")

DT = 0.005  # [s]: the RK4 step, the controller held over it (a 200 Hz loop)


def flat(x=(0.0, 0.0, 0.0), yaw=0.0, yaw_dot=0.0, rng=None) -> dict:
    """RotorPy's flat outputs: a still reference at x, or a random one with rng."""
    if rng is not None:
        return {
            "x": rng.normal(size=3),
            "x_dot": rng.normal(size=3),
            "x_ddot": rng.normal(size=3),
            "x_dddot": rng.normal(size=3),
            "x_ddddot": rng.normal(size=3),
            "yaw": rng.uniform(-3, 3),
            "yaw_dot": rng.normal(),
        }
    zero = np.zeros(3)
    return {
        "x": np.array(x, dtype=float),
        "x_dot": zero,
        "x_ddot": zero,
        "x_dddot": zero,
        "x_ddddot": zero,
        "yaw": yaw,
        "yaw_dot": yaw_dot,
    }


def rk4(f, s: np.ndarray, h: float) -> np.ndarray:
    """One classical Runge-Kutta step of ds/dt = f(s), the quaternion then normalised (as
    RotorPy's ``Multirotor.step`` does)."""
    k1 = f(s)
    k2 = f(s + h / 2 * k1)
    k3 = f(s + h / 2 * k2)
    k4 = f(s + h * k3)
    s = s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    q = s[L.MRS_Q : L.MRS_Q + 4]
    s[L.MRS_Q : L.MRS_Q + 4] = q / np.linalg.norm(q)
    return s


def fly_ours(vehicle, controller, s, reference, seconds, tether_force=None, feedforward=False):
    """Our derivative and controller: the state vector after ``seconds``."""
    pull = None if tether_force is None else np.asarray(tether_force, dtype=float)
    for _ in range(round(seconds / DT)):
        measured = pull if feedforward else None
        cmd = controller.update(0.0, vehicle.unpack_state(s), reference, measured)
        cmd = cmd["cmd_motor_speeds"]
        s = rk4(lambda x, c=cmd: vehicle.derivative(x, c, None, pull), s, DT)
    return s


def fly_rotorpy(quad_params, s, reference, seconds):
    """RotorPy's ``Multirotor._s_dot_fn`` and ``SE3Control``, the commands clipped as its
    ``Multirotor.step`` clips them; s in our layout (RotorPy's without the wind)."""
    from rotorpy.controllers.quadrotor_control import SE3Control
    from rotorpy.vehicles.multirotor import Multirotor as RotorPyMultirotor

    vehicle = RotorPyMultirotor(quad_params)  # aero on, RotorPy's default
    controller = SE3Control(quad_params)
    full = np.concatenate((s[:13], np.zeros(3), s[13:]))
    for _ in range(round(seconds / DT)):
        cmd = controller.update(0.0, RotorPyMultirotor._unpack_state(full), reference)
        cmd = np.clip(cmd["cmd_motor_speeds"], vehicle.rotor_speed_min, vehicle.rotor_speed_max)
        full = rk4(lambda x, c=cmd: vehicle._s_dot_fn(0.0, x, c), full, DT)
    return np.concatenate((full[:13], full[16:]))


@rotorpy_only
@pytest.mark.parametrize("name", sorted(MULTIROTOR_PRESETS))
def test_update_equals_rotorpy(name, rng):
    """``update`` = RotorPy's ``SE3Control.update`` at random states and flat outputs, every
    returned key, to 1e-9."""
    from rotorpy.controllers.quadrotor_control import SE3Control

    quad_params = importlib.import_module(f"rotorpy.vehicles.{ROTORPY_MODULES[name]}").quad_params
    ours, theirs = SE3Controller.from_rotorpy(quad_params), SE3Control(quad_params)
    for _ in range(10):
        q = rng.normal(size=4)
        state = {
            "x": rng.normal(size=3),
            "v": rng.normal(size=3),
            "q": q / np.linalg.norm(q),
            "w": rng.normal(size=3),
        }
        reference = flat(rng=rng)
        a, b = ours.update(0.0, state, reference), theirs.update(0.0, state, reference)
        assert a.keys() == b.keys()
        for key in b:
            scale = np.max(np.abs(b[key]))
            np.testing.assert_allclose(a[key], b[key], rtol=0, atol=1e-9 * scale, err_msg=key)


@rotorpy_only
@pytest.mark.parametrize("target", [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0)], ids=["hover", "step"])
def test_closed_loop_equals_rotorpy(target):
    """A hover and a 1 m step flown 10 s by our derivative and controller and by RotorPy's
    (drag on), with the same RK4 at 200 Hz: positions agree to 1e-6 m; the step arrives."""
    vehicle = Multirotor.preset("hummingbird")
    controller = SE3Controller.preset("hummingbird")
    s0 = vehicle.pack_state(vehicle.hover_trim().state)
    reference = flat(target)
    ours = fly_ours(vehicle, controller, s0, reference, 10.0)
    quad_params = importlib.import_module("rotorpy.vehicles.hummingbird_params").quad_params
    theirs = fly_rotorpy(quad_params, s0, reference, 10.0)
    np.testing.assert_allclose(ours[:3], theirs[:3], rtol=0, atol=1e-6)
    np.testing.assert_allclose(ours[:3], target, atol=1e-3)


def test_tether_feedforward_removes_the_offset():
    """A steady pull f_p on the PD position loop leaves the offset e_x = f_p / (m Kp) (the
    loop's steady state, SE3Control has no integrator); the feed-forward of the measured pull,
    force and moment about P, removes it."""
    pull = 1.5 * np.array([math.cos(0.6), 0.0, -math.sin(0.6)])  # [N] towards a winch
    for tether_point in ((0.0, 0.0, 0.0), (0.01, 0.0, -0.05)):
        vehicle = Multirotor.preset("hummingbird", tether_point=tether_point)
        controller = SE3Controller(vehicle, kp_att=544, kd_att=46.64)
        s0 = vehicle.pack_state(vehicle.hover_trim().state)
        kept = fly_ours(vehicle, controller, s0, flat(), 6.0, pull, feedforward=True)
        np.testing.assert_allclose(kept[:3], 0.0, atol=1e-5)
    vehicle = Multirotor.preset("hummingbird", aero=False)
    controller = SE3Controller(vehicle, kp_att=544, kd_att=46.64)
    s0 = vehicle.pack_state(vehicle.hover_trim().state)
    offset = fly_ours(vehicle, controller, s0, flat(), 6.0, pull)
    expected = pull / (vehicle.mass * controller.kp_pos)
    np.testing.assert_allclose(offset[:3], expected, rtol=1e-3, atol=1e-9)


def test_bad_gains_name_their_field():
    vehicle = Multirotor.preset("crazyflie")
    with pytest.raises(ParameterError, match=r"^kp_att = "):
        SE3Controller(vehicle, kp_att=-1.0)
    with pytest.raises(ParameterError, match=r"^kd_pos = "):
        SE3Controller(vehicle, kd_pos=(1.0, 2.0))
    with pytest.raises(ParameterError, match=r"^vehicle = "):
        SE3Controller(MULTIROTOR_PRESETS["crazyflie"])
    with pytest.raises(ParameterError, match=r"^preset = "):
        SE3Controller.preset("bumblebee")
    with pytest.raises(ParameterError, match=r"^tether_force = "):
        SE3Controller(vehicle).update(0.0, vehicle.hover_trim().state, flat(), (1.0, 2.0))
