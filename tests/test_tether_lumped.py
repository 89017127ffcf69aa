"""The lumped-mass tether (tether.lumped) against independent routes: Irvine's elastic
catenary (Cable Structures, MIT Press 1981, ch. 2), the wave speeds of a taut string and rod
(e.g. Graff, Wave Motion in Elastic Solids, ch. 1-2), energy conservation, SciPy's adaptive
integrators (Radau, DOP853), and for the coupling the tethered model (eq 28) and the
Newton-Euler route of tests/newton_euler.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tetherheli import ParameterError, TetheredHelicopter
from tetherheli.layout import LUMPED_CDN, LUMPED_CDT, LUMPED_G
from tetherheli.model import kernels
from tetherheli.tether import lumped as tl
from tetherheli.tether.catenary import (
    catenary_position_estimate,
    elastic_catenary,
    initial_chain,
    static_cable,
    straight_tether_estimates,
)
from tetherheli.tether.chain import LumpedTether, chain_energy, end_forces, static_chain
from tetherheli.tether.coupling import tethered_derivative_force_at_P
from tetherheli.tether.lumped_trim import hover_trim_lumped

from .newton_euler import NewtonEuler, dcm_table_i

G = 9.81
MU = 0.02  # the paper-scale cable [kg/m] (probes.md)


def _tether(n: int, **kw) -> LumpedTether:
    """The airborne cable: no ground (``ground_stiffness_Pa_m = 0``; the shapes and modes
    here pass below the winch's level, z = 0; tests/test_tether_ground.py has the ground)."""
    base = dict(segments=n, mass_per_length_kg_m=MU, EA_N=375.0, damping_ratio=0.0,
                ground_stiffness_Pa_m=0.0)  # fmt: skip
    base.update(kw)
    return LumpedTether(**base)


def _forces(x, v, wind, L0, p):
    n = x.shape[0] - 1
    F = np.empty((n + 1, 3))
    T = np.empty(n)
    blocks = [np.empty((n, 3, 3)) for _ in range(3)]
    tl.chain_forces(x, v, wind, L0, p, F, T, tuple(blocks), False)
    return F, T


# (span a, rise b, unstretched length L0) [m]: a near-vertical paper-like tether (q9 = 10 m,
# L0N = 9.375 m, P 2 m off the vertical), a sagging 10 m cable and a sagging 35 m cable
GEOMETRIES = [(2.0, 9.8, 9.375), (6.0, 7.0, 10.0), (30.0, 5.0, 35.0)]
#: the largest node-position error [m] at N = 20 against the catenary, per geometry (measured:
#: 2.9e-8, 2.8e-3, 9.8e-3 m)
SHAPE_TOL_N20 = [1e-7, 4e-3, 1.5e-2]


@pytest.mark.parametrize(("geometry", "tol20"), list(zip(GEOMETRIES, SHAPE_TOL_N20, strict=True)))
def test_static_chain_converges_to_irvine_elastic_catenary(geometry, tol20):
    """Irvine's elastic catenary (ch. 2, eqs for x(s), z(s) with Lagrangian s): the lumped
    chain's equilibrium nodes (at s = i L0/N) and end forces (with half an end segment's
    weight) converge to it at order 2 in N; the chain's own force balance vanishes there."""
    a, b, L0 = geometry
    cat = elastic_catenary(a, b, MU * G, 375.0, unstretched_length_m=L0)
    errors, force_errors = [], []
    for n in (10, 20, 40):
        t = _tether(n)
        x = static_chain(np.zeros(3), np.array([a, 0.0, b]), L0, t, G)
        zero = np.zeros_like(x)
        F, _ = _forces(x, zero, zero, L0, t.packed(G))
        assert np.abs(F[1:-1]).max() < 1e-10  # the dynamic model is at rest there
        xs, zs = cat.position(np.linspace(0.0, L0, n + 1))
        errors.append(max(np.abs(x[:, 0] - xs).max(), np.abs(x[:, 2] - zs).max()))
        force_P = F[-1]
        force_errors.append(
            max(
                abs(-force_P[0] - cat.H_N),
                abs(-force_P[2] - (cat.V_N + MU * G * L0)),
                abs(F[0, 2] - cat.V_N),
            )
        )
    if errors[0] > 1e-12:
        orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
        assert orders == pytest.approx([2.0, 2.0], abs=0.1)
        force_orders = np.log2(np.array(force_errors[:-1]) / np.array(force_errors[1:]))
        assert force_orders == pytest.approx([2.0, 2.0], abs=0.1)
    assert errors[1] < tol20
    assert force_errors[1] < 1e-3 * cat.tension_B_N


def test_vertical_chain_is_the_exact_catenary():
    """Hanging vertically (a = 0, H = 0) the tension grows linearly with s, so the lumped chain
    with the half-segment convention is exact at any N (Irvine's z(s) = s + (V s + w s^2/2)/EA)."""
    L0 = 9.375
    cat = elastic_catenary(0.0, 10.0, MU * G, 375.0, unstretched_length_m=L0)
    t = _tether(5)
    x = static_chain(np.zeros(3), np.array([0.0, 0.0, 10.0]), L0, t, G)
    _, zs = cat.position(np.linspace(0.0, L0, 6))
    assert x[:, 2] == pytest.approx(zs, abs=1e-12)
    zero = np.zeros_like(x)
    force_winch, force_P, _ = end_forces(x, zero, zero, L0, t.packed(G))
    assert force_winch[2] == pytest.approx(cat.tension_A_N, rel=1e-12)
    assert -force_P[2] == pytest.approx(cat.tension_B_N, rel=1e-12)


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_end_tensions_differ_by_the_cables_weight(geometry):
    """Statics of the whole cable: the vertical end forces carry its weight mu g L0 exactly,
    and the end tensions differ as the catenary's sqrt(H^2 + (V + w L0)^2) - sqrt(H^2 + V^2)
    (to the N = 20 discretisation error)."""
    a, b, L0 = geometry
    t = _tether(20)
    x = static_chain(np.zeros(3), np.array([a, 0.0, b]), L0, t, G)
    zero = np.zeros_like(x)
    force_winch, force_P, _ = end_forces(x, zero, zero, L0, t.packed(G))
    assert force_winch[2] + force_P[2] == pytest.approx(-MU * G * L0, rel=1e-12)
    cat = elastic_catenary(a, b, MU * G, 375.0, unstretched_length_m=L0)
    difference = np.linalg.norm(force_P) - np.linalg.norm(force_winch)
    assert difference == pytest.approx(cat.tension_B_N - cat.tension_A_N, abs=2e-3)
    # the inextensible statics T_B - T_A = w b holds to the cable's strain T/EA
    assert difference == pytest.approx(MU * G * b, rel=2 * cat.tension_B_N / 375.0)


def _modes(t: LumpedTether, length: float, L0: float) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies [Hz] of a straight taut chain along n1 without gravity, from the
    eigenvalues of M^-1 dF/dx by central differences of the force kernel, and each mode's
    share of motion along the chain (1: axial, 0: transverse)."""
    n = t.segments
    p = t.packed(G)
    p[LUMPED_G] = 0.0
    x = np.zeros((n + 1, 3))
    x[:, 0] = np.linspace(0.0, length, n + 1)
    zero = np.zeros_like(x)
    m = MU * L0 / n
    J = np.zeros((3 * (n - 1), 3 * (n - 1)))
    eps = 1e-7
    for k in range(3 * (n - 1)):
        xp, xm = x.copy(), x.copy()
        xp[1 + k // 3, k % 3] += eps
        xm[1 + k // 3, k % 3] -= eps
        dF = _forces(xp, zero, zero, L0, p)[0] - _forces(xm, zero, zero, L0, p)[0]
        J[:, k] = dF[1:-1].ravel() / (2 * eps * m)
    values, vectors = np.linalg.eig(J)
    order = np.argsort(-values.real)
    f = np.sqrt(-values.real[order]) / (2 * math.pi)
    shapes = np.abs(vectors[:, order].real) ** 2
    axial_share = shapes[0::3].sum(axis=0) / shapes.sum(axis=0)
    return f, axial_share


def test_axial_and_transverse_frequencies_of_a_taut_tether():
    """A taut tether with fixed ends: the axial modes n/(2 L0) sqrt(EA/mu) (rod, wave speed
    sqrt(EA/mu) in the unstretched coordinate) and the transverse modes n/(2 L) sqrt(T/mu_s)
    (string, mu_s = mu L0/L the stretched line density; each twice), first three of each
    within 1% at N = 20."""
    EA, L0, length = 375.0, 9.375, 10.0
    t = _tether(20, EA_N=EA)
    tension = EA * (length - L0) / L0
    f, axial_share = _modes(t, length, L0)
    mu_s = MU * L0 / length
    transverse = [k / (2 * length) * math.sqrt(tension / mu_s) for k in (1, 1, 2, 2, 3, 3)]
    assert f[axial_share < 1e-6][:6] == pytest.approx(transverse, rel=0.01)
    axial = [k / (2 * L0) * math.sqrt(EA / MU) for k in (1, 2, 3)]
    assert f[axial_share > 1.0 - 1e-6][:3] == pytest.approx(axial, rel=0.01)


def _run_reference(t, p, x0, v0, L0, wind, P, VP, t_end, method, rtol):
    n = t.segments
    m = t.mass_per_length_kg_m * L0 / n

    def rhs(time, y):
        x = x0.copy()
        v = v0.copy()
        x[1:-1] = y[: 3 * (n - 1)].reshape(-1, 3)
        v[1:-1] = y[3 * (n - 1) :].reshape(-1, 3)
        x[-1] = P(time)
        v[-1] = VP(time)
        F, _ = _forces(x, v, wind, L0, p)
        return np.concatenate([v[1:-1].ravel(), (F[1:-1] / m).ravel()])

    y0 = np.concatenate([x0[1:-1].ravel(), v0[1:-1].ravel()])
    sol = solve_ivp(rhs, (0.0, t_end), y0, method=method, rtol=rtol, atol=rtol * 1e-2)
    assert sol.success
    return sol.y[: 3 * (n - 1), -1].reshape(-1, 3)


def _run_ros2(p, x0, v0, L0, wind, P, VP, t_end, h):
    x, v = x0.copy(), v0.copy()
    work = tl.ros2_work(x.shape[0] - 1)
    for k in range(round(t_end / h)):
        tl.ros2_step(x, v, wind, L0, p, h, P((k + 1) * h), VP((k + 1) * h), work)
    return x[1:-1]


@pytest.mark.parametrize(
    ("EA", "n", "t_end", "tol_10ms", "order"),
    [(375.0, 5, 1.0, 1e-2, 1.7), (20000.0, 5, 0.3, 1e-2, 0.8)],
)
def test_ros2_against_radau_with_moving_top_drag_and_damping(EA, n, t_end, tol_10ms, order):
    """ROS2 (Verwer et al. 1999) at the control sample 10 ms against SciPy's Radau (rtol
    1e-10): P moves on a 3D Lissajous path (0.6 m/s, starting abruptly), 5 m/s wind, drag and
    10 % damping; largest node-position error at the end. The soft paper cable (EA = 375 N):
    error 6.7e-3 m at 10 ms, order 2 from 5 to 2.5 ms. A stiff one (EA = 20 kN, axial modes
    up to 160 Hz, where explicit RK4 is unstable above ~3 ms): 6.9e-3 m at 10 ms, order ~1
    from 5 to 2.5 ms (the axial modes are still unresolved there: Rosenbrock order reduction;
    ROS2's L-stability damps them instead of blowing up)."""
    t = _tether(n, EA_N=EA, damping_ratio=0.1, diameter_m=0.006, tangential_drag_coefficient=0.02)
    p = t.packed(G)
    L0 = 10.0 * (1.0 - 10.0 / EA)
    P0 = np.array([1.0, 0.0, 10.0])

    def P(time):
        return P0 + np.array(
            [0.3 * math.sin(2 * time), 0.2 * math.sin(3 * time), 0.1 * math.sin(5 * time)]
        )

    def VP(time):
        return np.array(
            [0.6 * math.cos(2 * time), 0.6 * math.cos(3 * time), 0.5 * math.cos(5 * time)]
        )

    x0 = static_chain(np.zeros(3), P(0.0), L0, t, G)
    v0 = np.zeros_like(x0)
    v0[-1] = VP(0.0)
    wind = np.zeros_like(x0)
    wind[:, 0] = 5.0
    ref = _run_reference(t, p, x0, v0, L0, wind, P, VP, t_end, "Radau", 1e-10)
    err = [
        np.abs(_run_ros2(p, x0, v0, L0, wind, P, VP, t_end, h) - ref).max()
        for h in (0.01, 0.005, 0.0025)
    ]
    assert err[0] < tol_10ms
    assert math.log2(err[1] / err[2]) > order


def _energy_case(n=6):
    t = _tether(n)
    p = t.packed(G)
    p[LUMPED_CDN] = 0.0
    p[LUMPED_CDT] = 0.0
    L0 = 9.9
    x0 = static_chain(np.zeros(3), np.array([1.0, 0.0, 10.0]), L0, t, G)
    x0[1:-1, 1] += 0.2 * np.sin(np.pi * np.arange(1, n) / n)  # a transverse pluck
    x0[1:-1, 0] += 0.02 * np.sin(2 * np.pi * np.arange(1, n) / n)  # and an axial one
    return t, p, L0, x0


def test_energy_is_conserved_without_drag_and_damping():
    """Fixed ends, no drag, no damping: kinetic + gravitational + elastic energy is a constant
    of the model's forces (DOP853 at rtol 1e-12 keeps it to 1e-9 relative), and ROS2's energy
    error shrinks with the step at order >= 2 once the axial modes are resolved (h <= 1 ms;
    at longer steps the L-stable ROS2 damps them, by design)."""
    t, p, L0, x0 = _energy_case()
    zero = np.zeros_like(x0)
    E0 = chain_energy(x0, zero, L0, p)
    P0 = x0[-1].copy()
    fixed_P, still = (lambda time: P0), (lambda time: np.zeros(3))
    n = t.segments
    m = MU * L0 / n

    def rhs(time, y):
        x = x0.copy()
        v = zero.copy()
        x[1:-1] = y[: 3 * (n - 1)].reshape(-1, 3)
        v[1:-1] = y[3 * (n - 1) :].reshape(-1, 3)
        F, _ = _forces(x, v, zero, L0, p)
        return np.concatenate([v[1:-1].ravel(), (F[1:-1] / m).ravel()])

    y0 = np.concatenate([x0[1:-1].ravel(), np.zeros(3 * (n - 1))])
    sol = solve_ivp(rhs, (0.0, 2.0), y0, method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
    scale = (
        abs(E0)
        + chain_energy(x0, zero, L0, p)
        - chain_energy(static_chain(np.zeros(3), P0, L0, t, G), zero, L0, p)
    )
    for time in np.linspace(0.0, 2.0, 21):
        y = sol.sol(time)
        x = x0.copy()
        v = zero.copy()
        x[1:-1] = y[: 3 * (n - 1)].reshape(-1, 3)
        v[1:-1] = y[3 * (n - 1) :].reshape(-1, 3)
        assert abs(chain_energy(x, v, L0, p) - E0) < 1e-9 * scale
    drift = []
    for h in (0.001, 0.0005, 0.00025):
        x, v = x0.copy(), zero.copy()
        work = tl.ros2_work(n)
        worst = 0.0
        for k in range(round(0.5 / h)):
            tl.ros2_step(x, v, zero, L0, p, h, fixed_P(k), still(k), work)
            worst = max(worst, abs(chain_energy(x, v, L0, p) - E0))
        drift.append(worst)
    assert math.log2(drift[0] / drift[1]) > 1.8
    assert math.log2(drift[1] / drift[2]) > 1.8


def test_relaxation_from_the_static_shape_stays_put():
    """Started at rest on the chain's static shape (no wind, P fixed), 3 s of ROS2 steps at the
    control sample 10 ms move no node by more than 1e-9 m; started on Irvine's catenary (the
    continuous shape) at N = 20, the nodes stay within the N = 20 shape tolerance of it."""
    for EA in (375.0, 20000.0):
        t = _tether(20, EA_N=EA, damping_ratio=0.1)
        p = t.packed(G)
        P = np.array([2.0, 0.0, 9.8])
        L0 = 9.375 if EA < 1000 else 9.99
        for start, tol in (
            (static_chain(np.zeros(3), P, L0, t, G), 1e-9),
            (initial_chain(np.zeros(3), P, L0, t, G), 1e-4),
        ):
            x = start.copy()
            v = np.zeros_like(x)
            work = tl.ros2_work(20)
            for _ in range(300):
                tl.ros2_step(x, v, v * 0.0, L0, p, 0.01, P, np.zeros(3), work)
            assert np.abs(x - start).max() < tol


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("segments", 0),
        ("segments", -3),
        ("segments", 2.5),
        ("segments", True),
        ("mass_per_length_kg_m", 0.0),
        ("mass_per_length_kg_m", -0.01),
        ("EA_N", 0.0),
        ("diameter_m", 0.0),
        ("diameter_m", -1.0),
        ("drag_coefficient", 0.0),
        ("drag_coefficient", math.nan),
        ("damping_ratio", -0.1),
        ("tangential_drag_coefficient", -0.1),
    ],
)
def test_bad_input_is_refused_with_one_line(field, value):
    """Non-positive segments, mass, stiffness, diameter, drag coefficient (and negative damping
    or skin friction): one ParameterError line naming the field."""
    with pytest.raises(ParameterError) as info:
        LumpedTether(**{field: value})
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"tether.{field} = ")


