"""A run in turbulence starts at rest in the equilibrium of its air at t = 0 (``hover_trim``
with ``N_F_wind``, ``runs.start.start_point``), in the compiled loop, the Python loop and the
Gymnasium environment alike; ``Scenario.metrics_start`` windows the metrics."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import tetherheli as th
from tetherheli.envs.env import TetheredHoverEnv
from tetherheli.errors import InfeasibleError
from tetherheli.params import Params
from tetherheli.runs.setup import engine_setup, run_setup
from tetherheli.runs.start import start_point
from tetherheli.scenario.core import Scenario
from tetherheli.wind import ConstantForce, DragModel, GaussMarkovTurbulence, NoWind, Turbulence
from tetherheli.wind.evaluate import wind_force

DRAG = DragModel((0.4, 0.4, 0.8))
WIND = (4.0, 3.0, 0.0)  # [m/s] 5 m/s, off the n1 axis
F_WIND = 0.5 * 1.225 * 0.4 * 5.0 * np.array(WIND)  # its drag on HO at rest [N]


def _still_air(duration: float, mean=WIND) -> Turbulence:
    """A mean wind with zero gusts (K = 0)."""
    return Turbulence(
        GaussMarkovTurbulence(gain=(0.0, 0.0, 0.0)), DRAG, 1, duration, 0.01, N_v_mean_wind=mean
    )


@pytest.mark.parametrize("tension", [0.0, 25.0])
def test_trim_in_wind_balances_the_forces(tension):
    """A second formulation of the equilibrium: the sum of the external forces on the
    helicopter, fMR3 f3 + fTR2 f2 - m g n3 + F_wind - TC c3 (Table I's f2, f3 with q6 = 0,
    c3 = [s8, -s7 c8, c7 c8] from docs/paper.md), is zero; the outputs are the windless trim's and
    the dynamic equations vanish; the tether keeps its tension (q9 - LN = TC / KC)."""
    params = Params.paper()
    model = th.TetheredHelicopter(params)
    calm = model.trim(tension)
    windy = model.trim(tension, N_F_wind=F_WIND)
    q4, q5, q6, q7, q8, q9 = windy.x[:6]
    assert q6 == 0.0 and abs(q5) > 0.02  # it leans into the wind
    f3 = np.array([math.sin(q5), -math.sin(q4) * math.cos(q5), math.cos(q4) * math.cos(q5)])
    f2 = np.array([0.0, math.cos(q4), math.sin(q4)])
    c3 = np.array([math.sin(q8), -math.sin(q7) * math.cos(q8), math.cos(q7) * math.cos(q8)])
    h = params.helicopter
    u = windy.u_total
    total = u[0] * f3 + u[3] * f2 - h.m * h.g * np.array([0, 0, 1.0]) + F_WIND - tension * c3
    np.testing.assert_allclose(total, 0.0, atol=1e-9 * h.m * h.g)
    np.testing.assert_allclose(windy.y, calm.y, atol=1e-12)
    dx = model.derivative(windy.x, u, wind=F_WIND, reel_rate=0.0)
    np.testing.assert_allclose(dx, 0.0, atol=1e-10)
    assert math.isclose(params.tether.K_C * (q9 - windy.x[12]), tension, abs_tol=1e-12)
    np.testing.assert_array_equal(model.trim(tension, N_F_wind=(0.0, 0.0, 0.0)).x, calm.x)


@pytest.mark.parametrize("configuration", ["free", "tethered"])
def test_mean_wind_without_gusts_stays_put(configuration):
    """In a 5 m/s mean wind with zero gusts the run stays where it starts: over 30 s, HO moves
    less than 1e-9 m from the windless trim's position and the state less than 1e-9 from the
    start, in the compiled loop. The same force as a ``ConstantForce`` (not a mean wind, so
    the run starts at the windless trim) moves HO by more than 1 cm: the test can fail."""
    s = Scenario(configuration=configuration, duration=30.0, wind=_still_air(30.0))
    r = th.simulate(s)
    assert r.ok
    assert np.max(np.abs(r.outputs[:, :3] - r.trim_output[:3])) < 1e-9
    assert np.max(np.abs(r.states - r.states[0])) < 1e-9
    step = th.simulate(s.replace(wind=ConstantForce(tuple(F_WIND))))
    assert np.max(np.abs(step.outputs[:, :3] - step.trim_output[:3])) > 0.01


@pytest.mark.parametrize("configuration", ["free", "tethered"])
def test_python_loop_and_environment_start_in_the_wind_too(configuration):
    """The Python loop (a ``PaperController`` through ``simulate(controller=...)``) and the
    Gymnasium environment (zero residual action) start from the same state and integrators:
    both stay put to 1e-9 m over 2 s, and the Python loop equals the compiled one."""
    s = Scenario(configuration=configuration, duration=2.0, wind=_still_air(2.0))
    setup = engine_setup(s)
    compiled = th.simulate(s)
    python = th.simulate(s, controller=setup.paper_controller())
    np.testing.assert_allclose(python.states, compiled.states, rtol=0, atol=1e-12)
    env = TetheredHoverEnv(s.replace(wind=NoWind()), max_episode_time=2.0)
    env.reset(seed=0, options={"wind": _still_air(2.1)})
    np.testing.assert_array_equal(env.state, setup.start.x)
    y0 = setup.trim.y
    for _ in range(200):
        _, _, terminated, _truncated, info = env.step(np.zeros(4))
        assert not terminated
        assert np.max(np.abs(info["outputs"][:3] - y0[:3])) < 1e-9
    env.close()


def test_integrators_hold_the_wind_trim_inputs():
    """z0 solves K_z z0 = u0 - K_x (x_w - x_ref) - u_w: the paper law's command at the start
    (eq 54, feed-forward on) is the wind trim's u0|T, to 1e-10."""
    s = Scenario(configuration="tethered", duration=1.0, wind=_still_air(1.0))
    setup = engine_setup(s)
    K, x_ref, _, u0, _, z0 = setup.law
    u = u0 - K[:, :12] @ (setup.start.x[:12] - x_ref) - K[:, 12:] @ z0
    np.testing.assert_allclose(u, setup.start.trim.u, atol=1e-10)
    assert np.any(z0 != 0.0)


