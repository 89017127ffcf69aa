"""Issue 9: a user's files are never lost, names from files are never paths, runs that cannot
fit are refused before allocating, and the CLI tells user errors from internal ones."""

from __future__ import annotations

import json
import os
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from tetherheli import ParameterError, load_scenario
from tetherheli._io import (
    OUTPUT_RECORD,
    OutputPathError,
    check_output_location,
    output_directory,
)
from tetherheli.cli import EXIT_INTERNAL, main
from tetherheli.resources import (
    DEFAULT_MEMORY_LIMIT,
    MEMORY_LIMIT_ENV,
    ResourceLimitError,
    memory_limit,
)
from tetherheli.runs import simulate
from tetherheli.runs.batch import run_batch
from tetherheli.scenario import Scenario
from tetherheli.scenario.core import MAX_SAMPLES

SHORT = """
name = "{name}"
configuration = "{cfg}"
duration = {duration}
[control]
dt = 0.01
[[wind]]
type = "pulse"
start = 0.2
duration = 0.3
magnitude = 10.0
direction = [1, 0, 0]
"""


#: the folder rules are under test here, not the plots: the commands' figures are drawn blank
#: and still saved (``tests/blank_figures.py``)
pytestmark = pytest.mark.usefixtures("blank_figures")


def scenario_file(folder: Path, name: str = "short", cfg: str = "free", duration=0.5) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{name}.toml"
    path.write_text(SHORT.format(name=name, cfg=cfg, duration=duration))
    return path


def tree(folder: Path) -> dict[str, bytes]:
    """Every file below ``folder`` with its content."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


@pytest.fixture
def workdir(tmp_path: Path, monkeypatch) -> Path:
    """A scratch current directory with a scenario in scenarios/ and a user's own file."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    (tmp_path / "home").mkdir()
    scenario_file(tmp_path / "scenarios")
    (tmp_path / "thesis.tex").write_text("months of work\n")
    return tmp_path


# --- 1. output directories ------------------------------------------------------------------


@pytest.mark.parametrize("out", [".", "..", "/", "home", "scenarios", "link_to_cwd", "home/.."])
def test_dangerous_out_is_refused_and_nothing_changes(workdir: Path, capsys, out):
    """--out may not be the cwd, an ancestor, home, root, or a folder holding an input; links
    are resolved first. Exit 2, one line, every file intact."""
    (workdir / "link_to_cwd").symlink_to(workdir)
    out = out.replace("home", str(workdir / "home"))
    before = tree(workdir)
    code = main(["simulate", "scenarios/short.toml", "--out", out])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("tetherheli: error: --out ")
    assert "Traceback" not in err
    assert tree(workdir) == before


def test_out_inside_an_input_folder_is_refused(workdir: Path):
    (workdir / "runs").mkdir()
    with pytest.raises(OutputPathError, match="inside the input folder"):
        check_output_location(workdir / "runs" / "a", inputs=[workdir / "runs"])


@pytest.mark.parametrize("command", ["simulate", "sweep", "paper"])
def test_foreign_directory_is_refused_without_force(workdir: Path, capsys, command):
    """A non-empty directory tetherheli did not create is refused before any run."""
    (workdir / "mine").mkdir()
    (workdir / "mine" / "data.csv").write_text("1,2,3\n")
    argv = {
        "simulate": ["simulate", "scenarios/short.toml"],
        "sweep": ["sweep", "scenarios/short.toml", "--param", "q9", "--values", "9,10"],
        "paper": ["paper"],
    }[command]
    assert main([*argv, "--out", "mine"]) == 2
    err = capsys.readouterr().err
    assert "was not created by tetherheli" in err and "data.csv" in err and "--force" in err
    assert tree(workdir / "mine") == {"data.csv": b"1,2,3\n"}


def test_force_writes_beside_foreign_files_and_never_over_them(workdir: Path, capsys):
    (workdir / "mine").mkdir()
    (workdir / "mine" / "data.csv").write_text("1,2,3\n")
    assert main(["simulate", "scenarios/short.toml", "--out", "mine", "--force"]) == 0
    files = tree(workdir / "mine")
    assert files["data.csv"] == b"1,2,3\n"
    assert {"short.csv", "short.json", "report.md", OUTPUT_RECORD} <= set(files)
    record = json.loads(files[OUTPUT_RECORD])["files"]
    assert "data.csv" not in record and record["short.csv"]["writer"] == "simulate"
    # a foreign file where tetherheli would write: refused even with --force, nothing changes
    (workdir / "other").mkdir()
    (workdir / "other" / "report.md").write_text("my report\n")
    before = tree(workdir)
    assert main(["simulate", "scenarios/short.toml", "--out", "other", "--force"]) == 2
    assert "report.md was not written by tetherheli" in capsys.readouterr().err
    assert tree(workdir) == before