def test_catenary_needs_exactly_one_of_length_and_tension():
    """elastic_catenary takes L0 or H, not both, not neither; H with a given span solves for
    the L0 that gives it back."""
    with pytest.raises(ParameterError, match="exactly one"):
        elastic_catenary(5.0, 5.0, 0.2, 375.0)
    with pytest.raises(ParameterError, match="exactly one"):
        elastic_catenary(5.0, 5.0, 0.2, 375.0, unstretched_length_m=8.0, horizontal_tension_N=1.0)
    cat = elastic_catenary(30.0, 5.0, MU * G, 375.0, unstretched_length_m=35.0)
    back = elastic_catenary(30.0, 5.0, MU * G, 375.0, horizontal_tension_N=cat.H_N)
    assert back.unstretched_length_m == pytest.approx(35.0, rel=1e-10)
    assert back.V_N == pytest.approx(cat.V_N, rel=1e-9)


def test_paper_stiffness_conversion():
    """EA = K_C L0N: the paper's K_C = 40 N/m at L0N = 9.375 m (Table III) is EA = 375 N."""
    assert LumpedTether.from_paper_stiffness(40.0, 9.375).EA_N == pytest.approx(375.0)


def test_stiff_cable_going_slack_and_snapping_taut_at_the_control_sample():
    """A stiff cable (EA = 20 kN) whose top comes closer than its unstretched length, so it
    hangs slack for ~0.5 s of 3 s and snaps taut again: ROS2 at the 10 ms control sample stays
    bounded and gives the force at P of the 1 ms solution (the step-converged reference:
    0.5 ms agrees with 1 ms to 0.1 %) within 2 % on average and 1 % at its peak."""
    n, EA = 10, 20000.0
    t = _tether(n, EA_N=EA, damping_ratio=0.1, diameter_m=0.006)
    p = t.packed(G)
    L0 = 10.0 * (1.0 - 10.0 / EA)
    P0 = np.array([1.0, 0.0, 10.0])
    w = np.array([2.0, 3.0, 5.0])
    amp = np.array([0.3, 0.2, 0.1])
    wind = np.zeros((n + 1, 3))
    wind[:, 0] = 5.0
    results = []
    for h in (0.01, 0.001):
        x = static_chain(np.zeros(3), P0, L0, t, G)
        v = np.zeros_like(x)
        v[-1] = amp * w
        work = tl.ros2_work(n)
        every = round(0.01 / h)
        force, slack = [], 0
        for k in range(round(3.0 / h)):
            time = (k + 1) * h
            tl.ros2_step(
                x, v, wind, L0, p, h, P0 + amp * np.sin(w * time), amp * w * np.cos(w * time), work
            )
            _, force_P, tensions = end_forces(x, v, wind, L0, p)
            slack += tensions.min() == 0.0
            if (k + 1) % every == 0:
                force.append(np.linalg.norm(force_P))
        assert slack * h > 0.3  # the case does go slack
        results.append(np.array(force))
    coarse, fine = results
    assert np.isfinite(coarse).all()
    assert coarse.mean() == pytest.approx(fine.mean(), rel=0.02)
    assert coarse.max() == pytest.approx(fine.max(), rel=0.01)


