"""Eq 40 said right: the cyclic limit applied to sweep runs, the tether's real moment about HO
against the eq-40 worst case, the bound from the scenario's limits, and the smallest cyclic
limit that keeps the peak deviation within 10% of the unlimited run."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tetherheli import simulate
from tetherheli._io import read_json
from tetherheli.analysis import run_metrics, tether_moment
from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.scenario.core import (
    ActuatorSettings,
    load_scenario,
    paper_scenario,
    scenario_from_dict,
)
from tetherheli.studies.cyclic_limit import (
    bisect_criterion,
    bracket_from_above,
    minimum_cyclic_limit,
)
from tetherheli.studies.sweep import paper_cyclic_limit, scenario_cyclic_limit, sweep

from .newton_euler import dcm_table_i

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
INF = math.inf


def _cyclic(limit: float) -> ActuatorSettings:
    return ActuatorSettings(u_min=(-INF, -limit, -limit, -INF), u_max=(INF, limit, limit, INF))


def test_tether_moment_is_r_cross_f_by_hand(paper, rng):
    """Eqs 33-34 / 55 (C1, C2): the moment about HO of the tether force -TC c3 at P, with
    r_HO->P = (dO-P,3 - dO-HO,3) f3, c3 = [s8, -s7 c8, c7 c8] (eqs 43-45) and f_j from Table
    I typed by hand, expressed in F; against ``analysis.tether_moment`` on random states."""
    from tetherheli.results.result import SimulationResult

    n = 20
    x = np.zeros((n, 13))
    x[:, 0:5] = rng.uniform(-0.5, 0.5, (n, 5))  # q4..q8
    x[:, 5] = rng.uniform(5.0, 15.0, n)  # q9
    x[:, 12] = x[:, 5] - rng.uniform(0.0, 1.0, n)  # LN
    tension = paper.tether.K_C * (x[:, 5] - x[:, 12])
    arm = paper.helicopter.tether_arm
    expected = np.empty((n, 2))
    for k in range(n):
        q4, q5, q6, q7, q8 = x[k, :5]
        R = dcm_table_i(q4, q5, q6)
        c3 = np.array([np.sin(q8), -np.sin(q7) * np.cos(q8), np.cos(q7) * np.cos(q8)])
        m_N = np.cross(arm * R[:, 2], -tension[k] * c3)
        expected[k] = (R.T @ m_N)[:2]
    base = simulate(paper_scenario(1, "tethered").replace(duration=0.01))
    result = SimulationResult(
        **{**base.__dict__, "states": x, "tension": tension, "time": np.arange(n) * 0.01}
    )
    tm = tether_moment(result, paper)
    np.testing.assert_allclose(tm.moment, expected, rtol=1e-12, atol=1e-12)
    # |C| = |arm| TC sin(angle between tether and shaft)
    f3 = np.array([dcm_table_i(*x[k, :3])[:, 2] for k in range(n)])
    c3 = np.column_stack(
        [np.sin(x[:, 4]), -np.sin(x[:, 3]) * np.cos(x[:, 4]), np.cos(x[:, 3]) * np.cos(x[:, 4])]
    )
    angle = np.degrees(np.arccos(np.einsum("ij,ij->i", f3, c3)))
    np.testing.assert_allclose(tm.angle_deg, angle, rtol=0, atol=1e-6)
    np.testing.assert_allclose(tm.worst_case, abs(arm) * tension, rtol=1e-15)


def test_sweep_saturates_the_runs_at_the_given_cyclic_limit():
    """With ``cyclic_limit`` every run's tMR1, tMR2 saturate there: a point equals simulate()
    of the scenario with those [actuators] limits and differs from the unlimited sweep."""
    s = paper_scenario(1, "tethered")
    limit = paper_cyclic_limit(s.params)  # 5.0643 N m
    limited = sweep(s, "tension_control.T_ref", np.array([25.0]), "rms_q1", cyclic_limit=limit)
    free = sweep(s, "tension_control.T_ref", np.array([25.0]), "rms_q1", moments=False)
    one = simulate(s.replace(actuators=_cyclic(limit)))
    assert np.abs(one.inputs[:, 1:3]).max() == pytest.approx(limit, rel=1e-12)  # it binds
    assert limited.metric[0] == pytest.approx(run_metrics(one).rms_dev["q1"], rel=1e-12)
    assert limited.metric[0] != free.metric[0]
    assert limited.limit_applied and limited.cyclic_limit == limit
    with pytest.raises(ParameterError, match="cyclic_limit"):
        sweep(s, "actuators.cyclic_limit", np.array([4.0]), cyclic_limit=4.0)


def test_bound_follows_the_scenario_actuator_limits(paper):
    """A scenario with +-4 N m cyclic limits reports eq 40's bound 4 / |arm| = 19.55 N (was
    24.75 N, the 20% rule, whatever the limits)."""
    s = paper_scenario(1, "tethered").replace(duration=1.0, actuators=_cyclic(4.0))
    assert scenario_cyclic_limit(s) == 4.0
    r = sweep(s, "tension_control.T_ref", np.array([10.0]), moments=False)
    assert r.bound == pytest.approx(4.0 / abs(paper.helicopter.tether_arm), rel=1e-12)
    assert r.bound == pytest.approx(19.551, abs=1e-3)
    assert r.limit_applied and r.cyclic_limit == 4.0
    assert scenario_cyclic_limit(paper_scenario(1, "tethered")) is None


def test_eq40_is_a_worst_case_in_simulation_1():
    """Audit of issue 11: saturated at the paper's 20% rule (+-5.064 N m) simulation 1
    completes at 25 N (the paper's own Tref, above its 24.75 N bound) and at 80 N, RMS q1 keeps
    falling (0.679 -> 0.387 m), because the tether's real peak moment (1.36 and 2.93 N m, on
    f2) stays below the authority while eq 40's worst case |arm| TC (5.1 and 16.4 N m)
    exceeds it: the tether stays within 16 deg of the shaft."""
    s = paper_scenario(1, "tethered")
    limit = paper_cyclic_limit(s.params)
    r = sweep(s, "tension_control.T_ref", np.array([25.0, 80.0]), cyclic_limit=limit)
    assert all(r.completed)
    assert r.metric[1] < r.metric[0]
    assert r.bound < 25.0
    assert np.all(r.peak_tether_moment < limit)
    assert np.all(r.peak_worst_case_moment > limit)
    assert np.all(r.peak_tether_angle_deg < 16.0)
    # the moment reproduces: the run at 80 N recorded and measured separately
    run = simulate(
        s.replace(params=s.params.replace({"tension_control.T_ref": 80.0})).replace(
            actuators=_cyclic(limit)
        )
    )
    assert r.peak_tether_moment[1] == tether_moment(run, s.params).peak


def test_bracket_from_above_and_bisection_on_a_non_monotone_criterion():
    """The bracket is the last failing grid point below the top run of passes; bisection then
    keeps false at lo, true at hi. A criterion true on [1, 2) and on [4.37, inf) (like the free
    simulation 1's completions) gives [4.37 - tol, 4.37]."""
    assert bracket_from_above(np.array([True, False, True, True])) == 2
    assert bracket_from_above(np.array([True, True])) == 0
    assert bracket_from_above(np.array([True, False])) is None

    def criterion(v: float) -> bool:
        return 1.0 <= v < 2.0 or v >= 4.37

    grid = np.arange(1.0, 8.01, 0.5)
    i = bracket_from_above(np.array([criterion(v) for v in grid]))
    assert grid[i - 1] == 4.0 and grid[i] == 4.5
    lo, hi, evaluated = bisect_criterion(grid[i - 1], grid[i], criterion, 1e-3)
    assert not criterion(lo) and criterion(hi) and hi - lo <= 1e-3
    assert lo < 4.37 <= hi
    assert len(evaluated) == math.ceil(math.log2(0.5 / 1e-3))


def test_minimum_cyclic_limit_contains_the_fine_scan_answer():
    """The interval from grid scan + bisection contains the answer of an independent fine
    scan (step 2 mN m) on a cheap case: free simulation 1 up to 20 s (the pulse)."""
    s = paper_scenario(1, "free").replace(duration=20.0)
    r = minimum_cyclic_limit(s, np.arange(3.0, 8.01, 0.25), within=0.10, tol=0.002)
    assert r.lo is not None and r.hi is not None and r.hi - r.lo <= 0.002
    step = 0.002
    fine = np.round(np.arange(3.5, 5.0 + step / 2, step), 9)
    f = sweep(s, "actuators.cyclic_limit", fine, "peak_q1")
    meets = np.isfinite(f.metric) & (f.metric <= 1.10 * r.reference)
    v = fine[bracket_from_above(meets)]
    assert r.lo < v < r.hi + step
    # the reference is the run without cyclic limits
    assert r.reference == pytest.approx(run_metrics(simulate(s)).peak_abs_dev["q1"], rel=1e-12)


def test_find_min_cli(tmp_path, capsys):
    """``tetherheli sweep --find-min actuators.cyclic_limit``: the interval on stdout and in
    summary.json; --cyclic-limit is refused with it."""
    text = (SCENARIOS / "paper_sim1_free.toml").read_text()
    scen = tmp_path / "short.toml"
    scen.write_text(text.replace("duration = 60.0", "duration = 20.0"))
    out = tmp_path / "fm"
    argv = ["sweep", str(scen), "--find-min", "actuators.cyclic_limit", "--values", "3:8:11"]
    assert main([*argv, "--tol", "0.01", "--out", str(out)]) == 0
    info = read_json(out / "summary.json")  # the configuration's "Infinity" strings: floats
    assert info["metric"] == "peak_q1" and info["within"] == 0.1
    assert info["hi"] - info["lo"] <= 0.01
    assert scenario_from_dict(info["configuration"]) == load_scenario(scen)
    assert info["interval"] in capsys.readouterr().out
    assert (out / "sweep.png").exists()
    bad = [*argv, "--cyclic-limit", "4", "--out", str(tmp_path / "x")]
    assert main(bad) == 2
