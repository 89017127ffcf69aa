"""Issue 22, sections 1-3 (and issue 25's ``save`` into a missing folder): no run name, link or
half-finished write can cost a result. Each class through the API and the CLI; a killed run
is either a real SIGKILL (of a small writer in a subprocess) or the temporary files such a
run leaves, named as ``tetherheli._io`` names them."""

from __future__ import annotations

import errno
import json
import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from tetherheli import ParameterError, _io, load_scenario
from tetherheli._io import (
    OUTPUT_RECORD,
    OWN_FILE_STEMS,
    TEMPORARY_TAG,
    OutputPathError,
    atomic_open,
    claim_output_directory,
    is_own_temporary,
    output_directory,
)
from tetherheli.cli import main
from tetherheli.runs import simulate
from tetherheli.scenario import Scenario

from . import test_output_safety as safety
from .test_montecarlo import SHORT as MC_SHORT
from .test_montecarlo import _chunks_of, _run
from .test_output_safety import scenario_file, tree

ROOT = Path(__file__).resolve().parents[1]
workdir = safety.workdir  # the fixture: a scratch current directory and HOME


#: the folder rules are under test here, not the plots: the commands' figures are drawn blank
#: and still saved (``tests/blank_figures.py``)
pytestmark = pytest.mark.usefixtures("blank_figures")


def names_no_temporary(message: str) -> bool:
    return re.search(rf"{TEMPORARY_TAG}-[0-9]+-", message) is None


def one_line(err: str) -> str:
    """The one error line of a refusal: no traceback, no temporary file named."""
    assert err.count("\n") == 1 and err.startswith("tetherheli: error: "), err
    assert names_no_temporary(err), err
    return err


def dead_pid() -> int:
    """The process id of a process that has ended (as a killed run's is)."""
    done = subprocess.Popen([sys.executable, "-c", "pass"])
    done.wait()
    return done.pid


def leftovers(folder: Path) -> list[str]:
    """tetherheli's temporary files and folders in and beside ``folder``."""
    inside = [p.name for p in folder.rglob("*") if is_own_temporary(p.name)]
    beside = [p.name for p in folder.parent.iterdir() if is_own_temporary(p.name)]
    return inside + beside


# --- 1. a run's name can never be one of tetherheli's own files ----------------------------

RESERVED = [
    "summary",
    "Summary",
    "summary.json",
    "SUMMARY.JSON",
    "report.md",
    "outputs",
    "outputs.png",
    "inputs.svg",
    "animation.gif",
    ".tetherheli-output",
    ".tetherheli-output.json",
    ".hidden",
]


@pytest.mark.parametrize("name", RESERVED)
def test_reserved_names_are_refused_by_scenario(tmp_path: Path, name: str):
    """A name that is (the stem of) one of tetherheli's own files, or that starts with '.'
    as its record and temporaries do, is refused in one line naming the field."""
    with pytest.raises(ParameterError, match=r"^name = .* own file names") as info:
        Scenario(name=name)
    assert "\n" not in str(info.value)
    path = tmp_path / "s.toml"
    path.write_text(f'name = "{name}"\n')
    with pytest.raises(ParameterError, match=r"s\.toml: name = "):
        load_scenario(path)


def test_names_near_reserved_ones_are_plain_names():
    for name in ("summary_2", "my.summary", "reports", "outputs-b", "paper_sim1_free", "a.b"):
        assert Scenario(name=name).name == name


def test_own_files_beside_runs_have_reserved_stems(workdir: Path):
    """The construction behind the rule: every file simulate and animate write beside a
    run's files or folders has a stem of OWN_FILE_STEMS (or is hidden, or a .toml no run
    writes), so no valid name reaches it. A new own file fails here until it is listed."""
    scenario_file(workdir / "scenarios", "other", "tethered")
    assert main(["simulate", "scenarios/short.toml", "--out", "one"]) == 0
    assert main(["simulate", "scenarios/short.toml", "scenarios/other.toml", "--out", "two"]) == 0
    assert main(["animate", "two", "--max-frames", "2", "--fps", "2", "--quiet"]) == 0
    beside = {p.name for p in (workdir / "one").iterdir()} - {"short.csv", "short.json"}
    beside |= {p.name for p in (workdir / "two").iterdir() if p.is_file()}
    for name in beside:
        stem = name.partition(".")[0]
        assert name.startswith(".") or name.endswith(".toml") or stem in OWN_FILE_STEMS, name


