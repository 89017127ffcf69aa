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
from tetherheli.disturbances import Step
from tetherheli.sim import engine
from tetherheli.sim.batch import run_batch
from tetherheli.sim.scenario import ActuatorSettings, Scenario

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
    from tetherheli.sim.simulate import _engine_setup

    s = _releasing()
    setup = _engine_setup(s)
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
    assert engine.SUMMARY_FIELDS[-2:] == ("release_time", "release_tension")
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
    from tetherheli.montecarlo import load_montecarlo, run_montecarlo

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
    from tetherheli.envs import TetheredHoverEnv

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
    assert main(["paper", "--dt", "1", "--out", str(out)]) == 1
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
    from tetherheli.report import paper_summary
    from tetherheli.sim.scenario import paper_scenario

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
    assert main(["sensing", "--scenario", str(path), "--out", str(out)]) == 1
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
