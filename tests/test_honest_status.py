"""Issue 22, class 4: a failure is never "completed" (solver fallbacks, impossible tethers,
controllers a configuration cannot fly, settings that cannot work together)."""

from __future__ import annotations

import dataclasses
import json
import tomllib

import numpy as np
import pytest

from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.scenario.core import Scenario, TetherSettings, load_scenario, scenario_from_dict
from tetherheli.status import (
    DEGRADED_FALLBACK_FRACTION,
    FAILED_FALLBACK_FRACTION,
    Status,
    ran_to_end,
    solver_status,
    status_message,
)
from tetherheli.wind.profiles import Pulse


def _write(tmp_path, text: str, name: str = "s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_fallback_fraction_sets_the_status_by_the_documented_rule():
    n = 1000
    assert DEGRADED_FALLBACK_FRACTION == 0.01 and FAILED_FALLBACK_FRACTION == 0.10
    at = lambda k: [1.0] * k + [0.0] * (n - k)  # noqa: E731
    assert solver_status(Status.OK, at(0)) == Status.OK
    assert solver_status(Status.OK, at(10)) == Status.OK  # 1 %: not above
    assert solver_status(Status.OK, at(11)) == Status.DEGRADED
    assert solver_status(Status.OK, at(100)) == Status.DEGRADED  # 10 %: not above
    assert solver_status(Status.OK, at(101)) == Status.SOLVER_FAILED
    assert solver_status(Status.GROUND, at(1000)) == Status.GROUND  # a stop keeps its own
    assert solver_status(Status.OK, []) == Status.OK
    assert ran_to_end(Status.DEGRADED) and ran_to_end(Status.SOLVER_FAILED)
    assert not ran_to_end(Status.GROUND)
    msg = status_message(Status.DEGRADED, None, 0.05)
    assert msg.startswith("degraded") and "5 % (more than 1 %)" in msg
    assert "completed" not in status_message(Status.SOLVER_FAILED, None, 0.9)


MPC_FAILING = """
name = "mpc_fails"
configuration = "tethered"
duration = 1.0
q9 = 10.0
[control]
dt = 0.01
controller = "mpc"
[control.mpc]
max_iterations = 1
[[wind]]
type = "pulse"
start = 0.2
duration = 0.5
magnitude = 20.0
direction = [1.0, 0.0, 0.0]
"""


def test_mpc_whose_solver_fails_is_a_failed_run_through_the_cli(tmp_path, capsys):
    """``max_iterations = 1`` (allowed): every sample falls back; exit 1, the summary says
    failed, the message names the fraction."""
    import json

    path = _write(tmp_path, MPC_FAILING)
    out = tmp_path / "out"
    assert main(["simulate", str(path), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "mpc_fails ended at t = 1 s" in err and "100 % (more than 10 %)" in err
    text = json.dumps(json.loads(next(out.rglob("*.json")).read_text()))
    assert '"completed": true' not in text.replace(" ", "").replace('"completed":true', "")


def test_lumped_tether_obeys_the_strain_rule(tmp_path, capsys):
    """EA = 10 N (inside the key's range, >= 1 N) stretches the chain beyond 100 %: refused
    at set-up, naming tether.EA, as the massless tether refuses a T_ref above its limit."""
    s = Scenario().replace(configuration="tethered")
    with pytest.raises(ParameterError, match=r"tether\.EA = 10\.0.*EA >= 26\.9") as err:
        s.replace(tether=TetherSettings(model="lumped", EA=10.0))
    assert len(str(err.value).splitlines()) == 1
    s.replace(tether=TetherSettings(model="lumped", EA=375.0))  # the paper's holds
    text = Scenario(name="lumped").to_toml().replace("[tether]\n", "[tether]\n", 1)
    text = text.replace('model = "elastic"', 'model = "lumped"').replace("EA = 0.0", "EA = 10.0")
    assert "EA = 10.0" in text
    path = _write(tmp_path, text)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "tether.EA" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_a_natural_length_at_zero_ends_the_run():
    """LN <= 0 of an attached tether is ``Status.TETHER_LENGTH`` (engine.check_state)."""
    from tetherheli.engine import loop as engine
    from tetherheli.runs.setup import engine_setup

    setup = engine_setup(Scenario())
    x = setup.start.x.copy()
    y = setup.trim.y.copy()
    assert engine.check_state(x, y, y, 25.0, setup.cfg) == Status.OK
    x[12] = -1e-6
    assert engine.check_state(x, y, y, 25.0, setup.cfg) == Status.TETHER_LENGTH
    assert "natural length" in Status.TETHER_LENGTH.message


def test_tether_lqi_on_a_free_configuration_is_refused(tmp_path, capsys):
    c = dataclasses.replace(Scenario().control, controller="tether_lqi")
    with pytest.raises(ParameterError, match=r"control\.controller = 'tether_lqi'"):
        Scenario(configuration="free", control=c)
    text = Scenario(name="free", configuration="free").to_toml()
    text = text.replace('controller = "paper"', 'controller = "tether_lqi"')
    assert 'controller = "tether_lqi"' in text
    path = _write(tmp_path, text)
    with pytest.raises(ParameterError, match=r"control\.controller"):
        load_scenario(path)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    assert "control.controller" in capsys.readouterr().err


def test_the_environment_refuses_a_controller_it_does_not_fly():
    from tetherheli.envs.env import TetheredHoverEnv

    c = dataclasses.replace(Scenario().control, controller="mpc")
    with pytest.raises(ParameterError, match=r"scenario\.control\.controller = 'mpc'"):
        TetheredHoverEnv(Scenario(control=c))


def test_mpc_tension_bounds_follow_T_ref_unless_given():
    """Unset, the bounds are [T_ref/2, 1.5 T_ref] of the scenario's own T_ref (their doc): the
    paper's [12.5, 37.5] N at 25 N, [22.5, 67.5] N at 45 N (which with the old fixed default
    crashed into the ground at t = 12.6 s); given, they are used as written."""
    from tetherheli.runs.mpc_setup import mpc_controller
    from tetherheli.runs.setup import engine_setup

    s = Scenario(name="t45")
    assert s.control.mpc.tension_bounds is None
    assert s.control.mpc.bounds_about(25.0) == (12.5, 37.5)
    c = dataclasses.replace(s.control, controller="mpc")
    tc = dataclasses.replace(s.params.tension_control, T_ref=45.0)
    p = dataclasses.replace(s.params, tension_control=tc)
    s45 = s.replace(control=c, params=p)
    assert mpc_controller(s45, engine_setup(s45)).tension_bounds == (22.5, 67.5)
    given = dataclasses.replace(c.mpc, tension_bounds=(30.0, 60.0))
    s_given = s45.replace(control=dataclasses.replace(c, mpc=given))
    assert mpc_controller(s_given, engine_setup(s_given)).tension_bounds == (30.0, 60.0)
    # unset is written as absent and read back as unset; given bounds round-trip
    assert "tension_bounds" not in s45.to_toml()
    back = scenario_from_dict(tomllib.loads(s45.to_toml()))
    assert back.control.mpc.tension_bounds is None and back == s45
    back = scenario_from_dict(tomllib.loads(s_given.to_toml()))
    assert back.control.mpc.tension_bounds == (30.0, 60.0)
    # and the run's JSON record (None kept as null) reads back unset
    assert scenario_from_dict(json.loads(json.dumps(s45.to_dict()))) == s45


def test_the_mpc_at_45_N_with_default_bounds_flies_past_the_old_crash(tmp_path, capsys):
    """The issue's case through the CLI: T_ref = 45 N, the MPC, the default bounds, past
    t = 12.6 s where the old fixed bounds put it on the ground."""
    s = Scenario(name="t45", duration=15.0)
    c = dataclasses.replace(s.control, controller="mpc")
    text = s.replace(control=c).to_toml().replace("T_ref = 25.0", "T_ref = 45.0")
    assert "T_ref = 45.0" in text
    path = _write(tmp_path, text)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 0
    assert "completed" in capsys.readouterr().out


def test_mpc_tension_bounds_that_exclude_T_ref_are_refused(tmp_path, capsys):
    """Bounds given that exclude T_ref are refused at set-up, naming both fields."""
    s = Scenario(name="t45")
    mpc = dataclasses.replace(s.control.mpc, tension_bounds=(12.5, 37.5))
    c = dataclasses.replace(s.control, controller="mpc", mpc=mpc)
    tc = dataclasses.replace(s.params.tension_control, T_ref=45.0)
    p = dataclasses.replace(s.params, tension_control=tc)
    with pytest.raises(ParameterError, match=r"control\.mpc\.tension_bounds.*T_ref = 45"):
        s.replace(control=c, params=p)
    text = s.replace(control=c).to_toml().replace("T_ref = 25.0", "T_ref = 45.0")
    assert "T_ref = 45.0" in text
    path = _write(tmp_path, text)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "control.mpc.tension_bounds" in err and "[22.5, 67.5]" in err


def test_the_free_reference_of_a_lumped_study_is_the_free_helicopter():
    from tetherheli.studies.robust import FREE, _flown

    lumped = Scenario(tether=TetherSettings(model="lumped"))
    free = _flown(lumped, FREE)
    assert free.configuration == "free" and not free.tether.lumped
    assert free.control.controller == "paper"
    assert _flown(lumped, "paper").tether.lumped


def test_monte_carlo_compare_of_a_lumped_study_flies_its_free_reference():
    """compare --montecarlo's free draws of a lumped study are set up and fly (they were all
    refused, and every controller showed a 100 % reduction)."""
    from tetherheli.runs import simulate
    from tetherheli.studies.robust import FREE, _flown

    lumped = Scenario(
        duration=1.0, tether=TetherSettings(model="lumped"),
        wind=Pulse(0.2, 0.3, 5.0, (1.0, 0.0, 0.0)),
    )  # fmt: skip
    r = simulate(_flown(lumped, FREE))
    assert r.ok and np.all(np.isfinite(r.states))


def test_tether_study_calls_a_hover_beyond_the_thrust_limit_failed():
    """A negative thrust margin (1000 m of power cable, or --max-thrust 100) is never a
    "completed" dynamic row."""
    import math

    from tetherheli.params import Params
    from tetherheli.studies.tether_study import (
        DYNAMIC_CASES,
        STUDY_CABLES,
        mark_thrust_infeasible,
        static_rows,
    )

    cable = STUDY_CABLES[0]
    static = static_rows(Params.paper(), [cable], [10.0], max_thrust_N=100.0)
    assert static[0]["lift_margin_N"] < 0.0
    dynamic = [{"cable": cable.key, "length_m": 10.0, "completed": True}]
    for case, metrics in DYNAMIC_CASES:
        dynamic[0][f"{case}_status"] = "completed"
        for m in metrics:
            dynamic[0][f"{case}_{m}_reduction_pct"] = 50.0
    mark_thrust_infeasible(static, dynamic, 100.0)
    row = dynamic[0]
    assert row["completed"] is False
    assert "exceeds the maximum thrust 100 N" in row["sim1_status"]
    assert math.isnan(row["sim1_peak_q1_reduction_pct"])


@pytest.mark.parametrize("shipped, extra", [
    ("montecarlo_sensing", ""),  # position from the tether: the free draw flies the GNSS
    ("montecarlo_paper_sim1", '\n[tether]\nmodel = "lumped"\nsegments = 5\n'),
])  # fmt: skip
def test_montecarlo_free_runs_are_the_free_helicopter(tmp_path, capsys, shipped, extra):
    """Each draw's free run is ``free_reference`` of the draw: no tether table, GNSS in place
    of the tether as position source. A lumped study was refused with a message blaming a
    free configuration the file never wrote, and the shipped sensed Monte Carlo could not run
    at all (its free draw kept position_source = "tether")."""
    from tetherheli.shipped import shipped_scenario_text

    text = shipped_scenario_text(shipped).replace("duration = 60.0", "duration = 1.0")
    path = _write(tmp_path, text.replace("runs = 1000", "runs = 2") + extra)
    out = tmp_path / "o"
    assert main(["montecarlo", str(path), "--out", str(out), "--quiet"]) == 0, capsys.readouterr()
    rows = (out / "results.csv").read_text().splitlines()
    header = rows[0].split(",")
    status = header.index("status")
    assert len(rows) == 5 and all(r.split(",")[status] == "0" for r in rows[1:])


def test_free_reference_removes_the_tether_and_its_sensor():
    from tetherheli.sensing.config import SensorConfig
    from tetherheli.studies.montecarlo.draws import free_reference

    s = Scenario(
        tether=TetherSettings(model="lumped"),
        sensors=SensorConfig.from_presets(
            "consumer_gnss", "joint_encoders", "laser_altimeter", position_source="tether"
        ),
    )
    s = s.replace(control=dataclasses.replace(s.control, controller="tether_lqi"))
    free = free_reference(s)
    assert free.configuration == "free" and free.tether == TetherSettings()
    assert free.sensors.position_source == "gps"
    assert dataclasses.replace(free.sensors, position_source="tether") == s.sensors
    assert free.control.controller == "paper"


def test_compare_counts_a_failed_solver_as_a_failure(tmp_path, capsys):
    """The fallback rule through ``compare``: the MPC with ``max_iterations = 1`` is a failed
    run in the table (it said "failed 0/1"), exit 1; so is each of its Monte Carlo draws
    (counted in the table; a Monte Carlo's failures are its results, exit 0)."""
    import csv

    path = _write(tmp_path, MPC_FAILING)
    out = tmp_path / "c"
    assert main(["compare", str(path), "--controllers", "mpc", "--out", str(out), "--quiet"]) == 1
    rows = list(csv.DictReader((out / "compare.csv").read_text().splitlines()))
    (row,) = [r for r in rows if r["controller"] == "mpc"]
    assert row["completed"] == "False" and "solver failed" in row["status"]
    mc = _write(
        tmp_path,
        MPC_FAILING + "[montecarlo]\nruns = 2\nseed = 3\namplitude_std_percent = 10.0\n",
        "mc.toml",
    )
    out = tmp_path / "m"
    code = main(["compare", "--montecarlo", str(mc), "--controllers", "mpc", "--out", str(out),
                 "--quiet"])  # fmt: skip
    assert code == 0
    rows = list(csv.DictReader((out / "compare.csv").read_text().splitlines()))
    mpc_rows = [r for r in rows if r["controller"] == "mpc"]
    assert mpc_rows and all(r["failures"] == "2" and r["status"].startswith("2/2 failed")
                            for r in mpc_rows)  # fmt: skip


def test_weights_without_a_design_are_refused_by_every_study_naming_the_file(tmp_path, capsys):
    """Extreme weights (no stabilising solution of eq 49's DARE) are the file's error: compare
    recorded a failed row naming no file (exit 1), montecarlo and compare --montecarlo ran
    every draw into a set-up failure and then crashed (exit 70). Now each refuses them at
    set-up, exit 2, one line naming the file and the weights, nothing written."""
    from tetherheli.errors import WeightsError
    from tetherheli.shipped import shipped_scenario_text
    from tetherheli.studies.controllers import check_design

    bad_qy = "Qy = [1e300, 1.0, 1.0, 1.0, 10.0, 10.0, 10.0, 10.0]"
    text = shipped_scenario_text("paper_sim1_tethered")
    single = _write(tmp_path, _with_line(text, "Qy = ", bad_qy), "bad.toml")
    text = shipped_scenario_text("montecarlo_paper_sim1").replace("runs = 1000", "runs = 2")
    mc = _write(tmp_path, _with_line(text, "Qy = ", bad_qy), "badmc.toml")
    for args in (
        ["compare", str(single)],
        ["montecarlo", str(mc)],
        ["compare", "--montecarlo", str(mc)],
    ):
        out = tmp_path / f"out{len(args)}{args[0]}"
        assert main([*args, "--out", str(out), "--quiet"]) == 2, args
        err = capsys.readouterr().err.strip()
        path = args[-1]
        assert err.startswith(f"tetherheli: error: {path}: control.Qy/Ru = "), err
        assert len(err.splitlines()) == 1 and not out.exists()
    with pytest.raises(WeightsError, match=r"control\.Qy/Ru"):
        check_design(load_scenario(single))


def _with_line(text: str, prefix: str, line: str) -> str:
    lines = text.splitlines()
    (k,) = [i for i, x in enumerate(lines) if x.startswith(prefix)]
    lines[k] = line
    return "\n".join(lines) + "\n"