@pytest.mark.parametrize(
    "names", [("summary",), (".tetherheli-output",), ("summary.json", "outputs.png")]
)
def test_cli_refuses_a_reserved_name_before_any_run(workdir: Path, capsys, monkeypatch, names):
    """The issue's cases: exit 2, one line naming the field, no run flown, nothing written."""
    import tetherheli.runs.closed_loop

    def no_run(*args, **kwargs):
        raise AssertionError("a run was flown")

    # the command flies its checked runs through simulate's private twin
    monkeypatch.setattr(tetherheli.runs.closed_loop, "_simulate", no_run)
    files = [str(scenario_file(workdir / f"s{k}", "x")) for k in range(len(names))]
    for path, name in zip(files, names, strict=True):
        Path(path).write_text(Path(path).read_text().replace('name = "x"', f'name = "{name}"'))
    assert main(["simulate", *files, "--out", "r"]) == 2
    err = one_line(capsys.readouterr().err)
    assert f"name = '{names[0]}' is invalid" in err
    assert not (workdir / "r").exists()


def test_names_equal_but_for_case_are_refused(workdir: Path, capsys):
    """Two runs A and a would share one folder on a case-insensitive file system."""
    scenario_file(workdir / "up", "Short")
    assert main(["simulate", "scenarios/short.toml", "up/Short.toml", "--out", "r"]) == 2
    err = one_line(capsys.readouterr().err)
    assert "name = 'Short'" in err and "names must differ" in err
    assert not (workdir / "r").exists()
    from tetherheli.report.paper import write_comparison

    runs = [simulate(Scenario(name=n, duration=0.05)) for n in ("run", "RUN")]
    with pytest.raises(ParameterError, match="names must differ"):
        write_comparison(runs, workdir / "api", command="test")
    assert not (workdir / "api").exists()


def test_animation_never_takes_a_run_file_for_a_record(workdir: Path):
    """animate --out OUT/.tetherheli-output/anim.gif, where that folder holds a run's JSON
    named like the record (as a run named '.tetherheli-output' wrote it before this rule):
    the JSON is not a record, stays byte-identical, and the animation is listed in OUT's."""
    scenario_file(workdir / "scenarios", "other", "tethered")
    assert main(["simulate", "scenarios/short.toml", "scenarios/other.toml", "--out", "r"]) == 0
    hidden = workdir / "r" / ".tetherheli-output"
    hidden.mkdir()
    shutil.copy(workdir / "r" / "short" / "short.json", hidden / OUTPUT_RECORD)
    run_json = (hidden / OUTPUT_RECORD).read_bytes()
    out = "r/.tetherheli-output/anim.gif"
    argv = ["animate", "r", "--runs", "short/short", "--max-frames", "2", "--fps", "2"]
    assert main([*argv, "--out", out, "--quiet"]) == 0
    assert (hidden / OUTPUT_RECORD).read_bytes() == run_json
    record = json.loads((workdir / "r" / OUTPUT_RECORD).read_text())["files"]
    assert record[".tetherheli-output/anim.gif"]["writer"] == "animate"
    with pytest.raises(OutputPathError, match="own bookkeeping"):
        _io.check_output_file(workdir / "r" / "sub" / OUTPUT_RECORD)


# --- 2. writes are all or nothing ----------------------------------------------------------


