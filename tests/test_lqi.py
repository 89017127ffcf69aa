"""Tests of the discrete LQI design (paper Sec. V-A, eqs 46-53) and of the ZOH discretisation.

Two test plants are built here, independent of the helicopter model:

* ``random_plant``: a random continuous system (fixed seed) with n = 6, m = 2, p = 2 that has
  unstable open-loop modes, ZOH-discretised at dt = 0.05 s;
* ``hover_plant``: the linearised hover of a rigid body with the helicopter's sizes
  (n = 12: position, roll/pitch/yaw, their rates; m = 4: thrust and three torques; p = 4:
  position and yaw), ZOH-discretised at dt = 0.01 s and weighted with the paper's Qy and Ru.
"""

from __future__ import annotations

import math

import control
import numpy as np
import pytest
from scipy.signal import cont2discrete

from tetherheli.control.lqi import (
    PAPER_QY,
    PAPER_RU,
    LQIGain,
    augment_lqi,
    design_lqi,
    discretize_zoh,
)

# --------------------------------------------------------------------------------------------
# test plants and an independent Riccati solver
# --------------------------------------------------------------------------------------------


def _random_continuous(seed: int = 7) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(6, 6))
    B = rng.normal(size=(6, 2))
    C = rng.normal(size=(2, 6))
    return A, B, C


