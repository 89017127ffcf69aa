"""The position Kalman filter (tetherheli.sensing.estimation) against independent routes: its
steady-state covariance against scipy.linalg.solve_discrete_are (a fix every sample, and a fix
every 20 samples through the lifted 20-step system), its error variance over a long run
against its own predicted covariance, its handling of late fixes against a filter re-run from
scratch on the data arrived by each sample, and on a recorded closed-loop run."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are

from tetherheli.errors import ParameterError
from tetherheli.report.paper import sensing_scenario
from tetherheli.runs import simulate
from tetherheli.sensing.config import SensorConfig
from tetherheli.sensing.estimation import Fixes, position_filter, run_filter
from tetherheli.sensing.noise import random_walk
from tetherheli.studies.estimation import estimate_run

DT = 0.01
IMU = SensorConfig.from_presets("mems_imu")
R = np.array([0.02, 0.03, 0.05]) ** 2  # fix variance per axis [m^2]


def _posterior_from_dare(F, Q, H, r):
    """Steady-state a-posteriori covariance: P- from the DARE, then one update with the
    rows of H (m, ns) and the diagonal noise r (m,)."""
    H, r = np.atleast_2d(H), np.atleast_1d(r)
    P = solve_discrete_are(F.T, H.T, Q, np.diag(r))
    PH = P @ H.T
    return P - PH @ np.linalg.solve(H @ PH + np.diag(r), PH.T)


@pytest.mark.parametrize("gnss", [False, True])
def test_steady_state_covariance_every_sample_equals_dare(gnss):
    """A fix at every sample: the filter's covariance converges to the DARE's. With
    ``gnss`` the GNSS (H = [1, 0, 0, 1], its Gauss-Markov state) and the tether
    (H = [1, 0, 0, 0]) both fix every sample, two sequential updates against the DARE's
    joint one."""
    config = SensorConfig.flown() if gnss else IMU
    model = position_filter(config, DT, gnss=gnss)
    n = 20000
    times = np.arange(n)
    H_t = np.zeros(model.n_states)
    H_t[0] = 1.0
    fixes = [Fixes(times, np.zeros((n, 3)), 0, H_t, R)]
    rows, noise = [H_t], [R]
    if gnss:
        H_g = H_t.copy()
        H_g[3] = 1.0
        R_g = np.array(config.gps_std) ** 2
        fixes.append(Fixes(times, np.zeros((n, 3)), 0, H_g, R_g))
        rows.append(H_g)
        noise.append(R_g)
    _, _, std = run_filter(model, np.zeros((n, 3)), fixes, np.zeros(3))
    for i in range(3):
        P = _posterior_from_dare(model.F, model.Q[i], np.array(rows), np.array(noise)[:, i])
        assert std[-1, i] ** 2 == pytest.approx(P[0, 0], rel=1e-6)


def test_steady_state_covariance_at_a_slower_fix_rate_equals_lifted_dare():
    """Fixes every 20 samples (a 5 Hz GNSS at 100 Hz): at the fix samples the covariance is
    the DARE's of the 20-step system F^20, sum F^i Q F^i'."""
    model = position_filter(IMU, DT, gnss=False)
    n, period = 40001, 20
    H = np.array([1.0, 0.0, 0.0])
    times = np.arange(0, n, period)
    fixes = [Fixes(times, np.zeros((times.size, 3)), 0, H, R)]
    _, _, std = run_filter(model, np.zeros((n, 3)), fixes, np.zeros(3))
    F20 = np.linalg.matrix_power(model.F, period)
    for i in range(3):
        Q20 = sum(
            np.linalg.matrix_power(model.F, j) @ model.Q[i] @ np.linalg.matrix_power(model.F, j).T
            for j in range(period)
        )
        P = _posterior_from_dare(F20, Q20, H, R[i])
        assert std[times[-1], i] ** 2 == pytest.approx(P[0, 0], rel=1e-6)


def test_error_variance_matches_predicted_covariance():
    """Monte Carlo over 2000 independent flights drawn from the filter's own model (initial
    state from P0, a true acceleration, the accelerometer's white noise and bias random walk
    as ``sensors`` draws them, 5 Hz fixes 0.15 s late): the variance of the position error at
    several times equals the filter's predicted one (standard error about 3 %)."""
    rng = np.random.default_rng(11)
    n, m = 1501, 2000
    base = position_filter(IMU, DT, gnss=False)
    model = replace(base, Q=np.repeat(base.Q[:1], m, 0), P0=np.repeat(base.P0[:1], m, 0))
    x0 = rng.standard_normal((m, 3)) * np.sqrt(np.diag(base.P0[0]))
    t = np.arange(n) * DT
    a_true = np.sin(0.3 * t)[:, None] * np.ones(m)
    v = x0[:, 1] + np.vstack([np.zeros(m), np.cumsum(a_true[:-1] * DT, axis=0)])
    p = x0[:, 0] + np.vstack(
        [np.zeros(m), np.cumsum(v[:-1] * DT + 0.5 * DT * DT * a_true[:-1], axis=0)]
    )
    bias = x0[:, 2] + random_walk(IMU.accel_random_walk, DT, rng.standard_normal((n, m)))
    accel = a_true + bias + rng.standard_normal((n, m)) * IMU.accel_density / math.sqrt(DT)
    times = np.arange(0, n, 20)
    r = np.full(m, R[0])
    values = p[times] + rng.standard_normal((times.size, m)) * math.sqrt(R[0])
    H = np.array([1.0, 0.0, 0.0])
    est, _, std = run_filter(model, accel, [Fixes(times, values, 15, H, r)], np.zeros(m))
    for k in (300, 907, 1500):
        assert np.var(est[k] - p[k]) == pytest.approx(std[k, 0] ** 2, rel=0.1)


