"""The drum winch (``[winch] model = "drum"``, ``tether.winch``), each check against an
independent route: the static balance, the analytic first-order response of the speed loop,
the Coulomb stick/slip thresholds and the analytic stopping time, the constant acceleration at
the torque limit, the drum's energy balance by quadrature, and the limit of a stiff, light
drum (the paper's ideal winch, eq 37)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from tetherheli import cli
from tetherheli.engine import loop as engine
from tetherheli.errors import ParameterError
from tetherheli.layout import (
    ACT_DRUM,
    HELD_DRUM_SPEED,
    HELD_MOTOR_TORQUE,
    HELD_SIZE,
    default_actuators,
)
from tetherheli.results.result import load_result
from tetherheli.runs.batch import run_batch
from tetherheli.runs.closed_loop import simulate
from tetherheli.runs.packing import winch_into
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import (
    ActuatorSettings,
    WinchSettings,
    load_scenario,
    paper_scenario,
    scenario_from_dict,
)
from tetherheli.tether.winch import drum_step
from tetherheli.wind import NoWind

DT = 0.01
DRUM = WinchSettings(model="drum")  # the documented default drum


def _act(winch: WinchSettings) -> np.ndarray:
    act = default_actuators()
    winch_into(act, winch)
    return act


def _actuate(act, held, rate_cmd, tension, measured=None, length=1e6):
    """The engine's actuator phase for the winch alone (rotor inputs unused), at a natural
    length ``length`` [m] (default: far from the payout limits)."""
    inp = np.zeros(4)
    measured = tension if measured is None else measured
    drum = act[ACT_DRUM] > 0.5
    return engine.actuate(
        inp, held, rate_cmd, act, DT, False, (tension, measured), length, 0.0, drum
    )


# --- the drum alone ------------------------------------------------------------------------


def test_static_hold_torque_equals_r_times_tension():
    """At rest with a zero reel-rate command the drive holds the tether: motor torque = r T
    (the static balance of J w' = r T - tau_m - b w - tau_c sign w), no motion; with a load
    cell misreading by less than the Coulomb friction the drum still sticks, its torque then
    r T_meas."""
    act = _act(DRUM)
    r, tc = DRUM.drum_radius, DRUM.coulomb_friction
    for tension, measured in ((25.0, 25.0), (25.0, 25.0 + 0.9 * tc / r)):
        held = np.zeros(HELD_SIZE)
        for _ in range(100):
            rate = _actuate(act, held, 0.0, tension, measured)
            assert rate == 0.0 and held[HELD_DRUM_SPEED] == 0.0
        assert held[HELD_MOTOR_TORQUE] == pytest.approx(r * measured, rel=1e-12)
    held = np.zeros(HELD_SIZE)
    assert _actuate(act, held, 0.0, 25.0, 25.0 + 1.1 * tc / r) < 0.0  # beyond: it hauls in


def test_speed_loop_step_response_is_first_order():
    """No tension, no Coulomb friction, torque limit out of reach: w(t) = K w_c / (K + b)
    (1 - exp(-(K + b) t / J)) with K = J omega_w, so the reel rate averaged over sample k is
    r times the analytic integral of w over it (the time constant 1/omega_w for b = 0)."""
    w = dataclasses.replace(
        DRUM, coulomb_friction=0.0, viscous_friction=0.002, torque_limit=1e6,
        tension_feedforward=False,
    )  # fmt: skip
    act = _act(w)
    held = np.zeros(HELD_SIZE)
    rate_cmd = 0.3  # [m/s]
    w_c = rate_cmd / w.drum_radius
    gain = w.drum_inertia * w.speed_loop_bandwidth
    lam = (gain + w.viscous_friction) / w.drum_inertia
    w_ss = gain * w_c / (gain + w.viscous_friction)

    def integral(t):  # int_0^t w dt
        return w_ss * (t - (1.0 - math.exp(-lam * t)) / lam)

    for k in range(30):
        rate = _actuate(act, held, rate_cmd, 0.0)
        t0, t1 = k * DT, (k + 1) * DT
        assert rate == pytest.approx(w.drum_radius * (integral(t1) - integral(t0)) / DT, rel=1e-12)
        assert held[HELD_DRUM_SPEED] == pytest.approx(w_ss * (1 - math.exp(-lam * t1)), rel=1e-12)


def test_coulomb_stick_slip_thresholds():
    """From rest the drum stays put while |tau_m - r T| <= tau_c and slips, with initial
    acceleration (|tau_m - r T| - tau_c) / J, once above; a spinning drum with the drive off
    stops at the analytic time t* = (J / b) ln(1 + b w0 / tau_c) and then sticks."""
    J, tc, load = 0.005, 0.05, 1.25
    gain = J * 50.0
    for sign in (1.0, -1.0):
        below = sign * tc * (1 - 1e-9) / gain  # command whose torque at rest is just below
        w1, s_int, _ = drum_step(0.0, below, load, load, DT, J, gain, 10.0, 0.0, tc)
        assert w1 == 0.0 and s_int == 0.0
        above = sign * tc * 1.01 / gain
        h = 1e-7
        w1, _, _ = drum_step(0.0, above, load, load, h, J, gain, 10.0, 0.0, tc)
        assert w1 == pytest.approx(sign * 0.01 * tc / J * h, rel=1e-4)
    # stopping: the drive's torque equal to the load (no proportional action: gain tiny)
    b, w0 = 0.004, 3.0
    t_stop = J / b * math.log(1 + b * w0 / tc)
    assert 0.0 < t_stop < 1.0
    w1, s_int, _ = drum_step(w0, 0.0, load, load, 1.0, J, 1e-300, 10.0, b, tc)
    assert w1 == 0.0
    # int_0^t* w dt with w = -tc/b + (w0 + tc/b) exp(-b t / J)
    expected = -tc / b * t_stop + (w0 + tc / b) * J / b * (1 - math.exp(-b * t_stop / J))
    assert s_int == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("viscous", [0.0, 0.003])
@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_torque_limit_saturation_slope(viscous, direction):
    """A command far beyond reach saturates the drive: paying out (direction +1) the reel
    rate's slope is r (tau_max + r T - b w) / J, hauling in (-1) it is -r (tau_max - r T +
    b w) / J, i.e. the reel-in speed grows at r (tau_max - r T - b |w|) / J (exactly constant
    without viscous friction)."""
    w = dataclasses.replace(DRUM, coulomb_friction=0.0, viscous_friction=viscous)
    act = _act(w)
    held = np.zeros(HELD_SIZE)
    r, J, tension = w.drum_radius, w.drum_inertia, 25.0
    rates, speeds = [], []
    for _ in range(20):
        rates.append(_actuate(act, held, 50.0 * direction, tension, 0.0))  # no feed-forward
        speeds.append(held[HELD_DRUM_SPEED])
    assert held[HELD_MOTOR_TORQUE] == -direction * w.torque_limit
    slopes = np.diff(rates) / DT
    # the means of samples k and k+1 straddle t_{k+1}, where the speed is speeds[k]
    speed = np.array(speeds[:-1])
    expected = r * (direction * w.torque_limit + r * tension - viscous * speed) / J
    np.testing.assert_allclose(slopes, expected, rtol=1e-12 if viscous == 0 else 1e-5)


def _energy_ledger(m: int, n: int = 600) -> tuple[float, float, float]:
    """Motor work on the drum minus (work against the tension + viscous and Coulomb losses +
    kinetic energy gained) [J] over n samples of varied commands and tensions (saturation, sticking,
    reversals), the powers integrated by the trapezoidal rule on m sub-steps per sample (the
    held-input solution composes over sub-intervals); with the sum of |work| terms [J] and the
    Coulomb loss [J]."""
    J, gain, tmax, b, tc, r = 0.005, 0.25, 2.5, 0.002, 0.05, 0.05
    rng = np.random.default_rng(7)
    w = 0.0
    work = {"motor": 0.0, "tension": 0.0, "viscous": 0.0, "coulomb": 0.0}
    for _ in range(n):
        w_c = rng.normal(0.0, 4.0) if rng.random() < 0.8 else 0.0
        tension = 25.0 + rng.normal(0.0, 8.0)
        ffwd = r * (tension + rng.normal(0.0, 0.5))
        ws = [w]
        for _ in range(m):
            w, _, _ = drum_step(w, w_c, r * tension, ffwd, DT / m, J, gain, tmax, b, tc)
            ws.append(w)
        ws = np.array(ws)
        torque = np.clip(gain * (ws - w_c) + ffwd, -tmax, tmax)  # tau_m, hauling in
        for name, power in (
            ("motor", -torque * ws), ("tension", -r * tension * ws), ("viscous", b * ws * ws),
            ("coulomb", tc * np.abs(ws)),
        ):  # fmt: skip
            work[name] += np.trapezoid(power, dx=DT / m)
    kinetic = 0.5 * J * w * w
    residual = work["motor"] - (work["tension"] + work["viscous"] + work["coulomb"] + kinetic)
    return residual, sum(abs(v) for v in work.values()), work["coulomb"]


def test_energy_balance_over_a_run():
    """Motor work = kinetic energy gained + viscous and Coulomb losses + work against the
    tension: the ledger's residual is the trapezoidal rule's error alone, falling as 1/m^2
    with m sub-steps per sample, and its Richardson extrapolation is zero to 3e-6 of the
    energies moved (the kinks at saturation and sticking keep it from vanishing further)."""
    coarse, scale, coulomb = _energy_ledger(50)
    fine, _, _ = _energy_ledger(100)
    assert scale > 0.5 and coulomb > 0.05 * scale  # a run that does work and slips
    assert 3.5 < coarse / fine < 4.5  # second order: quadrature error, not a model error
    assert abs((4.0 * fine - coarse) / 3.0) < 3e-6 * scale


def test_bad_drum_input_refused_in_one_line(tmp_path, capsys):
    for key, value in (
        ("drum_radius", 0.0), ("drum_radius", -0.1), ("drum_inertia", 0.0),
        ("torque_limit", 0.0), ("torque_limit", -1.0), ("viscous_friction", -1e-3),
        ("coulomb_friction", -0.01), ("speed_loop_bandwidth", 0.0), ("model", "hydraulic"),
        ("tension_feedforward", 1),
    ):  # fmt: skip
        with pytest.raises(ParameterError) as err:
            scenario_from_dict({"winch": {key: value}})
        text = str(err.value)
        assert f"winch.{key}" in text and "\n" not in text
    with pytest.raises(ParameterError, match=r"winch\.spool"):
        scenario_from_dict({"winch": {"spool": 1.0}})
    with pytest.raises(ParameterError, match=r"actuators\.reel_acceleration_limit"):
        paper_scenario(1, "tethered").replace(
            winch=DRUM, actuators=ActuatorSettings(reel_acceleration_limit=2.0)
        )
    path = tmp_path / "bad.toml"
    path.write_text('[winch]\nmodel = "drum"\ntorque_limit = -2.5\n')
    assert cli.main(["simulate", str(path), "--out", str(tmp_path / "out")]) != 0
    err = capsys.readouterr().err.strip()
    assert "winch.torque_limit" in err and "-2.5" in err and len(err.splitlines()) == 1
    assert "Traceback" not in err


# --- in the closed loop ----------------------------------------------------------------------


def _sim1_drum(duration: float, winch: WinchSettings = DRUM):
    return paper_scenario(1, "tethered").replace(duration=duration, winch=winch)


def test_hover_without_wind_holds_at_rest():
    """At the trim without wind the PI commands nothing and the drive holds r Tref: the drum
    never moves and the run equals the ideal winch's bit for bit."""
    s = _sim1_drum(2.0).replace(wind=NoWind())
    drum = simulate(s)
    ideal = simulate(s.replace(winch=WinchSettings()))
    assert drum.ok
    np.testing.assert_array_equal(drum.extra["drum_speed"], 0.0)
    r, t_ref = DRUM.drum_radius, s.params.tension_control.T_ref
    np.testing.assert_allclose(drum.extra["motor_torque"], r * t_ref, rtol=1e-12)
    np.testing.assert_array_equal(drum.states, ideal.states)