def _old_folder(out: Path) -> None:
    """An own folder as a first run of writer "w" leaves it, and a file the user added."""
    with output_directory(out, writer="w") as build:
        (build / "a.txt").write_text("old a\n")
        (build / "sub").mkdir()
        (build / "sub" / "b.txt").write_text("old b\n")
        (build / "stale.txt").write_text("written last time only\n")
    (out / "notes.txt").write_text("the user's notes\n")


def _new_files(build: Path) -> None:
    (build / "a.txt").write_text("new a\n")
    (build / "sub").mkdir()
    (build / "sub" / "b.txt").write_text("new b\n")
    (build / "sub2").mkdir()
    (build / "sub2" / "c.txt").write_text("new c\n")


NEW_TREE = {
    "a.txt": b"new a\n",
    "notes.txt": b"the user's notes\n",
    "sub/b.txt": b"new b\n",
    "sub2/c.txt": b"new c\n",
}


def _without_record(files: dict[str, bytes]) -> dict[str, bytes]:
    return {k: v for k, v in files.items() if k != OUTPUT_RECORD}


def _count_renames(monkeypatch, fail_at: int | None = None) -> list[str]:
    """Count the renames from now on; the one numbered ``fail_at`` fails as in a read-only
    folder (once: undoing it works)."""
    calls: list[str] = []
    replace = os.replace

    def counted(a, b):
        calls.append(str(b))
        if len(calls) - 1 == fail_at:
            raise PermissionError(errno.EACCES, "Permission denied", str(a), None, str(b))
        replace(a, b)

    monkeypatch.setattr(_io.os, "replace", counted)
    return calls


def test_a_failure_at_any_rename_of_the_swap_changes_nothing(tmp_path: Path, monkeypatch):
    """Whichever rename of the swap fails (a read-only folder, a full disk), the folder is
    left byte-identical with a record that still matches, the error is one line naming a
    file of the folder, and the next run succeeds without force."""
    out = tmp_path / "r"
    _old_folder(out)
    with monkeypatch.context() as m:
        with output_directory(out, writer="w") as build:
            _new_files(build)
            calls = _count_renames(m)  # the swap's renames only
    renames = len(calls)
    assert renames == 9  # record and journal staged, 3 aside (stale.txt too), 3 in, commit
    assert _without_record(tree(out)) == NEW_TREE
    for fail_at in range(renames):
        shutil.rmtree(out)
        _old_folder(out)
        before = tree(out)
        with monkeypatch.context() as m:
            with pytest.raises(OutputPathError) as info:
                with output_directory(out, writer="w") as build:
                    _new_files(build)
                    _count_renames(m, fail_at)
        message = str(info.value)
        assert "\n" not in message and "nothing in it changed" in message, message
        assert names_no_temporary(message) and ".tetherheli-swap" not in message, message
        assert tree(out) == before, fail_at
        assert leftovers(out) == [], fail_at
        with output_directory(out, writer="w") as build:  # not locked: no force needed
            _new_files(build)
        assert _without_record(tree(out)) == NEW_TREE


def test_cli_rerun_into_a_folder_that_cannot_be_written_changes_nothing(
    workdir: Path, capsys, monkeypatch
):
    """The issue's case: a run subfolder made read-only (as root, simulated by refusing
    renames into it). Exit 2, one line naming the run's file, the folder unchanged, and the
    next run works without --force."""
    scenario_file(workdir / "scenarios", "other", "tethered")
    argv = ["simulate", "scenarios/short.toml", "scenarios/other.toml", "--out", "r"]
    assert main(argv) == 0
    before = tree(workdir / "r")
    locked = str(workdir / "r" / "short")
    replace = os.replace

    def read_only(a, b):
        if str(b).startswith(locked + os.sep) or str(a).startswith(locked + os.sep):
            raise PermissionError(errno.EACCES, "Permission denied", str(a), None, str(b))
        replace(a, b)

    with monkeypatch.context() as m:
        m.setattr(_io.os, "replace", read_only)
        assert main(argv) == 2
    err = one_line(capsys.readouterr().err)
    assert "--out r: short/" in err and "Permission denied" in err
    assert tree(workdir / "r") == before
    assert leftovers(workdir / "r") == []
    assert main(argv) == 0  # no lock left behind


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root ignores modes")
def test_cli_read_only_run_folder_for_real(workdir: Path, capsys):
    scenario_file(workdir / "scenarios", "other", "tethered")
    argv = ["simulate", "scenarios/short.toml", "scenarios/other.toml", "--out", "r"]
    assert main(argv) == 0
    before = tree(workdir / "r")
    (workdir / "r" / "short").chmod(0o555)
    try:
        assert main(argv) == 2
        one_line(capsys.readouterr().err)
        assert tree(workdir / "r") == before
    finally:
        (workdir / "r" / "short").chmod(0o755)
    assert main(argv) == 0


