"""The consistency of the MPC's Kalman filter (issue 23, item 7): NEES and NIS
(``studies.estimation.kalman_consistency``) against hand-computed cases and a linear system
whose noises are the filter's own, then the shipped sensed scenarios flown by the MPC."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from tetherheli import simulate
from tetherheli.control.mpc import KALMAN_NIS_COLUMN
from tetherheli.control.observer import DisturbanceKalman
from tetherheli.errors import ParameterError, TetherheliError
from tetherheli.scenario.core import load_scenario
from tetherheli.sensing.estimation import ConsistencyTest, chi2_mean_band, normalized_squares
from tetherheli.studies.estimation import kalman_consistency

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
#: every shipped scenario with flown sensors (``tetherheli scenarios``: sensing_*,
#: turbulence_sensing_*; montecarlo_sensing's draws are in docs/studies/controllers.md)
SENSED = sorted(p.stem for p in SCENARIOS.glob("*sensing*.toml") if "montecarlo" not in p.stem)


def test_normalized_squares_by_hand():
    """e' P^-1 e on a diagonal and a full 2 x 2 covariance, written out."""
    e = np.array([[1.0, 2.0], [3.0, -1.0], [np.nan, 0.0]])
    out = normalized_squares(e, np.diag([4.0, 0.5]))
    assert out[0] == pytest.approx(1 / 4 + 4 / 0.5)
    assert out[1] == pytest.approx(9 / 4 + 1 / 0.5)
    assert math.isnan(out[2])
    P = np.array([[2.0, 1.0], [1.0, 3.0]])  # inverse [[3, -1], [-1, 2]] / 5
    x, y = e[1]
    assert normalized_squares(e[1:2], P)[0] == pytest.approx(
        (3 * x * x - 2 * x * y + 2 * y * y) / 5
    )
    # one covariance per sample gives the same
    per = normalized_squares(e[:2], np.stack([P, P]))
    np.testing.assert_allclose(per, normalized_squares(e[:2], P))


def test_chi2_band_closed_forms():
    """With 2 degrees of freedom chi-square is exponential (mean 2): one sample's 95 % band is
    [-2 ln 0.975, -2 ln 0.025]; many samples' mean tends to 2 +- 1.96 sqrt(4 / n)."""
    lo, hi = chi2_mean_band(2, 1)
    assert lo == pytest.approx(-2 * math.log(0.975), rel=1e-9)
    assert hi == pytest.approx(-2 * math.log(0.025), rel=1e-9)
    lo, hi = chi2_mean_band(16, 10_000)
    half = 1.959964 * math.sqrt(2 * 16 / 10_000)
    assert lo == pytest.approx(16 - half, abs=2e-3) and hi == pytest.approx(16 + half, abs=2e-3)
    with pytest.raises(ParameterError, match="samples"):
        chi2_mean_band(2, 0)
    with pytest.raises(ParameterError, match="confidence"):
        chi2_mean_band(2, 5, confidence=1.5)


def _toy_filter(force_accel: float) -> tuple[DisturbanceKalman, dict]:
    """A 6-state stable linear plant (two inputs, the wind force through Hd) and the filter
    designed on it with known noises."""
    rng = np.random.default_rng(3)
    n, m, dt = 6, 2, 0.01
    G = np.eye(n) + dt * (rng.normal(size=(n, n)) * 0.5 - 2.0 * np.eye(n))
    H = dt * rng.normal(size=(n, m))
    Hd = dt * rng.normal(size=(n, 3)) * 0.2
    R = np.diag(rng.uniform(1e-4, 1e-3, n))
    noise = dict(
        force_std=0.5, force_rate=0.8, input_std=np.array([0.3, 0.2]), coordinate_std=1e-3,
        force_accel=force_accel,
    )  # fmt: skip
    k = DisturbanceKalman.design(G, H, Hd, None, R, dt, **noise)
    return k, dict(noise, G=G, H=H, Hd=Hd, R=R, dt=dt)


