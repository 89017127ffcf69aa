"""Progress on stderr (``tetherheli.progress``): a tqdm bar with rate and ETA on a terminal,
one summary line in a log file (no carriage returns), nothing with ``--quiet``."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

from tetherheli.progress import Progress

ROOT = Path(__file__).resolve().parents[1]


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_terminal_gets_a_bar_with_rate_and_eta():
    out = _Terminal()
    with Progress("montecarlo", 10, "draws", stream=out) as bar:
        assert bar.terminal
        for _ in range(10):
            bar.update(1)
        bar.note("tetherheli: a note")
    text = out.getvalue()
    assert "\r" in text and "10/10" in text and "draws/s" in text
    assert "<" in text  # tqdm's "[elapsed<remaining" ETA field
    assert "tetherheli: a note\n" in text


def test_a_log_gets_one_summary_line():
    out = io.StringIO()
    with Progress("sweep", 4, "runs", stream=out) as bar:
        bar.update(3)
        bar.note("tetherheli: a note")
        bar.update_to(4)
    lines = out.getvalue().splitlines()
    assert "\r" not in out.getvalue()
    assert lines[0] == "tetherheli: a note"
    assert lines[1].startswith("sweep: 4/4 runs in ") and "runs/s" in lines[1]
    assert len(lines) == 2


def test_quiet_prints_nothing_but_notes():
    for stream in (io.StringIO(), _Terminal()):
        with Progress("animate", 3, "frames", enabled=False, stream=stream) as bar:
            bar.update(3)
        assert stream.getvalue() == ""


def test_an_interrupted_job_still_ends_its_line():
    out = io.StringIO()
    try:
        with Progress("paper", 4, "runs", stream=out) as bar:
            bar.update(1)
            raise KeyboardInterrupt
    except KeyboardInterrupt:
        pass
    assert out.getvalue().startswith("paper: 1/4 runs in ")


def _cli(args: list[str], tmp_path: Path) -> tuple[int, str]:
    log = tmp_path / "stderr.log"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    with open(log, "w") as fh:
        code = subprocess.run(
            [sys.executable, "-m", "tetherheli", *args],
            stderr=fh,
            stdout=subprocess.DEVNULL,
            env=env,
            timeout=900,
        ).returncode
    return code, log.read_text()


MC = """
name = "mc_log"
duration = 0.5
[[wind]]
type = "pulse"
start = 0.1
duration = 0.2
magnitude = 20.0
direction = [1.0, 0.0, 0.0]
[montecarlo]
runs = 4
seed = 3
amplitude_std_percent = 10.0
"""


def test_montecarlo_into_a_log_file_has_no_carriage_returns(tmp_path):
    scenario = tmp_path / "mc.toml"
    scenario.write_text(MC)
    code, err = _cli(
        ["montecarlo", str(scenario), "--out", str(tmp_path / "o"), "--chunk-size", "2"], tmp_path
    )
    assert code == 0, err
    assert "\r" not in err
    assert err.splitlines()[-1].startswith("montecarlo: 4/4 draws in ")


def test_quiet_montecarlo_prints_no_progress(tmp_path, capsys):
    from tetherheli.cli import main

    scenario = tmp_path / "mc.toml"
    scenario.write_text(MC)
    assert main(["montecarlo", str(scenario), "--out", str(tmp_path / "q"), "--quiet"]) == 0
    assert capsys.readouterr().err == ""