def _tethered_states(model, trim, n=6, seed=3):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        x = trim.x.copy()
        x[:5] += 0.2 * rng.standard_normal(5)  # q4..q8
        x[5] += 0.3 * rng.standard_normal()  # q9
        x[6:12] += 0.5 * rng.standard_normal(6)
        yield x


def test_radial_force_at_P_reproduces_the_tethered_model():
    """Eq 28's tension -TC c3 at P, fed as a general force at P (wind at HO + rotor torques,
    ``force_at_P_as_loads``) into the generated RHS at zero tension, gives today's tethered
    derivative (``kernels.tethered_derivative``) to rounding."""
    model = TetheredHelicopter()
    trim = model.trim(25.0)
    c = model.constants
    arm = model.params.helicopter.tether_arm
    K_C = model.params.tether.K_C
    wind = np.array([3.0, -1.0, 0.5])
    for x in _tethered_states(model, trim):
        out_ref = np.empty(13)
        kernels.tethered_derivative(x, trim.u_total, wind, 0.2, c, K_C, 0.0, out_ref)
        q7, q8, q9 = x[3:6]
        c3 = np.array([math.sin(q8), -math.sin(q7) * math.cos(q8), math.cos(q7) * math.cos(q8)])
        tension = kernels.tension_from_state(q9, x[12], K_C)
        assert tension > 0.0
        out = np.empty(13)
        tethered_derivative_force_at_P(x, trim.u_total, wind, -tension * c3, 0.2, c, arm, out)
        assert out == pytest.approx(out_ref, rel=1e-12, abs=1e-12)


