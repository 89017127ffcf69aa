"""Design sweeps and the tension bound of eq 40."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tetherheli import ParameterError, Params
from tetherheli._io import read_json
from tetherheli.cli import main
from tetherheli.scenario.core import load_scenario, paper_scenario, scenario_from_dict
from tetherheli.studies.sweep import paper_cyclic_limit, sweep, tension_bound

SIM1_TETHERED = str(Path(__file__).resolve().parents[1] / "scenarios" / "paper_sim1_tethered.toml")


def test_eq40_bound_is_twenty_percent_of_hover_lift(paper):
    """Eq 40: tmax / |dO-P,3 - dO-HO,3| = 0.2 fMR3,hover (Table IV: 0.2 x 123.7633 N)."""
    limit = paper_cyclic_limit(paper)
    assert tension_bound(paper, limit) == pytest.approx(0.2 * 123.7633, abs=5e-5)
    assert tension_bound(paper, 5.0) == pytest.approx(5.0 / 0.2045951, rel=1e-6)


def test_tension_sweep_best_value_and_best_within_bound():
    """More tension steadies the hover (Sec. IV-A); without actuator limits the eq-40 bound
    comes from the paper's 20% rule and is not applied to the runs: the best value is the
    largest tension, the best within the bound 20 N."""
    s = paper_scenario(1, "tethered").replace(duration=40.0)
    r = sweep(s, "tension_control.T_ref", np.array([0.0, 10.0, 20.0, 30.0]), "rms_q1")
    assert np.all(np.diff(r.metric) < 0)
    assert r.bound == pytest.approx(24.7527, abs=1e-3)
    assert not r.limit_applied and "not applied" in r.limit_source
    assert r.best_value == 30.0 and r.best_within_bound == 20.0


def test_sweep_other_parameters():
    """KC and dt sweeps: each point equals a separate simulate() of the scenario with that
    value (run_metrics of the run, a second route), the two KC values give different
    results (the value reaches the run), and halving dt changes the peak by < 5 cm."""
    from tetherheli import simulate
    from tetherheli.analysis import run_metrics
    from tetherheli.scenario.core import ControlSettings

    s = paper_scenario(1, "tethered").replace(duration=15.0)
    r = sweep(s, "tether.K_C", np.array([20.0, 80.0]), "peak_q1")
    assert r.bound is None and r.metric[0] != r.metric[1]
    for v, m in zip(r.values, r.metric, strict=True):
        one = simulate(s.replace(params=s.params.replace({"tether.K_C": float(v)})))
        assert m == pytest.approx(run_metrics(one).peak_abs_dev["q1"], rel=1e-12)
    r = sweep(s, "control.dt", np.array([0.01, 0.005]), "peak_q1")
    one = simulate(s.replace(control=ControlSettings(dt=0.005)))
    assert r.metric[1] == pytest.approx(run_metrics(one).peak_abs_dev["q1"], rel=1e-12)
    assert abs(r.metric[0] - r.metric[1]) < 0.05


@pytest.mark.parametrize(
    ("param", "metric", "match"),
    [("tether.KC", "rms_q1", "parameter"), ("tether.K_C", "rms_q9", "metric")],
)
def test_sweep_bad_names(param, metric, match):
    with pytest.raises(ParameterError, match=match):
        sweep(paper_scenario(1, "tethered"), param, np.array([1.0]), metric)


def test_sweep_cli(tmp_path, capsys):
    out = tmp_path / "sw"
    argv = [
        "sweep",
        SIM1_TETHERED,
        "--param",
        "tension_control.T_ref",
        "--values",
        "10,20",
        "--out",
        str(out),
        "--quiet",
    ]
    assert main(argv) == 0
    info = read_json(out / "summary.json")  # the configuration's "Infinity" strings: floats
    assert info["best_value"] == 20.0 and (out / "sweep.png").exists()
    # the summary records the whole swept scenario, which re-creates it
    recorded = scenario_from_dict(info["configuration"])
    assert recorded == load_scenario(SIM1_TETHERED)
    bad = [
        "sweep",
        SIM1_TETHERED,
        "--param",
        "nope",
        "--values",
        "1",
        "--out",
        str(tmp_path / "x"),
    ]
    assert main(bad) == 2
    assert not (tmp_path / "x").exists()
    assert main([*bad[:5], "1:2:0", "--out", str(tmp_path / "y")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 2


def test_params_field_docs_cover_sweepable_names():
    assert "tension_control.T_ref" in Params.field_docs()


def test_sweep_actuator_settings_and_batch_equals_simulate():
    """Actuator settings sweep like parameters; the compiled batch gives simulate's metric
    (to rounding) and the failed runs' statuses. A cyclic limit (eq 40's tmax_MR1,2) between
    3 and 4 N m separates lost from held in simulation 1 (the paper gives none)."""
    from tetherheli import simulate
    from tetherheli.analysis import run_metrics
    from tetherheli.scenario.core import ActuatorSettings

    s = paper_scenario(1, "tethered")
    r = sweep(s, "actuators.cyclic_limit", np.array([3.0, 3.5, 5.0]), "peak_q1")
    assert "diverged" in r.statuses[0] and np.isnan(r.metric[0])
    assert r.statuses[1:] == ("completed", "completed")
    limits = dict(u_min=(-np.inf, -3.5, -3.5, -np.inf), u_max=(np.inf, 3.5, 3.5, np.inf))
    one = simulate(s.replace(actuators=ActuatorSettings(**limits)))
    assert r.metric[1] == pytest.approx(run_metrics(one).peak_abs_dev["q1"], rel=1e-12)
    lag = sweep(s.replace(duration=12.0), "actuators.time_constant", np.array([0.0, 0.05]))
    assert lag.metric[0] != lag.metric[1]
    with pytest.raises(ParameterError, match=r"actuators\.cyclic_limit"):
        sweep(s, "actuators.cyclic_limit", np.array([-1.0]))


@pytest.mark.parametrize("find_min", [False, True], ids=["sweep", "find_min"])
def test_sweep_default_metric_and_parquet_table(tmp_path, find_min):
    """Without --metric the sweep (and its --find-min) reports peak_q1, the default of every
    command (``names.DEFAULT_METRIC``; the sweep's was rms_q1); ``--format parquet`` writes
    sweep.parquet, which pyarrow reads back equal to sweep.csv, units in its fields."""
    import pyarrow.parquet as pq

    from tests.tables import assert_same_table

    scenario = tmp_path / "short.toml"
    scenario.write_text(load_scenario(SIM1_TETHERED).replace(duration=12.0).to_toml())
    what = (
        ["--find-min", "actuators.cyclic_limit", "--values", "2,8", "--tol", "4"]
        if find_min
        else ["--param", "tension_control.T_ref", "--values", "10,20"]
    )
    argv = ["sweep", str(scenario), *what, "--quiet"]
    assert main([*argv, "--out", str(tmp_path / "c")]) in (0, 1)
    assert read_json(tmp_path / "c" / "summary.json")["metric"] == "peak_q1"
    assert main([*argv, "--format", "parquet", "--out", str(tmp_path / "p")]) in (0, 1)
    assert not (tmp_path / "p" / "sweep.csv").exists()
    assert_same_table(tmp_path / "c" / "sweep.csv", tmp_path / "p" / "sweep.parquet")
    schema = pq.read_schema(tmp_path / "p" / "sweep.parquet")
    first = "cyclic_limit_Nm" if find_min else "value"
    assert schema.field(first).metadata[b"units"] == (b"N m" if find_min else b"N")
    assert schema.field("metric").metadata[b"units"] == b"m"
