"""Tests of the ground winch's PI tension controller (paper Sec. V-B, eq 56).

Plant: the helicopter held fixed (q9 constant) and the tether taut, so T_C = K_C (q9 - L_N)
(eq 28) and dL_N/dt = R_C (eq 37) give dT_C/dt = -K_C R_C. With the paper's K_C = 40 N/m
(Table III), K_P = 1 and K_I = 0.1 (Sec. V-B) the continuous loop on e = T_C - T_ref is

    w'' + K_C K_P w' + K_C K_I w = 0,   w = int e dt,  w(0) = 0,  w'(0) = e0,

with roots s1 ~ -0.1003 1/s and s2 ~ -39.90 1/s, so
e(t) = e0 (s1 e^{s1 t} - s2 e^{s2 t}) / (s1 - s2): a fast drop by the proportional action,
a small undershoot, and a slow (10 s) first-order-like return to the reference.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tetherheli.control.tension import TensionPI, tension_pi_step
from tetherheli.params import Params

K_C = 40.0  # N/m, Table III
Q9 = 10.0  # m, trim (Table IV)
L_N0 = 9.375  # m, trim natural length: T_C = K_C (Q9 - L_N0) = 25 N


def _simulate(
    pi: TensionPI, q9: float, duration: float, *, naive: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sample-and-hold loop: T_k from eq 28 (pulls only), (R_k, I_k+1) from the controller,
    L_N advanced exactly over one sample with R_k held (eq 37).

    ``naive`` replaces the controller by a clamped PI that always integrates (no anti-windup).
    Returns tension (N + 1,) [N], rate (N,) [m/s] and integral (N + 1,) [N s].
    """
    steps = round(duration / pi.dt)
    tension = np.empty(steps + 1)
    rate = np.empty(steps)
    integral = np.empty(steps + 1)
    L_N, acc = L_N0, 0.0
    for k in range(steps):
        integral[k] = acc
        tension[k] = K_C * max(q9 - L_N, 0.0)
        if naive:
            error = tension[k] - pi.T_ref
            v = pi.K_P * error + pi.K_I * acc
            rate[k] = min(max(v, -pi.rate_limit), pi.rate_limit)
            acc += pi.dt * error
        else:
            rate[k], acc = pi.step(acc, tension[k])
        L_N += pi.dt * rate[k]
    integral[steps] = acc
    tension[steps] = K_C * max(q9 - L_N, 0.0)
    return tension, rate, integral


def _continuous_error(t: np.ndarray, e0: float, K_P: float, K_I: float) -> np.ndarray:
    s2, s1 = np.sort(np.roots([1.0, K_C * K_P, K_C * K_I]).real)  # s2 < s1 < 0
    return e0 * (s1 * np.exp(s1 * t) - s2 * np.exp(s2 * t)) / (s1 - s2)


@pytest.fixture
def paper_pi() -> TensionPI:
    return TensionPI.from_params(Params.paper().tension_control, dt=0.001)


def test_paper_gains_and_sign(paper_pi: TensionPI) -> None:
    """eq 56 with K_P = 1, K_I = 0.1, T_ref = 25 N: a tension above the reference reels out
    (R_C > 0, eq 37), below it reels in; at the reference with I = 0 the rate is zero."""
    assert (paper_pi.K_P, paper_pi.K_I, paper_pi.T_ref) == (1.0, 0.1, 25.0)
    rate, integral = paper_pi.step(0.0, 29.0)
    assert rate == pytest.approx(4.0) and integral == pytest.approx(0.004)
    rate, integral = paper_pi.step(2.0, 21.0)
    assert rate == pytest.approx(-4.0 + 0.1 * 2.0) and integral == pytest.approx(2.0 - 0.004)
    assert paper_pi.step(0.0, 25.0) == (0.0, 0.0)