def test_general_force_at_P_matches_newton_euler():
    """A force at P off the tether direction (what a lumped tether gives): the accelerations of
    ``tethered_derivative_force_at_P`` equal the independent Newton-Euler route
    (tests/newton_euler.py: force and moment r_P x F about HO)."""
    model = TetheredHelicopter()
    trim = model.trim(25.0)
    ne = NewtonEuler(model.params)
    arm = model.params.helicopter.tether_arm
    rng = np.random.default_rng(5)
    wind = np.array([1.0, 2.0, -0.5])
    for x in _tethered_states(model, trim):
        force_P = rng.normal(0.0, 20.0, 3)
        out = np.empty(13)
        tethered_derivative_force_at_P(
            x, trim.u_total, wind, force_P, 0.0, model.constants, arm, out
        )
        R = dcm_table_i(*x[:3])
        a, w_dot = ne.accelerations(R, x[6:9], x[9:12], trim.u_total, wind, force_P)
        assert out[6:9] == pytest.approx(a, rel=1e-10, abs=1e-10)
        assert out[9:12] == pytest.approx(w_dot, rel=1e-10, abs=1e-10)


# ----------------------------------------------------------------------------------------------
# item 3: hover trim with a massive tether
# ----------------------------------------------------------------------------------------------


def test_hover_trim_lumped_massless_limit_is_table_v(paper):
    """mu -> 0: Table V's tethered trim (TC = 25 N, q9 = 10 m: fMR3 = 148.6568 N, tMR1 =
    1.3132 N m, tMR2 = 0, fTR2 = 13.7645 N, q4 = 5.29 deg) and eq 28's LN = q9 - TC / KC with
    EA = KC LN0 (Table III: 40 N/m x 9.375 m)."""
    lt = hover_trim_lumped(paper, _tether(10, mass_per_length_kg_m=1e-12), 25.0, 10.0)
    assert lt.trim.u == pytest.approx([148.6568, 1.3132, 0.0, 13.7645], abs=5e-5)
    assert math.degrees(lt.trim.x[0]) == pytest.approx(5.29, abs=0.005)
    assert lt.top_tension_N == pytest.approx(25.0, abs=1e-9)
    assert lt.unstretched_length_m == pytest.approx(10.0 - 25.0 / paper.tether.K_C, abs=1e-9)


