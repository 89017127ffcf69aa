"""Issue 47 item 3: every JSON file a command writes is strict JSON (RFC 8259: no bare
Infinity or NaN, which JavaScript's ``JSON.parse`` refuses); a float that is not finite is
written as one of the strings of ``_io.NONFINITE_JSON`` and read back as that float, so a
saved run's configuration (its infinite actuator and winch limits among them) comes back
bit for bit, through ``load_result``, its scenario TOML and a Monte Carlo's resume."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from tetherheli import ParameterError, load_result, load_scenario
from tetherheli._io import (
    NONFINITE_JSON,
    json_from_text,
    json_text,
    read_json,
    write_json,
)
from tetherheli.cli import main
from tetherheli.runs import simulate
from tetherheli.scenario import Scenario
from tetherheli.scenario.core import scenario_from_dict, scenario_toml

from .test_output_safety import SHORT

#: the commands' figures are drawn blank: the JSON files are under test (tests/blank_figures.py)
pytestmark = pytest.mark.usefixtures("blank_figures")

MONTECARLO = """
name = "mc_json"
configuration = "tethered"
duration = 1.0
[control]
dt = 0.01
[[wind]]
type = "pulse"
start = 0.2
duration = 0.3
magnitude = 10.0
direction = [1.0, 0.0, 0.0]
[montecarlo]
runs = 2
seed = 7
amplitude_std_percent = 20.0
"""

SENSING = """
name = "sensing_json"
configuration = "tethered"
duration = 1.0
seed = 1
[[wind]]
type = "pulse"
start = 0.2
duration = 0.3
magnitude = 10.0
direction = [1.0, 0.0, 0.0]
[sensors]
presets = ["consumer_gnss", "mems_imu", "laser_altimeter", "joint_encoders", "load_cell",
           "winch_encoder"]
