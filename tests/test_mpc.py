"""The constrained linear MPC (``control.mpc``, ``[control] controller = "mpc"``), flown by
``simulate``'s Python loop; each check against an independent route."""

from __future__ import annotations

import csv
import dataclasses

import control
import numpy as np
import pytest

from tetherheli import simulate
from tetherheli.control.base import Measurement
from tetherheli.control.mpc import MPCController, design_mpc, mpc_plant
from tetherheli.control.tether_lqi import design_tether_lqi
from tetherheli.errors import ParameterError
from tetherheli.model import TetheredHelicopter
from tetherheli.model.linearization import linearize
from tetherheli.names import WIND
from tetherheli.params import Params
from tetherheli.runs.batch import run_batch
from tetherheli.runs.mpc_setup import mpc_controller
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import MPCSettings, Scenario, load_scenario
from tetherheli.status import Status
from tetherheli.studies.controllers import eq40_saturated
from tetherheli.studies.sweep import paper_cyclic_limit
from tetherheli.wind.profiles import Pulse, Step

DT = 0.01
S = MPCSettings()  # the shipped defaults


def _scenario(duration: float = 10.0, **mpc) -> Scenario:
    s = Scenario(name="mpc", duration=duration)
    c = dataclasses.replace(
        s.control, controller="mpc", mpc=dataclasses.replace(s.control.mpc, **mpc)
    )
    return s.replace(control=c)


def _tethered_plant():
    p = Params.paper()
    return mpc_plant(p, "tethered", p.tension_control.T_ref, 10.0, DT)


def _design(**kw):
    G, H, C, Hd, c_t = _tethered_plant()
    return design_mpc(G, H, C, Hd, DT, Qy=np.diag(S.Qy), Ru=np.diag(S.Ru), c_tension=c_t,
                      q_tension=S.q_tension, **kw)  # fmt: skip


def test_wind_column_is_newtons_second_law_on_HO():
    """The disturbance enters as a force on HO, the whole helicopter's centre of mass:
    d(u1..u3)/dt = F / (mF + mMR) (u1..u3 are HO's velocity in N, eq 7) and nothing else
    moves at first; the discrete column integrates it over the sample."""
    p = Params.paper()
    model = TetheredHelicopter(p)
    lin = linearize(model, model.trim(p.tension_control.T_ref, 10.0))
    E = lin.input_matrix(WIND)
    m = p.helicopter.m_F + p.helicopter.m_MR
    expected = np.zeros_like(E)
    expected[6:9] = np.eye(3) / m
    np.testing.assert_allclose(E, expected, rtol=0, atol=1e-12)
    Hd = _tethered_plant()[3]
    np.testing.assert_allclose(Hd[6:9], DT * np.eye(3) / m, rtol=0, atol=1e-3 * DT / m)


def test_unconstrained_first_move_equals_finite_horizon_riccati():
    """With a terminal weight Pf other than the DARE's, the condensed QP's unconstrained
    first move is the finite-horizon LQ gain of the same weights and horizon: the backward
    Riccati recursion P_N = Pf, K_j = (R + B' P_{j+1} B)^{-1} B' P_{j+1} A,
    P_j = Q + A' P_{j+1} (A - B K_j), first move -K_0 xi_0."""
    N = 15
    ref = _design(horizon=N)
    Pf = 3.0 * ref.Qx
    d = _design(horizon=N, terminal=Pf)
    A, B, Q, R = d.G_aug, d.H_aug, d.Qx, d.Ru
    P = Pf
    for _ in range(N):
        K = np.linalg.solve(R + B.T @ P @ B, B.T @ P @ A)
        P = Q + A.T @ P @ (A - B @ K)
    np.testing.assert_allclose(d.K, K, rtol=0, atol=1e-7 * np.max(np.abs(K)))
    assert np.max(np.abs(d.K - ref.K)) > 1e-4 * np.max(np.abs(K))  # the terminal matters


