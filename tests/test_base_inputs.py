"""The moving base's inputs (issue 43): the ``[base]`` keys and the track files (CSV) are
bounded by one physical rule, read by one reader that streams them in bounded memory and
never shows their contents, recorded by resolved path and SHA-256 with the run (a saved
scenario flies the same track again, a Monte Carlo resumes only over the same bytes), and
protected by the output rules like the scenario file."""

from __future__ import annotations

import hashlib
import math
import os
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from tetherheli.base import motion
from tetherheli.base.motion import FileBase, HarmonicBase, VelocityBase, read_base_csv
from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.resources import ResourceLimitError
from tetherheli.scenario.core import BaseSettings, Scenario, load_scenario, scenario_toml
from tetherheli.studies.montecarlo import load_montecarlo
from tetherheli.studies.montecarlo.runner import run_montecarlo_chunks

SECRET = "hunter2-SECRET-TOKEN"


def _track(path: Path, rows: int = 200, *, step: float = 0.02, extra: str = "") -> Path:
    """A heaving deck sampled every ``step`` from t = -0.1 s (``rows`` rows)."""
    t = -0.1 + step * np.arange(rows)
    body = "".join(f"{x:.6f},0,0,{0.3 * math.sin(1.9 * x):.6f}\n" for x in t)
    path.write_text("t,n1,n2,n3\n" + body + extra, encoding="utf-8")
    return path


def _scenario(folder: Path, file: str, *, name: str = "deck", duration: float = 2.0) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(
        f'name = "{name}"\nduration = {duration}\n[base]\nmotion = "file"\nfile = "{file}"\n',
        encoding="utf-8",
    )
    return path


def _one_line(text: str) -> str:
    """The single stderr line of a refusal (no traceback)."""
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in text, text
    return lines[0]


# --- finding 5: a value whose consequences overflow is refused with its bound ----------------


@pytest.mark.parametrize(
    ("key", "value", "bound"),
    [
        ("velocity", [1e308, 0.0, 0.0], "[-100, 100] [m/s]"),
        ("position", [0.0, -1e308, 0.0], "[-1e+06, 1e+06] [m]"),
        ("amplitude", [0.0, 0.0, 1e308], "[0, 100] [m]"),
        ("phase", [1e308, 0.0, 0.0], "[-6.28319, 6.28319] [rad]"),
    ],
)
def test_absurd_but_finite_base_values_are_refused_with_their_bound(tmp_path, key, value, bound):
    motion_of = {"velocity": "velocity", "position": "fixed"}.get(key, "harmonic")
    path = tmp_path / "absurd.toml"
    path.write_text(
        f'name = "absurd"\nduration = 1.0\n[base]\nmotion = "{motion_of}"\n{key} = {value}\n'
    )
    with pytest.raises(ParameterError) as loaded:
        load_scenario(path)
    assert f"base.{key} = " in str(loaded.value) and bound in str(loaded.value)
    # the Python API refuses it with the loader's message, without the file's name
    cls = {"velocity": VelocityBase, "fixed": motion.FixedBase}.get(motion_of, HarmonicBase)
    with pytest.raises(ParameterError) as built:
        cls(**{key: tuple(value)})
    assert str(loaded.value) == f"{path}: {built.value}"


# --- findings 10 and 13: bounded columns and plain decimal cells -----------------------------


def test_a_track_of_huge_finite_values_is_one_line_naming_row_and_column(tmp_path, capsys):
    track = tmp_path / "huge.csv"
    track.write_text("t,n1,n2,n3\n-1,1e308,0,0\n1,-1e308,0,0\n2,1e308,0,0\n3,0,0,0\n")
    with pytest.raises(ParameterError, match=r"row 2 column n1 = 'out of its range'.*"
                       r"\[-1e\+06, 1e\+06\] \[m\]"):  # fmt: skip
        read_base_csv(track)
    code = main(["simulate", str(_scenario(tmp_path, "huge.csv")), "--out", str(tmp_path / "o")])
    assert code == 2 and "row 2 column n1" in _one_line(capsys.readouterr().err)
    assert not (tmp_path / "o").exists()
    # the same rule for a track given as arrays
    with pytest.raises(ParameterError, match=r"row 1 column n1 = 'out of its range'"):
        FileBase(np.arange(4.0) - 1, np.array([[0, 0, 0], [1e308, 0, 0], [0, 0, 0], [0, 0, 0]]))
    with pytest.raises(ParameterError, match=r"row 1 column t.*at least 0.0001 s"):
        FileBase(np.array([-1.0, -1.0 + 1e-300, 1, 2]), np.zeros((4, 3)))