@pytest.mark.parametrize("q9", [10.0, 50.0, 100.0])
def test_hover_trim_lumped_balance(paper, q9):
    """At trim without wind: (i) the rotors' extra vertical force over the free hover (Table IV,
    TC = 0) equals the vertical tension at P; (ii) top minus ground tension is the cable's
    weight mu g L0 (the vertical catenary); (iii) the lumped chain's end forces at its static
    nodes (chain_forces) are the catenary's; (iv) the helicopter's derivative with the force at
    P as loads (tethered_derivative_force_at_P, not eq 28) vanishes."""
    tether = _tether(20, mass_per_length_kg_m=0.03)
    lt = hover_trim_lumped(paper, tether, 25.0, q9)
    h = paper.helicopter

    def vertical_rotor_force(trim):
        R = np.empty((3, 3))
        kernels.kinematics_dcm(trim.x[0:3], R)
        u = trim.u_total
        return u[0] * R[2, 2] + u[3] * R[2, 1]

    from tetherheli.model.trim import hover_trim

    extra = vertical_rotor_force(lt.trim) - vertical_rotor_force(hover_trim(paper, 0.0, q9))
    assert extra == pytest.approx(-lt.force_P[2], rel=1e-10)
    L0 = lt.unstretched_length_m
    assert lt.top_tension_N - lt.ground_tension_N == pytest.approx(0.03 * h.g * L0, rel=1e-12)
    # the chain's own forces at its static shape
    zero = np.zeros_like(lt.nodes)
    f_winch, f_P, _ = end_forces(lt.nodes, zero, zero, L0, tether.packed(h.g))
    np.testing.assert_allclose(f_winch, [0.0, 0.0, 25.0], atol=1e-9)
    np.testing.assert_allclose(f_P, lt.force_P, atol=1e-9)
    # the helicopter at rest
    out = np.empty(13)
    c = kernels.model_constants("tethered", h)
    tethered_derivative_force_at_P(
        lt.trim.x, lt.trim.u_total, np.zeros(3), lt.force_P, 0.0, c, h.tether_arm, out
    )
    assert np.abs(out[:12]).max() < 1e-9


