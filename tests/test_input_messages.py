"""Issue 22, class 6: a refusal names what the user wrote (the key in the file, its value and
what is allowed), never an internal value; bad input of any depth or shape is exit 2, one
line, through the CLI and the API."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from tetherheli.cli import main
from tetherheli.errors import InfeasibleError, ParameterError
from tetherheli.params import Params
from tetherheli.runs import simulate
from tetherheli.runs.setup import engine_setup, run_setup
from tetherheli.scenario import load_scenario
from tetherheli.scenario.core import (
    ActuatorSettings,
    ControlSettings,
    MPCSettings,
    Scenario,
    TetherSettings,
    scenario_from_dict,
)

#: weights far apart enough that eq 49's Riccati equation has no stabilising solution
EXTREME_QY = (1e200, 1.0, 1.0, 1.0, 10.0, 10.0, 10.0, 10.0)


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert "internal error" not in err and "Traceback" not in err
    return err


def _write(tmp_path, scenario: Scenario, name: str = "s.toml"):
    path = tmp_path / name
    path.write_text(scenario.to_toml())
    return path


def _lumped(**changes) -> Scenario:
    return Scenario(duration=0.1, tether=TetherSettings(model="lumped", **changes))


# --- the weights of a design with no stabilising solution ------------------------------------


def test_extreme_lqi_weights_name_control_qy_ru(tmp_path, capsys):
    s = Scenario(duration=0.1, control=ControlSettings(Qy=EXTREME_QY))
    with pytest.raises(InfeasibleError, match=r"^control\.Qy/Ru = .*1e\+200") as err:
        engine_setup(s)
    assert "stabilising" in str(err.value) and "1e10" in str(err.value)
    path = _write(tmp_path, s, "weights.toml")
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = _one_error_line(capsys)
    assert "weights.toml: control.Qy/Ru = " in err and "1e+200" in err
    assert not (tmp_path / "o").exists()


def test_extreme_mpc_weights_name_control_mpc():
    mpc = MPCSettings(Qy=EXTREME_QY)
    s = Scenario(duration=0.1, control=ControlSettings(controller="mpc", mpc=mpc))
    with pytest.raises(InfeasibleError, match=r"^control\.mpc\.Qy/q_tension/Ru = .*1e\+200"):
        simulate(s)


# --- the lumped tether ----------------------------------------------------------------------


def test_stiff_lumped_cable_is_refused_naming_ea_not_an_internal_length(tmp_path, capsys):
    """EA = 1e30 N used to fail the trim's round trip through L0 ("unstretched_length_m
    = 10.0 is invalid"); the vertical catenary is built from T_ref itself now, so the trim
    holds. The cable is then refused in one line naming tether.EA and the stiffest EA the
    engine can step (its coupled step would need ~1e13 RK4 steps per sample: it used to be
    flown for 50 s a sample with capped, unstable steps to a failure), exit 2."""
    s = _lumped(EA=1e30)
    assert run_setup(s).trim.x[12] == pytest.approx(s.q9)
    with pytest.raises(
        InfeasibleError, match=r"^tether\.EA = 1e\+30 is invalid; allowed: at most about"
    ) as err:
        engine_setup(s)
    path = _write(tmp_path, s)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = _one_error_line(capsys)
    assert "tether.EA = 1e+30" in err and "unstretched_length_m" not in err
    assert not (tmp_path / "o").exists()


def test_the_stiffest_cable_allowed_is_flown():
    """The bound the refusal names is one the engine flies: EA just below it is set up."""
    s = _lumped(EA=1e30)
    with pytest.raises(InfeasibleError) as err:
        engine_setup(s)
    ea_max = float(str(err.value).split("at most about ")[1].split()[0])
    engine_setup(_lumped(EA=0.9 * ea_max))
    with pytest.raises(InfeasibleError):
        engine_setup(_lumped(EA=1.2 * ea_max))


def test_lumped_zero_reference_tension_names_t_ref(tmp_path, capsys):
    params = Params.paper().replace(tension_control={"T_ref": 0.0})
    with pytest.raises(ParameterError, match=r"^params\.tension_control\.T_ref = 0\.0") as err:
        dataclasses.replace(_lumped(), params=params)
    assert "lumped" in str(err.value)
    path = tmp_path / "s.toml"
    path.write_text(
        'duration = 0.1\n[tether]\nmodel = "lumped"\n[params.tension_control]\nT_ref = 0.0\n'
    )
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = _one_error_line(capsys)
    assert "params.tension_control.T_ref = 0.0" in err and "ground_tension_N" not in err


def test_tiny_cyclic_limit_on_a_lumped_run_names_the_actuator_limits(tmp_path, capsys):
    inf = math.inf
    act = ActuatorSettings(u_min=(-inf, -1e-6, -1e-6, -inf), u_max=(inf, 1e-6, 1e-6, inf))
    s = dataclasses.replace(_lumped(), actuators=act)
    with pytest.raises(InfeasibleError, match=r"^actuators\.u_min/u_max = 'tMR\d in") as err:
        engine_setup(s)
    assert "tension" not in str(err.value).split(" is invalid")[0]
    path = _write(tmp_path, s, "cyclic.toml")
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = _one_error_line(capsys)
    assert "cyclic.toml: actuators.u_min/u_max" in err and "ground_tension_N" not in err


# --- tether-study --duration ----------------------------------------------------------------


@pytest.mark.parametrize("duration", [0.001, 0.015, 61.0])
def test_tether_study_duration_names_duration(tmp_path, capsys, duration):
    from tetherheli.report import run_tether_study

    with pytest.raises(ParameterError, match=r"^duration = ") as err:
        run_tether_study(str(tmp_path / "api"), duration_s=duration, progress=False)
    assert "control.dt" in str(err.value) and "allowed: a duration in [0.01, 60] s" in str(
        err.value
    )
    assert main(["tether-study", "--duration", str(duration), "--out", str(tmp_path / "o")]) == 2
    err = _one_error_line(capsys)
    assert f"duration = {duration}" in err and "control.dt = 0.01 is invalid" not in err
    assert not (tmp_path / "o").exists() and not (tmp_path / "api").exists()


# --- deep nesting ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text",
    [
        "a = " + "[" * 10_000 + "]" * 10_000,
        'name = "x"\nx = ' + "{a = " * 5_000 + "1" + "}" * 5_000,
        "[control]\nQy = " + "[" * 300 + "]" * 300,
    ],
    ids=["array-10000", "inline-table-5000", "control.Qy-300"],
)
def test_deeply_nested_toml_is_bad_input(tmp_path, capsys, text):
    path = tmp_path / "deep.toml"
    path.write_text(text + "\n")
    with pytest.raises(ParameterError) as err:
        load_scenario(path)
    assert len(str(err.value)) < 600 and "\n" not in str(err.value)
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = _one_error_line(capsys)
    assert "deep.toml" in err and len(err) < 600


def test_deeply_nested_data_through_the_api_is_one_line():
    wind = {"type": "pulse", "start": 1.0, "duration": 1.0, "magnitude": 1.0,
            "direction": [1.0, 0.0, 0.0]}  # fmt: skip
    for _ in range(3_000):
        wind = {"type": "sum", "components": [wind]}
    with pytest.raises(ParameterError, match=r"api: scenario = .* nested a few levels deep"):
        scenario_from_dict({"wind": [wind]}, source="api")
    table: object = 1.0
    for _ in range(5_000):
        table = {"a": table}
    with pytest.raises(ParameterError, match=r"^control\.a = \{'a': \{'a': .*\.\.\.") as err:
        scenario_from_dict({"control": table})
    assert len(str(err.value)) < 600


# --- environment actions --------------------------------------------------------------------


def test_env_action_of_the_wrong_shape_or_not_finite_is_refused():
    pytest.importorskip("gymnasium")
    from tetherheli.envs.env import TetheredHoverEnv

    env = TetheredHoverEnv(wind="pulse", max_episode_time=1.0)
    env.reset(seed=0)
    for bad in (np.zeros((2, 2)), np.zeros(5), np.zeros((1, 4)), 0.0, "abcd"):
        with pytest.raises(ParameterError, match=r"^action = .*shape \(4,\)"):
            env.step(bad)
    for bad in ([math.inf, 0.0, 0.0, 0.0], [0.0, -math.inf, 0.0, 0.0], [math.nan] * 4):
        with pytest.raises(ParameterError, match=r"^action = .*finite numbers"):
            env.step(np.array(bad))
    env.step(np.zeros(4, dtype=np.float32))  # the right shape still flies
    env.step([0.1, 0.0, 0.0, 0.0])


def test_vector_env_action_of_the_wrong_shape_is_refused():
    pytest.importorskip("gymnasium")
    from tetherheli.envs.vector import TetheredHoverVectorEnv

    env = TetheredHoverVectorEnv(3, wind="pulse", max_episode_time=1.0)
    env.reset(seed=0)
    for bad in (np.zeros(12), np.zeros((4, 3)), np.zeros((3, 4, 1))):
        with pytest.raises(ParameterError, match=r"^action = .*shape \(3, 4\)"):
            env.step(bad)
    with pytest.raises(ParameterError, match=r"finite numbers"):
        env.step(np.full((3, 4), math.inf))
    env.step(np.zeros((3, 4)))


# --- compare's table ------------------------------------------------------------------------


def _cells(line: str) -> int:
    return line.count("|") - 1


def test_compare_table_of_a_failed_run_has_one_cell_per_column(tmp_path, capsys):
    """A run that cannot be set up (a main-rotor limit of 100 N, below the hover's thrust) is
    a failed row of 17 cells under 17 columns (it had 18). Weights without a design are the
    file's error instead: refused, exit 2, naming the file."""
    from tetherheli.compare import markdown_table

    row = {"scenario": "s", "controller": "paper", "status": "bad", "completed": False}
    lines = markdown_table([row]).splitlines()
    assert {_cells(line) for line in lines} == {_cells(lines[0])} == {17}
    a = ActuatorSettings()
    s = Scenario(name="no_hover", duration=0.1, actuators=dataclasses.replace(
        a, u_max=(100.0, *a.u_max[1:])))  # fmt: skip
    path = _write(tmp_path, s)
    out = tmp_path / "o"
    assert main(["compare", str(path), "--controllers", "paper", "--out", str(out)]) == 1
    printed = capsys.readouterr()
    assert "actuators" in printed.err
    for text in (printed.out, (out / "compare.md").read_text()):
        lines = [line for line in text.splitlines() if line.startswith("|")]
        assert len(lines) == 3 and {_cells(line) for line in lines} == {17}
    s = Scenario(name="bad_weights", duration=0.1, control=ControlSettings(Qy=EXTREME_QY))
    path = _write(tmp_path, s)
    assert main(["compare", str(path), "--controllers", "paper", "--out", str(out) + "2"]) == 2
    err = capsys.readouterr().err
    assert f"{path}: control.Qy/Ru" in err and not (tmp_path / "o2").exists()