KILLER = """
import os, shutil, signal, sys
from pathlib import Path
from tetherheli import _io

out, kill_at = Path(sys.argv[1]), int(sys.argv[2])
replace, rmtree, calls = os.replace, shutil.rmtree, []

def or_die(step):
    def call(*args, **kwargs):
        if len(calls) == kill_at:
            os.kill(os.getpid(), signal.SIGKILL)
        calls.append(args)
        return step(*args, **kwargs)
    return call

with _io.output_directory(out, writer="w") as build:
    (build / "a.txt").write_text("new a\\n")
    (build / "sub").mkdir()
    (build / "sub" / "b.txt").write_text("new b\\n")
    (build / "sub2").mkdir()
    (build / "sub2" / "c.txt").write_text("new c\\n")
    os.replace, shutil.rmtree = or_die(replace), or_die(rmtree)
print(len(calls))
"""


@pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="POSIX signals")
def test_sigkill_at_any_rename_of_the_swap_is_undone_by_the_next_run(tmp_path: Path):
    """A real SIGKILL before each rename of the swap and before the temporary folder is
    removed: the next claim of the folder leaves it either exactly as before (killed before
    the commit) or whole as the new run wrote it (after), with no temporary file or folder
    left, and it can be written again."""
    out = tmp_path / "r"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}

    def killed_at(k: int) -> subprocess.CompletedProcess:
        return subprocess.run(
            [sys.executable, "-c", KILLER, str(out), str(k)],
            env=env,
            capture_output=True,
            text=True,
            check=False,
        )

    _old_folder(out)
    whole = killed_at(-1)
    assert whole.returncode == 0, whole.stderr
    steps = int(whole.stdout)
    assert steps == 10  # the nine renames of the swap, then the temporary folder's removal
    outcomes = []
    for k in range(steps):
        shutil.rmtree(out)
        _old_folder(out)
        before = tree(out)
        done = killed_at(k)
        assert done.returncode == -signal.SIGKILL, done.stderr
        claim_output_directory(out)  # what every next run does first
        after = tree(out)
        if after == before:
            outcomes.append("old")
        else:
            assert _without_record(after) == NEW_TREE, k
            assert _io.foreign_files(out) == ["notes.txt"], k  # the record matches
            outcomes.append("new")
        assert leftovers(out) == [], k
        with output_directory(out, writer="w") as build:
            _new_files(build)
        assert _without_record(tree(out)) == NEW_TREE
    assert outcomes == ["old"] * (steps - 1) + ["new"]  # the last rename is the commit


def test_own_temporary_names_are_the_ones_the_writers_make(tmp_path: Path):
    """The names the recovery recognises are the names the atomic writers really give."""
    with atomic_open(tmp_path / "results.csv") as fh:
        fh.write("x\n")
        (tmp_name,) = [p.name for p in tmp_path.iterdir()]
    assert tmp_name.startswith(f".results.csv.{TEMPORARY_TAG}-{os.getpid()}-")
    assert tmp_name.endswith(".tmp") and is_own_temporary(tmp_name)
    with _io.atomic_path(tmp_path / "anim.gif") as tmp:
        assert tmp.suffix == ".gif" and is_own_temporary(tmp.name)
    with output_directory(tmp_path / "o", writer="w") as build:
        assert is_own_temporary(build.name) and build.name.startswith(".o.")
    assert not is_own_temporary(".results.csv.k2j4h5x_.tmp")  # mkstemp's alone: maybe a user's
    assert not is_own_temporary("results.csv")


