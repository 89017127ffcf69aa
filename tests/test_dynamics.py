"""Numeric dynamics against an independent Newton-Euler formulation, invariants, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tetherheli import (
    FreeHelicopter,
    Params,
    SingularConfigurationError,
    TetheredHelicopter,
)

from .newton_euler import NewtonEuler


def _random_tethered_state(rng, taut: bool) -> np.ndarray:
    x = np.empty(13)
    x[:5] = rng.uniform(-0.8, 0.8, 5)
    x[5] = rng.uniform(5.0, 15.0)
    x[6:12] = rng.normal(scale=[1, 1, 1, 2, 2, 2])
    x[12] = x[5] - (rng.uniform(0.1, 1.0) if taut else -rng.uniform(0.1, 1.0))
    return x


@pytest.mark.parametrize("taut", [True, False])
def test_tethered_equals_newton_euler(tethered, paper, rng, taut):
    """Eqs 10-12, 28-37 against Newton-Euler (docs/paper.md's J, h; tether force from P's Cartesian
    position): agreement to 1e-12 relative at random states, taut and slack."""
    ne = NewtonEuler(paper)
    for _ in range(50):
        x = _random_tethered_state(rng, taut)
        inp = rng.normal([130, 1, 0.5, 12], [20, 2, 2, 3])
        wind = rng.normal(scale=20, size=3)
        rate = rng.normal()
        ours = tethered.derivative(x, inp, wind, rate)
        ref = ne.tethered(x, inp, wind, rate)
        scale = np.maximum(np.abs(ref), 1.0)
        np.testing.assert_allclose(ours / scale, ref / scale, rtol=0, atol=1e-12)


def test_free_equals_newton_euler(free, paper, rng):
    """Eqs 9-18 against the Newton-Euler formulation, 1e-12 relative."""
    ne = NewtonEuler(paper)
    for _ in range(50):
        x = np.concatenate(
            [rng.normal(scale=5, size=3), rng.uniform(-0.8, 0.8, 3), rng.normal(size=6)]
        )
        inp = rng.normal([130, 1, 0.5, 12], [20, 2, 2, 3])
        wind = rng.normal(scale=20, size=3)
        ref = ne.free(x, inp, wind)
        scale = np.maximum(np.abs(ref), 1.0)
        np.testing.assert_allclose(free.derivative(x, inp, wind) / scale, ref / scale, atol=1e-12)


def test_slack_tethered_equals_free_trajectory(tethered, free):
    """Eq 28: with a slack tether (TC = 0) the tethered model flies the free model's path."""
    trim = free.trim()
    inp = trim.u + np.array([3.0, 0.05, -0.04, 0.5])
    wind = np.array([4.0, -3.0, 1.0])
    x_free = trim.x.copy()
    x_free[6:12] = [0.2, -0.1, 0.05, 0.1, 0.05, -0.02]
    x_teth = tethered.trim(0.0).x.copy()
    x_teth[6:12] = x_free[6:12]
    x_teth[12] = 30.0  # natural length far beyond reach: always slack
    opts = dict(method="DOP853", rtol=1e-12, atol=1e-12, dense_output=False)
    t_eval = np.linspace(0.0, 3.0, 31)
    a = solve_ivp(lambda t, x: free.derivative(x, inp, wind), (0, 3), x_free, t_eval=t_eval, **opts)
    b = solve_ivp(
        lambda t, x: tethered.derivative(x, inp, wind), (0, 3), x_teth, t_eval=t_eval, **opts
    )
    assert np.all(tethered.tension(b.y.T) == 0.0)
    np.testing.assert_allclose(tethered.outputs(b.y.T)[:, :3], a.y[:3].T, atol=1e-8)
    np.testing.assert_allclose(b.y[:3].T, a.y[3:6].T, atol=1e-8)  # attitude
    np.testing.assert_allclose(b.y[6:12].T, a.y[6:12].T, atol=1e-8)  # speeds


def test_energy_conserved_taut_no_gravity(paper):
    """No gravity, no inputs, LN fixed, taut tether: 1/2 m v^2 + 1/2 w.J.w + 1/2 KC (q9-LN)^2
    is constant (the rotor's spin is prescribed, docs/paper.md's J), to the integrator's
    tolerance."""
    params = paper.replace(helicopter={"g": 0.0, "rotor_drag_arm": 1e-9})
    model = TetheredHelicopter(params)
    ne = NewtonEuler(params)
    x0 = np.array([0.1, -0.05, 0.2, 0.3, -0.2, 10.5, 0.0, 0.0, 0.0, 0.6, -0.4, 0.3, 9.5])
    # orbit the ground point so the centripetal load keeps the tether taut: m v^2 / r = TC
    c3 = np.array([np.sin(x0[4]), -np.sin(x0[3]) * np.cos(x0[4]), np.cos(x0[3]) * np.cos(x0[4])])
    tangent = np.cross(c3, [1.0, 0.0, 0.0])
    tangent /= np.linalg.norm(tangent)
    speed = np.sqrt(params.tether.K_C * (x0[5] - x0[12]) * x0[5] / ne.m)
    x0[6:9] = speed * tangent + np.array([0.1, -0.05, 0.08])

    def energy(x):
        m = ne.m
        stretch = max(x[5] - x[12], 0.0)
        return (
            0.5 * m * x[6:9] @ x[6:9]
            + 0.5 * x[9:12] @ ne.J @ x[9:12]
            + 0.5 * params.tether.K_C * stretch**2
        )

    sol = solve_ivp(
        lambda t, x: model.derivative(x, np.zeros(4)),
        (0, 5),
        x0,
        method="DOP853",
        rtol=1e-11,
        atol=1e-11,
        t_eval=np.linspace(0, 5, 51),
    )
    assert np.all(sol.y[5] > sol.y[12])  # stayed taut
    e = np.array([energy(col) for col in sol.y.T])
    assert np.max(np.abs(e - e[0])) / e[0] < 1e-8