def _hover_continuous() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linearised hover: x = [p1, p2, p3, roll, pitch, yaw, v1, v2, v3, w1, w2, w3]."""
    g, mass, inertia = 9.81, 12.67, (0.83, 1.23, 1.46)
    A = np.zeros((12, 12))
    A[0:3, 6:9] = np.eye(3)
    A[3:6, 9:12] = np.eye(3)
    A[6, 4] = g  # pitch tilts thrust along +1
    A[7, 3] = -g  # roll tilts thrust along -2
    A[6, 9] = 0.05  # a little coupling, so the axes are not decoupled copies
    B = np.zeros((12, 4))
    B[8, 0] = -1.0 / mass  # z down: thrust accelerates along -3
    B[9, 1] = 1.0 / inertia[0]
    B[10, 2] = 1.0 / inertia[1]
    B[11, 3] = 1.0 / inertia[2]
    B[9, 3] = 0.1 / inertia[0]  # tail-rotor force also rolls the body
    C = np.zeros((4, 12))
    C[0, 0] = C[1, 1] = C[2, 2] = C[3, 5] = 1.0
    return A, B, C


@pytest.fixture(scope="module")
def random_plant() -> dict:
    A, B, C = _random_continuous()
    dt = 0.05
    G, H = discretize_zoh(A, B, dt)
    Qy = np.diag([1.0, 2.0, 10.0, 5.0])
    Ru = np.array([[1.0, 0.2], [0.2, 0.5]])
    return dict(A=A, B=B, C=C, G=G, H=H, dt=dt, Qy=Qy, Ru=Ru)


@pytest.fixture(scope="module")
def hover_plant() -> dict:
    A, B, C = _hover_continuous()
    dt = 0.01
    G, H = discretize_zoh(A, B, dt)
    return dict(A=A, B=B, C=C, G=G, H=H, dt=dt, Qy=PAPER_QY, Ru=PAPER_RU)


PLANTS = ["random_plant", "hover_plant"]


def _design(plant: dict) -> LQIGain:
    return design_lqi(
        plant["G"], plant["H"], plant["C"], plant["dt"], Qy=plant["Qy"], Ru=plant["Ru"]
    )


def _relerr(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def _riccati_value_iteration(
    G: np.ndarray, H: np.ndarray, Q: np.ndarray, R: np.ndarray, *, tol: float = 1e-14
) -> np.ndarray:
    """Iterate the Riccati difference equation from P = 0 until it stops changing.

    P_{j+1} = G' P_j G - G' P_j H (R + H' P_j H)^{-1} H' P_j G + Q: the cost-to-go of the
    finite-horizon problem, which converges to the DARE's stabilising solution (eq 49).
    """
    P = np.zeros_like(Q)
    for _ in range(500_000):
        HtP = H.T @ P
        HtPG = HtP @ G
        P_next = G.T @ P @ G - HtPG.T @ np.linalg.solve(R + HtP @ H, HtPG) + Q
        P_next = 0.5 * (P_next + P_next.T)  # suppress the drift of round-off asymmetry
        if np.max(np.abs(P_next - P)) <= tol * np.max(np.abs(P_next)):
            return P_next
        P = P_next
    raise AssertionError("Riccati value iteration did not converge")


# --------------------------------------------------------------------------------------------
# discretize_zoh
# --------------------------------------------------------------------------------------------


def test_discretize_zoh_matches_scipy_cont2discrete(random_plant: dict) -> None:
    """eq 46: G, H equal scipy.signal.cont2discrete(method='zoh') to 1e-12 relative."""
    A, B, C, dt = random_plant["A"], random_plant["B"], random_plant["C"], random_plant["dt"]
    G, H = discretize_zoh(A, B, dt)
    Gs, Hs, *_ = cont2discrete((A, B, C, np.zeros((2, 2))), dt, method="zoh")
    assert _relerr(G, Gs) < 1e-12
    assert _relerr(H, Hs) < 1e-12


def test_discretize_zoh_matches_eigendecomposition(random_plant: dict) -> None:
    """eq 46 without a matrix exponential: for A = V diag(l) V^-1 (the random A is
    diagonalisable, no zero eigenvalue), G = V diag(e^{l dt}) V^-1 and
    H = V diag((e^{l dt} - 1) / l) V^-1 B. (cont2discrete uses the same block-exponential
    route as ours and agrees bitwise; this route shares nothing with it.)"""
    A, B, dt = random_plant["A"], random_plant["B"], random_plant["dt"]
    lam, V = np.linalg.eig(A)
    Vinv = np.linalg.inv(V)
    G_eig = (V @ np.diag(np.exp(lam * dt)) @ Vinv).real
    H_eig = (V @ np.diag(np.expm1(lam * dt) / lam) @ Vinv @ B).real
    G, H = discretize_zoh(A, B, dt)
    assert _relerr(G, G_eig) < 1e-12
    assert _relerr(H, H_eig) < 1e-12


def test_discretize_zoh_scalar_closed_form() -> None:
    """eq 46 for x' = a x + b u: G = e^{a dt}, H = (e^{a dt} - 1) b / a."""
    for a in (-3.0, 0.7):
        b, dt = 2.5, 0.02
        G, H = discretize_zoh([[a]], [[b]], dt)
        assert G.shape == (1, 1) and H.shape == (1, 1)
        assert G[0, 0] == pytest.approx(math.exp(a * dt), rel=1e-14)
        assert H[0, 0] == pytest.approx(math.expm1(a * dt) / a * b, rel=1e-13)


def test_discretize_zoh_double_integrator_closed_form() -> None:
    """eq 46 for a double integrator (singular A): G = [[1, dt], [0, 1]], H = [dt^2/2, dt]."""
    dt = 0.1
    G, H = discretize_zoh([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], dt)
    np.testing.assert_allclose(G, [[1.0, dt], [0.0, 1.0]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(H, [[dt**2 / 2], [dt]], rtol=1e-14, atol=0)


# --------------------------------------------------------------------------------------------
# the augmented system and the gain
# --------------------------------------------------------------------------------------------


def test_augmented_system_blocks(random_plant: dict) -> None:
    """eq 53: G_LQI = [[G, 0], [-dt C, I]], H_LQI = [[H], [0]], C_LQI = [[C, 0], [0, I]]."""
    G, H, C, dt = (random_plant[k] for k in ("G", "H", "C", "dt"))
    G_lqi, H_lqi, C_lqi = augment_lqi(G, H, C, dt)
    n, p = 6, 2
    np.testing.assert_array_equal(G_lqi[:n, :n], G)
    np.testing.assert_array_equal(G_lqi[:n, n:], 0.0)
    np.testing.assert_array_equal(G_lqi[n:, :n], -dt * C)
    np.testing.assert_array_equal(G_lqi[n:, n:], np.eye(p))
    np.testing.assert_array_equal(H_lqi, np.vstack([H, np.zeros((p, 2))]))
    np.testing.assert_array_equal(
        C_lqi, np.block([[C, np.zeros((p, p))], [np.zeros((p, n)), np.eye(p)]])
    )
    # eq 50 as one step of the augmented system with r = 0:
    rng = np.random.default_rng(1)
    x, z, u = rng.normal(size=n), rng.normal(size=p), rng.normal(size=2)
    nxt = G_lqi @ np.concatenate([x, z]) + H_lqi @ u
    np.testing.assert_allclose(nxt[n:], z + dt * (0.0 - C @ x), rtol=1e-14, atol=1e-15)


@pytest.mark.parametrize("plant_name", PLANTS)
def test_gain_equals_riccati_value_iteration(
    plant_name: str, request: pytest.FixtureRequest
) -> None:
    """eqs 48-49 on eq 53: K from the DARE equals K from iterating the Riccati difference
    equation to convergence (no solve_discrete_are involved), to 1e-8 relative."""
    plant = request.getfixturevalue(plant_name)
    gain = _design(plant)
    G_lqi, H_lqi, C_lqi = augment_lqi(plant["G"], plant["H"], plant["C"], plant["dt"])
    Q = C_lqi.T @ plant["Qy"] @ C_lqi
    R = np.asarray(plant["Ru"])
    P = _riccati_value_iteration(G_lqi, H_lqi, Q, R)
    K = np.linalg.solve(R + H_lqi.T @ P @ H_lqi, H_lqi.T @ P @ G_lqi)
    assert _relerr(gain.K, K) < 1e-8
    assert _relerr(gain.P, P) < 1e-8


@pytest.mark.parametrize("plant_name", PLANTS)
def test_gain_equals_python_control_dlqr(plant_name: str, request: pytest.FixtureRequest) -> None:
    """eqs 47-53: control.dlqr on the hand-built (G_LQI, H_LQI) with Q = C_LQI' Qy C_LQI and
    R = Ru gives the same K (1e-10 relative)."""
    plant = request.getfixturevalue(plant_name)
    gain = _design(plant)
    G_lqi, H_lqi, C_lqi = augment_lqi(plant["G"], plant["H"], plant["C"], plant["dt"])
    K, _, E = control.dlqr(G_lqi, H_lqi, C_lqi.T @ plant["Qy"] @ C_lqi, plant["Ru"])
    assert _relerr(gain.K, K) < 1e-10
    assert np.max(np.abs(E)) == pytest.approx(gain.spectral_radius, rel=1e-9)


@pytest.mark.parametrize("plant_name", PLANTS)
def test_python_control_integral_action_minus_dt_C_is_the_paper(
    plant_name: str, request: pytest.FixtureRequest
) -> None:
    """eq 50/53: dlqr(G, H, Q, R, integral_action=M) augments with z+ = z + M x; with
    M = -dt C that is the paper's T = -dt C, and K equals ours (1e-10 relative)."""
    plant = request.getfixturevalue(plant_name)
    gain = _design(plant)
    G, H, C, dt = (plant[k] for k in ("G", "H", "C", "dt"))
    _, _, C_lqi = augment_lqi(G, H, C, dt)
    Q = C_lqi.T @ plant["Qy"] @ C_lqi
    K, _, _ = control.dlqr(G, H, Q, plant["Ru"], integral_action=-dt * C)
    assert _relerr(gain.K, K) < 1e-10


@pytest.mark.parametrize("plant_name", PLANTS)
def test_python_control_integral_action_C_is_a_rescaled_integrator(
    plant_name: str, request: pytest.FixtureRequest
) -> None:
    """eq 50: python-control's natural choice integral_action = C builds w+ = w + C x, so
    z = -dt w. With the same Q its gain is not the paper's; with Q's integrator block scaled
    by dt^2 (the paper's cost in w) it is, up to the change of variable: Kx equal,
    Kw = -dt Kz."""
    plant = request.getfixturevalue(plant_name)
    gain = _design(plant)
    G, H, C, dt = (plant[k] for k in ("G", "H", "C", "dt"))
    n, p = gain.n, gain.p
    _, _, C_lqi = augment_lqi(G, H, C, dt)
    Q = C_lqi.T @ plant["Qy"] @ C_lqi

    K_same_q, _, _ = control.dlqr(G, H, Q, plant["Ru"], integral_action=C)
    assert _relerr(K_same_q[:, :n], gain.Kx) > 1e-2  # a different design, not just rescaled
    assert _relerr(K_same_q[:, n:], -dt * gain.Kz) > 1e-2

    S = np.diag(np.concatenate([np.ones(n), np.full(p, -dt)]))  # [x; z] = S [x; w]
    K_scaled, _, _ = control.dlqr(G, H, S.T @ Q @ S, plant["Ru"], integral_action=C)
    assert _relerr(K_scaled[:, :n], gain.Kx) < 1e-9
    assert _relerr(K_scaled[:, n:], -dt * gain.Kz) < 1e-9
    assert _relerr(K_scaled, gain.K @ S) < 1e-9


@pytest.mark.parametrize("plant_name", PLANTS)
def test_loop_decays_at_the_reported_spectral_radius(
    plant_name: str, request: pytest.FixtureRequest
) -> None:
    """eqs 48, 50, 53: the loop run as the controller runs it (plant G, H, C; u = -Kx x - Kz z
    from ``control``; z+ = z + dt (r - y) from ``integrate``; not the matrix G_LQI - H_LQI K)
    decays at the rate of ``spectral_radius``: the slope of log |[x; z]| over the second half
    of a run long enough to lose ten decades equals log(rho) within 5 %. (That rho < 1 needs
    no test: design_lqi raises otherwise.)"""
    plant = request.getfixturevalue(plant_name)
    gain = _design(plant)
    G, H, C = plant["G"], plant["H"], plant["C"]
    assert np.max(np.abs(np.linalg.eigvals(gain.G_lqi))) >= 1.0 - 1e-12  # integrators
    rho = gain.spectral_radius
    steps = math.ceil(math.log(1e-10) / math.log(rho))
    rng = np.random.default_rng(2)
    x, z, r = rng.normal(size=gain.n), rng.normal(size=gain.p), np.zeros(gain.p)
    log_norm = np.empty(steps)
    for k in range(steps):
        log_norm[k] = math.log(np.linalg.norm(np.concatenate([x, z])))
        x, z = G @ x + H @ gain.control(x, z), gain.integrate(z, r, C @ x)
    half = steps // 2
    rate = (log_norm[-1] - log_norm[half]) / (steps - 1 - half)
    assert rate == pytest.approx(math.log(rho), rel=0.05)


def test_random_plant_is_open_loop_unstable(random_plant: dict) -> None:
    """The random test plant is a meaningful stabilisation problem: G has a mode outside the
    unit circle (so eq 48's gain must stabilise, not merely damp)."""
    assert np.max(np.abs(np.linalg.eigvals(random_plant["G"]))) > 1.0


def test_paper_defaults_and_gain_record(hover_plant: dict) -> None:
    """Sec. V-A after eq 53: Qy = diag(1,1,1,1,10,10,10,10), Ru = I4 are the defaults for
    p = m = 4; the gain has shape (m, n + p) = (4, 16) and its blocks and record agree."""
    np.testing.assert_array_equal(np.diag(PAPER_QY), [1, 1, 1, 1, 10, 10, 10, 10])
    np.testing.assert_array_equal(PAPER_RU, np.eye(4))
    gain = design_lqi(hover_plant["G"], hover_plant["H"], hover_plant["C"], hover_plant["dt"])
    assert (gain.n, gain.m, gain.p) == (12, 4, 4)
    assert gain.K.shape == (4, 16) and gain.Kx.shape == (4, 12) and gain.Kz.shape == (4, 4)
    np.testing.assert_array_equal(np.hstack([gain.Kx, gain.Kz]), gain.K)
    np.testing.assert_array_equal(gain.Qy, PAPER_QY)
    record = gain.as_dict()
    assert record["dt"] == hover_plant["dt"]
    assert np.array_equal(np.array(record["K"]), gain.K)
    assert record["spectral_radius"] == gain.spectral_radius < 1.0
    with pytest.raises(ValueError, match="read-only"):
        gain.K[0, 0] = 1.0
    x, z = np.arange(12.0), np.arange(4.0)
    np.testing.assert_allclose(gain.control(x, z), -gain.K @ np.concatenate([x, z]), rtol=1e-14)


def test_eq49_residual_and_eq48_optimality(random_plant: dict) -> None:
    """eq 49: P is symmetric positive definite and satisfies the DARE to round-off; eq 48:
    K = (Ru + H' P H)^{-1} H' P G."""
    gain = _design(random_plant)
    G, H, P, R = gain.G_lqi, gain.H_lqi, gain.P, gain.Ru
    _, _, C_lqi = augment_lqi(random_plant["G"], random_plant["H"], random_plant["C"], gain.dt)
    Q = C_lqi.T @ gain.Qy @ C_lqi
    residual = G.T @ P @ G - G.T @ P @ H @ np.linalg.solve(R + H.T @ P @ H, H.T @ P @ G) + Q - P
    assert np.max(np.abs(residual)) < 1e-9 * np.max(np.abs(P))
    assert np.min(np.linalg.eigvalsh(P)) > 0.0
    np.testing.assert_allclose(gain.K, np.linalg.solve(R + H.T @ P @ H, H.T @ P @ G), rtol=1e-12)


# --------------------------------------------------------------------------------------------
# zero steady-state error (the purpose of eq 50)
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("plant_name", PLANTS)
def test_zero_steady_state_error_under_constant_disturbances(
    plant_name: str, request: pytest.FixtureRequest
) -> None:
    """eqs 50-53: with u = -Kx x - Kz z, the integrators of eq 50 drive y to a constant
    reference r despite a constant input disturbance d and a constant output (sensor) offset
    w: x+ = G x + H (u + d), y = C x + w, z+ = z + dt (r - y)."""
    plant = request.getfixturevalue(plant_name)
    gain = _design(plant)
    G, H, C = plant["G"], plant["H"], plant["C"]
    n, m, p = gain.n, gain.m, gain.p
    rng = np.random.default_rng(11)
    d, w, r = rng.normal(size=m), 0.1 * rng.normal(size=p), rng.normal(size=p)
    steps = math.ceil(math.log(1e-13) / math.log(gain.spectral_radius))
    x, z = np.zeros(n), np.zeros(p)
    for _ in range(steps):
        y = C @ x + w
        u = gain.control(x, z)
        x, z = G @ x + H @ (u + d), gain.integrate(z, r, y)
    y = C @ x + w
    assert np.max(np.abs(y - r)) < 1e-8 * max(1.0, float(np.max(np.abs(r))))
    # without the integrators (Kz = 0) the same loop keeps an offset:
    x = np.zeros(n)
    for _ in range(steps):
        x = G @ x + H @ (-(gain.Kx @ x) + d)
    assert np.max(np.abs(C @ x + w - r)) > 1e-3


# --------------------------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("dt", [0.0, -0.01, math.nan, math.inf, "0.01", True])
def test_bad_dt(dt: object, random_plant: dict) -> None:
    """eq 46/50: dt must be a finite number > 0 (one-line ValueError naming dt)."""
    with pytest.raises(ValueError, match=r"^dt = ") as info:
        discretize_zoh(random_plant["A"], random_plant["B"], dt)  # type: ignore[arg-type]
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match=r"^dt = "):
        design_lqi(
            random_plant["G"],
            random_plant["H"],
            random_plant["C"],
            dt,
            Qy=random_plant["Qy"],
            Ru=random_plant["Ru"],
        )  # type: ignore[arg-type]


def test_bad_shapes_and_values(random_plant: dict) -> None:
    """eqs 46-53: shape, finiteness, symmetry and definiteness errors name the argument."""
    G, H, C, dt, Qy, Ru = (random_plant[k] for k in ("G", "H", "C", "dt", "Qy", "Ru"))
    cases = [
        (dict(A=np.ones((2, 3)), B=np.ones((2, 1))), discretize_zoh, "^A "),
        (dict(A=np.eye(2), B=np.ones((3, 1))), discretize_zoh, "^B "),
        (dict(A=[[math.nan]], B=[[1.0]]), discretize_zoh, "^A has non-finite"),
    ]
    for kwargs, func, pattern in cases:
        with pytest.raises(ValueError, match=pattern):
            func(dt=dt, **kwargs)

    def design(**over: object) -> LQIGain:
        args = dict(G=G, H=H, C=C, dt=dt, Qy=Qy, Ru=Ru) | over
        return design_lqi(args.pop("G"), args.pop("H"), args.pop("C"), args.pop("dt"), **args)

    bad = [
        (dict(G=G[:, :5]), "^G has shape"),
        (dict(H=H[:5]), "^H has shape"),
        (dict(C=C[:, :5]), "^C has shape"),
        (dict(G=np.where(np.eye(6) > 0, math.inf, G)), "^G has non-finite"),
        (dict(Qy=np.eye(3)), "^Qy has shape"),
        (dict(Qy=np.diag([1.0, 1.0, -1.0, 1.0])), "^Qy has eigenvalue"),
        (dict(Qy=np.triu(np.ones((4, 4)))), "^Qy is not symmetric"),
        (dict(Ru=np.eye(3)), "^Ru has shape"),
        (dict(Ru=np.diag([1.0, 0.0])), "^Ru has eigenvalue"),
        (dict(Ru=[[1.0, 2.0], [0.0, 1.0]]), "^Ru is not symmetric"),
        (dict(Qy=None), "^Qy is required when p = 2"),
        (dict(Ru=None), "^Ru is required when m = 2"),
    ]
    for over, pattern in bad:
        with pytest.raises(ValueError, match=pattern) as info:
            design(**over)
        assert "\n" not in str(info.value)


def test_not_stabilisable_raises(random_plant: dict) -> None:
    """eq 49: with H = 0 the unstable random plant cannot be stabilised, so the DARE has no
    stabilising solution and design_lqi raises a ValueError saying so."""
    G, C, dt, Qy, Ru = (random_plant[k] for k in ("G", "C", "dt", "Qy", "Ru"))
    with pytest.raises(ValueError, match="stabilis") as info:
        design_lqi(G, np.zeros((6, 2)), C, dt, Qy=Qy, Ru=Ru)
    assert "\n" not in str(info.value)
