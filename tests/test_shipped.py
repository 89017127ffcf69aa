"""Scenarios shipped inside the package (issue 12, item 3): listed, loaded by name, copied
out without overwriting a user's file, and included in a wheel."""

from __future__ import annotations

import fnmatch
import tomllib
from pathlib import Path

import pytest

from tetherheli import cli
from tetherheli._io import OutputPathError
from tetherheli.errors import ParameterError
from tetherheli.scenario.core import load_scenario
from tetherheli.shipped import copy_scenario, shipped_scenario, shipped_scenarios

ROOT = Path(__file__).resolve().parents[1]
PACKAGE_SCENARIOS = ROOT / "src" / "tetherheli" / "scenarios"


def test_listing_is_every_packaged_toml_with_its_description():
    listing = shipped_scenarios()
    files = sorted(p.stem for p in PACKAGE_SCENARIOS.glob("*.toml"))
    assert list(listing) == files and len(files) >= 16
    for name, description in listing.items():
        data = tomllib.loads((PACKAGE_SCENARIOS / f"{name}.toml").read_text(encoding="utf-8"))
        assert description == " ".join(data["description"].split()), name
        assert description and "\n" not in description


def test_top_level_scenarios_folder_is_the_package_folder():
    """The README's ``scenarios/<name>.toml`` paths still work in a clone."""
    assert (ROOT / "scenarios").resolve() == PACKAGE_SCENARIOS.resolve()


def test_shipped_scenario_by_name_equals_loading_the_file():
    for name in ("paper_sim1_tethered", "sensing_tether_outage", "turbulence_hover_free"):
        assert shipped_scenario(name) == load_scenario(PACKAGE_SCENARIOS / f"{name}.toml")
    with pytest.raises(ParameterError, match=r"scenario = 'paper_sim3'.*paper_sim1_free"):
        shipped_scenario("paper_sim3")


def test_package_data_includes_every_scenario():
    """What setuptools puts into a wheel: the ``package-data`` globs of pyproject.toml match
    every shipped TOML (checked by building a wheel when this was written)."""
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    globs = pyproject["tool"]["setuptools"]["package-data"]["tetherheli"]
    for path in PACKAGE_SCENARIOS.glob("*.toml"):
        rel = path.relative_to(ROOT / "src" / "tetherheli").as_posix()
        assert any(fnmatch.fnmatch(rel, g) for g in globs), rel


def test_copy_out_never_overwrites_a_users_file(tmp_path):
    out = tmp_path / "mine.toml"
    assert copy_scenario("paper_sim2_free", out) == out.resolve()
    assert out.read_bytes() == (PACKAGE_SCENARIOS / "paper_sim2_free.toml").read_bytes()
    assert load_scenario(out) == shipped_scenario("paper_sim2_free")
    with pytest.raises(OutputPathError, match="not written by tetherheli"):
        copy_scenario("paper_sim1_free", out)
    assert out.read_bytes() == (PACKAGE_SCENARIOS / "paper_sim2_free.toml").read_bytes()
    with pytest.raises(OutputPathError, match="is a directory"):
        copy_scenario("paper_sim1_free", tmp_path)


def test_cli_lists_and_copies(tmp_path, capsys):
    assert cli.main(["scenarios"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == len(shipped_scenarios())
    assert [line.split()[0] for line in lines] == sorted(shipped_scenarios())
    out = tmp_path / "s.toml"
    assert cli.main(["scenarios", "paper_sim1_tethered", "--out", str(out)]) == 0
    assert out.is_file() and "wrote" in capsys.readouterr().out
    for argv in (
        ["scenarios", "paper_sim1_tethered"],  # no --out
        ["scenarios", "nope", "--out", str(tmp_path / "n.toml")],
        ["scenarios", "paper_sim1_free", "--out", str(out)],  # a user's file now
        ["scenarios", "--out", str(tmp_path / "m.toml")],
    ):
        assert cli.main(argv) == 2, argv
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "n.toml").exists() and not (tmp_path / "m.toml").exists()