def test_late_fixes_equal_a_filter_rerun_on_the_arrived_data():
    """The estimate at sample k with late fixes (5-sample GNSS-like fixes 3 samples late,
    plus a fix every sample on time) equals a filter re-run from the start on the fixes
    that have arrived by k, each applied at the sample it was taken."""
    rng = np.random.default_rng(2)
    n = 60
    model = position_filter(IMU, DT, gnss=False)
    accel = rng.standard_normal((n, 3))
    H = np.array([1.0, 0.0, 0.0])
    slow = Fixes(np.arange(0, n, 5), rng.standard_normal((12, 3)), 3, H, R)
    fast = Fixes(np.arange(n), 0.1 * rng.standard_normal((n, 3)), 0, H, 4 * R)
    est, vel, _ = run_filter(model, accel, [slow, fast], np.zeros(3))
    for k in range(n):
        arrived = slow.times + slow.latency <= k
        ref = Fixes(slow.times[arrived], slow.values[arrived], 0, H, R)
        e, v, _ = run_filter(model, accel[: k + 1], [ref, fast], np.zeros(3))
        np.testing.assert_allclose(est[k], e[k], rtol=0, atol=1e-12)
        np.testing.assert_allclose(vel[k], v[k], rtol=0, atol=1e-12)


def test_estimate_run_on_the_recorded_closed_loop():
    """Paper simulation 1 flown on the tether with the flown sensors: fused with the
    tether the filter's error stays within 3 sigma of its own prediction on every axis; fused
    with the consumer GNSS it errs by metres (the receiver's Gauss-Markov error is not
    observable from the GNSS alone) and its predicted sigma says so."""
    s = sensing_scenario("tether").replace(duration=30.0)
    r = simulate(s)
    tether = estimate_run(r, s, "tether")
    rms = np.array(list(tether.error_rms().values()))
    predicted = np.sqrt(np.mean(tether.position_std[100:] ** 2, axis=0))
    assert np.all(rms < 3.0 * predicted) and np.all(rms < 0.01)
    gnss = estimate_run(r, s, "gnss")
    assert np.all(gnss.position_std[-1] > 1.0)
    assert np.all(np.abs(gnss.error[-1]) < 4.0 * gnss.position_std[-1])
    with pytest.raises(ParameterError):
        estimate_run(r, s, "lidar")
