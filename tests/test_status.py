"""Statuses that tell the truth (issue 9, section 4) and physically meaningless input refused
where it enters (section 3): tether release as an event, failed runs reported by every
command, sweeps that count their failures, impossible tensions, lengths and gust grids."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from tetherheli import load_scenario, simulate
from tetherheli.cli import main
from tetherheli.engine import loop as engine
from tetherheli.runs.batch import run_batch
from tetherheli.scenario.core import ActuatorSettings, Scenario
from tetherheli.wind import Step

BREAK = 25.5  # [N]: the upward step below pulls the tension to 25.71 N, the tether gives way

RELEASING = """
name = "releasing"
configuration = "tethered"
duration = 3.0
[[wind]]
type = "step"
start = 0.5
magnitude = 20.0
direction = [0, 0, 1]
[actuators]
breaking_tension = 25.5
"""


def _releasing(**changes) -> Scenario:
    """An upward 20 N step at 0.5 s lifts the helicopter; the tension peaks at 25.71 N."""
    s = Scenario(
        name="releasing",
        duration=3.0,
        wind=Step(0.5, 20.0, (0.0, 0.0, 1.0)),
        actuators=ActuatorSettings(breaking_tension=BREAK),
    )
    return s.replace(**changes)


# --- A. the tether release is an event -------------------------------------------------------


def test_release_time_is_the_first_sample_above_breaking_tension_in_both_integrators():
    """The release is recorded at the first control sample whose tension exceeds the
    breaking tension (found on the same run with an unbreakable tether), with that sample's
    tension; the compiled RK4 and the adaptive Python loop record the same sample, and the
    status is a success that says so, never a plain "completed"."""
    unbreakable = simulate(_releasing(actuators=ActuatorSettings()))
    assert unbreakable.release_time is None and unbreakable.message == "completed"
    k = int(np.argmax(unbreakable.tension > BREAK))
    assert k > 0 and unbreakable.tension[k] > BREAK >= unbreakable.tension[:k].max()
    rk4 = simulate(_releasing())
    adaptive = simulate(_releasing(), method="adaptive")
    for r in (rk4, adaptive):
        assert r.ok and r.status == engine.STATUS_OK and r.released
        assert r.release_time == unbreakable.time[k]
        assert r.message == f"completed (tether released at t = {unbreakable.time[k]:g} s)"
        assert np.all(r.tension[k:] == 0.0) and np.all(r.tension[:k] > 0.0)
    # identical trajectory up to the release: the very same tension in the compiled engine
    assert rk4.release_tension == unbreakable.tension[k]
    assert adaptive.release_tension == pytest.approx(unbreakable.tension[k], abs=1e-8)
    meta = rk4.metadata()
    assert meta["tether_release"] == {
        "time": unbreakable.time[k],
        "tension": unbreakable.tension[k],
        "breaking_tension": BREAK,
    }
    assert meta["message"] == rk4.message
    assert "tether released at t = 0.96 s" in rk4.release_note()


def test_release_in_python_rk4_loop_equals_engine():
    """A custom controller runs the Python loop; wrapping the paper's controller there must
    record the release exactly as the compiled engine does."""
    from tetherheli.control.paper import PaperController
    from tetherheli.runs.setup import engine_setup

    s = _releasing()
    setup = engine_setup(s)
    ctl = PaperController(
        setup.gain.K, setup.trim.x, setup.trim.y, setup.trim.u, setup.ctrl, setup.model.constants
    )
    python = simulate(s, controller=ctl)
    compiled = simulate(s)
    assert python.release_time == compiled.release_time
    assert python.release_tension == compiled.release_tension
    assert python.message == compiled.message


def test_batch_records_release_per_run():
    """run_batch keeps the release in its summaries: per-run accessor and messages."""
    s = _releasing()
    one = simulate(s)
    b = run_batch([s, s.replace(actuators=ActuatorSettings())], workers=1)
    assert b.ok.all()
    assert b.release(0) == (one.release_time, one.release_tension)
    assert b.release(1) is None and math.isnan(b.release_time[1])
    assert b.messages() == [one.message, "completed"]
    # the release slots extend the summary; the metrics keep their meaning
    assert engine.SUMMARY_FIELDS[-4:-2] == ("release_time", "release_tension")
    assert engine.SUMMARY_FIELDS[-2:] == ("winch_limit_time", "winch_limit")
    assert b.metrics(0)["n_samples"] == one.time.size


def test_simulate_cli_reports_release(tmp_path, capsys):
    """`simulate` prints one line per release, exits 0 (the run completed), and writes the
    release into summary.json, the run's JSON and report.md."""
    path = tmp_path / "releasing.toml"
    path.write_text(RELEASING)
    out = tmp_path / "out"
    assert main(["simulate", str(path), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    line = [x for x in err.splitlines() if "released" in x]
    assert line == [
        "tetherheli: run releasing: tether released at t = 0.96 s (tension 25.5033 N > "
        "breaking 25.5 N); continued free"
    ]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == 0
    assert summary["message"] == "completed (tether released at t = 0.96 s)"
    assert summary["tether_release"]["time"] == 0.96
    assert summary["tether_release"]["tension"] > 25.5
    run = json.loads((out / "releasing.json").read_text())
    assert run["tether_release"] == summary["tether_release"]
    report = (out / "report.md").read_text()
    assert "Status: completed (tether released at t = 0.96 s)." in report
    assert "continued free" in report


def test_comparison_reports_release(tmp_path, capsys):
    """Several runs: the released one is marked in the comparison's summary and report."""
    rel = tmp_path / "releasing.toml"
    rel.write_text(RELEASING)
    keep = tmp_path / "keep.toml"
    keep.write_text(RELEASING.replace('"releasing"', '"keep"').replace("25.5", "inf"))
    out = tmp_path / "out"
    assert main(["simulate", str(rel), str(keep), "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["runs"]["releasing"]["tether_release"]["time"] == 0.96
    assert summary["runs"]["keep"]["tether_release"] is None
    assert "completed (tether released at t = 0.96 s)" in (out / "report.md").read_text()
    assert capsys.readouterr().err.count("released") == 1


def test_montecarlo_rows_record_release(tmp_path):
    """Monte Carlo rows carry the release time and tension (NaN for a run that kept its
    tether, e.g. every free run) and the summary counts the releases per configuration."""
    from tetherheli.report import run_montecarlo
    from tetherheli.studies.montecarlo import load_montecarlo

    path = tmp_path / "mc.toml"
    path.write_text(RELEASING + "[montecarlo]\nruns = 2\nseed = 3\n")
    base, config = load_montecarlo(path)
    summary = run_montecarlo(base, config, tmp_path / "mc", chunk_size=1, progress=False)
    with (tmp_path / "mc" / "results.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    expected = simulate(base.replace(configuration="tethered"))
    for row in rows:
        if row["configuration"] == "tethered":
            assert float(row["release_time"]) == expected.release_time
            assert float(row["release_tension"]) == expected.release_tension
            assert row["message"] == expected.message
        else:
            assert math.isnan(float(row["release_time"])) and row["message"] == "completed"
    stats = summary["statistics"]
    assert stats["tethered"]["tether_released"] == 2 and stats["free"]["tether_released"] == 0


def test_env_info_reports_release():
    """The Gymnasium environment puts the release into ``info``."""
    pytest.importorskip("gymnasium")
    from tetherheli.envs.env import TetheredHoverEnv

    env = TetheredHoverEnv(scenario=_releasing(), wind=_releasing().wind, max_episode_time=3.0)
    _, info = env.reset(seed=0)
    assert info["tether_release"] is None
    released = None
    for _ in range(200):
        _, _, term, trunc, info = env.step(np.zeros(4))
        if info["tether_release"] is not None:
            released = info
            break
        assert not (term or trunc)
    assert released is not None
    assert released["tether_release"]["time"] == pytest.approx(0.96)
    assert released["tether_release"]["tension"] > BREAK
    assert "tether released" in released["message"]


# --- B. physically failed runs are reported, never a traceback -------------------------------


def test_paper_with_coarse_dt_reports_failures(tmp_path, capsys):
    """`paper --dt 1`: every run fails (the 1 s sample time cannot hold the hover). The job
    writes its outputs, records each run's status and failure time, leaves the reductions
    null / n/a, prints one line per failed run and exits 1."""
    out = tmp_path / "paper"
    assert main(["paper", "--dt", "1", "--out", str(out), "--quiet"]) == 1
    captured = capsys.readouterr()
    lines = [x for x in captured.err.splitlines() if x]
    assert len(lines) == 4 and all(x.startswith("tetherheli: run sim") for x in lines)
    assert "Traceback" not in captured.err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["reduction_percent"] == dict.fromkeys(
        ("sim1_q1_peak", "sim1_q1_rms", "sim2_q2_peak", "sim2_q2_rms")
    )
    statuses = summary["statuses"]
    assert set(statuses) == {"sim1_free", "sim1_tethered", "sim2_free", "sim2_tethered"}
    for key, st in statuses.items():
        run = json.loads((out / f"{key}.json").read_text())
        assert not st["completed"] and st["status"] == run["status"] != 0
        assert st["message"] == run["message"]
        # the failure is detected at the first control sample not recorded
        n = len((out / f"{key}.csv").read_text().splitlines()) - 1
        assert st["end_time"] == n * 1.0
        assert f"run {key} failed at t = {st['end_time']:g} s: {st['message']}" in captured.err
    report = (out / "report.md").read_text()
    assert "## Failed runs" in report and "NaN" not in report and "nan" not in report
    assert "| n/a |" in report and "No reduction can be computed" in report
    for fig in ("fig6_sim1_outputs", "fig7_sim1_inputs", "fig8_sim2_outputs", "fig9_sim2_inputs"):
        assert (out / f"{fig}.png").stat().st_size > 0


def test_paper_summary_of_successful_runs_records_completed_statuses():
    """The four paper runs complete; summary's statuses say so (numbers as before)."""
    from tetherheli.report.paper import paper_summary
    from tetherheli.scenario.core import paper_scenario

    results = {
        f"sim{s}_{c}": simulate(paper_scenario(s, c).replace(duration=20.0))
        for s in (1, 2)
        for c in ("free", "tethered")
    }
    summary = paper_summary(results, dt=0.01, pulse_duration=1.0)
    assert all(
        st["completed"] and st["message"] == "completed" for st in summary["statuses"].values()
    )
    assert all(isinstance(v, float) for v in summary["reduction_percent"].values())


def _sensing_failing_text() -> str:
    """The shipped GPS sensing scenario, 20 s, with a 3 N m cyclic limit that loses it."""
    text = (Path(__file__).resolve().parents[1] / "scenarios" / "sensing_gps.toml").read_text()
    text = text.replace('name = "sensing_gps"', 'name = "sensing_fails"')
    text = text.replace("duration = 60.0", "duration = 20.0")
    return text + "\n[actuators]\nu_min = [-1e9, -3.0, -3.0, -1e9]\nu_max = [1e9, 3.0, 3.0, 1e9]\n"


def test_sensing_with_failing_scenario_reports_it(tmp_path, capsys):
    """`sensing` with a scenario whose saturated cyclic loses the helicopter: outputs
    written, the run's status and failure time in summary.json, one line, exit 1."""
    path = tmp_path / "fails.toml"
    path.write_text(_sensing_failing_text())
    direct = simulate(load_scenario(path))
    assert not direct.ok
    out = tmp_path / "sensing"
    assert main(["sensing", str(path), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.strip().splitlines() == [
        f"tetherheli: run sensing_fails failed at t = {direct.end_time:g} s: {direct.message} "
        f"(partial results in {out})"
    ]
    info = json.loads((out / "summary.json").read_text())
    row = info["runs"]["sensing_fails"]
    assert info["failed"] == ["sensing_fails"]
    assert row["status"] == direct.status and row["end_time"] == direct.end_time
    assert row["true_deviation_rms"]["q1"] > 0.0
    assert (out / "sensing.png").stat().st_size > 0


def test_unplottable_wind_keeps_status_and_figures(tmp_path, capsys):
    """A 1e308 N wind pulse: the run becomes non-finite; its figures leave out the samples
    that cannot be drawn (with a note) instead of crashing, and the status is kept."""
    from tetherheli.viz.plots import PLOT_LIMIT, figure_outputs, plottable

    path = tmp_path / "huge.toml"
    path.write_text(
        'name = "huge"\nduration = 3.0\n[[wind]]\ntype = "pulse"\nstart = 1.0\n'
        "duration = 1.0\nmagnitude = 1e308\ndirection = [1, 0, 0]\n"
    )
    out = tmp_path / "out"
    assert main(["simulate", str(path), "--out", str(out)]) == 1
    assert "Traceback" not in capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == engine.STATUS_NONFINITE
    assert (out / "outputs.png").stat().st_size > 0 and (out / "inputs.png").exists()
    r = simulate(load_scenario(path))
    assert r.end_time == pytest.approx(1.01) and np.abs(r.wind).max() > PLOT_LIMIT
    clean, dropped = plottable(r.wind[:, 0])
    assert dropped == int(np.sum(np.abs(r.wind[:, 0]) > PLOT_LIMIT)) > 0
    assert np.all(np.isnan(clean[np.abs(r.wind[:, 0]) > PLOT_LIMIT]))
    fig = figure_outputs([r])
    assert any("not drawn" in t.get_text() for t in fig.texts)
    assert "stopped at t = 1.01 s" in fig.axes[0].get_legend().get_texts()[0].get_text()


# --- C. a sweep tells the truth --------------------------------------------------------------


def test_sweep_records_impossible_and_failed_points():
    """A T_ref sweep beyond what the tether gives records those points as invalid (with the
    reason, metric NaN) and still runs the others; a cyclic limit below the hover need is
    invalid, one that loses the helicopter failed; neither is reported as completed."""
    from tetherheli.scenario.core import paper_scenario
    from tetherheli.studies.sweep import sweep

    s = paper_scenario(1, "tethered").replace(duration=12.0)
    r = sweep(s, "tension_control.T_ref", np.array([20.0, 199.0, 201.0, 450.0]), "rms_q1")
    assert r.completed == (True, True, False, False) and r.failed == (2, 3)
    assert np.all(np.isfinite(r.metric[:2])) and np.all(np.isnan(r.metric[2:]))
    for st in r.statuses[2:]:
        assert st.startswith("invalid: params.tension_control.T_ref") and "<= 200 N" in st
    assert r.as_dict()["failed"] == 2 and r.as_dict()["completed"] == [True, True, False, False]
    full = paper_scenario(1, "tethered")  # 3 N m loses the helicopter at about 20 s
    c = sweep(full, "actuators.cyclic_limit", np.array([0.5, 3.0, 5.0]), "peak_q1")
    assert c.statuses[0].startswith("invalid: actuators.u_min/u_max") and "hover" in c.statuses[0]
    assert c.completed == (False, False, True) and c.best_value == 5.0


def test_sweep_cli_exits_1_when_a_point_fails(tmp_path, capsys):
    """`sweep` with failed or invalid points: outputs written (the CSV quotes reasons with
    commas), one stderr line per such point and a count, exit 1; all completed: exit 0."""
    scenario = str(Path(__file__).resolve().parents[1] / "scenarios" / "paper_sim1_tethered.toml")
    out = tmp_path / "sw"
    argv = ["sweep", scenario, "--param", "tension_control.T_ref", "--values", "20,450", "--quiet"]
    assert main([*argv, "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2
    assert err[0].startswith("tetherheli: sweep point tension_control.T_ref = 450: invalid:")
    assert err[1].startswith("tetherheli: 1 of 2 sweep points failed or were invalid")
    with (out / "sweep.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [r["status"][:8] for r in rows] == ["complete", "invalid:"]
    info = json.loads((out / "summary.json").read_text())
    assert info["completed"] == [True, False] and info["metric_values"][1] is None
    assert (
        main(["sweep", scenario, "--param", "tether.K_C", "--values", "40", "--out", str(out)]) == 0
    )


# --- D. physically meaningless input refused where it enters ---------------------------------


def test_trim_refuses_tension_beyond_tether_and_names_the_bound(paper):
    """LN = q9 - TC/K_C (eq 28) must stay >= q9 / 2: at most K_C q9 / 2 = 200 N at 10 m for
    the paper's tether; 500 N (LN = -2.5 m) is refused, 200 N gives LN = 5 m."""
    from tetherheli import InfeasibleError, ParameterError
    from tetherheli.model.trim import hover_trim
    from tetherheli.params import MAX_TETHER_STRAIN

    assert paper.tether.max_tension(10.0) == 200.0
    assert paper.tether.natural_length(10.0, 25.0) == 9.375  # Table V
    t = hover_trim(paper, 200.0, 10.0)
    ln = t.x[12]
    assert ln == 5.0 and (10.0 - ln) == MAX_TETHER_STRAIN * ln
    for tension in (200.0001, 400.0, 500.0):
        with pytest.raises(InfeasibleError, match=r"tension = .* allowed: a tension <= 200 N"):
            hover_trim(paper, tension, 10.0)
    assert issubclass(InfeasibleError, ParameterError)
    # the bound scales with the length: 20 N at 1 m
    with pytest.raises(InfeasibleError, match="<= 20 N"):
        hover_trim(paper, 25.0, 1.0)


def test_trim_cli_refuses_impossible_tension_and_length(capsys):
    assert main(["trim", "--tension", "500"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "tension = 500.0" in err[0] and "<= 200 N" in err[0]
    assert "LN = q9 - TC/K_C = -2.5 m" in err[0]
    assert main(["trim", "--q9", "1e308"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "tetherheli: error: q9 = 1e+308 is invalid; allowed: a tether length in [0.5, 1000] m"
    ]
    assert main(["trim", "--tension", "200", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["trim"]["LN"] == 5.0


@pytest.mark.parametrize(
    ("text", "field", "exc"),
    [
        ("[params.tension_control]\nT_ref = 450.0\n", "params.tension_control.T_ref", "Infeasible"),
        ("q9 = 1.0\n", "params.tension_control.T_ref", "Infeasible"),  # 25 N > 20 N at 1 m
        ("[params.tether]\nK_C = 4.0\n", "params.tension_control.T_ref", "Infeasible"),
        ("q9 = 1e308\n", "q9", "Parameter"),
        ("q9 = 0.1\n", "q9", "Parameter"),
        ("[params.tether]\nL_N0 = 1e308\n", "tether.L_N0", "Parameter"),
        ("[params.helicopter]\nd_O_P3 = -300.0\n", "helicopter.d_O_P3", "Parameter"),
        ("[params.helicopter]\nrotor_drag_arm = 50.0\n", "helicopter.rotor_drag_arm", "Parameter"),
    ],
)
def test_scenario_refuses_meaningless_values(tmp_path, capsys, text, field, exc):
    """Each is refused when the scenario is loaded, with one line naming the field (exit 2
    from the CLI); the free configuration does not use T_ref."""
    from tetherheli import InfeasibleError, ParameterError

    path = tmp_path / "bad.toml"
    path.write_text('name = "bad"\nduration = 2.0\n' + text)
    expected = InfeasibleError if exc == "Infeasible" else ParameterError
    with pytest.raises(expected, match=field.replace(".", r"\.")):
        load_scenario(path)
    assert main(["simulate", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and field in err[0]
    assert not (tmp_path / "out").exists()
    if exc == "Infeasible":
        path.write_text('name = "bad"\nconfiguration = "free"\nduration = 2.0\n' + text)
        assert load_scenario(path).configuration == "free"


def test_short_gust_grid_refused_in_every_path(tmp_path, capsys):
    """A turbulence whose gust grid ends before the run is refused at set-up by the one
    check (``check_wind_covers``): the scenario (both integrators, batch, sweep, Monte
    Carlo use it) and the Gymnasium environment; one grid covering the run is accepted."""
    from tetherheli import ParameterError
    from tetherheli.wind import (
        DragModel,
        GaussMarkovTurbulence,
        Turbulence,
        check_wind_covers,
    )

    drag = DragModel(cd_area_m2=(0.4, 0.4, 0.8))
    turb = Turbulence(GaussMarkovTurbulence(), drag, seed=1, duration=2.0, dt=0.1)
    with pytest.raises(ParameterError, match=r"wind\.duration = 2\.0 .*run's duration \(3 s"):
        Scenario(duration=3.0, wind=turb)
    with pytest.raises(ParameterError, match=r"wind\[1\]\.duration"):
        Scenario(duration=3.0, wind=Step(0.5, 1.0, (1.0, 0.0, 0.0)) + turb)
    ok = Scenario(duration=2.0, wind=turb)
    assert simulate(ok).ok and simulate(ok, method="adaptive").ok
    check_wind_covers(turb, 2.0)
    # the scenario file: one line naming the field, exit 2
    text = Path(__file__).resolve().parents[1] / "scenarios" / "turbulence_hover_free.toml"
    body = text.read_text().replace("duration = 120.0  # [s]", "duration = 130.0  # [s]")
    assert "duration = 130.0" in body
    path = tmp_path / "short.toml"
    path.write_text(body)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "wind.duration = 120.0" in err[0] and "130 s" in err[0]
    # the environment: an episode longer than the gust series is refused (when built)
    pytest.importorskip("gymnasium")
    from tetherheli.envs.env import TetheredHoverEnv

    with pytest.raises(ParameterError, match=r"wind\.duration"):
        TetheredHoverEnv(wind=turb, max_episode_time=3.0).reset(seed=0)
