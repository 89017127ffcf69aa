"""The LQI on the tethered linearization with the reel rate as a fifth input
(``control.tether_lqi``, ``[control] controller = "tether_lqi"``), flown by the compiled
engine's control phase (``control.paper.paper_control_sc``)."""

from __future__ import annotations

import dataclasses

import control
import numpy as np
import pytest

from tetherheli import simulate
from tetherheli.control.paper import paper_control
from tetherheli.control.tether_lqi import design_tether_lqi, tethered_design
from tetherheli.errors import ParameterError
from tetherheli.layout import CTRL_ANTI_WINDUP, CTRL_U_MAX, CTRL_U_MIN, CTRL_WINCH
from tetherheli.params import Params
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import Scenario, TetherLQISettings, load_scenario
from tetherheli.wind.profiles import Step

DT = 0.01
WEIGHTS = TetherLQISettings()  # the shipped defaults


def _scenario(**control_changes) -> Scenario:
    s = Scenario(name="tlqi", duration=60.0)
    c = dataclasses.replace(s.control, controller="tether_lqi", **control_changes)
    return s.replace(control=c)


def test_gain_equals_python_control_dlqr_with_integral_action():
    """Eqs 47-53 on the tethered plant (Table V trim, 13 states, reel rate as 5th input):
    python-control's dlqr with integral_action = -dt C (its integrator z+ = z + M x is eq
    50's with r = 0) and Q = blockdiag(C' Qy_y C + q_T c_T c_T', Qy_z) gives our K."""
    p = Params.paper()
    G, H, C, c_t = tethered_design(p, p.tension_control.T_ref, 10.0, DT)
    Qy = np.diag(WEIGHTS.Qy)
    q_t = 1e-3
    R = np.diag(WEIGHTS.Ru)
    gain = design_tether_lqi(G, H, C, c_t, DT, Qy=Qy, q_tension=q_t, Ru=R)
    n = G.shape[0]
    Q = np.zeros((n + 4, n + 4))
    Q[:n, :n] = C.T @ Qy[:4, :4] @ C + q_t * np.outer(c_t, c_t)
    Q[n:, n:] = Qy[4:, 4:]
    sys = control.ss(G, H, C, np.zeros((4, 5)), DT)
    K, _, E = control.dlqr(sys, Q, R, integral_action=-DT * C)
    assert gain.K.shape == (5, 17)
    np.testing.assert_allclose(gain.K, K, rtol=0, atol=1e-9 * np.max(np.abs(K)))
    assert np.max(np.abs(E)) == pytest.approx(gain.spectral_radius, rel=1e-9)


def test_tension_weight_changes_the_gain_and_plant_has_tension_row():
    """Eq 28 in the design: the tension row is KC (dq9 - dLN), and its weight matters."""
    p = Params.paper()
    G, H, C, c_t = tethered_design(p, p.tension_control.T_ref, 10.0, DT)
    assert c_t[5] == p.tether.K_C and c_t[12] == -p.tether.K_C and np.count_nonzero(c_t) == 2
    a = design_tether_lqi(G, H, C, c_t, DT, Qy=np.diag(WEIGHTS.Qy), q_tension=0.0,
                          Ru=np.diag(WEIGHTS.Ru))  # fmt: skip
    b = design_tether_lqi(G, H, C, c_t, DT, Qy=np.diag(WEIGHTS.Qy), q_tension=1.0,
                          Ru=np.diag(WEIGHTS.Ru))  # fmt: skip
    assert np.max(np.abs(a.K - b.K)) > 1e-3 * np.max(np.abs(a.K))


def test_tethered_closed_loop_is_stable_and_uses_the_reel():
    """The discrete closed loop of the tethered linearization (13 states + 4 integrators)
    under the shipped weights has all eigenvalues inside the unit circle, and the reel-rate
    row of the gain is not zero (the winch is an actuator of the design)."""
    setup = engine_setup(_scenario())
    gain = setup.gain.tethered
    eig = np.linalg.eigvals(gain.G_lqi - gain.H_lqi @ gain.K)
    assert np.max(np.abs(eig)) < 1.0
    assert np.max(np.abs(gain.K[4])) > 0.0
    K = setup.law[0]
    assert K.shape == (9, 17) and setup.law[1].shape == (13,)
    np.testing.assert_array_equal(K[5:, 12], 0.0)  # the free law does not see LN


def test_constant_wind_leaves_no_steady_state_position_error():
    """Integral action (eq 50) on q1, q2, q3, q6: a 6 N step of wind along n1 at t = 1 s moves
    the helicopter, and 60 s later the position error is back below 1 mm (simulated with the
    compiled engine and the nonlinear plant)."""
    s = _scenario().replace(wind=Step(1.0, 6.0, (1.0, 0.0, 0.0)))
    r = simulate(s)
    assert r.ok
    d = r.outputs[:, :3] - r.trim_output[:3]
    assert np.max(np.abs(d[:, 0])) > 0.02  # the wind did displace it
    assert np.max(np.abs(d[-100:])) < 1e-3
    assert abs(r.reel_rate[-1]) < 1e-4  # the winch at rest again