def test_dare_terminal_cost_gives_the_infinite_horizon_lq_gain():
    """With the DARE's terminal cost the unconstrained MPC is the infinite-horizon LQ law at
    any horizon: python-control's dlqr (integral_action = -dt C, eq 50) and the tethered
    LQI's design of the same weights give the same gain."""
    G, H, C, _, c_t = _tethered_plant()
    n = G.shape[0]
    Qy = np.diag(S.Qy)
    Q = np.zeros((n + 4, n + 4))
    Q[:n, :n] = C.T @ Qy[:4, :4] @ C + S.q_tension * np.outer(c_t, c_t)
    Q[n:, n:] = Qy[4:, 4:]
    Q = 0.5 * (Q + Q.T)  # python-control wants it symmetric to the last bit
    sys = control.ss(G, H, C, np.zeros((4, 5)), DT)
    K_dlqr, _, _ = control.dlqr(sys, Q, np.diag(S.Ru), integral_action=-DT * C)
    lqi = design_tether_lqi(G, H, C, c_t, DT, Qy=Qy, q_tension=S.q_tension, Ru=np.diag(S.Ru))
    for N in (1, 8):
        d = _design(horizon=N)
        scale = np.max(np.abs(K_dlqr))
        np.testing.assert_allclose(d.K, K_dlqr, rtol=0, atol=1e-7 * scale)
        np.testing.assert_allclose(d.K, lqi.K, rtol=0, atol=1e-7 * scale)


def _controller(scenario: Scenario) -> MPCController:
    return mpc_controller(scenario, engine_setup(scenario))


def test_osqp_first_move_equals_the_lq_law_when_no_bound_binds():
    """A small perturbation of the trim, no bound near: the command OSQP returns is the LQ
    law u = u_trim - K xi_0 to the solver's tolerance (xi_0 = [x - x_trim; z = 0])."""
    s = _scenario(tolerance=1e-8)
    c = _controller(s)
    x = c.x_ref.copy()
    x[6] += 0.05  # u1 [m/s]
    x[1] -= 0.01  # q5 [rad]
    cmd = c.step(0.0, Measurement(state=x, tension=25.0))
    xi0 = np.concatenate([x - c.x_ref, np.zeros(4)])
    du = -c.design.K @ xi0
    assert c.fallbacks == [0]
    np.testing.assert_allclose(cmd.inputs, c.u_trim + du[:4], rtol=0, atol=1e-5)
    assert cmd.reel_rate == pytest.approx(du[4], abs=1e-5)
    assert np.max(np.abs(du)) > 0.05  # a move, not trim


def _fly_recording(scenario: Scenario, every: int = 1):
    """Fly ``scenario`` with its MPC; record each command and, every ``every`` samples,
    the QP posed and OSQP's solution."""
    c = _controller(scenario)
    commands, qps = [], []
    step = c.step

    def recording_step(t, measurement):
        cmd = step(t, measurement)
        commands.append((cmd.inputs.copy(), cmd.reel_rate))
        if len(commands) % every == 0 and c.solution is not None:
            qps.append((c.qp_data(), c.solution, c.tolerance))
        return cmd

    c.step = recording_step
    return simulate(scenario, controller=c), c, commands, qps


def test_bounds_hold_over_a_paper_run_with_eq40():
    """Paper simulation 1 (tethered, the 20 N pulse) with eq 40's cyclic limit, a reel-rate
    limit and a reel acceleration limit: the cyclic bound and the winch limits bind, and no
    command of the MPC leaves them (checked on the commands, before the actuators' own
    saturation); the QP's plan itself is within them to OSQP's tolerance."""
    base = eq40_saturated(load_scenario("scenarios/paper_sim1_tethered.toml"))
    act = dataclasses.replace(base.actuators, reel_rate_limit=0.05,
                              reel_acceleration_limit=0.5)  # fmt: skip
    s = base.replace(duration=14.0, actuators=act,
                     control=dataclasses.replace(base.control, controller="mpc"))  # fmt: skip
    r, _, commands, _ = _fly_recording(s)
    assert r.ok
    lim = paper_cyclic_limit(s.params)
    u = np.array([cmd[0] for cmd in commands])
    rate = np.array([0.0] + [cmd[1] for cmd in commands])
    assert np.max(np.abs(u[:, 1:3])) <= lim * (1 + 1e-12)
    assert np.max(np.abs(u[:, 1:3])) >= lim * (1 - 1e-6)  # the bound was active
    assert np.max(np.abs(rate)) <= 0.05 * (1 + 1e-12)
    step = np.max(np.abs(np.diff(rate)))
    assert step <= 0.5 * DT * (1 + 1e-9)
    assert step >= 0.5 * DT * (1 - 1e-6)  # the acceleration limit was active
    np.testing.assert_allclose(r.inputs, u[: r.time.size], rtol=1e-15, atol=1e-12)  # no clip
    # where OSQP stopped short the previous plan flew (counted), within the bounds too
    assert r.extra["mpc_fallback"].sum() < 0.05 * r.time.size