def test_a_live_writers_temporaries_are_left_alone(tmp_path: Path):
    out = tmp_path / "r"
    _old_folder(out)
    mine = out / f".a.txt.{TEMPORARY_TAG}-{os.getpid()}-abcd1234.tmp"
    mine.write_text("being written\n")
    claim_output_directory(out)
    assert mine.is_file()  # this process is alive: not a leftover
    assert _io.foreign_files(out) == ["notes.txt"]  # and not foreign


def test_cli_simulate_and_compare_clean_what_a_killed_run_left(workdir: Path, capsys):
    """SIGKILL during simulate or compare leaves a hidden build folder beside --out (and,
    in an existing folder, an atomic write's .tmp): the next run removes them and works."""
    pid = dead_pid()
    for command in (["simulate", "scenarios/short.toml"], ["compare", "scenarios/short.toml"]):
        out = workdir / command[0]
        build = workdir / f".{out.name}.{TEMPORARY_TAG}-{pid}-x7k2m9q1.partial"
        build.mkdir()
        (build / "short.csv").write_text("half a run\n")
        argv = [*command, "--out", out.name]
        if command[0] == "compare":
            argv += ["--controllers", "paper"]
        assert main(argv) == 0
        assert not build.exists()
        (out / f".report.md.{TEMPORARY_TAG}-{pid}-abcd1234.tmp").write_text("half\n")
        (out / f".{out.name}.{TEMPORARY_TAG}-{pid}-abcd1234.partial").mkdir()  # nested build
        assert main(argv) == 0
        assert leftovers(out) == [], command
    capsys.readouterr()
    # a user's file that merely looks temporary is not tetherheli's
    (workdir / "simulate" / ".report.md.abcd1234.tmp").write_text("mine\n")
    assert main(["simulate", "scenarios/short.toml", "--out", "simulate"]) == 0
    assert (workdir / "simulate" / ".report.md.abcd1234.tmp").read_text() == "mine\n"


# --- 2 (Monte Carlo): a killed first job resumes; chunks are verified by content -------------


@pytest.fixture
def mc_file(tmp_path: Path) -> Path:
    p = tmp_path / "mc.toml"
    p.write_text(MC_SHORT)
    return p


def test_montecarlo_resumes_after_a_kill_while_writing_results(
    mc_file, uninterrupted, tmp_path, capsys
):
    """SIGKILL while a first job writes results.csv: its chunks are done, no record yet, and
    the temporaries of the table (in the build folder beside OUT, or beside results.csv
    as before the build) are left. The resume is no foreign folder: it removes them and
    writes the table of an uninterrupted job."""
    out = tmp_path / "k"
    assert _run(mc_file, out, max_chunks=2) is None  # a first job, stopped before the table
    assert _run(mc_file, out, max_chunks=3) is not None
    (out / OUTPUT_RECORD).unlink()  # as before its record was written
    for name in ("results.csv", "summary.json", "peak_q1_hist.png", "peak_q1_cdf.png"):
        (out / name).unlink()
    (out / "peak_q1_paired.png").unlink()
    pid = dead_pid()
    (out / f".results.csv.{TEMPORARY_TAG}-{pid}-ab12cd34.tmp").write_text("run,seed\n0,7\n")
    build = tmp_path / f".k.{TEMPORARY_TAG}-{pid}-zz99yy88.partial"
    build.mkdir()
    (build / f".results.csv.{TEMPORARY_TAG}-{pid}-ef56gh78.tmp").write_text("run,seed\n")
    chunk_tmp = f".chunk_000000003_000000006.csv.{TEMPORARY_TAG}-{pid}-q1w2e3r4.tmp"
    (out / "partial" / chunk_tmp).write_text("3,7")
    argv = ["montecarlo", str(mc_file), "--out", str(out), "--chunk-size", "3", "--quiet"]
    assert main(argv) == 0, capsys.readouterr().err
    assert (out / "results.csv").read_bytes() == uninterrupted
    assert leftovers(out) == []


