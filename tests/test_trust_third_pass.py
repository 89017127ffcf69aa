"""Issue 43 ("Trust, third pass"), the engine's findings: every command passes the one
actuator stage last (finding 2), a run whose recorded values are not finite is never completed
(finding 5), one success rule (finding 7), the landing's and Monte Carlo's messages (finding
13) and the touchdown limits' physical ranges (finding 15). Each test failed on b9b549d."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tetherheli import simulate
from tetherheli._validation import trusted
from tetherheli.base.motion import VelocityBase
from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.runs.batch import _finished, run_batch
from tetherheli.scenario.core import scenario_from_dict
from tetherheli.scenario.tables import ActuatorSettings, BaseSettings
from tetherheli.shipped import shipped_scenario
from tetherheli.status import (
    SUCCESS_STATUSES,
    Status,
    finite_status,
    is_success,
    markdown_table,
    stopped,
)

ROOT = Path(__file__).resolve().parents[1]


def _landing(duration: float, **actuators) -> object:
    s = shipped_scenario("landing_calm_deck").replace(duration=duration)
    if actuators:
        s = s.replace(actuators=ActuatorSettings(**actuators))
    return s


@pytest.fixture(scope="module")
def landed():
    """The calm-deck landing flown to its touchdown (about 37 s)."""
    s = _landing(45.0)
    return s, simulate(s)


def test_the_reel_rate_limit_holds_in_a_landing():
    """Finding 2: with ``[actuators] reel_rate_limit = 0.01`` the landing's reel-rate
    feed-forward (0.3 m/s of descent) was added after the limiter: the recorded rate reached
    0.31 m/s and the run "landed". Now every recorded rate is within 0.01 m/s, the recorded
    series keep every limit, and the landing does not land (it cannot reel in)."""
    r = simulate(_landing(12.0, reel_rate_limit=0.01))
    assert np.abs(r.reel_rate).max() <= 0.01 * (1 + 1e-12)
    assert np.abs(r.reel_rate).max() == pytest.approx(0.01)  # the limit binds
    assert r.limit_violations() == []
    assert r.status != Status.LANDED


def test_the_reel_rate_limit_holds_for_the_ground_reference_over_a_moving_base():
    """Finding 2: ``reference = "ground"`` over a ship under way feeds dq9/dt forward; the
    limit holds there too (the one actuator stage, last)."""
    s = scenario_from_dict(
        {
            "configuration": "tethered",
            "duration": 3.0,
            "control": {"reference": "ground"},
            "base": {"motion": "velocity", "velocity": [1.0, 0.0, 0.0]},
            "actuators": {"reel_rate_limit": 0.05},
        }
    )
    free = s.replace(actuators=ActuatorSettings())
    unlimited = simulate(free)
    assert np.abs(unlimited.reel_rate).max() > 0.2  # the feed-forward asks for more
    r = simulate(s)
    assert np.abs(r.reel_rate).max() <= 0.05 * (1 + 1e-12)
    assert r.limit_violations() == []


def test_limit_violations_reports_a_series_beyond_its_limit(landed):
    """The independent check names the limit, the worst value and its time."""
    _, r = landed
    assert r.limit_violations() == []
    cfg = {**r.configuration, "actuators": {**r.configuration["actuators"]}}
    cfg["actuators"]["reel_rate_limit"] = 0.01
    broken = type(r)(**{**r.__dict__, "configuration": cfg})
    (line,) = broken.limit_violations()
    assert line.startswith("actuators.reel_rate_limit: ") and "outside [-0.01, 0.01]" in line


def test_a_run_whose_recorded_values_overflow_is_never_completed():
    """Finding 5 (the engine's side): ``base.velocity = [1e308, 0, 0]`` (now refused by the
    scenario's bounds; flown here past them) recorded inf in 321 of 501 rows with status 0.
    A successful run with a non-finite recorded value is NONFINITE."""
    s = scenario_from_dict(
        {"configuration": "tethered", "duration": 5.0, "base": {"motion": "velocity"}}
    )
    absurd = trusted(BaseSettings, motion="velocity", velocity=(1e308, 0.0, 0.0))
    object.__setattr__(s, "base", absurd)
    object.__setattr__(s, "_base_motion", trusted(VelocityBase, velocity=absurd.velocity))
    r = simulate(s)
    assert r.status == Status.NONFINITE and not r.ok
    assert "non-finite" in r.message
    assert finite_status(Status.OK, np.array([1.0, math.inf])) == Status.NONFINITE
    assert finite_status(Status.LANDED, np.array([np.nan])) == Status.NONFINITE
    assert finite_status(Status.GROUND, np.array([np.nan])) == Status.GROUND  # its own
    assert finite_status(Status.OK, np.array([1.0]), np.array([2], dtype=int)) == Status.OK


def test_a_batch_run_whose_metrics_are_not_finite_is_never_completed():
    """Finding 5 for run_batch: its summaries' metrics (not the NaN of "no release")."""
    summaries = np.zeros((2, 15))
    summaries[:, 11:] = np.nan  # release and payout-limit slots: none
    summaries[1, 0] = math.inf
    status = np.array([Status.OK, Status.OK])
    batch = _finished(summaries, status, np.array([5, 5]), ["", ""])
    assert batch.status.tolist() == [Status.OK, Status.NONFINITE]


def test_one_success_rule():
    """Finding 7: OK and LANDED are the successes, for one status and for arrays."""
    assert SUCCESS_STATUSES == (Status.OK, Status.LANDED)
    assert [s for s in Status if s.is_success] == [Status.OK, Status.LANDED]
    codes = np.array([int(s) for s in Status])
    assert is_success(codes).tolist() == [s.is_success for s in Status]


def test_a_landed_run_succeeds_in_run_batch_as_in_simulate(landed):
    """Finding 7: ``run_batch`` said ``ok = False`` where ``simulate`` said True."""
    s, r = landed
    assert r.status == Status.LANDED and r.ok
    batch = run_batch([s], workers=1)
    assert batch.status.tolist() == [Status.LANDED]
    assert batch.ok.tolist() == [True]


def test_a_sweep_over_a_landing_counts_landed_points_as_successes(tmp_path, capsys):
    """Finding 7: ``sweep`` over a landing printed "landed" then "2 of 2 sweep points
    failed" (exit 1)."""
    path = tmp_path / "land.toml"
    assert main(["scenarios", "landing_calm_deck", "--out", str(path)]) == 0
    text = path.read_text(encoding="utf-8").replace("duration = 60.0", "duration = 45.0")
    path.write_text(text, encoding="utf-8")
    args = ["sweep", str(path), "--param", "actuators.reel_rate_limit", "--values", "1"]
    code = main([*args, "--out", str(tmp_path / "out"), "--workers", "1"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "landed" in out and "failed" not in err


def test_the_statuses_page_lists_every_status():
    """Finding 7: docs/tutorials/statuses.md listed codes 0-9 only; its table is
    ``status.markdown_table()`` (``docs/regenerate_tables.py --only statuses``)."""
    page = (ROOT / "docs" / "tutorials" / "statuses.md").read_text(encoding="utf-8")
    assert markdown_table() in page
    assert all(f"`{s.name}`" in page for s in Status)


def test_a_landing_that_did_not_touch_down_ended_at_the_runs_end():
    """Finding 13: NOT_LANDED said "stopped at t = 60.01 s" for a 60 s run; it ran to its
    end, at its last sample."""
    r = simulate(_landing(6.0))
    assert r.status == Status.NOT_LANDED
    assert not stopped(r.status)
    assert r.end_time == pytest.approx(6.0)
    assert stopped(Status.GROUND) and not stopped(Status.LANDED)


def test_montecarlo_of_a_landing_is_refused_for_its_own_reason(tmp_path, capsys):
    """Finding 13: ``montecarlo`` of a landing file was refused as "'none' in the free
    configuration" (the file is tethered); a file without [montecarlo] as "montecarlo =
    None"."""
    path = tmp_path / "land.toml"
    assert main(["scenarios", "landing_calm_deck", "--out", str(path)]) == 0
    assert main(["montecarlo", str(path), "--out", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err
    assert "[montecarlo]" in err and "None" not in err and len(err.splitlines()) == 1
    with path.open("a", encoding="utf-8") as fh:
        fh.write("\n[montecarlo]\nruns = 2\nseed = 1\n")
    assert main(["montecarlo", str(path), "--out", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err
    assert "maneuver.type = 'tethered_landing'" in err and "free configuration" not in err
    assert "Monte Carlo" in err and len(err.splitlines()) == 1


def test_montecarlo_prints_no_median_among_the_failed_runs(capsys):
    """Finding 13: when every free reference failed the summary printed "median (among the
    failed runs) %"; it now says there is no reduction."""
    from tetherheli.cli.montecarlo import _print_statistics

    summary = {
        "statistics": {
            "free": {"runs": 2, "completed": 0, "failed": 2},
            "tethered": {
                "runs": 2,
                "completed": 2,
                "failed": 0,
                "peak_q1": {"p50": 1.0, "p95": 1.2},
            },
        },
        "reduction_percent": {
            "peak_q1": {
                "p50": None,
                "p5": None,
                "ci95": {"p50": [None, None]},
                "draws": 2,
                "draws_with_reference": 0,
            },
        },
    }
    assert _print_statistics(summary, "peak_q1", ("free", "tethered")) == 2
    out = capsys.readouterr().out
    assert "among the failed runs" not in out
    assert "none (the free reference of every one of the 2 draws failed)" in out


@pytest.mark.parametrize(
    ("key", "value"),
    [
        ("max_touchdown_speed", 1e300),
        ("max_touchdown_offset", 1e300),
        ("max_touchdown_speed", 16.0),
        ("max_touchdown_offset", 50.0),
    ],
)
def test_touchdown_limits_have_a_physical_range(key, value):
    """Finding 15: ``max_touchdown_speed = 1e300`` called a 16 m/s impact "landed"."""
    with pytest.raises(ParameterError, match=rf"maneuver\.{key} = .* is invalid; allowed: "):
        scenario_from_dict(
            {"configuration": "tethered", "maneuver": {"type": "tethered_landing", key: value}}
        )


def test_a_sweep_point_a_landing_cannot_fly_names_the_file_and_the_point(tmp_path, capsys):
    """Finding 13: a sweep point a landing cannot fly (q9 = 0.5 m puts the start below the
    gear) aborted without naming the file or the point."""
    path = tmp_path / "land.toml"
    assert main(["scenarios", "landing_calm_deck", "--out", str(path)]) == 0
    args = ["sweep", str(path), "--param", "q9", "--values", "0.5,10"]
    assert main([*args, "--out", str(tmp_path / "out")]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert f"{path}, sweep point q9 = 0.5: maneuver.gear_height = 0.35 is invalid" in line
    assert not (tmp_path / "out").exists()


def test_a_name_too_long_for_its_draws_is_refused_by_the_users_field(tmp_path, capsys):
    """Finding 13: a Monte Carlo of a 95-character name failed every draw with a message
    naming the derived name ``NAME_mcI``; it is refused up front, naming ``name``."""
    path = tmp_path / "mc.toml"
    assert main(["scenarios", "montecarlo_paper_sim1", "--out", str(path)]) == 0
    text = path.read_text(encoding="utf-8").replace(
        'name = "montecarlo_paper_sim1"', 'name = "' + "m" * 95 + '"'
    )
    path.write_text(text, encoding="utf-8")
    assert main(["montecarlo", str(path), "--runs", "2", "--out", str(tmp_path / "o")]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert "name = '" + "m" * 95 + "' is invalid" in line and "_mc" in line
    assert "m" * 95 + "_mc0" not in line