def test_iteration_limit_falls_back_to_the_previous_plan_and_counts_it():
    """OSQP limited to 1 iteration cannot converge: every sample flies the previous plan's
    next move (the LQ law at the first), the run reaches its end, no NaN, the result's
    ``mpc_fallback`` column counts every sample, and the run is a failure
    (``Status.SOLVER_FAILED``: more than 10 % of the samples fell back), never "completed"."""
    s = _scenario(duration=2.0, max_iterations=1).replace(
        wind=Pulse(0.5, 0.5, 10.0, (1.0, 0.0, 0.0))
    )
    r = simulate(s)
    assert not r.ok and r.status == Status.SOLVER_FAILED and np.all(np.isfinite(r.inputs))
    assert "100 % (more than 10 %) of the samples" in r.message
    assert r.end_time == pytest.approx(r.time[-1])  # flown to its end, not stopped
    np.testing.assert_array_equal(r.extra["mpc_fallback"], 1.0)
    assert r.extra["mpc_fallback"].size == r.time.size


def test_osqp_solutions_satisfy_the_kkt_conditions():
    """On sampled steps of paper simulation 2 with eq 40 (cyclic and tension bounds
    active), OSQP's primal x and dual y satisfy the QP's KKT conditions to the solver's
    tolerance: stationarity P x + q + A' y = 0, primal feasibility l <= A x <= u, and
    complementarity (y_i > 0 only at an active upper bound, y_i < 0 at a lower one)."""
    base = eq40_saturated(load_scenario("scenarios/paper_sim2_tethered.toml"))
    s = base.replace(duration=13.0, control=dataclasses.replace(base.control, controller="mpc"))
    _, _, _, qps = _fly_recording(s, every=37)
    assert len(qps) > 20
    active = 0
    for (P, q, A, lower, u), (x, y), eps in qps:
        Ax = A @ x
        scale_p = max(np.max(np.abs(Ax)), 1.0)
        assert np.all(Ax >= lower - (eps + eps * scale_p) * 10)
        assert np.all(Ax <= u + (eps + eps * scale_p) * 10)
        grad = P @ x + q + A.T @ y
        scale_d = max(np.max(np.abs(P @ x)), np.max(np.abs(A.T @ y)), np.max(np.abs(q)))
        assert np.max(np.abs(grad)) <= 10 * (eps + eps * scale_d)
        tol = 10 * (eps + eps * scale_p)
        up, lo = y > 1e-6 * max(1.0, np.max(np.abs(y))), y < -1e-6 * max(1.0, np.max(np.abs(y)))
        assert np.all(u[up] - Ax[up] <= tol)
        assert np.all(Ax[lo] - lower[lo] <= tol)
        active += int(np.count_nonzero(up | lo))
    assert active > 0  # some constraint was active on the sampled steps


def test_constant_wind_leaves_no_steady_state_position_error():
    """A 6 N step of wind along n1 at t = 1 s: the helicopter moves, and 30 s later the
    position error is below 1 mm (integral action, eq 50), the disturbance estimate reads
    the wind force (Newton's law on HO) to 10%, and the winch comes to rest."""
    s = _scenario(duration=30.0).replace(wind=Step(1.0, 6.0, (1.0, 0.0, 0.0)))
    r, c, _, _ = _fly_recording(s)
    assert r.ok
    d = r.outputs[:, :3] - r.trim_output[:3]
    assert np.max(np.abs(d[:, 0])) > 0.01
    assert np.max(np.abs(d[-100:])) < 1e-3
    assert c.d_hat[0] == pytest.approx(6.0, rel=0.1)
    assert abs(r.reel_rate[-1]) < 1e-3  # the winch settling