def test_rerun_keeps_user_files_and_replaces_only_its_own(workdir: Path):
    """The README's workflow: re-running into an output directory works; files the user or
    another command (an animation) added survive; stale runs of the same command go."""
    scenario_file(workdir / "scenarios", "other", "tethered")
    assert main(["simulate", "scenarios/short.toml", "scenarios/other.toml", "--out", "r"]) == 0
    out = workdir / "r"
    assert (out / "other" / "other.csv").is_file()
    (out / "notes.txt").write_text("my notes\n")
    (out / "short" / "notes.txt").write_text("more notes\n")
    assert main(["animate", "r", "--max-frames", "2", "--fps", "2"]) == 0
    gif = (out / "animation.gif").read_bytes()
    assert main(["simulate", "scenarios/short.toml", "--out", "r"]) == 0
    assert (out / "notes.txt").read_text() == "my notes\n"
    assert (out / "short" / "notes.txt").read_text() == "more notes\n"
    assert (out / "animation.gif").read_bytes() == gif  # another command's file is kept
    assert not (out / "other").exists()  # the stale run of the same command is removed
    assert (out / "short.csv").is_file() and (out / "report.md").is_file()
    # an edited own file is the user's now: refused, not overwritten
    (out / "report.md").write_text("edited\n")
    assert main(["simulate", "scenarios/short.toml", "--out", "r"]) == 2
    assert (out / "report.md").read_text() == "edited\n"


def test_failed_write_leaves_existing_directory_as_it_was(workdir: Path, monkeypatch):
    assert main(["simulate", "scenarios/short.toml", "--out", "r"]) == 0
    before = tree(workdir / "r")
    with pytest.raises(RuntimeError, match="disk full"), output_directory("r", writer="x") as tmp:
        (tmp / "half.csv").write_text("1\n")
        raise RuntimeError("disk full")
    assert tree(workdir / "r") == before
    assert sorted(os.listdir(workdir)) == sorted(["home", "r", "scenarios", "thesis.tex"])


# --- 2. names from files are data, never paths ----------------------------------------------


@pytest.mark.parametrize(
    "name", ["../victim", "/tmp/abs", "a/b", "a\\b", ".", "..", "", "x" * 101, "tab\tname", "é"]
)
def test_names_that_could_be_paths_are_refused(tmp_path: Path, name):
    with pytest.raises(ParameterError, match=r"name = .* allowed: a plain name"):
        Scenario(name=name)
    path = tmp_path / "s.toml"
    path.write_text(SHORT.format(name=name.replace("\\", "\\\\"), cfg="free", duration=0.5))
    with pytest.raises(ParameterError, match=r"s\.toml: name = "):
        load_scenario(path)


def test_plain_names_are_accepted():
    for name in ("paper_sim1_free", "run-2.b", "A" * 100):
        assert Scenario(name=name).name == name


def test_two_scenarios_with_one_name_are_refused(workdir: Path, capsys):
    scenario_file(workdir / "copy", "short")
    assert main(["simulate", "scenarios/short.toml", "copy/short.toml", "--out", "r"]) == 2
    assert "names must differ" in capsys.readouterr().err
    assert not (workdir / "r").exists()


# --- 3. bounded resources -------------------------------------------------------------------


def test_memory_budget_from_the_environment(monkeypatch):
    monkeypatch.delenv(MEMORY_LIMIT_ENV, raising=False)
    assert memory_limit() == DEFAULT_MEMORY_LIMIT == 4 * 2**30
    for text, value in (("512M", 512e6), ("8G", 8e9), ("1.5GiB", 1.5 * 2**30), ("1000", 1000)):
        monkeypatch.setenv(MEMORY_LIMIT_ENV, text)
        assert memory_limit() == int(value)
    for bad in ("lots", "-1G", "0", "1e3"):
        monkeypatch.setenv(MEMORY_LIMIT_ENV, bad)
        with pytest.raises(ResourceLimitError, match=MEMORY_LIMIT_ENV):
            memory_limit()