@pytest.mark.parametrize("cell", ["1_0", "inf", "nan", "0x10", "1e", "١", "--1", "1.2.3", ""])
def test_track_cells_are_plain_decimal_numbers(tmp_path, cell):
    track = tmp_path / "cells.csv"
    track.write_text(f"t,n1,n2,n3\n-1,0,0,0\n0,{cell},0,0\n1,0,0,0\n2,0,0,0\n", encoding="utf-8")
    with pytest.raises(ParameterError, match=r"row 3 column n1 = 'not a plain decimal number'"):
        read_base_csv(track)


def test_plain_decimal_forms_are_read(tmp_path):
    track = tmp_path / "ok.csv"
    track.write_text("t, n1 ,n2,n3\r\n-1,+1,.5,5.\r\n\r\n0,-2E-3,1e+2,0\r\n1,0,0,0\r\n2,0,0,0")
    got = read_base_csv(track)
    np.testing.assert_array_equal(got.positions[:2], [[1.0, 0.5, 5.0], [-2e-3, 100.0, 0.0]])
    assert got.sha256 == hashlib.sha256(track.read_bytes()).hexdigest()


# --- finding 9: one reader, no echo of a file's contents, the path rule ----------------------


@pytest.mark.parametrize(
    "text",
    [
        f"{SECRET}:x:0:0:root:/root:/bin/bash\n",  # a passwd-like first line
        f"PATH=/usr/bin\0{SECRET}=1\0",  # an environment block
        f"t,n1,n2,n3\n0,0,0,0\n{SECRET},0,0,0\n1,0,0,0\n",  # a secret in a row
        f"t,n1,n2,n3\n0,0,0,0,{SECRET}\n",  # in an extra cell
        f"t,n1,n2,n3\n0,0,0,{SECRET * 20}\n",  # in a long line
    ],
)
def test_a_refusal_never_shows_the_files_contents(tmp_path, capsys, text):
    (tmp_path / "secret.csv").write_text(text)
    with pytest.raises(ParameterError) as err:
        read_base_csv(tmp_path / "secret.csv")
    assert SECRET not in str(err.value) and "/bin/bash" not in str(err.value)
    code = main(["simulate", str(_scenario(tmp_path, "secret.csv")), "--out", str(tmp_path / "o")])
    line = _one_line(capsys.readouterr().err)
    assert code == 2 and SECRET not in line and "base.file row" in line


def test_binary_junk_is_refused_without_echo(tmp_path):
    junk = bytes(range(256)) * 8
    (tmp_path / "junk.csv").write_bytes(b"t,n1,n2,n3\n" + junk)
    with pytest.raises(ParameterError, match=r"row 2") as err:
        read_base_csv(tmp_path / "junk.csv")
    assert "\\x" not in str(err.value) and "\n" not in str(err.value)


def test_only_regular_files_are_read_and_never_waited_on(tmp_path):
    with pytest.raises(ParameterError, match=r"base.file = .* a regular file you may read"):
        read_base_csv(tmp_path)  # a folder
    if hasattr(os, "mkfifo"):
        os.mkfifo(tmp_path / "pipe.csv")  # opened without blocking, refused
        with pytest.raises(ParameterError, match=r"not a folder, device or pipe"):
            read_base_csv(tmp_path / "pipe.csv")
    with pytest.raises(ParameterError, match=r"an existing file"):
        read_base_csv(tmp_path / "missing.csv")


def test_a_relative_path_is_taken_from_the_scenario_folder_and_recorded_resolved(tmp_path):
    """The documented rule: any file the user may read; '..' allowed; the resolved path and
    the SHA-256 of the bytes read are recorded."""
    (tmp_path / "tracks").mkdir()
    (tmp_path / "scenarios").mkdir()
    track = _track(tmp_path / "tracks" / "deck.csv")
    s = load_scenario(_scenario(tmp_path / "scenarios", "../tracks/deck.csv"))
    assert s.base.file == str(track.resolve())
    assert s.base.file_sha256 == hashlib.sha256(track.read_bytes()).hexdigest()
    assert s.input_files == {str(track.resolve()): s.base.file_sha256}


# --- finding 12: bounded memory ---------------------------------------------------------------