def _reseal(path: Path, rows: list[str]) -> None:
    """A chunk file holding ``rows`` under a valid checksum line (as ``_seal`` writes it)."""
    from tetherheli.studies.montecarlo.runner import _CHUNK_END, _seal

    lo, hi = (int(v) for v in _CHUNK_END.fullmatch(path.read_text().splitlines()[-1]).groups()[:2])
    path.write_text(_seal("".join(rows), lo, hi + 1))


def test_chunks_are_verified_by_their_rows_not_only_their_checksum(
    mc_file, uninterrupted, tmp_path, capsys
):
    """A chunk re-sealed with a valid checksum but its rows permuted (a draw's free and
    tethered rows swapped; two draws swapped), a chunk replaced by an empty folder or by a
    link: each is named in one line and computed again; the table equals the uninterrupted
    one. A folder that holds files where a chunk belongs is refused, never emptied."""
    out = tmp_path / "v"
    _run(mc_file, out)
    capsys.readouterr()
    outside = tmp_path / "outside.csv"
    outside.write_text("someone's file\n")

    def swap_configurations(p: Path) -> None:
        rows = p.read_text().splitlines(True)[:-1]
        _reseal(p, [rows[1], rows[0], *rows[2:]])

    def swap_draws(p: Path) -> None:
        rows = p.read_text().splitlines(True)[:-1]
        _reseal(p, [*rows[2:4], *rows[0:2], *rows[4:]])

    def folder(p: Path) -> None:
        p.unlink()
        p.mkdir()

    def link(p: Path) -> None:
        p.unlink()
        p.symlink_to(outside)

    damages = {
        "configurations swapped": (swap_configurations, "is not draw 0's free run"),
        "draws swapped": (swap_draws, "is not draw 3's free run"),
        "an empty folder": (folder, "is a folder, not a chunk file"),
        "a link": (link, "is a link, not a chunk file"),
    }
    for what, (damage, said) in damages.items():
        chunk = _chunks_of(out)[0 if what != "draws swapped" else 1]
        damage(chunk)
        assert _run(mc_file, out) is not None, what
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and str(chunk) in err[0] and said in err[0], (what, err)
        assert "computing it again" in err[0]
        assert chunk.is_file() and not chunk.is_symlink(), what
        assert (out / "results.csv").read_bytes() == uninterrupted, what
    assert outside.read_text() == "someone's file\n"
    # through the CLI: a folder with a file in it is the user's
    chunk = _chunks_of(out)[2]
    chunk.unlink()
    chunk.mkdir()
    (chunk / "keep.txt").write_text("mine\n")
    argv = ["montecarlo", str(mc_file), "--out", str(out), "--chunk-size", "3", "--quiet"]
    assert main(argv) == 2
    err = one_line(capsys.readouterr().err)
    assert str(chunk) in err and "holds files" in err
    assert (chunk / "keep.txt").read_text() == "mine\n"
    shutil.rmtree(chunk)
    chunk.mkdir()  # empty: computed again through the CLI too
    assert main(argv) == 0
    assert (out / "results.csv").read_bytes() == uninterrupted


def test_montecarlo_results_are_swapped_in_whole(mc_file, tmp_path, monkeypatch):
    """A failure while the job's results are written (here, its last figure) leaves the
    earlier results, summary and figures byte-identical and the job resumable."""
    out = tmp_path / "w"
    _run(mc_file, out)
    before = tree(out)
    import tetherheli.viz.figure as figure

    save = figure._save_figure  # the writer's, its format checked at its entry

    def full_disk(fig, path, *args, **kwargs):
        if "paired" in Path(path).name:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return save(fig, path, *args, **kwargs)

    with monkeypatch.context() as m:
        m.setattr(figure, "_save_figure", full_disk)
        with pytest.raises(OutputPathError, match=r"peak_q1_paired\.png could not be written"):
            _run(mc_file, out, metric="peak_q1")
    assert tree(out) == before and leftovers(out) == []
    assert _run(mc_file, out) is not None