def test_hover_trim_lumped_refusals(paper):
    """A zero ground tension, a non-tether, a length out of range and a cable too heavy for the
    rotor's limits are each refused with one line."""
    from tetherheli.errors import InfeasibleError

    tether = _tether(10, mass_per_length_kg_m=0.1)
    for call in (
        lambda: hover_trim_lumped(paper, tether, 0.0),
        lambda: hover_trim_lumped(paper, "cable", 25.0),
        lambda: hover_trim_lumped(paper, tether, 25.0, -5.0),
    ):
        with pytest.raises(ParameterError) as err:
            call()
        assert "\n" not in str(err.value)
    # 100 m of 0.1 kg/m (98 N) on top of 25 N: fMR3 ~ 232 N > 170 N; fine at 10 m (158 N)
    with pytest.raises(InfeasibleError, match="fMR3") as err:
        hover_trim_lumped(paper, tether, 25.0, 100.0, u_max=(170.0, 10.0, 10.0, 50.0))
    assert "\n" not in str(err.value)
    hover_trim_lumped(paper, tether, 25.0, 10.0, u_max=(170.0, 10.0, 10.0, 50.0))


# ----------------------------------------------------------------------------------------------
# item 5: the tether as a sensor with sag
# ----------------------------------------------------------------------------------------------