def test_a_file_of_blank_lines_is_refused_by_rows_in_bounded_memory(tmp_path, monkeypatch):
    """Blank lines count as rows; the file is streamed, so refusing it holds neither the
    file nor a list of its lines (the row limit lowered to 100000 to keep the test quick)."""
    monkeypatch.setattr(motion, "FILE_MAX_ROWS", 100_000)
    path = tmp_path / "blank.csv"
    path.write_bytes(b"t,n1,n2,n3\n" + b"\n" * 100_001)
    tracemalloc.start()
    try:
        with pytest.raises(ParameterError, match=r"more than 100000 rows.*blank lines count"):
            read_base_csv(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 100_000, peak  # not the file (100 kB), not a list of its lines (800 kB)


def test_a_file_over_the_size_limit_is_refused_before_reading(tmp_path, monkeypatch):
    path = _track(tmp_path / "deck.csv")
    monkeypatch.setattr(motion, "FILE_MAX_BYTES", 100)
    with pytest.raises(ParameterError, match=r"bytes\)' is invalid; allowed: .* at most 100 bytes"):
        read_base_csv(path)


def test_the_memory_budget_covers_the_track(tmp_path, monkeypatch):
    path = _track(tmp_path / "deck.csv", rows=2000)
    monkeypatch.setenv("TETHERHELI_MEMORY_LIMIT", "1M")
    with pytest.raises(ResourceLimitError, match=r"reading the track .*deck.csv \(2000 rows\)"):
        read_base_csv(path)
    monkeypatch.setenv("TETHERHELI_MEMORY_LIMIT", "64M")
    assert read_base_csv(path).times.size == 2000


# --- finding 8: the saved scenario flies the same track again, and detects a changed one -----


def test_a_saved_scenario_flies_the_track_again_and_refuses_a_changed_one(tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    track = _track(work / "deck.csv")
    _scenario(work, "deck.csv")
    monkeypatch.chdir(work)
    s = load_scenario("deck.toml")  # named relative to the working folder
    out = tmp_path / "elsewhere" / "run"
    out.mkdir(parents=True)
    saved = out / "scenario.toml"
    saved.write_text(scenario_toml(s.to_dict()), encoding="utf-8")  # as write_run saves it
    monkeypatch.chdir(tmp_path)  # another folder than the original one
    again = load_scenario(saved)
    assert again == s and again.input_files == s.input_files
    track.write_text(track.read_text().replace(",0,0,", ",0,0.001,", 1))
    with pytest.raises(ParameterError) as err:
        load_scenario(saved)
    assert "base.file_sha256" in str(err.value) and str(track.resolve()) in str(err.value)
    # a Scenario built in Python records the same
    built = Scenario(duration=2.0, base=BaseSettings(motion="file", file=str(track)))
    assert built.base.file == str(track.resolve()) and len(built.base.file_sha256) == 64


# --- finding 3: a Monte Carlo resumes only over the same bytes --------------------------------


def test_a_montecarlo_is_not_resumed_over_a_changed_track(tmp_path):
    track = _track(tmp_path / "deck.csv", rows=400)
    path = tmp_path / "mc.toml"
    path.write_text(
        'name = "mc_deck"\nduration = 2.0\n[base]\nmotion = "file"\nfile = "deck.csv"\n'
        "[montecarlo]\nruns = 4\nseed = 7\namplitude_std_percent = 10.0\n"
    )
    out = tmp_path / "out"
    base, config = load_montecarlo(path)
    assert run_montecarlo_chunks(base, config, out, max_chunks=0, progress=False) is None
    text = track.read_text()
    track.write_text(text.replace(",0,0,", ",0,0.001,", 1))  # one cell edited
    base, config = load_montecarlo(path)
    with pytest.raises(ParameterError) as err:
        run_montecarlo_chunks(base, config, out, max_chunks=0, progress=False)
    message = str(err.value)
    assert message.startswith(f"base.file = '{track.resolve()}' is invalid")
    assert "changed since" in message and "\n" not in message
    track.write_text(text)  # restored: the job resumes
    base, config = load_montecarlo(path)
    assert run_montecarlo_chunks(base, config, out, max_chunks=0, progress=False) is None


# --- finding 14: the inputs of a run are protected alike --------------------------------------


@pytest.mark.parametrize(
    "command",
    [
        ["simulate", "{s}"],
        ["sweep", "{s}", "--param", "params.tether.K_C", "--values", "30,40"],
        ["compare", "{s}", "--controllers", "paper"],
        ["compare", "--montecarlo", "{mc}", "--controllers", "paper"],
        ["montecarlo", "{mc}"],
    ],
    ids=["simulate", "sweep", "compare", "compare_montecarlo", "montecarlo"],
)
def test_out_may_not_hold_the_track_even_with_force(tmp_path, capsys, command):
    (tmp_path / "tracks").mkdir()
    (tmp_path / "sc").mkdir()
    _track(tmp_path / "tracks" / "deck.csv")
    scenario = _scenario(tmp_path / "sc", "../tracks/deck.csv")
    mc = tmp_path / "sc" / "mc.toml"
    mc.write_text(scenario.read_text() + "[montecarlo]\nruns = 2\nseed = 1\n")
    argv = [a.format(s=scenario, mc=mc) for a in command]
    for out in ("tracks", "sc"):  # the track's folder as the scenario's
        code = main([*argv, "--out", str(tmp_path / out), "--force"])
        line = _one_line(capsys.readouterr().err)
        assert code == 2 and "holds the input" in line, line
    assert sorted(p.name for p in (tmp_path / "tracks").iterdir()) == ["deck.csv"]