def test_free_configuration_and_batch():
    """The free configuration flies the MPC on the free linearization (12 states, 4
    inputs); ``run_batch`` flies MPC scenarios with the numbers of ``simulate``."""
    free = _scenario(duration=3.0).replace(
        configuration="free", wind=Pulse(0.5, 0.5, 10.0, (0.0, 1.0, 0.0))
    )
    c = _controller(free)
    assert c.design.n_states == 12 and c.design.n_inputs == 4 and not c.tethered
    r = simulate(free)
    assert r.ok and np.max(np.abs(r.outputs[:, 1] - r.trim_output[1])) > 1e-3
    tethered = free.replace(configuration="tethered")
    batch = run_batch([free, tethered], workers=1)
    for i, s in enumerate((free, tethered)):
        one = simulate(s)
        m = batch.metrics(i)
        assert batch.status[i] == 0
        dev = one.outputs[:, :3] - one.trim_output[:3]
        assert m["peak_q2"] == pytest.approx(np.max(np.abs(dev[:, 1])), rel=1e-12)
        assert m["rms_q2"] == pytest.approx(np.sqrt(np.mean(dev[:, 1] ** 2)), rel=1e-12)
        assert m["tension_max"] == pytest.approx(np.max(one.tension), rel=1e-12)


@pytest.mark.parametrize(
    ("key", "value"),
    [
        ("horizon", 0),
        ("tension_bounds", (30.0, 20.0)),
        ("tolerance", -1.0),
        ("disturbance_time_constant", -0.1),
        ("Ru", (1.0, 1.0, 1.0, 1.0, 0.0)),
    ],
)
def test_bad_settings_are_refused_in_one_line(tmp_path, key, value):
    with pytest.raises(ParameterError, match=rf"control\.mpc\.{key}") as err:
        _scenario(**{key: value})
    assert len(str(err.value).splitlines()) == 1
    path = tmp_path / "s.toml"
    path.write_text(_scenario().to_toml())
    text = path.read_text().replace(f"horizon = {S.horizon}\n", "horizon = 2.5\n")
    assert "horizon = 2.5" in text
    path.write_text(text)
    with pytest.raises(ParameterError, match=r"control\.mpc\.horizon"):
        load_scenario(path)


def test_compare_flies_the_mpc_next_to_the_others(tmp_path):
    """``tetherheli compare --controllers paper,tether_lqi,mpc --eq40``: one row per
    controller, the MPC's peak cyclic torque within eq 40's limit."""
    from tetherheli.cli import main

    s = Scenario(name="short", duration=3.0, wind=Pulse(0.5, 1.0, 20.0, (0.0, 1.0, 0.0)))
    path = tmp_path / "short.toml"
    path.write_text(s.to_toml())
    out = tmp_path / "out"
    args = ["compare", str(path), "--controllers", "paper,tether_lqi,mpc", "--eq40"]
    assert main([*args, "--out", str(out)]) == 0
    with open(out / "compare.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["controller"] for r in rows] == ["paper", "tether_lqi", "mpc"]
    mpc = rows[2]
    assert mpc["completed"] == "True"
    assert float(mpc["peak_cyclic"]) <= paper_cyclic_limit(s.params) * (1 + 1e-12)
    assert float(mpc["peak_q2"]) != float(rows[1]["peak_q2"])  # not the LQI's run


def test_after_a_release_the_free_law_flies():
    """The safety device releases the tether during a 20 N pulse (breaking tension 25.05 N,
    Sec. IV-C): from then on the MPC solves no QP (the paper's free law flies, as the tethered
    LQI does), the run completes free, and before it the MPC was solving."""
    act = dataclasses.replace(Scenario().actuators, breaking_tension=25.05)
    s = _scenario(duration=6.0).replace(actuators=act, wind=Pulse(0.5, 1.0, 20.0, (1.0, 0.0, 0.0)))
    r = simulate(s)
    assert r.ok and r.release_time is not None
    k = round(r.release_time / DT)
    it = r.extra["mpc_iterations"]
    assert np.all(it[:k] > 0) and np.all(it[k:] == 0)
    assert np.max(np.abs(r.outputs[-1, :3] - r.trim_output[:3])) < 1.0