def test_discrete_loop_is_exact_recursion(paper_pi: TensionPI) -> None:
    """eq 56 discretised: with R held over each sample the plant dT/dt = -K_C R_C is exact,
    so [e; I]_{k+1} = [[1 - K_C K_P dt, -K_C K_I dt], [dt, 1]] [e; I]_k; the simulated loop
    equals the matrix powers to 1e-12 relative."""
    dt, e0 = paper_pi.dt, 4.0
    tension, _, integral = _simulate(paper_pi, Q9 + e0 / K_C, 5.0)
    M = np.array([[1.0 - K_C * paper_pi.K_P * dt, -K_C * paper_pi.K_I * dt], [dt, 1.0]])
    state = np.array([e0, 0.0])
    expected = np.empty((len(tension), 2))
    for k in range(len(tension)):
        expected[k] = state
        state = M @ state
    np.testing.assert_allclose(tension - paper_pi.T_ref, expected[:, 0], rtol=0, atol=1e-12 * e0)
    np.testing.assert_allclose(integral, expected[:, 1], rtol=0, atol=1e-12 * e0)


def test_step_in_q9_matches_continuous_solution(paper_pi: TensionPI) -> None:
    """eq 56 + eqs 28, 37: after a 0.1 m step in q9 (T_C jumps 25 -> 29 N) the sampled loop
    at dt = 1 ms follows the analytic solution of s^2 + K_C K_P s + K_C K_I = 0 to within
    1 % of the step, returns to T_ref (first-order-like, 10 s time constant), and keeps the
    tether taut."""
    e0 = 4.0
    tension, rate, _ = _simulate(paper_pi, Q9 + e0 / K_C, 60.0)
    t = np.arange(len(tension)) * paper_pi.dt
    analytic = _continuous_error(t, e0, paper_pi.K_P, paper_pi.K_I)
    error = np.max(np.abs(tension - paper_pi.T_ref - analytic))
    assert error < 0.01 * e0  # measured ~0.030 N (0.75 % of the step)
    assert np.min(tension) > 0.0
    assert rate[0] > 0.0  # too much tension: reel out
    assert abs(tension[-1] - paper_pi.T_ref) < 1e-4  # analytic: 2.5e-5 N at 60 s
    # first-order-like: the slow pole s1 ~ -0.1 dominates after the fast transient
    late = t > 5.0
    slope = np.polyfit(t[late], np.log(np.abs(tension[late] - paper_pi.T_ref)), 1)[0]
    assert slope == pytest.approx(-0.10025, rel=1e-2)


def test_discretisation_error_is_first_order() -> None:
    """eq 56 discretised: the gap to the continuous solution halves with dt (order 1, from
    the sample-and-hold of R_C and the forward-Euler integral)."""
    gaps = []
    for dt in (0.002, 0.001, 0.0005):
        pi = TensionPI(K_P=1.0, K_I=0.1, T_ref=25.0, dt=dt)
        tension, _, _ = _simulate(pi, Q9 + 0.1, 10.0)
        t = np.arange(len(tension)) * dt
        gaps.append(np.max(np.abs(tension - 25.0 - _continuous_error(t, 4.0, 1.0, 0.1))))
    orders = np.log2(np.array(gaps[:-1]) / np.array(gaps[1:]))
    np.testing.assert_allclose(orders, 1.0, atol=0.05)


def test_anti_windup_holds_integral_in_saturation() -> None:
    """eq 56 with |R_C| <= rate_limit: while saturated the integral is held if the error
    pushes further into saturation, and integrates if it pulls out of it."""
    pi = TensionPI(K_P=1.0, K_I=0.1, T_ref=25.0, dt=0.01, rate_limit=0.5)
    assert pi.step(3.0, 30.0) == (0.5, 3.0)  # v = 5.3 > 0.5, e > 0: held
    assert pi.step(-3.0, 20.0) == (-0.5, -3.0)  # v = -5.3 < -0.5, e < 0: held
    rate, integral = pi.step(100.0, 24.0)  # v = 9 > 0.5 but e = -1 < 0: integrates
    assert rate == 0.5 and integral == pytest.approx(100.0 - 0.01)
    rate, integral = pi.step(0.0, 25.2)  # unsaturated
    assert rate == pytest.approx(0.2) and integral == pytest.approx(0.002)