position_source = "gps"
"""


def _refuse(word: str) -> float:
    raise ValueError(f"not strict JSON: {word}")


def strict(text: str) -> object:
    """``text`` parsed as strict JSON: a bare Infinity, -Infinity or NaN raises."""
    return json.loads(text, parse_constant=_refuse)


def test_nonfinite_floats_are_strings_and_come_back_exactly():
    data = {"a": [math.inf, -math.inf, 1.5, -0.0], "b": {"c": math.nan}, "d": (1, "x", None)}
    text = json_text(data)
    assert strict(text) == {
        "a": ["Infinity", "-Infinity", 1.5, -0.0],
        "b": {"c": "NaN"},
        "d": [1, "x", None],
    }
    back = json_from_text(text)
    assert back["a"] == [math.inf, -math.inf, 1.5, -0.0]
    assert math.copysign(1.0, back["a"][3]) == -1.0 and math.isnan(back["b"]["c"])
    # a file of an older version, bare Infinity, still reads
    assert json_from_text('{"x": Infinity, "y": -Infinity}') == {"x": math.inf, "y": -math.inf}
    # what the one writer does not encode (a key) fails loudly instead of writing Infinity
    with pytest.raises(ValueError, match="not JSON compliant"):
        json_text({math.inf: 1.0})
    assert set(NONFINITE_JSON) == {"Infinity", "-Infinity", "NaN"}


def test_write_and_read_json_round_trip(tmp_path: Path):
    path = tmp_path / "x.json"
    write_json(path, {"limit": [-math.inf, math.inf]})
    text = path.read_text(encoding="utf-8")
    assert text.endswith("\n") and "Infinity" in strict(text)["limit"][1]
    assert read_json(path) == {"limit": [-math.inf, math.inf]}


@pytest.mark.parametrize("word", sorted(NONFINITE_JSON))
def test_text_keys_refuse_the_words_for_nonfinite_numbers(word: str):
    """No text is ever read back as a number: the three words are refused where a scenario
    takes free text or a name, in one line naming the field."""
    with pytest.raises(ParameterError, match=rf"^description = '{word}' is invalid") as info:
        Scenario(description=word)
    assert "\n" not in str(info.value) and "'NaN'" in str(info.value)
    with pytest.raises(ParameterError, match=rf"^name = '{word}' is invalid"):
        Scenario(name=word)


def test_a_saved_run_round_trips_its_infinite_limits(tmp_path: Path):
    """The run's JSON is strict; load_result gives the configuration back equal (inf as inf),
    and the scenario TOML written from it reads back as the same scenario."""
    path = tmp_path / "s.toml"
    path.write_text(SHORT.format(name="rt", cfg="tethered", duration=0.1))
    scenario = load_scenario(path)
    result = simulate(scenario)
    files = result.save(tmp_path / "out")
    text = files["json"].read_text(encoding="utf-8")
    meta = strict(text)
    assert meta["configuration"]["actuators"]["u_max"] == ["Infinity"] * 4
    assert meta["configuration"]["winch"]["max_length"] == "Infinity"
    loaded = load_result(tmp_path / "out")
    assert loaded.configuration == json_from_text(json_text(scenario.to_dict()))  # lists
    assert loaded.configuration["actuators"]["u_min"] == [-math.inf] * 4
    again = scenario_from_dict(tomllib_loads(scenario_toml(loaded.configuration)))
    assert again == scenario
    assert np.array_equal(loaded.states, result.states)


def tomllib_loads(text: str) -> dict:
    import tomllib

    return tomllib.loads(text)


def _json_files(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*.json") if p.is_file())


def test_every_json_file_the_commands_write_is_strict(tmp_path: Path, monkeypatch, capsys):
    """simulate, sweep, montecarlo (and its resume), compare, sensing, trim --json: every
    *.json they write, their records included, parses as strict JSON; the runs' own JSON
    holds the infinite limits as strings."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "short.toml").write_text(SHORT.format(name="short", cfg="tethered", duration=0.5))
    (tmp_path / "mc.toml").write_text(MONTECARLO)
    (tmp_path / "sensing.toml").write_text(SENSING)
    commands = [
        ["simulate", "short.toml", "--out", "sim", "--quiet"],
        ["sweep", "short.toml", "--param", "q9", "--values", "9,10", "--out", "sweep", "--quiet"],
        ["montecarlo", "mc.toml", "--out", "mc", "--quiet", "--chunk-size", "1"],
        ["montecarlo", "mc.toml", "--out", "mc", "--quiet", "--chunk-size", "1"],  # resumed
        ["compare", "short.toml", "--controllers", "paper", "--out", "compare", "--quiet"],
        ["sensing", "--scenario", "sensing.toml", "--out", "sensing", "--quiet"],
    ]
    for argv in commands:
        assert main(argv) == 0, (argv, capsys.readouterr().err)
    capsys.readouterr()
    assert main(["trim", "--tension", "25", "--json"]) == 0
    strict(capsys.readouterr().out)
    written = _json_files(tmp_path)
    folders = {p.relative_to(tmp_path).parts[0] for p in written}
    assert folders == {"sim", "sweep", "mc", "compare", "sensing"}
    for path in written:
        strict(path.read_text(encoding="utf-8"))
    run = strict((tmp_path / "sim" / "short.json").read_text(encoding="utf-8"))
    assert run["configuration"]["actuators"]["breaking_tension"] == "Infinity"
    job = strict((tmp_path / "mc" / "partial" / "job.json").read_text(encoding="utf-8"))
    assert "Infinity" in json.dumps(job)  # the resumed job matched a record with infinities


@pytest.mark.slow
def test_paper_and_tether_study_json_is_strict(tmp_path: Path, monkeypatch, capsys):
    """The paper's manifest.json held 48 bare Infinity and each run's JSON 12 (the actuator
    and winch limits of the saved configuration); the tether study's summary.json too is
    strict. The paper's saved runs load back with their infinite limits."""
    monkeypatch.chdir(tmp_path)
    assert main(["paper", "--out", "paper", "--quiet"]) == 0
    study = ["tether-study", "--out", "study", "--cables", "paper", "--lengths", "20",
             "--winds", "5", "--elevations", "90", "--duration", "12", "--workers", "1",
             "--quiet"]  # fmt: skip
    assert main(study) == 0
    capsys.readouterr()
    written = _json_files(tmp_path)
    assert {p.relative_to(tmp_path).as_posix() for p in written} >= {
        "paper/manifest.json",
        "paper/summary.json",
        "paper/sim1_tethered.json",
        "study/summary.json",
    }
    for path in written:
        strict(path.read_text(encoding="utf-8"))
    manifest = (tmp_path / "paper" / "manifest.json").read_text(encoding="utf-8")
    assert manifest.count('"Infinity"') + manifest.count('"-Infinity"') == 48
    run = load_result(tmp_path / "paper", "sim1_tethered")
    assert run.configuration["winch"]["max_length"] == math.inf