def test_oversized_runs_are_refused_before_allocating(workdir: Path, capsys, monkeypatch):
    """duration / dt beyond MAX_SAMPLES is refused by validation; a run that fits the sample
    bound but not the memory budget is refused by its estimate, with bounded memory."""
    monkeypatch.delenv(MEMORY_LIMIT_ENV, raising=False)
    huge = scenario_file(workdir / "big", "huge", duration=1e12)
    assert main(["simulate", str(huge), "--out", "r"]) == 2
    assert f"at most {MAX_SAMPLES:.0e} control samples" in capsys.readouterr().err
    long = scenario_file(workdir / "big", "long", duration=2e5)
    tracemalloc.start()
    try:
        assert main(["simulate", str(long), "--out", "r"]) == 2
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    err = capsys.readouterr().err
    # 20,000,001 samples x 35 recorded floats (``layout.Signals``) x 8 B x a peak factor of 3
    assert "needs about 15.6 GiB, more than the memory budget of 4.0 GiB" in err
    assert MEMORY_LIMIT_ENV in err and err.count("\n") == 1
    assert peak < 50e6  # the 20 M-sample recorder was never allocated
    assert not (workdir / "r").exists()
    with pytest.raises(ResourceLimitError):
        simulate(load_scenario(long))


def test_budget_counts_sensor_noise_and_concurrent_batch_runs(monkeypatch):
    from tetherheli.sensing.config import SensorConfig

    s = Scenario(name="n", duration=100.0, sensors=SensorConfig.typical_gps())
    monkeypatch.setenv(MEMORY_LIMIT_ENV, "1M")  # 10001 rows x 17 channels x 8 B = 1.36 MB
    with pytest.raises(ResourceLimitError, match=r"run n: .*10001 samples"):
        run_batch([s], workers=1)
    monkeypatch.setenv(MEMORY_LIMIT_ENV, "2M")
    run_batch([s], workers=1)  # fits alone ...
    with pytest.raises(ResourceLimitError, match="2 runs at once"):
        run_batch([s, s], workers=2)  # ... not twice at once


def test_streamed_csv_holds_every_sample_exactly(tmp_path: Path):
    """The CSV is written in blocks; read back it equals the result's columns bit for bit."""
    from tetherheli.results import files as result_module

    r = simulate(Scenario(name="csv", duration=0.5, configuration="tethered"))
    original = result_module._CSV_BLOCK_ROWS
    result_module._CSV_BLOCK_ROWS = 7  # several blocks and a partial one
    try:
        path = r.to_csv(tmp_path / "csv.csv")
    finally:
        result_module._CSV_BLOCK_ROWS = original
    header = path.read_text().splitlines()[0].split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    cols = r.columns()
    assert header == list(cols)
    assert data.shape == (r.time.size, len(cols))
    for i, values in enumerate(cols.values()):
        np.testing.assert_array_equal(data[:, i], values)


# --- 6. the CLI boundary --------------------------------------------------------------------


def test_internal_error_is_not_a_usage_error(workdir: Path, capsys, monkeypatch):
    """A bug (a plain exception) exits 70 with one line pointing to --debug; --debug prints
    the traceback. A ValueError that is not ours is a bug too, not 'bad input'."""
    import tetherheli.runs.closed_loop

    def broken(*args, **kwargs):
        raise ValueError("index arithmetic went wrong")

    # the command flies its checked runs through simulate's private twin
    monkeypatch.setattr(tetherheli.runs.closed_loop, "_simulate", broken)
    assert main(["simulate", "scenarios/short.toml", "--out", "r"]) == EXIT_INTERNAL == 70
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "internal error" in err and "--debug" in err
    assert main(["simulate", "scenarios/short.toml", "--out", "r", "--debug"]) == 70
    err = capsys.readouterr().err
    assert "Traceback" in err and "index arithmetic went wrong" in err