def test_batch_equals_single(tethered, free, rng):
    """Batch (n, 13) and single-state derivatives agree exactly."""
    xs = np.array([_random_tethered_state(rng, taut=bool(i % 2)) for i in range(20)])
    us = rng.normal([130, 1, 0.5, 12], [20, 2, 2, 3], size=(20, 4))
    ws = rng.normal(size=(20, 3))
    rates = rng.normal(size=20)
    batch = tethered.derivative(xs, us, ws, rates)
    for i in range(20):
        np.testing.assert_array_equal(batch[i], tethered.derivative(xs[i], us[i], ws[i], rates[i]))
    xf = np.column_stack([rng.normal(size=(20, 3)), xs[:, :3], xs[:, 6:12]])
    batch_f = free.derivative(xf, us[0])
    for i in range(20):
        np.testing.assert_array_equal(batch_f[i], free.derivative(xf[i], us[0]))


def test_tension_eq28(tethered):
    """Eq 28: TC = KC (q9 - LN) when taut, 0 when slack; TC = 25 N at q9 = 10 m, LN = 9.375 m."""
    x = tethered.trim(25.0).x
    assert tethered.tension(x) == pytest.approx(25.0, rel=1e-14)
    assert x[12] == pytest.approx(9.375, rel=1e-15)
    x2 = x.copy()
    x2[12] = 10.5
    assert tethered.tension(x2) == 0.0


@pytest.mark.parametrize(
    ("mutate", "match"),
    [
        (lambda x: x.__setitem__(1, np.pi / 2), "q5"),
        (lambda x: x.__setitem__(4, -np.pi / 2), "q8"),
        (lambda x: x.__setitem__(5, 0.0), "q9"),
        (lambda x: x.__setitem__(5, -1.0), "q9"),
    ],
)
def test_singular_configurations_raise(tethered, mutate, match):
    """Singular configurations give a clear error, never inf or NaN."""
    x = tethered.trim(25.0).x.copy()
    mutate(x)
    with pytest.raises(SingularConfigurationError, match=match):
        tethered.derivative(x, np.zeros(4))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"x": np.zeros(12)}, "x has shape"),
        ({"x": np.full(13, np.nan)}, "x has non-finite"),
        ({"u": np.zeros(3)}, "u has shape"),
        ({"u": [np.inf, 0, 0, 0]}, "u has non-finite"),
        ({"wind": (1.0, 2.0)}, "wind has shape"),
        ({"reel_rate": np.nan}, "reel_rate"),
        ({"x": "abc"}, "x must be numeric"),
    ],
)
def test_bad_input_names_argument(tethered, kwargs, match):
    args = {"x": tethered.trim(25.0).x, "u": np.zeros(4)}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        tethered.derivative(**args)


def test_free_singular_q5(free):
    x = free.trim().x.copy()
    x[4] = -np.pi / 2
    with pytest.raises(SingularConfigurationError, match="q5"):
        free.derivative(x, np.zeros(4))


def test_params_type_checked():
    with pytest.raises(TypeError, match="params"):
        TetheredHelicopter({"K_C": 3})  # type: ignore[arg-type]
    assert isinstance(FreeHelicopter(None).params, Params)


def test_stage_trigonometry_matches_libm():
    """The engine's RK4 stages take sin/cos of q4..q8 by angle addition from the step start
    (kernels.angle_trig_from): equal to libm within a few units in the last place, for small
    steps (Taylor series) and large ones (libm fallback); the _sc model functions with libm's
    values equal the plain ones to rounding (SymPy orders their terms differently)."""
    from tetherheli.model import kernels

    rng = np.random.default_rng(5)
    sc0, sc, ref = np.empty(10), np.empty(10), np.empty(10)
    worst = 0.0
    for _ in range(2000):
        base = rng.uniform(-3.0, 3.0, 13)
        step = base + rng.choice([1e-6, 1e-3, 0.04, 0.3]) * rng.standard_normal(13)
        kernels.angle_trig(base, sc0)
        kernels.angle_trig_from(step, base, sc0, sc)
        kernels.angle_trig(step, ref)
        worst = max(worst, float(np.max(np.abs(sc - ref))))
    assert worst < 1e-15
    x = rng.uniform(-0.5, 0.5, 13)
    x[5], x[12] = 10.0, 9.4
    inp, wind = np.array([150.0, 1.0, -0.5, 13.0]), np.array([3.0, -2.0, 1.0])
    c = kernels.model_constants("tethered", Params.paper().helicopter)
    a, b = np.empty(12), np.empty(12)
    kernels.tethered_rhs(x, inp, wind, 25.0, c, a)
    kernels.angle_trig(x, sc)
    kernels.tethered_rhs_sc(x, sc, inp, wind, 25.0, c, b)
    np.testing.assert_allclose(b, a, rtol=1e-14, atol=1e-15)
