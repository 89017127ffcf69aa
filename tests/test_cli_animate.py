"""`tetherheli animate`: the CLI side (the rendering is tested in test_animation.py)."""

from __future__ import annotations

import pytest
from PIL import Image

from tetherheli.cli import main
from tetherheli.runs import simulate
from tetherheli.scenario import Scenario
from tetherheli.wind import Pulse


def test_animate_cli_errors(tmp_path, capsys):
    """A missing folder or a folder with no results: one line naming it, exit 2."""
    assert main(["animate", str(tmp_path / "missing")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "missing" in err
    assert main(["animate", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and str(tmp_path) in err


def test_animate_cli_writes_gif(tmp_path):
    """A simulated run is animated into a GIF with the requested frame budget."""
    r = simulate(Scenario(duration=1.0, wind=Pulse(0.2, 0.3, 20.0, (1.0, 0.0, 0.0))))
    r.save(tmp_path, "run")
    out = tmp_path / "a.gif"
    assert main(["animate", str(tmp_path), "--out", str(out), "--max-frames", "5"]) == 0
    with Image.open(out) as img:
        assert img.n_frames == 5


@pytest.mark.usefixtures("blank_figures")  # the runs are read, not the plots
def test_animate_accepts_multi_scenario_simulate_output(tmp_path, capsys):
    """`simulate a.toml b.toml` writes OUT/<name>/<name>.csv; `animate OUT` overlays both,
    the free run red and the tethered run blue as in the figures."""
    from tetherheli.viz.animation import _load_runs, run_colours
    from tetherheli.viz.plots import CONFIGURATION_COLOURS

    files = []
    for cfg in ("free", "tethered"):
        f = tmp_path / f"{cfg}.toml"
        f.write_text(
            f'name = "{cfg}_run"\nconfiguration = "{cfg}"\nduration = 0.3\n'
            '[[wind]]\ntype = "pulse"\nstart = 0.1\nduration = 0.1\nmagnitude = 20.0\n'
            "direction = [1.0, 0.0, 0.0]\n"
        )
        files.append(str(f))
    out = tmp_path / "cmp"
    assert main(["simulate", *files, "--out", str(out)]) == 0
    assert main(["animate", str(out), "--max-frames", "3", "--quiet"]) == 0
    assert capsys.readouterr().err == ""
    with Image.open(out / "animation.gif") as img:
        assert img.n_frames == 3
    runs = _load_runs(out, None)
    assert [r.stem for r in runs] == ["free_run/free_run", "tethered_run/tethered_run"]
    assert run_colours(runs) == [CONFIGURATION_COLOURS["free"], CONFIGURATION_COLOURS["tethered"]]