def test_ideal_limit():
    """A light drum (J = 1e-6 kg m^2) with a fast speed loop, no friction and no torque limit
    in reach follows the command as the ideal winch applies it (eq 37): on simulation 1 the
    peak and RMS of q1 and the tension range agree within 1e-4 relative, and the gap shrinks
    as the bandwidth grows."""
    s = _sim1_drum(40.0)
    ideal = simulate(s.replace(winch=WinchSettings()))

    def metrics(r):
        q1 = r.outputs[:, 0] - r.trim_output[0]
        return np.array([np.abs(q1).max(), np.sqrt(np.mean(q1**2)), r.tension.min(),
                         r.tension.max()])  # fmt: skip

    gaps = []
    for bandwidth in (1e2, 1e3, 1e4):
        w = WinchSettings(
            model="drum", drum_inertia=1e-6, speed_loop_bandwidth=bandwidth, torque_limit=1e6,
            viscous_friction=0.0, coulomb_friction=0.0,
        )  # fmt: skip
        drum = simulate(s.replace(winch=w))
        gaps.append(np.max(np.abs(metrics(drum) / metrics(ideal) - 1)))
    assert gaps[0] > gaps[1] > gaps[2]
    assert gaps[2] < 1e-4


def test_result_records_drum_signals(tmp_path):
    """The drum's speed and motor torque are extra columns with units, saved and reloaded;
    the reel rate averaged over a sample is r times the mean of the drum speeds at its ends
    to the trapezoid's accuracy."""
    s = load_scenario("scenarios/paper_sim1_drum.toml").replace(duration=15.0)
    r = simulate(s)
    assert r.ok and set(r.extra) == {"drum_speed", "motor_torque"}
    units = r.column_units()
    assert units["drum_speed"] == "rad/s" and units["motor_torque"] == "N m"
    speed = r.extra["drum_speed"]
    assert np.abs(speed).max() > 1.0  # the pulse at t = 10 s turns the drum
    trapezoid = s.winch.drum_radius * 0.5 * (speed[:-1] + speed[1:])
    np.testing.assert_allclose(r.reel_rate[:-1], trapezoid, atol=2e-3 * np.abs(r.reel_rate).max())
    r.save(tmp_path, "drum")
    back = load_result(tmp_path / "drum.csv")
    np.testing.assert_allclose(back.extra["motor_torque"], r.extra["motor_torque"], rtol=1e-12)


def test_lanes_and_python_loop_run_the_drum():
    """The lane engine and the Python loop advance the drum with the same ``actuate`` as the
    compiled loop: equal summaries, equal recorded runs."""
    runs = [_sim1_drum(12.0), _sim1_drum(12.0, dataclasses.replace(DRUM, torque_limit=1.3))]
    lanes = run_batch(runs, workers=1)
    alone = run_batch(runs, workers=1, lanes=False)
    assert lanes.ok.all()
    np.testing.assert_array_equal(lanes.summaries, alone.summaries)
    assert lanes.summaries[0, 0] != lanes.summaries[1, 0]  # the torque limit matters
    s = runs[1].replace(duration=11.0)
    compiled = simulate(s)
    python = simulate(s, controller=engine_setup(s).paper_controller())
    np.testing.assert_allclose(python.states, compiled.states, rtol=0, atol=1e-9)
    np.testing.assert_allclose(
        python.extra["motor_torque"], compiled.extra["motor_torque"], rtol=0, atol=1e-9
    )