def test_file_system_error_on_a_user_path_is_exit_2(workdir: Path, capsys):
    """An OSError about a user's path is a user error: one line naming the path, exit 2."""
    assert main(["simulate", "scenarios/short.toml", "--out", "thesis.tex/run"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("tetherheli: error: ") and "thesis.tex" in err and err.count("\n") == 1
    assert (workdir / "thesis.tex").read_text() == "months of work\n"


def test_negative_sweep_values_need_no_equals_sign(workdir: Path, capsys):
    argv = ["sweep", "scenarios/short.toml", "--param", "helicopter.d_O_P3", "--out", "sw"]
    assert main([*argv, "--values", "-0.2:-0.1:2"]) == 0
    rows = (workdir / "sw" / "sweep.csv").read_text().splitlines()[1:]
    assert [float(r.split(",")[0]) for r in rows] == [-0.2, -0.1]


def test_interrupt_starts_on_a_new_line_after_a_progress_bar(workdir: Path, capsys, monkeypatch):
    from tetherheli import progress

    def interrupted(args):
        with progress.Progress("montecarlo", 10, "draws") as bar:
            bar.update(3)
            raise KeyboardInterrupt

    from tetherheli.cli import trim

    monkeypatch.setattr(trim, "run", interrupted)
    assert main(["trim"]) == 130
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 2 and lines[0].startswith("montecarlo: 3/10 draws in ")
    assert lines[1] == "tetherheli: interrupted"


def test_animation_run_names_are_names_not_paths(workdir: Path, capsys):
    """--runs picks runs the folder lists (nested runs of a comparison included); anything
    else, e.g. a path out of the folder, is refused."""
    from tetherheli.viz.animation import list_runs

    scenario_file(workdir / "scenarios", "other", "tethered")
    assert main(["simulate", "scenarios/short.toml", "scenarios/other.toml", "--out", "r"]) == 0
    assert list_runs(workdir / "r") == ["other/other", "short/short"]
    assert main(["simulate", "scenarios/short.toml", "--out", "single"]) == 0
    for stem in ("../single/short", str(workdir / "single" / "short")):
        assert main(["animate", "r", "--runs", stem, "--out", "r/a.gif"]) == 2
        assert "stem = " in capsys.readouterr().err
    assert not (workdir / "r" / "a.gif").exists()


def test_derive_never_overwrites_a_users_file(tmp_path: Path, capsys):
    """derive --out writes a new file, or one derive wrote; never a user's file."""
    thesis = tmp_path / "thesis.py"
    thesis.write_text("# mine\n")
    assert main(["derive", "--out", str(thesis)]) == 2
    assert "not written by tetherheli" in capsys.readouterr().err
    assert thesis.read_text() == "# mine\n"
    fresh = tmp_path / "gen.py"
    assert main(["derive", "--out", str(fresh)]) == 0
    assert main(["derive", "--check", "--out", str(fresh)]) == 0


MC = (
    SHORT.format(name="mc", cfg="tethered", duration=0.5)
    + """
[montecarlo]
runs = 2
seed = 3
amplitude_std_percent = 10.0
"""
)


def test_montecarlo_never_overwrites_results_it_did_not_write(workdir: Path, capsys):
    """montecarlo --out: refused where the others are; a foreign results.csv or figure is
    never replaced (even with --force); its own finished job re-runs and keeps added files."""
    (workdir / "mc.toml").write_text(MC)
    base = ["montecarlo", "mc.toml", "--quiet", "--out"]
    assert main([*base, "."]) == 2
    assert "current directory" in capsys.readouterr().err
    (workdir / "theirs").mkdir()
    (workdir / "theirs" / "results.csv").write_text("precious\n")
    assert main([*base, "theirs"]) == 2
    assert main([*base, "theirs", "--force"]) == 2
    assert "results.csv exists and was not written by tetherheli" in capsys.readouterr().err
    assert tree(workdir / "theirs") == {"results.csv": b"precious\n"}  # not even partial/
    assert main([*base, "mine"]) == 0
    table = (workdir / "mine" / "results.csv").read_bytes()
    (workdir / "mine" / "notes.txt").write_text("mine\n")
    assert main([*base, "mine"]) == 0  # the same job again: resumed, results rewritten
    assert (workdir / "mine" / "results.csv").read_bytes() == table
    assert (workdir / "mine" / "notes.txt").read_text() == "mine\n"
    record = json.loads((workdir / "mine" / OUTPUT_RECORD).read_text())["files"]
    assert {"results.csv", "summary.json", "peak_q1_hist.png"} <= set(record)


def test_importing_tetherheli_leaves_the_matplotlib_backend_alone():
    """Library code never switches the process's backend (a notebook keeps its figures)."""
    code = (
        "import matplotlib; matplotlib.use('svg'); "
        "import tetherheli.viz.plots, tetherheli.viz.animation, tetherheli.report, "
        "tetherheli.studies.sweep, tetherheli.studies.montecarlo; print(matplotlib.get_backend())"
    )
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "svg"


def test_montecarlo_chunk_that_cannot_fit_is_refused_before_any_draw(workdir: Path, capsys):
    """A chunk holds its draws' scenarios and gust series at once: --chunk-size 1000000 of a
    turbulence job (75 kB a draw) is refused before any draw is made, naming the option."""
    shipped = Path(__file__).resolve().parents[1] / "scenarios" / "montecarlo_turbulence.toml"
    argv = ["montecarlo", str(shipped), "--quiet", "--runs", "1000000", "--out", "mc"]
    tracemalloc.start()
    try:
        assert main([*argv, "--chunk-size", "1000000"]) == 2
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    err = capsys.readouterr().err
    assert "a Monte Carlo chunk of 1000000 draws needs about" in err and "--chunk-size" in err
    assert peak < 50e6
    assert not (workdir / "mc").exists()