def test_static_cable_is_the_elastic_catenary():
    """Without wind the shot static cable (ODE in s) is Irvine's elastic catenary through the
    same ends with the same L0: its ground tension vector is (H, V)."""
    tether = _tether(10, mass_per_length_kg_m=0.03)
    d = np.array([30.0, -20.0, 60.0])
    cab = static_cable(d, 25.0, tether, G)
    a = math.hypot(d[0], d[1])
    cat = elastic_catenary(a, d[2], 0.03 * G, 375.0, unstretched_length_m=cab.unstretched_length_m)
    T0 = cab.ground_tension
    assert math.hypot(T0[0], T0[1]) == pytest.approx(cat.H_N, rel=1e-8)
    assert T0[2] == pytest.approx(cat.V_N, rel=1e-8)
    assert np.linalg.norm(cab.top_tension) == pytest.approx(cat.tension_B_N, rel=1e-8)
    # and the winch tangent points along d's azimuth
    assert T0[1] / T0[0] == pytest.approx(d[1] / d[0], rel=1e-10)


def test_sensor_sag_bias_and_correction():
    """Sec. IV-F's straight-tether estimate from the winch tangent: unbiased in the massless
    limit, biased with sag (P at 60 deg elevation, 50 m, 0.03 kg/m); the catenary estimator
    (tension, tangent, L0) recovers P to solver tolerance, and with the known wind too."""
    d = 50.0 * np.array([0.5, 0.0, math.sqrt(0.75)])
    light = static_cable(d, 25.0, _tether(10, mass_per_length_kg_m=1e-9), G)
    alt, _ = straight_tether_estimates(light, 375.0)
    assert np.abs(alt - d).max() < 1e-6
    for mu, wind in ((0.03, None), (0.03, (6.0, 3.0, 0.0))):
        tether = _tether(10, mass_per_length_kg_m=mu)
        cab = static_cable(d, 25.0, tether, G, wind if wind is not None else (0.0, 0.0, 0.0))
        alt, _ = straight_tether_estimates(cab, 375.0)
        assert np.abs(alt - d).max() > 1.0  # metres of bias
        est = catenary_position_estimate(
            *cab.encoder_angles, 25.0, cab.unstretched_length_m, tether, G, wind
        )
        assert np.abs(est - d).max() < 1e-8


def test_sensor_vertical_no_wind_unbiased():
    """P straight above the winch without wind: the cable hangs vertically whatever its mass,
    the tangent is the chord and the IV-F estimate is exact; a side wind biases it downwind."""
    tether = _tether(10, mass_per_length_kg_m=0.03)
    d = np.array([0.0, 0.0, 40.0])
    alt, _ = straight_tether_estimates(static_cable(d, 25.0, tether, G), 375.0)
    assert np.abs(alt - d).max() < 1e-9
    windy = static_cable(d, 25.0, tether, G, (5.0, 0.0, 0.0))
    alt, _ = straight_tether_estimates(windy, 375.0)
    assert alt[0] > 0.5


def test_static_cable_refuses_a_cable_on_the_ground():
    """A 0.1 kg/m cable over 90 m of span and 10 m of rise with 5 N at the winch would leave
    the winch downwards (lie on the ground): refused with one line."""
    from tetherheli.errors import InfeasibleError

    with pytest.raises(InfeasibleError, match="ground_tension_N") as err:
        static_cable((90.0, 0.0, 10.0), 5.0, _tether(10, mass_per_length_kg_m=0.1), G)
    assert "\n" not in str(err.value)