def test_anti_windup_prevents_undershoot() -> None:
    """eq 56 with a reel-rate limit of 5 cm/s and a 0.25 m step in q9 (T_C 25 -> 35 N): the
    rate stays within the limit, the held integral gives no undershoot and the tension
    settles at T_ref; a clamped PI that keeps integrating winds up and undershoots by > 1 N."""
    pi = TensionPI(K_P=1.0, K_I=0.1, T_ref=25.0, dt=0.001, rate_limit=0.05)
    tension, rate, integral = _simulate(pi, Q9 + 0.25, 60.0)
    assert np.max(np.abs(rate)) <= 0.05
    saturated = np.abs(rate) == 0.05
    assert saturated[:4000].all()  # 0.25 m at 5 cm/s: about 5 s of saturation
    assert np.all(integral[1:4000] == 0.0)  # held throughout
    assert np.min(tension) > pi.T_ref - 0.01
    assert abs(tension[-1] - pi.T_ref) < 1e-5

    naive, naive_rate, _ = _simulate(pi, Q9 + 0.25, 60.0, naive=True)
    assert np.max(np.abs(naive_rate)) <= 0.05
    assert np.min(naive) < pi.T_ref - 1.0


def test_no_limit_equals_plain_pi(paper_pi: TensionPI) -> None:
    """eq 56: with the default rate_limit = inf the law is R = K_P e + K_I I, I+ = I + dt e."""
    assert math.isinf(paper_pi.rate_limit)
    rng = np.random.default_rng(3)
    for integral, tension in rng.normal(0.0, 1e4, size=(50, 2)):
        rate, new = paper_pi.step(integral, tension)
        assert rate == pytest.approx((tension - 25.0) + 0.1 * integral, rel=1e-14)
        assert new == pytest.approx(integral + 0.001 * (tension - 25.0), rel=1e-14, abs=1e-12)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("K_P", -1.0),
        ("K_P", math.nan),
        ("K_I", -0.1),
        ("K_I", math.inf),
        ("T_ref", -1.0),
        ("T_ref", math.nan),
        ("dt", 0.0),
        ("dt", -0.001),
        ("dt", math.inf),
        ("rate_limit", 0.0),
        ("rate_limit", -1.0),
        ("rate_limit", math.nan),
        ("K_P", "1"),
        ("dt", True),
    ],
)
def test_bad_configuration(field: str, value: object) -> None:
    """eq 56's gains, reference and sample time are validated: one-line ValueError naming the
    field."""
    kwargs: dict[str, object] = dict(K_P=1.0, K_I=0.1, T_ref=25.0, dt=0.001)
    kwargs[field] = value
    with pytest.raises(ValueError, match=rf"^{field} = ") as info:
        TensionPI(**kwargs)  # type: ignore[arg-type]
    assert "\n" not in str(info.value)


def test_zero_gains_and_reference_allowed() -> None:
    """eq 56 with K_P = K_I = 0 and T_ref = 0 is a valid (inactive) controller."""
    pi = TensionPI(K_P=0.0, K_I=0.0, T_ref=0.0, dt=0.01)
    assert pi.step(0.0, 10.0) == (0.0, 0.1)


def test_numba_compiled_core_matches_python() -> None:
    """eq 56: the scalar core compiled with Numba (as the closed-loop kernel uses it) gives
    bit-identical results to the Python version, saturated and unsaturated."""
    from numba import njit

    compiled = njit(tension_pi_step)
    rng = np.random.default_rng(5)
    for integral, tension in rng.normal([0.0, 25.0], [50.0, 10.0], size=(200, 2)):
        for limit in (0.5, math.inf):
            args = (float(integral), float(tension), 1.0, 0.1, 25.0, 0.001, limit)
            assert compiled(*args) == tension_pi_step(*args)
