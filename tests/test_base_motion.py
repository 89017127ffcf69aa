"""A winch on a moving base (issue 26): the motions b(t), their packed compiled form, Kane's
equations with a moving base against the Newton-Euler oracle, and the linearization's base
acceleration input."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from tetherheli.base import (
    FixedBase,
    HarmonicBase,
    SeaStateBase,
    VelocityBase,
    base_state,
    compile_base,
    jonswap,
    read_base_csv,
)
from tetherheli.errors import ParameterError
from tetherheli.model.derive import derive
from tetherheli.model.linearization import linearize
from tetherheli.params import PARAM_ORDER

from .newton_euler import NewtonEuler

HARMONIC = HarmonicBase(amplitude=(0.2, 0.1, 0.5), frequency=(0.3, 0.7, 0.15), phase=(0.4, 0, 1))


def _numeric_derivative(motion, t, h=1e-5):
    """b' and b'' by central differences of b (an independent route to the motion's own)."""
    b = lambda s: motion.state(s)[:, 0]  # noqa: E731
    return (b(t + h) - b(t - h)) / (2 * h), (b(t + h) - 2 * b(t) + b(t - h)) / h**2


@pytest.mark.parametrize(
    "motion",
    [
        FixedBase(position=(1.0, -2.0, 0.5)),
        VelocityBase(velocity=(5.0, -1.0, 0.2), position=(1.0, 0.0, 0.0)),
        HARMONIC,
        SeaStateBase(significant_wave_height=2.0, peak_period=7.0, seed=3, sway_scale=0.3),
    ],
    ids=["fixed", "velocity", "harmonic", "sea_state"],
)
def test_velocity_and_acceleration_are_the_positions_derivatives(motion):
    t = np.linspace(0.0, 30.0, 61)
    s = motion.state(t)
    v, a = _numeric_derivative(motion, t)
    np.testing.assert_allclose(s[:, 1], v, atol=1e-7)
    np.testing.assert_allclose(s[:, 2], a, atol=2e-4)
    # the engine's packed form gives the same numbers
    np.testing.assert_allclose(base_state(compile_base(motion), t), s, rtol=1e-13, atol=1e-13)


def test_harmonic_is_the_documented_sinusoid():
    t = np.array([0.0, 1.3, 7.9])
    expected = np.array(HARMONIC.amplitude) * np.sin(
        2 * math.pi * np.array(HARMONIC.frequency) * t[:, None] + np.array(HARMONIC.phase)
    )
    np.testing.assert_allclose(HARMONIC.state(t)[:, 0], expected, rtol=1e-14)


def test_sea_state_has_the_significant_wave_height_and_the_jonswap_peak():
    """Hs = 4 sqrt(m0) exactly; the spectrum peaks at 2 pi / Tp; over a long record the
    sample standard deviation of the heave is Hs / 4 (ergodic sum of sinusoids) and the
    seed alone decides the record."""
    sea = SeaStateBase(significant_wave_height=1.5, peak_period=6.0, seed=11)
    amp = sea.parts().waves[:, 1]
    assert 4 * math.sqrt(0.5 * np.sum(amp**2)) == pytest.approx(1.5, rel=1e-12)
    w = np.linspace(0.3, 3.0, 2001)
    assert w[np.argmax(jonswap(w, 1.0, 6.0))] == pytest.approx(2 * math.pi / 6.0, rel=2e-3)
    # the JONSWAP integral is Hs^2 / 16 (DNV's normalisation A_g, within its 1 %)
    w = np.linspace(0.05, 20.0, 200001)
    m0 = np.sum(jonswap(w, 2.0, 8.0)) * (w[1] - w[0])
    assert m0 == pytest.approx(2.0**2 / 16, rel=0.02)
    t = np.arange(0.0, 3600.0, 0.25)
    heave = sea.state(t)[:, 0, 2]
    assert np.std(heave) == pytest.approx(1.5 / 4, rel=0.05)
    assert np.all(sea.state(t[:5])[:, 0, :2] == 0.0)  # no sway, no surge by default
    again = SeaStateBase(significant_wave_height=1.5, peak_period=6.0, seed=11)
    np.testing.assert_array_equal(again.state(t[:100]), sea.state(t[:100]))
    other = SeaStateBase(significant_wave_height=1.5, peak_period=6.0, seed=12)
    assert not np.allclose(other.state(t[:100]), sea.state(t[:100]))


def test_file_motion_reproduces_a_sampled_harmonic_within_the_splines_error(tmp_path):
    """A cubic spline (not-a-knot) through samples every h of a sinusoid of angular
    frequency w errs by about 5/384 h^4 w^4 A in position and h^2 w^4 A / 12 in
    acceleration; the test bounds both by those estimates."""
    h, A, f = 0.05, 0.5, 0.5
    w = 2 * math.pi * f
    motion = HarmonicBase(amplitude=(0, 0, A), frequency=(0, 0, f), phase=(0, 0, 0.3))
    times = np.arange(-0.5, 20.0 + 1e-9, h)
    rows = motion.state(times)[:, 0]
    path = tmp_path / "deck.csv"
    path.write_text(
        "t,n1,n2,n3\n"
        + "".join(
            f"{t:.17g},{r[0]:.17g},{r[1]:.17g},{r[2]:.17g}\n"
            for t, r in zip(times, rows, strict=True)
        )
    )
    track = read_base_csv(path)
    t = np.linspace(0.0, 19.5, 977)
    got, ref = track.state(t), motion.state(t)
    assert np.max(np.abs(got[:, 0] - ref[:, 0])) < 5 / 384 * h**4 * w**4 * A * 1.5
    assert np.max(np.abs(got[:, 2] - ref[:, 2])) < h**2 * w**4 * A / 12 * 1.5
    np.testing.assert_allclose(base_state(compile_base(track), t), got, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("t,x,y,z\n0,0,0,0\n", "header"),
        ("t,n1,n2,n3\n0,0,0,0\n1,0,0,0\n", "at least 4 rows"),
        ("t,n1,n2,n3\n0,0,0,0\n1,0,0,0\n1,0,0,0\n2,0,0,0\n", "row 4.*strictly increasing"),
        ("t,n1,n2,n3\n0,0,0,0\n1,0,0,0\n2,0,0,0\n3,0,0,0\n40,0,0,0\n", "row 6.*gap"),
        ("t,n1,n2,n3\n0.5,0,0,0\n1,0,0,0\n2,0,0,0\n3,0,0,0\n", "first time <= 0"),
        ("t,n1,n2,n3\n0,0,0,0\n1,0,x,0\n2,0,0,0\n3,0,0,0\n", "row 3 column n2.*plain decimal"),
        ("t,n1,n2,n3\n0,0,0,0\n1,0,nan,0\n2,0,0,0\n3,0,0,0\n", "row 3 column n2.*plain decimal"),
        ("t,n1,n2,n3\n0,0,0,0\n1,0,0\n2,0,0,0\n3,0,0,0\n", "row 3 = '3 cells'.*4 plain decimal"),
    ],
)
def test_a_bad_file_is_one_line_naming_the_row(tmp_path, text, match):
    path = tmp_path / "deck.csv"
    path.write_text(text)
    with pytest.raises(ParameterError, match=match) as err:
        read_base_csv(path)
    assert "\n" not in str(err.value) and str(path) in str(err.value)


def test_bad_motion_settings_name_the_key():
    with pytest.raises(ParameterError, match=r"base\.significant_wave_height"):
        SeaStateBase(significant_wave_height=-1.0)
    with pytest.raises(ParameterError, match=r"base\.peak_period"):
        SeaStateBase(peak_period=0.0)
    with pytest.raises(ParameterError, match=r"base\.amplitude"):
        HarmonicBase(amplitude=(-1, 0, 0))
    with pytest.raises(ParameterError, match=r"base\.velocity"):
        VelocityBase(velocity=(1.0, math.inf, 0))


# --- the model over a moving base -----------------------------------------------------------


@pytest.fixture(scope="module")
def moving_tethered():
    return derive("tethered", moving_base=True)


def test_kane_with_a_moving_base_equals_newton_euler(moving_tethered, paper, rng):
    """Issue 26 item 2: Kane's method with the winch on b(t) (coordinates and u1..u3 relative
    to the base, b'' the symbols a1..a3) against the Newton-Euler oracle written in N
    (m (b'' + u') = F), at random states, base accelerations and inputs: 1e-9."""
    d = moving_tethered
    assert len(d.base_acceleration) == 3
    h = paper.helicopter
    values = [getattr(h, name) for name in PARAM_ORDER]
    state = d.state_symbols()
    qdot = sp.lambdify(
        (state, d.inputs, d.wind, d.tension, d.base_acceleration, d.params),
        [d.to_plain(e) for e in (*d.qdot, *d.udot)],
        "numpy",
    )
    ne = NewtonEuler(paper)
    K_C = paper.tether.K_C
    for _ in range(20):
        x = np.empty(13)
        x[:5] = rng.uniform(-0.6, 0.6, 5)
        x[5] = rng.uniform(6.0, 12.0)
        x[6:12] = rng.normal(scale=[1, 1, 1, 2, 2, 2])
        x[12] = x[5] - rng.uniform(0.1, 0.5)
        inp = rng.normal([130, 1, 0.5, 12], [20, 2, 2, 3])
        wind = rng.normal(scale=10, size=3)
        accel = rng.normal(scale=3.0, size=3)
        ref = ne.tethered(x, inp, wind, 0.0, base_acceleration=accel)
        tension = K_C * (x[5] - x[12])  # eq 28, |P - B| = q9 (eq 27), taut
        ours = np.array(qdot(x[:12], inp, wind, tension, accel, values), dtype=float)
        np.testing.assert_allclose(ours, ref[:12], rtol=0, atol=1e-9)


def test_the_numeric_models_take_the_base_acceleration(tethered, free, paper, rng):
    """``derivative(..., base_acceleration=)`` of both models equals the oracle's m (b'' + u')
    = F at random states (1e-12 relative), and a base at rest changes nothing (bit for bit)."""
    ne = NewtonEuler(paper)
    for _ in range(20):
        x = np.empty(13)
        x[:5] = rng.uniform(-0.6, 0.6, 5)
        x[5] = rng.uniform(6.0, 12.0)
        x[6:12] = rng.normal(size=6)
        x[12] = x[5] - 0.3
        inp = rng.normal([130, 1, 0.5, 12], [20, 2, 2, 3])
        wind, accel = rng.normal(scale=10, size=3), rng.normal(scale=3.0, size=3)
        ref = ne.tethered(x, inp, wind, 0.2, base_acceleration=accel)
        ours = tethered.derivative(x, inp, wind, 0.2, base_acceleration=accel)
        scale = np.maximum(np.abs(ref), 1.0)
        np.testing.assert_allclose(ours / scale, ref / scale, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(
            tethered.derivative(x, inp, wind, 0.2, base_acceleration=(0, 0, 0)),
            tethered.derivative(x, inp, wind, 0.2),
        )
        xf = np.concatenate([rng.normal(size=3), x[:3], x[6:12]])
        ref = ne.free(xf, inp, wind, base_acceleration=accel)
        scale = np.maximum(np.abs(ref), 1.0)
        got = free.derivative(xf, inp, wind, base_acceleration=accel)
        np.testing.assert_allclose(got / scale, ref / scale, rtol=0, atol=1e-12)


def test_the_linearizations_base_input_is_the_finite_difference_jacobian(tethered, free):
    """``LinearModel.E_base`` (the columns ab1..ab3 of ``to_statespace``) equals the central
    finite difference of ``derivative`` in the base's acceleration at trim."""
    for model, trim in ((tethered, tethered.trim(25.0, 10.0)), (free, free.trim())):
        lin = linearize(model, trim)
        x0, u0 = np.asarray(trim.x), trim.u_total
        fd = np.empty_like(lin.E_base)
        for j in range(3):
            e = np.zeros(3)
            e[j] = 1e-4
            fd[:, j] = (model.derivative(x0, u0, base_acceleration=e)
                        - model.derivative(x0, u0, base_acceleration=-e)) / 2e-4  # fmt: skip
        np.testing.assert_allclose(lin.E_base, fd, rtol=1e-7, atol=1e-9)
        assert np.abs(lin.E_base).max() > 0.5
        np.testing.assert_array_equal(lin.input_matrix(("ab1", "ab2", "ab3")), lin.E_base)