def _fly_toy(filters: list[DisturbanceKalman], z: dict, steps: int) -> list[tuple]:
    """The truth simulated with the noises of ``z`` (the force a random walk, with a rate
    state when ``force_accel`` > 0), each filter run on the same measurements; per filter
    the errors of [x; d] and the innovations, per sample."""
    rng = np.random.default_rng(11)
    n, dt = 6, z["dt"]
    x, d, r, u = np.zeros(n), np.zeros(3), np.zeros(3), np.zeros(2)
    states = [np.zeros(f.A.shape[0]) for f in filters]
    out = [(np.empty((steps, n + 3)), np.empty((steps, n))) for _ in filters]
    chol_R = np.linalg.cholesky(z["R"])
    for i in range(steps):
        a = z["input_std"] * rng.normal(size=2)
        w = z["force_std"] * rng.normal(size=3)
        c = z["coordinate_std"] * rng.normal(size=n)
        x = z["G"] @ x + z["H"] @ (u + a) + z["Hd"] @ (d + w) + c
        d = d + dt * r + z["force_rate"] * math.sqrt(dt) * rng.normal(size=3)
        if z["force_accel"] > 0.0:
            r = r + z["force_accel"] * math.sqrt(dt) * rng.normal(size=3)
        measured = x + chol_R @ rng.normal(size=n)
        for j, f in enumerate(filters):
            states[j], out[j][1][i] = f.step(states[j], u, measured)
            out[j][0][i] = np.concatenate([states[j][:n] - x, states[j][n : n + 3] - d])
        u = -0.1 * x[:2]  # a known input, applied over the next sample
    return out


@pytest.mark.parametrize("force_accel", [0.0, 2.0])
def test_filter_is_consistent_on_its_own_model(force_accel):
    """On the filter's own model and noises, mean NEES of [x; d] is in the band of n + 3 and
    mean NIS in that of p, with the posterior and innovation covariances the filter reports
    (an independent route: the errors against the simulated truth); a filter told a 4x
    smaller force noise on the same data is not consistent."""
    k, z = _toy_filter(force_accel)
    tight = dict(z, force_rate=z["force_rate"] / 4, force_accel=force_accel / 4)
    names = ("force_std", "force_rate", "input_std", "coordinate_std", "force_accel")
    k_tight = DisturbanceKalman.design(
        z["G"], z["H"], z["Hd"], None, z["R"], z["dt"], **{a: tight[a] for a in names}
    )
    assert k.force_states == (6 if force_accel else 3)
    (err, innov), (err_t, _) = _fly_toy([k, k_tight], z, 20_000)
    n, burn, stride = 6, 2000, 50
    P = k.posterior[: n + 3, : n + 3]
    nees = ConsistencyTest(normalized_squares(err[burn:], P), n + 3, stride)
    nis = ConsistencyTest(normalized_squares(innov[burn:], k.innovation_covariance), n, stride)
    assert nees.consistent, nees.summary()
    assert nis.consistent, nis.summary()
    P_t = k_tight.posterior[: n + 3, : n + 3]
    over = ConsistencyTest(normalized_squares(err_t[burn:], P_t), n + 3, stride)
    assert over.mean > over.band[1], over.summary()


def test_a_run_without_the_filter_is_refused():
    """The paper's controller records no Kalman estimate: one line naming the run."""
    s = load_scenario(SCENARIOS / "sensing_tether.toml")
    s = dataclasses.replace(s, duration=1.0)
    r = simulate(s)
    assert KALMAN_NIS_COLUMN not in r.extra
    with pytest.raises(TetherheliError, match=r"sensing_tether.*no Kalman estimate"):
        kalman_consistency(r, s)


@pytest.mark.parametrize("name", SENSED)
def test_shipped_sensed_scenarios_are_consistent(name):
    """Every shipped sensed scenario flown by the MPC with its Kalman filter: mean NEES of the
    16 states [x; d] inside the 95 % band (one independent sample per error time constant,
    ``kalman_consistency``), the run completed."""
    s = load_scenario(SCENARIOS / f"{name}.toml")
    s = dataclasses.replace(s, control=dataclasses.replace(s.control, controller="mpc"))
    r = simulate(s)
    assert r.ok, r.message
    c = kalman_consistency(r, s)
    assert c.nees.dim == 16
    assert c.nees.consistent, f"{name}: NEES {c.nees.summary()}"