def test_start_balances_the_first_gust():
    """With gusts, the start is the equilibrium in the drag of the mean wind plus the gust at
    t = 0 (not the mean wind alone): the plant's derivative there, with the engine's own
    wind force at t = 0, vanishes to 1e-10."""

    wind = Turbulence(GaussMarkovTurbulence(), DRAG, 5, 1.0, 0.01, N_v_mean_wind=WIND)
    s = Scenario(configuration="tethered", duration=1.0, wind=wind)
    setup = engine_setup(s)
    force = np.empty(3)
    w = setup.wind
    wind_force(w.program, w.gust, w.gust_dt, w.drag, 0.0, 1, 0.0, 0.0, 0.0, force)
    assert np.linalg.norm(force - F_WIND) > 0.05
    model = th.TetheredHelicopter(s.params)
    dx = model.derivative(setup.start.x, setup.start.trim.u_total, wind=force, reel_rate=0.0)
    np.testing.assert_allclose(dx, 0.0, atol=1e-10)


def test_no_mean_wind_starts_at_the_windless_trim():
    """Without a mean wind (the paper's runs) the start is the windless trim and z0 = 0."""
    s = th.load_scenario("scenarios/paper_sim1_tethered.toml")
    setup = engine_setup(s)
    assert setup.start.trim is setup.trim
    np.testing.assert_array_equal(setup.start.z, 0.0)


def test_a_singular_integrator_gain_is_refused():
    """K_z (the gain's integrator block) must be invertible for z0 to exist: a gain with a
    zero column there is one line naming control.Qy/Ru."""
    s = Scenario(configuration="free", duration=1.0, wind=_still_air(1.0))
    model, trim, gain, ctrl, _ = run_setup(s)
    K = np.array(gain.K)
    K[:, 14] = 0.0
    with pytest.raises(InfeasibleError, match=r"control\.Qy/Ru.*invertible K_z") as err:
        start_point(model, trim, SimpleNamespace(K=K), ctrl, s.wind, s.q9)
    assert "\n" not in str(err.value)


def test_a_wind_too_strong_to_hover_in_is_refused():
    """No trim in a 2000 N wind: one line naming N_F_wind."""
    with pytest.raises(InfeasibleError, match="N_F_wind"):
        th.TetheredHelicopter(Params.paper()).trim(0.0, N_F_wind=(2000.0, 0.0, 0.0))


def test_metrics_start_windows_the_online_and_the_recorded_metrics():
    """``metrics_start`` = 20 s on the first 29 s of paper simulation 1 (pulse at 10-11 s, no
    sine yet): the compiled loop's on-line metrics (``run_batch``), ``analysis.run_metrics``
    of the recording and a slice of the recorded outputs at t >= 20 s written here agree to
    1e-12; the windowed peak is far below the whole run's, which includes the pulse."""
    from tetherheli.analysis import run_metrics
    from tetherheli.runs.batch import run_batch

    base = th.load_scenario("scenarios/paper_sim1_tethered.toml").replace(duration=29.0)
    s = base.replace(metrics_start=20.0)
    r = th.simulate(s)
    keep = r.time >= 20.0 - 1e-9
    dev = r.outputs[keep, 0] - r.trim_output[0]
    peak, rms = np.max(np.abs(dev)), np.sqrt(np.mean(dev**2))
    online = run_batch([s], workers=1).metrics(0)
    recorded = run_metrics(r)
    for got in (online["peak_q1"], recorded.peak_abs_dev["q1"]):
        assert math.isclose(got, peak, rel_tol=1e-12)
    for got in (online["rms_q1"], recorded.rms_dev["q1"]):
        assert math.isclose(got, rms, rel_tol=1e-12)
    assert online["n_samples"] == np.count_nonzero(keep) == 901
    assert math.isclose(recorded.tension_min, r.tension[keep].min(), rel_tol=1e-15)
    assert peak < run_metrics(th.simulate(base)).peak_abs_dev["q1"] - 0.5


@pytest.mark.parametrize("value", [-1.0, 60.0, math.nan])
def test_metrics_start_must_lie_within_the_run(value):
    """0 <= metrics_start < duration: anything else is one line naming the key."""
    with pytest.raises(th.ParameterError, match="metrics_start"):
        Scenario(duration=60.0, metrics_start=value)