def _constants(setup) -> np.ndarray:
    """The model's constants as ``PaperController`` hands them to ``paper_control``: its
    writable copy of the set-up's read-only array (one compiled signature for both)."""
    return setup.paper_controller().c


def test_anti_windup_holds_the_integrators_while_clipped():
    """With CTRL_ANTI_WINDUP the integrators of eq 50 do not move while a rotor command lies
    outside its limits; without it, or within the limits, they do."""
    setup = engine_setup(_scenario())
    K, x_ref, y_ref, u0, _, _ = setup.law
    c = _constants(setup)
    x = setup.start.x.copy()
    x[7] += 0.5  # a sideways speed: the law commands a cyclic torque

    def step(anti_windup: bool, limit: float) -> np.ndarray:
        ctrl = setup.ctrl.copy()
        ctrl[CTRL_ANTI_WINDUP] = float(anti_windup)
        ctrl[CTRL_U_MIN + 1 : CTRL_U_MIN + 3] = -limit
        ctrl[CTRL_U_MAX + 1 : CTRL_U_MAX + 3] = limit
        z = np.array([0.1, -0.2, 0.3, 0.0])
        y, inp, ffwd = np.empty(4), np.empty(4), np.empty(4)
        xx = x.copy()
        xx[0] += 0.01  # and an output error, so that integration would move z
        paper_control(xx, 25.0, (z, np.zeros(2)), ctrl, c, (K, x_ref, y_ref, u0), (y, inp, ffwd))
        return z

    z_start = np.array([0.1, -0.2, 0.3, 0.0])
    np.testing.assert_array_equal(step(True, 1e-6), z_start)
    assert np.any(step(False, 1e-6) != z_start)
    assert np.any(step(True, 1e6) != z_start)


def test_after_release_the_free_rows_fly():
    """Winch stopped (a release, ``engine.release_if_broken``): the inputs come from rows 5-8
    (the paper's free law on q4..u6) and the reel rate is zero."""
    setup = engine_setup(_scenario())
    K, x_ref, y_ref, _, u0_free, _ = setup.law
    ctrl = setup.ctrl.copy()
    ctrl[CTRL_WINCH] = 0.0
    x = setup.start.x.copy()
    x[6] += 0.3
    z = np.array([0.01, 0.02, 0.03, 0.04])
    y, inp, ffwd = np.empty(4), np.empty(4), np.empty(4)
    rate = paper_control(x, 0.0, (z.copy(), np.zeros(2)), ctrl, _constants(setup),
                         (K, x_ref, y_ref, u0_free), (y, inp, ffwd))  # fmt: skip
    free = setup.gain.free
    expected = u0_free - free.Kx @ (x[:12] - x_ref[:12]) - free.Kz @ z
    np.testing.assert_allclose(inp, expected, rtol=1e-12)
    assert rate == 0.0


def test_scenario_keys_round_trip_and_bad_values(tmp_path):
    """``[control] controller`` and ``[control.tether_lqi]`` load from TOML and are written
    back; a bad value is a one-line ParameterError naming the key."""
    s = _scenario(tether_lqi=TetherLQISettings(q_tension=0.25, anti_windup=False))
    path = tmp_path / "s.toml"
    path.write_text(s.to_toml())
    back = load_scenario(path)
    assert back.control == s.control
    with pytest.raises(ParameterError, match=r"control\.controller"):
        s.replace(control=dataclasses.replace(s.control, controller="pid"))
    bad = path.read_text().replace("q_tension = 0.25", "q_tension = -1.0")
    path.write_text(bad)
    with pytest.raises(ParameterError, match=r"control\.tether_lqi\.q_tension"):
        load_scenario(path)


def test_start_in_turbulence_is_an_equilibrium_of_the_law():
    """In the mean wind of a turbulence scenario the tethered LQI starts at a windy trim
    (``start.start_point``) where its law commands that trim's total rotor input and a reel
    rate of zero (the trim's tension chosen by the secant method on the reel row)."""
    s = load_scenario("scenarios/turbulence_hover_tethered.toml")
    s = s.replace(control=dataclasses.replace(s.control, controller="tether_lqi"))
    setup = engine_setup(s)
    K, x_ref, y_ref, u0, _, z0 = setup.law
    y, inp, ffwd = np.empty(4), np.empty(4), np.empty(4)
    rate = paper_control(setup.start.x, setup.start.trim.tension, (z0.copy(), np.zeros(2)),
                         setup.ctrl.copy(), setup.model.constants, (K, x_ref, y_ref, u0),
                         (y, inp, ffwd))  # fmt: skip
    np.testing.assert_allclose(inp, setup.start.trim.u_total, rtol=0, atol=1e-9)
    assert abs(rate) < 1e-9
    np.testing.assert_allclose(y, y_ref, rtol=0, atol=1e-9)  # the windless trim's outputs
    assert setup.start.trim.tension != setup.trim.tension  # not a trivial start
