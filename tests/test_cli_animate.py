"""`tetherheli animate`: the CLI side (the rendering is tested in test_animation.py)."""

from __future__ import annotations

from PIL import Image

from tetherheli.cli import main
from tetherheli.disturbances import Pulse
from tetherheli.sim import Scenario, simulate


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
