"""Issue 47 item 5: a shipped scenario by name wherever a scenario file is taken
(``load_scenario``, ``load_montecarlo``, every command), from any working folder; a file the
user has always wins; an unknown name's message points at the shipped scenarios."""

from __future__ import annotations

import pytest

from tetherheli import load_scenario
from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.shipped import shipped_scenario, shipped_scenarios
from tetherheli.studies.montecarlo import load_montecarlo


@pytest.fixture(autouse=True)
def _elsewhere(tmp_path, monkeypatch):
    """Every test from an empty working folder, not the clone's root."""
    monkeypatch.chdir(tmp_path)


@pytest.mark.parametrize("name", ["paper_sim1_tethered", "paper_sim1_tethered.toml"])
def test_load_scenario_takes_a_shipped_name(name):
    assert load_scenario(name) == shipped_scenario("paper_sim1_tethered")


def test_every_shipped_scenario_loads_by_name():
    for name in shipped_scenarios():
        if name.startswith("montecarlo"):
            scenario, config = load_montecarlo(name)
            assert config.runs > 0 and scenario.duration > 0
        else:
            assert load_scenario(name).name == name


def test_a_file_the_user_has_wins(tmp_path):
    text = "name = 'mine'\nconfiguration = 'free'\nduration = 1.0\n"
    (tmp_path / "paper_sim1_tethered.toml").write_text(text, encoding="utf-8")
    assert load_scenario("paper_sim1_tethered.toml").name == "mine"


def test_an_unknown_name_points_at_the_shipped_scenarios():
    with pytest.raises(ParameterError) as info:
        load_scenario("paper_sim1_tetherd")
    message = str(info.value)
    assert "shipped scenario" in message and "shipped_scenario" in message
    assert "\n" not in message


def test_a_path_with_a_folder_is_never_a_name():
    with pytest.raises(ParameterError, match="an existing scenario TOML file"):
        load_scenario("nowhere/paper_sim1_tethered")


def test_the_commands_take_names(tmp_path, capsys):
    code = main(["simulate", "paper_sim1_free", "--out", str(tmp_path / "out"), "--quiet"])
    assert code == 0, capsys.readouterr().err
    assert (tmp_path / "out" / "paper_sim1_free.json").exists()