# --- 3. links inside an output folder are never followed ------------------------------------


def test_a_link_in_place_of_a_run_folder_is_refused(workdir: Path, capsys):
    """The issue's case: a run folder of an own output folder moved elsewhere and linked
    back (its files keep their stamps). Nothing is written through the link: exit 2, one
    line naming it; both sides byte-identical."""
    scenario_file(workdir / "scenarios", "other", "tethered")
    argv = ["simulate", "scenarios/short.toml", "scenarios/other.toml", "--out", "r"]
    assert main(argv) == 0
    elsewhere = workdir / "elsewhere"
    shutil.move(workdir / "r" / "short", elsewhere)
    (workdir / "r" / "short").symlink_to(elsewhere, target_is_directory=True)
    before, outside = tree(workdir / "r"), tree(elsewhere)
    assert main(argv) == 2
    err = one_line(capsys.readouterr().err)
    assert "short is a link" in err and "never writes through a link" in err
    assert tree(elsewhere) == outside and tree(workdir / "r") == before
    assert leftovers(workdir / "r") == []
    # the API: the same refusal, whatever writes the folder
    with pytest.raises(OutputPathError, match="short is a link"):
        with output_directory(workdir / "r", writer="simulate") as build:
            (build / "short").mkdir()
            (build / "short" / "x.csv").write_text("1\n")
    assert tree(elsewhere) == outside
    # an own file replaced by a link to a file outside: that file is never written
    target = workdir / "target.md"
    target.write_text("someone's text\n")
    (workdir / "r" / "short").unlink()
    (workdir / "r" / "report.md").unlink()
    (workdir / "r" / "report.md").symlink_to(target)
    assert main(argv) == 2
    assert "report.md was not written by tetherheli" in one_line(capsys.readouterr().err)
    assert target.read_text() == "someone's text\n"


def test_a_linked_partial_folder_of_a_montecarlo_is_refused(mc_file, tmp_path, capsys):
    """A finished Monte Carlo job's partial/ replaced by a link (and a chunk to compute
    again): no chunk is written through it, though the folder has its record."""
    out = tmp_path / "m"
    assert _run(mc_file, out) is not None
    elsewhere = tmp_path / "elsewhere"
    shutil.move(out / "partial", elsewhere)
    (out / "partial").symlink_to(elsewhere, target_is_directory=True)
    sorted(elsewhere.glob("chunk_*.csv"))[-1].unlink()
    outside = tree(elsewhere)
    argv = ["montecarlo", str(mc_file), "--out", str(out), "--chunk-size", "3", "--quiet"]
    assert main(argv) == 2
    err = one_line(capsys.readouterr().err)
    assert "partial is a link" in err
    assert tree(elsewhere) == outside
    with pytest.raises(OutputPathError, match="partial is a link"):
        _run(mc_file, out)
    assert tree(elsewhere) == outside


# --- issue 25: save into a missing folder ---------------------------------------------------


def test_save_creates_a_missing_folder_or_says_why_not(tmp_path: Path):
    """The docs' ``result.save("out", "sim1")`` on a missing folder creates it; a folder that
    cannot be made is one line naming it (a typed error), no temporary file named."""
    r = simulate(Scenario(name="s", duration=0.05))
    written = r.save(tmp_path / "out" / "deeper", "sim1")
    assert written["csv"].is_file() and written["json"].is_file()
    (tmp_path / "file").write_text("x\n")
    with pytest.raises(OutputPathError, match=r"cannot be created") as info:
        r.save(tmp_path / "file" / "out", "sim1")
    assert "\n" not in str(info.value) and TEMPORARY_TAG not in str(info.value)
    assert isinstance(info.value, ValueError)  # a tetherheli.errors.TetherheliError
