"""Issue 22, class 7: a property-based fuzzer of output-folder states (Hypothesis).

Each example builds the state of an ``--out`` folder in a scratch directory from a list of
operations, then runs a real command on it in-process (``tetherheli.cli.main``), with or
without ``--force``: ``simulate`` of one scenario, of two (run subfolders), or a small
``montecarlo`` job (two draws of 1 s, two chunks). The starting states: absent; empty; a
folder of an earlier run of each command (made once per session, copied with its links);
a foreign folder; an existing file; a link to an own folder, or a dangling one; a path below
a regular file. The operations: a foreign file or folder (also where a run's file or folder
goes), an own file edited (bytes appended, or only its time changed) or removed, an entry
replaced by a link to a folder or a file outside, or by a file where a folder was, an entry
pinned read-only, leftover temporaries of a dead process (``.OUT.tetherheli-<pid>-<r>.partial``
beside it, as a folder or a file; ``.results.csv.tetherheli-<pid>-<r>.tmp`` and nested build
folders inside), a live process's temporary and a user's file that only looks like one; and
last, now and then, a run of the command killed at its n-th rename (no undo, no clean-up;
its temporaries renamed to a dead process's), which the next run must undo or find
committed.

The property (docs/cli.md, "Output directories"): exit 0 means the folder holds the whole
run (its record lists every file it wrote, each unchanged; the runs load through
``load_result`` equal to a fresh run's; a Monte Carlo's table is a fresh job's), every file
tetherheli did not write is as it was, nothing outside the folder changed, and no temporary
of a process that no longer runs is left; any other exit is 2 with one line on stderr naming
``--out`` or a path (no traceback), and the whole scratch tree (the folder and the link
targets outside it) is as before, to the byte, mode and file time, except that a dead
process's temporaries may be gone (and a Monte Carlo's resumable ``partial/`` chunks and
``job.json`` may have been written or recomputed); after a killed run the tree may instead
be as it was before that run began. Trees are compared by walking with
``os.lstat``, never following a link.

Read-only: root ignores file modes, so an entry is pinned with ``chattr +i`` where that
binds (it does for root with CAP_LINUX_IMMUTABLE), else with ``chmod`` where that binds (not
root); where neither does, the pinning operation is not drawn (``test_read_only_pinning``
says so as a skip). A regular file in place of a folder binds for everyone.

The figures are drawn as blank figures (``viz.plots.save_figure`` still writes each one):
the folder rules are under test, not the plots, and a real figure costs a second.

The scripts that write into a folder the user names (issue 43: an example's OUT_DIR,
``examples/train_residual.py --out``, ``benchmarks/bench_mpc.py --pareto``,
``docs/regenerate_tables.py --figures``) are fuzzed over the same states and operations with
the same property (``test_a_script_writes_whole_or_changes_nothing``): each runs its real
command line and output rules in-process, its work a stub (a blank figure, a fake
evaluation, a CSV read back); a refusal is one line ``SCRIPT: error: ...`` naming its
option.

Bounded in CI: a fixed example budget, derandomized, no deadline, about 25 s on a shared
2-core Xeon for the commands and 10 s for the scripts. ``TETHERHELI_FUZZ_EXAMPLES=500`` runs
longer (and random) on demand.
"""

from __future__ import annotations

import csv
import hashlib
import json
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")

from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from tetherheli._io import (  # noqa: E402
    OUTPUT_RECORD,
    TEMPORARY_TAG,
    claim_output_directory,
    is_own_temporary,
)
from tetherheli.cli import main  # noqa: E402
from tetherheli.results.result import load_result  # noqa: E402

from .blank_figures import blank_figures  # noqa: E402

_ON_DEMAND = int(os.environ.get("TETHERHELI_FUZZ_EXAMPLES", "0") or 0)
_CI_EXAMPLES = 120
_SETTINGS = settings(
    max_examples=_ON_DEMAND or _CI_EXAMPLES,
    derandomize=not _ON_DEMAND,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    database=None,
)

SCENARIO = """
name = "{name}"
configuration = "{cfg}"
duration = 1.0
[control]
dt = 0.01
[[wind]]
type = "pulse"
start = 0.2
duration = 0.3
magnitude = 10.0
direction = [1.0, 0.0, 0.0]
"""

#: the same short run with a small Monte Carlo table
MONTECARLO = (
    SCENARIO.format(name="mc_fuzz", cfg="tethered")
    + """[montecarlo]
runs = 2
seed = 7
amplitude_std_percent = 20.0
"""
)

#: command -> (input files, extra arguments, writer recorded)
COMMANDS = {
    "single": (["one.toml"], [], "simulate"),
    "pair": (["a.toml", "b.toml"], [], "simulate"),
    "mc": (["mc.toml"], ["--chunk-size", "1", "--workers", "1"], "montecarlo"),
}
#: The run names each simulate command writes (load_result stems) and where.
RUNS = {"single": {"one": "."}, "pair": {"a": "a", "b": "b"}}

#: The journal a swap keeps in its temporary folder (``_io.output_directory``).
_SWAP_JOURNAL = ".tetherheli-swap/journal.json"
_CHUNK = re.compile(r"partial/(chunk_[0-9]+_[0-9]+\.csv|job\.json)")


def _dead_pid() -> int:
    done = subprocess.Popen([sys.executable, "-c", "pass"])
    done.wait()
    return done.pid


def _argv(command: str, inputs: Path, out: Path, force: bool) -> list[str]:
    files, extra, _ = COMMANDS[command]
    tool = "montecarlo" if command == "mc" else "simulate"
    argv = [tool, *(str(inputs / f) for f in files), "--out", str(out), "--quiet", *extra]
    return [*argv, "--force"] if force else argv


# --- read-only pinning: what binds on this machine ------------------------------------------


def _can_write_in(folder: Path) -> bool:
    try:
        (folder / "probe").write_text("x")
    except OSError:
        return False
    (folder / "probe").unlink()
    return True


def _pinning() -> str | None:
    """How an entry is made read-only here: "chattr" (the immutable flag, binds for root too),
    "chmod" (binds unless root), or None when neither stops a write."""
    with tempfile.TemporaryDirectory() as scratch:
        probe = Path(scratch, "p")
        probe.mkdir()
        chattr = shutil.which("chattr")
        if chattr and subprocess.run([chattr, "+i", probe], capture_output=True).returncode == 0:
            try:
                if not _can_write_in(probe):
                    return "chattr"
            finally:
                subprocess.run([chattr, "-i", probe], capture_output=True)
        probe.chmod(0o555)
        try:
            return None if _can_write_in(probe) else "chmod"
        finally:
            probe.chmod(0o755)


PINNING = _pinning()


def _pin(path: Path) -> None:
    if PINNING == "chattr":
        subprocess.run(["chattr", "+i", str(path)], check=True, capture_output=True)
    else:
        path.chmod(stat.S_IMODE(os.lstat(path).st_mode) & ~0o222)


def _unpin(path: Path) -> None:
    if not os.path.lexists(path) or os.path.islink(path):
        return
    if PINNING == "chattr":
        subprocess.run(["chattr", "-i", str(path)], check=True, capture_output=True)
    else:
        path.chmod(stat.S_IMODE(os.lstat(path).st_mode) | 0o200)


# --- the earlier runs, once per session -----------------------------------------------------


class Earlier:
    """The session's earlier runs (a plain class: Hypothesis prints it by its repr)."""

    def __init__(self, inputs: Path, folders: dict[str, Path], dead: int, live: int) -> None:
        self.inputs = inputs  # the scenario files
        self.folders = folders  # command -> its fresh output folder (copied as a start state)
        self.records = {c: _record(f) for c, f in folders.items()}  # -> what each lists
        self.dead = dead  # the id of a process that has ended
        self.live = live  # the id of another process that runs (this one's parent)

    def __repr__(self) -> str:
        return f"Earlier({self.inputs.parent})"


@pytest.fixture(scope="session")
def earlier(tmp_path_factory: pytest.TempPathFactory) -> Earlier:
    base = tmp_path_factory.mktemp("earlier")
    inputs = base / "in"
    inputs.mkdir()
    for name, cfg in (("one", "tethered"), ("a", "free"), ("b", "tethered")):
        (inputs / f"{name}.toml").write_text(SCENARIO.format(name=name, cfg=cfg))
    (inputs / "mc.toml").write_text(MONTECARLO)
    folders = {}
    with pytest.MonkeyPatch.context() as m:
        blank_figures(m)
        for command in COMMANDS:
            folders[command] = base / command
            code = main(_argv(command, inputs, folders[command], force=False))
            assert code == 0, command
    done = Earlier(inputs, folders, _dead_pid(), os.getppid())
    assert all(done.records.values()), done.records
    return done


# --- the folder states ----------------------------------------------------------------------

STARTS = ("absent", "empty", "own", "own", "own", "foreign", "file", "link", "dangling", "below")
#: Names where a run's files or folders go (and some that are nobody's).
PLACES = (
    "notes.txt",
    "report.md",
    "summary.json",
    "one.csv",
    "scenario.toml",
    "outputs.png",
    "a",
    "a/a.csv",
    "a/notes.txt",
    "b",
    "results.csv",
    "peak_q1_hist.png",
    "partial",
    "partial/notes.txt",
    "partial/chunk_000000000_000000001.csv",
    "mine/deep/x.txt",
    OUTPUT_RECORD,
)
OPS = (
    "foreign_file",
    "foreign_dir",
    "edit",
    "touch",
    "remove",
    "link_dir",
    "link_file",
    "file_for_dir",
    "pin",
    "pin",  # twice: a pinned entry is what makes a swap fail half-way
    "dead_partial",
    "dead_partial_file",
    "dead_tmp",
    "dead_nested",
    "live_tmp",
    "lookalike",
)


@dataclass(frozen=True)
class State:
    command: str
    start: str
    start_of: str  # which earlier run an "own" or "link" start copies
    force: bool
    ops: tuple[tuple[str, int, str], ...]  # (operation, which entry, which place)
    kill: int | None = None  # last, a run of the command killed at this rename of os.replace


@st.composite
def folder_states(draw) -> State:
    ops = tuple(o for o in OPS if o != "pin" or PINNING is not None)
    command = draw(st.sampled_from(sorted(COMMANDS)))
    return State(
        command=command,
        start=draw(st.sampled_from(STARTS)),
        # mostly a re-run of the same command (the usual workflow), sometimes another's folder
        start_of=draw(st.sampled_from([command, command, *sorted(COMMANDS)])),
        force=draw(st.booleans()),
        ops=tuple(
            draw(
                st.lists(
                    st.tuples(
                        st.sampled_from(ops),
                        st.integers(0, 10**6),
                        st.sampled_from(PLACES),
                    ),
                    max_size=5,
                )
            )
        ),
        kill=draw(st.none() | st.integers(0, 24)),
    )


def _entries(out: Path) -> list[Path]:
    """What lies below ``out`` (links not followed), sorted."""
    found = []
    for root, dirs, files in os.walk(out):
        found += [Path(root, n) for n in dirs + files]
    return sorted(found)


def _build(state: State, ex: Path, earlier: Earlier) -> tuple[Path, list[Path]]:
    """Make ``state`` in the scratch directory ``ex``; the --out path and the pinned entries."""
    outside = ex / "outside"
    (outside / "dir" / "sub").mkdir(parents=True)
    (outside / "dir" / "f.txt").write_text("a folder outside\n")
    (outside / "dir" / "sub" / "g.txt").write_text("deeper\n")
    (outside / "file.txt").write_text("a file outside\n")
    out = ex / "OUT"
    own = earlier.folders[state.start_of]
    if state.start == "empty":
        out.mkdir()
    elif state.start == "own":
        shutil.copytree(own, out, symlinks=True)
    elif state.start == "foreign":
        (out / "data").mkdir(parents=True)
        (out / "data" / "mine.csv").write_text("1,2,3\n")
    elif state.start == "file":
        out.write_text("not a folder\n")
    elif state.start == "link":
        shutil.copytree(own, ex / "real", symlinks=True)
        out.symlink_to(ex / "real", target_is_directory=True)
    elif state.start == "dangling":
        out.symlink_to(ex / "nowhere", target_is_directory=True)
    elif state.start == "below":
        (ex / "afile").write_text("a file, not a folder\n")
        out = ex / "afile" / "OUT"
    real = Path(os.path.realpath(out))
    pinned: list[Path] = []
    for op, pick, place in state.ops:
        _apply(op, pick, place, real, outside, earlier, pinned)
    return out, pinned


def _apply(
    op: str, pick: int, place: str, real: Path, outside: Path, earlier: Earlier, pinned: list
) -> None:
    """One operation on the folder ``real`` (the resolved --out)."""
    if not real.parent.is_dir() or any(real == p or p in real.parents for p in pinned):
        return  # below a file (start "below"), or pinned: left as it is
    entries = _entries(real) if real.is_dir() and not real.is_symlink() else []
    files = [p for p in entries if p.is_file() and not p.is_symlink()]
    dirs = [p for p in entries if p.is_dir() and not p.is_symlink()]
    folders = [real, *dirs] if real.is_dir() else []
    at = real / place

    def free(path: Path) -> bool:  # a place to create something: nothing there, parents real
        if os.path.lexists(path) or any(p in pinned for p in path.parents):
            return False
        for parent in path.relative_to(real.parent).parents:
            p = real.parent / parent
            if os.path.lexists(p) and (p.is_symlink() or not p.is_dir()):
                return False
        return True

    if op == "foreign_file" and free(at):
        at.parent.mkdir(parents=True, exist_ok=True)
        at.write_bytes(b"the user's own file\n")
    elif op == "foreign_dir" and free(at):
        at.mkdir(parents=True)
    elif op in ("edit", "touch", "remove") and files:
        path = files[pick % len(files)]
        if any(p in pinned for p in (path, path.parent)):
            return
        if op == "edit":
            with open(path, "ab") as fh:
                fh.write(b"edited by the user\n")
        elif op == "touch":
            st_ = os.lstat(path)
            os.utime(path, ns=(st_.st_atime_ns, st_.st_mtime_ns + 1_000_000_000))
        else:
            path.unlink()
    elif op in ("link_dir", "link_file", "file_for_dir"):
        # a folder by a link to a folder or by a file; a file by a link to a file
        choices = [p for p in (files if op == "link_file" else dirs) if p.parent == real]
        path = choices[pick // 2 % len(choices)] if choices and pick % 2 else at
        if any(p in pinned for p in (path, path.parent, *path.parents)):
            return
        if path in entries:
            if path.is_dir() and not path.is_symlink():
                if _holds_pinned(path, pinned):
                    return
                shutil.rmtree(path)
            else:
                path.unlink()
        elif not free(path):
            return
        path.parent.mkdir(parents=True, exist_ok=True)
        if op == "link_dir":
            path.symlink_to(outside / "dir", target_is_directory=True)
        elif op == "link_file":
            path.symlink_to(outside / "file.txt")
        else:
            path.write_bytes(b"a file where a folder was\n")
    elif op == "pin":
        near = pick % 2 == 0  # half the time the folder itself or an entry at its top
        choices = [p for p in [real, *entries] if os.path.lexists(p) and not p.is_symlink()]
        choices = [p for p in choices if p == real or p.parent == real or not near]
        if choices:
            path = choices[pick // 2 % len(choices)]
            _pin(path)
            pinned.append(path)
    elif op in ("dead_partial", "dead_partial_file"):
        path = real.parent / f".{real.name}.{TEMPORARY_TAG}-{earlier.dead}-x{pick}.partial"
        if op == "dead_partial" and not os.path.lexists(path):
            path.mkdir()
            (path / "one.csv").write_text("half a run\n")
        elif not os.path.lexists(path):
            path.write_text("a killed run's\n")
    elif op in ("dead_tmp", "dead_nested", "live_tmp", "lookalike") and folders:
        folder = folders[pick % len(folders)]
        if folder in pinned:
            return
        name = Path(place).name
        pid = earlier.live if op == "live_tmp" else earlier.dead
        if op == "lookalike":
            (folder / f".{name}.abcd{pick}.tmp").write_text("mine, though it looks temporary\n")
        elif op == "dead_nested":
            nested = folder / f".{name}.{TEMPORARY_TAG}-{pid}-n{pick}.partial"
            nested.mkdir(exist_ok=True)
            (nested / "x.csv").write_text("half\n")
        else:
            (folder / f".{name}.{TEMPORARY_TAG}-{pid}-t{pick}.tmp").write_text("half\n")


def _holds_pinned(folder: Path, pinned: list[Path]) -> bool:
    return any(folder == p or folder in p.parents for p in pinned)


# --- snapshots and the property -------------------------------------------------------------


def _snapshot(ex: Path) -> dict[str, tuple]:
    """Every entry below ``ex`` (never following a link): kind, permission bits, and for a
    file its bytes' hash and modification time, for a link its target."""
    snap: dict[str, tuple] = {}
    for root, dirs, files in os.walk(ex):
        for name in dirs + files:
            path = Path(root, name)
            st_ = os.lstat(path)
            rel = path.relative_to(ex).as_posix()
            mode = stat.S_IMODE(st_.st_mode)
            if stat.S_ISLNK(st_.st_mode):
                snap[rel] = ("link", os.readlink(path))
            elif stat.S_ISDIR(st_.st_mode):
                snap[rel] = ("dir", mode)
            else:
                digest = hashlib.sha256(path.read_bytes()).hexdigest()
                snap[rel] = ("file", mode, st_.st_size, st_.st_mtime_ns, digest)
    return snap


def _record(folder: Path) -> dict[str, dict]:
    """The files listed by ``folder``'s record (read here, not through ``_io``)."""
    path = folder / OUTPUT_RECORD
    if not path.is_file() or path.is_symlink():
        return {}
    try:
        files = json.loads(path.read_text(encoding="utf-8"))["files"]
    except (ValueError, KeyError, TypeError, UnicodeDecodeError):
        return {}
    return files if isinstance(files, dict) else {}


def _own(folder: Path, rel: str, entry: dict) -> bool:
    """``folder/rel`` is as its record entry says: a regular file, real folders on the way."""
    path = folder
    for part in Path(rel).parts[:-1]:
        path = path / part
        if path.is_symlink() or not path.is_dir():
            return False
    try:
        st_ = os.lstat(folder / rel)
    except OSError:
        return False
    return (
        stat.S_ISREG(st_.st_mode)
        and st_.st_size == entry.get("size")
        and st_.st_mtime_ns == entry.get("mtime_ns")
    )


def _dead_temporary(rel: str, dead: int, out_rel: str) -> bool:
    """``rel`` (below the scratch dir) is, or lies in, a dead process's temporary that the
    run may remove: beside the folder and named after it, or anywhere in it."""
    parts = Path(rel).parts
    out_parts = Path(out_rel).parts
    inside = parts[: len(out_parts)] == out_parts and len(parts) > len(out_parts)
    beside = parts[: len(out_parts) - 1] == out_parts[:-1] and len(parts) >= len(out_parts)
    for i, name in enumerate(parts):
        if not is_own_temporary(name) or f"-{dead}-" not in name:
            continue
        if inside and i >= len(out_parts):
            return True
        if beside and i == len(out_parts) - 1 and name.startswith(f".{out_parts[-1]}."):
            return name.endswith(".partial")
    return False


#: A Monte Carlo's note on a chunk it computes again (docs/cli.md): a line before the error.
_RECOMPUTED = re.compile(r"tetherheli: \S+/partial/chunk_[0-9_]+\.csv .*; computing it again")


def _check_refusal(
    code: int, out: str, stdout: str, err: str, prog: str = "tetherheli", option: str = "--out"
) -> None:
    assert code == 2, (code, err)
    notes = err.splitlines()[:-1]
    assert all(_RECOMPUTED.fullmatch(n) for n in notes), err
    err = err.splitlines(True)[-1]
    assert err.count("\n") == 1 and err.startswith(f"{prog}: error: "), err
    assert "Traceback" not in err and f"{TEMPORARY_TAG}-{os.getpid()}-" not in err, err
    assert option in err or out.split("/OUT")[0] in err, err
    assert "wrote" not in stdout, stdout


def _check_unchanged(before: dict, after: dict, state: State, earlier: Earlier, out_rel: str):
    """A refused run: everything as before but a dead process's temporaries, which may be
    gone, and (Monte Carlo) its resumable chunks."""
    mc = state.command == "mc"

    def resumable(rel: str) -> bool:
        parts = Path(rel).relative_to(out_rel).as_posix() if rel.startswith(out_rel + "/") else ""
        return mc and (parts == "partial" or _CHUNK.fullmatch(parts) is not None)

    for rel, entry in before.items():
        if rel not in after:
            assert _dead_temporary(rel, earlier.dead, out_rel), f"{rel} was removed"
        elif after[rel] != entry:
            assert resumable(rel), f"{rel} changed: {entry} -> {after[rel]}"
    for rel in sorted(set(after) - set(before)):
        made = mc and rel == out_rel and state.start in ("absent", "dangling")
        assert made or resumable(rel), f"{rel} appeared"


def _check_whole(
    before: dict, after: dict, state: State, earlier: Earlier, real: Path, ex: Path, record0
):
    """A run that succeeded: its files whole and listed, every other file as before."""
    out_rel = real.relative_to(ex).as_posix()
    _, _, writer = COMMANDS[state.command]
    record = _record(real)
    assert record, "no record"
    for rel, entry in record.items():
        assert _own(real, rel, entry), f"{rel} is not as its record says"
    fresh = earlier.records[state.command]
    for rel in fresh:
        assert record.get(rel, {}).get("writer") == writer, f"{rel} missing from the record"
    if state.command == "mc":
        table = earlier.folders["mc"] / "results.csv"
        assert (real / "results.csv").read_bytes() == table.read_bytes()
        with open(real / "results.csv", newline="") as fh:
            assert len(list(csv.DictReader(fh))) == 4
    else:
        for stem, sub in RUNS[state.command].items():
            got = load_result(real / sub, stem)
            want = load_result(earlier.folders[state.command] / sub, stem)
            assert got.name == want.name and got.status == want.status
            np.testing.assert_allclose(got.states, want.states, rtol=1e-12, atol=0)
            np.testing.assert_allclose(got.time, want.time, rtol=1e-12, atol=0)
    _check_kept(before, after, state, earlier, out_rel, record0)


def _check_kept(
    before: dict, after: dict, state: State, earlier: Earlier, out_rel: str, record0: dict
) -> None:
    """After a run that succeeded: every entry that was not tetherheli's (outside the folder,
    or the user's in it) is as before, nothing appeared outside the folder, and neither a
    dead process's temporaries nor this one's are left."""
    for rel, entry in before.items():
        inner = Path(rel).relative_to(out_rel).as_posix() if rel.startswith(out_rel + "/") else None
        if _dead_temporary(rel, earlier.dead, out_rel):
            continue
        if inner is None:  # outside the folder
            if rel == out_rel:
                continue
            assert after.get(rel) == entry, f"{rel} outside the folder changed"
            continue
        if entry[0] == "dir":
            continue  # a folder's files are checked one by one
        own = inner in record0 and _own_stamp(entry, record0[inner]) and _real_way(before, rel)
        own = own or (inner == OUTPUT_RECORD and bool(record0))  # the record itself
        if own or (state.command == "mc" and _CHUNK.fullmatch(inner)):
            continue
        assert after.get(rel) == entry, f"{inner}, not tetherheli's, changed"
    # nothing new outside the folder (a write through a link would land there)
    for rel in sorted(set(after) - set(before)):
        inside = rel.startswith(out_rel + "/") or rel == out_rel
        assert inside, f"{rel} appeared outside the folder"
    # what a process that no longer runs left is gone (unless pinned in place)
    for rel in after:
        if _dead_temporary(rel, earlier.dead, out_rel):
            assert state.ops and any(o == "pin" for o, _, _ in state.ops), f"{rel} left"
    leftovers = [r for r in after if f"{TEMPORARY_TAG}-{os.getpid()}-" in r]
    assert not leftovers, leftovers


def _own_stamp(entry: tuple, stamp: dict) -> bool:
    return (
        entry[0] == "file" and entry[2] == stamp.get("size") and entry[3] == stamp.get("mtime_ns")
    )


def _real_way(snap: dict, rel: str) -> bool:
    """Every folder on the way to ``rel`` in the snapshot is a real folder (up to the root
    of the scratch tree's --out, which may itself be reached by a link)."""
    parents = Path(rel).parents
    return all(snap.get(p.as_posix(), ("dir",))[0] == "dir" for p in parents if str(p) != ".")


def _unpin_all(pinned: list[Path], ex: Path) -> None:
    for path in reversed(pinned):
        _unpin(path)
    for root, dirs, _ in os.walk(ex):  # chmod'd folders that moved
        for d in dirs:
            p = Path(root, d)
            if PINNING == "chmod" and not p.is_symlink():
                p.chmod(stat.S_IMODE(os.lstat(p).st_mode) | 0o700)


class _Killed(BaseException):
    """SIGKILL, as far as the run can tell: nothing of it runs after (no undo, no clean-up)."""


def _kill_a_run(
    state: State, out: Path, ex: Path, earlier: Earlier, invoke: Callable | None = None
) -> None:
    """Leave what a run of the command killed at rename ``state.kill`` leaves: its swap
    half done, its temporary folder and files in place, named after a process now gone
    (``invoke``: a script's run instead of the command's)."""
    import tetherheli._io as io

    replace, calls = os.replace, []

    def replace_or_die(a, b):
        calls.append(b)
        if len(calls) > state.kill:
            raise _Killed
        replace(a, b)

    with pytest.MonkeyPatch.context() as m:
        blank_figures(m)
        m.setattr(io.os, "replace", replace_or_die)
        m.setattr(io, "_undo_swap", lambda *a, **k: None)
        m.setattr(io.shutil, "rmtree", lambda *a, **k: None)
        try:
            if invoke is None:
                main(_argv(state.command, earlier.inputs, out, state.force))
            else:
                invoke()
        except _Killed:
            pass
    mine = f"-{os.getpid()}-"
    for root, dirs, files in os.walk(ex, topdown=False):
        for name in dirs + files:
            if is_own_temporary(name) and mine in name:
                os.rename(Path(root, name), Path(root, name.replace(mine, f"-{earlier.dead}-")))


def _check_recovery(
    state: State, ex: Path, out_rel: str, killed: dict, before: dict, earlier: Earlier
) -> None:
    """On a copy of the killed state, the recovery alone (``claim_output_directory``, which
    puts right what killed runs left before it checks anything): a swap begun and not
    committed gives the tree as before the killed run; otherwise only the dead process's
    temporaries go."""
    copy = ex.parent / f"{ex.name}-recovered"
    shutil.copytree(ex, copy, symlinks=True)
    try:
        claim_output_directory(copy / out_rel, force=True)
        recovered = _snapshot(copy)
    finally:
        shutil.rmtree(copy)
    begun = any(r.endswith(f"/{_SWAP_JOURNAL}") for r in before)
    staged = any(r.endswith(f"/.tetherheli-swap/{OUTPUT_RECORD}") for r in before)
    _check_unchanged(killed if begun and staged else before, recovered, state, earlier, out_rel)


def _run_state(state: State, ex: Path, earlier: Earlier, capsys) -> None:
    out, pinned = _build(state, ex, earlier)
    try:
        real = Path(os.path.realpath(out))
        out_rel = real.relative_to(ex).as_posix()
        record0 = _record(real) if real.is_dir() else {}
        before = killed = _snapshot(ex)
        if state.kill is not None and not pinned and real.is_dir():
            _kill_a_run(state, out, ex, earlier)
            before = _snapshot(ex)  # the killed run's state; ``killed`` the one before it
            swap = any(r.endswith(f"/{_SWAP_JOURNAL}") for r in before)
            event("a killed run's swap left" if swap else "a killed run, no swap begun")
            _check_recovery(state, ex, out_rel, killed, before, earlier)
        capsys.readouterr()
        with pytest.MonkeyPatch.context() as m:
            blank_figures(m)
            code = main(_argv(state.command, earlier.inputs, out, state.force))
        stdout, err = capsys.readouterr()
        after = _snapshot(ex)
        event(f"{state.command}: exit {code}")  # pytest --hypothesis-show-statistics
        if code == 0:  # what the killed run did is undone first, or was committed whole
            _check_whole(killed, after, state, earlier, real, ex, record0)
        else:
            _check_refusal(code, str(out), stdout, err)
            try:  # refused before the killed run was undone (or it had committed) ...
                _check_unchanged(before, after, state, earlier, out_rel)
            except AssertionError:  # ... or after: the folder as before the killed run
                if killed is before:
                    raise
                _check_unchanged(killed, after, state, earlier, out_rel)
    finally:
        _unpin_all(pinned, ex)


@_SETTINGS
@given(state=folder_states())
def test_a_run_completes_whole_or_changes_nothing(tmp_path_factory, earlier, capsys, state):
    """Any folder state: a run either completes whole (listed, loadable, the user's files
    kept) or is refused in one line and leaves every byte as it was."""
    _run_state(state, tmp_path_factory.mktemp("folder"), earlier, capsys)


def test_read_only_pinning():
    """Which read-only pinning the fuzzer draws on this machine (a skip says none binds)."""
    if PINNING is None:
        pytest.skip("neither chattr +i nor chmod stops a write here (root without the flag)")
    assert PINNING in ("chattr", "chmod")


def test_fuzzer_budget_is_fixed_in_ci():
    """The CI run is bounded: derandomized with a fixed budget unless asked for more."""
    if not _ON_DEMAND:
        assert _SETTINGS.max_examples == _CI_EXAMPLES and _SETTINGS.derandomize


# --- the scripts that write (issue 43): examples, benchmarks, the docs' tables ----------------
#
# The same folder states and the same property for the repository's scripts that write into
# a folder the user names: an example's OUT_DIR (trim_and_linearization_poles.py),
# examples/train_residual.py --out, benchmarks/bench_mpc.py --pareto (from --pareto-csv) and
# docs/regenerate_tables.py --figures. Each runs its real command line, parsing, output
# rules and writing, in-process; its work is a stub (a blank figure, a fake evaluation, the
# CSV read back), so the folder rules are under test, not the physics.

ROOT = Path(__file__).resolve().parents[1]
_SCRIPT_EXAMPLES = 100
_SCRIPT_SETTINGS = settings(
    max_examples=_ON_DEMAND or _SCRIPT_EXAMPLES,
    derandomize=not _ON_DEMAND,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    database=None,
)
#: script -> (its path, the files it writes, the writer recorded, the option it names)
SCRIPTS = {
    "trim": (
        "examples/trim_and_linearization_poles.py",
        ("trim_poles.png",),
        "trim_and_linearization_poles.py",
        "OUT_DIR",
    ),
    "residual": (
        "examples/train_residual.py",
        (
            "residual_ars_curve.png",
            "residual_ars_table.md",
            "residual_ars.json",
            "residual_ars_gains.npy",
        ),
        "train_residual.py --algo ars",
        "--out",
    ),
    "pareto": (
        "benchmarks/bench_mpc.py",
        ("mpc_pareto.csv", "mpc_pareto.md", "mpc_pareto.png"),
        "bench_mpc --pareto",
        "--pareto",
    ),
    "figures": (
        "docs/regenerate_tables.py",
        ("release.png",),
        "regenerate_tables.py --figures",
        "--figures",
    ),
}
#: Names where the scripts' files go (and some that are nobody's).
SCRIPT_PLACES = (
    "notes.txt",
    "trim_poles.png",
    "residual_ars.json",
    "residual_ars_curve.png",
    "residual_ars_gains.npy",
    "mpc_pareto.csv",
    "mpc_pareto.md",
    "release.png",
    "sub",
    "sub/notes.txt",
    OUTPUT_RECORD,
)
_TINY_TRAINING = ["--steps", "1", "--directions", "1", "--episodes", "1", "--curve-episodes",
                  "2", "--test-episodes", "2"]  # fmt: skip


def _load_script(rel: str):
    import importlib.util

    path = ROOT / rel
    spec = importlib.util.spec_from_file_location(f"fuzzed_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(path.parent))  # bench_mpc imports its sibling tune_tether_lqi
    try:
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(path.parent))
    return module


def _blank_figure():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(0.5, 0.5))
    fig.add_subplot()
    return fig


def _fake_evaluate(policy, seeds, task=None) -> dict:
    n = len(seeds)
    return {
        "return": -1.0 - 0.1 * np.arange(n),
        "peak": np.full(n, 0.2),
        "rms": np.full(n, 0.1),
        "rms_force": np.zeros(n),
        "failed": np.zeros(n, dtype=bool),
        "steps": np.full(n, 1000),
    }


class Scripts:
    """The scripts' modules and how each is stubbed and run (a plain class: Hypothesis
    prints it by its repr)."""

    def __init__(self, csv_path: Path) -> None:
        self.modules = {key: _load_script(spec[0]) for key, spec in SCRIPTS.items()}
        self.csv = csv_path  # the --pareto-csv input

    def __repr__(self) -> str:
        return "Scripts()"

    def stub(self, m: pytest.MonkeyPatch) -> None:
        """Each script's work replaced by a quick stand-in (its writes kept)."""
        import tetherheli.viz.plots as plots

        trim, residual = self.modules["trim"], self.modules["residual"]
        m.setattr(trim, "figures", lambda: {"trim_poles.png": _blank_figure()})
        m.setattr(residual, "evaluate", _fake_evaluate)
        m.setattr(residual, "lqi_feedback_gains", lambda *a, **k: np.zeros((4, 13)))
        m.setattr(residual, "curve_figure", lambda *a, **k: _blank_figure())
        m.setattr(plots, "figure_pareto", lambda *a, **k: _blank_figure())

        def release(work: Path, staged: Path | None) -> None:
            (staged / "release.png").write_bytes(b"\x89PNG a figure\n")

        m.setitem(self.modules["figures"].TABLES, "release", (release, False))

    def argv(self, key: str, out: Path, force: bool) -> list[str]:
        flag = ["--force"] if force else []
        return {
            "trim": [str(out), *flag],
            "residual": [*_TINY_TRAINING, "--out", str(out), *flag],
            "pareto": ["--pareto", str(out), "--pareto-csv", str(self.csv), *flag],
            "figures": ["--only", "release", "--figures", str(out), *flag],
        }[key]

    def run(self, key: str, out: Path, force: bool) -> int:
        with pytest.MonkeyPatch.context() as m:
            self.stub(m)
            return self.modules[key].main(self.argv(key, out, force))


@pytest.fixture(scope="session")
def scripts(tmp_path_factory: pytest.TempPathFactory) -> Scripts:
    pytest.importorskip("gymnasium")
    pytest.importorskip("osqp")
    base = tmp_path_factory.mktemp("script-inputs")
    done = Scripts(base / "pareto" / "mpc_pareto.csv")
    bench = done.modules["pareto"]
    rows = [
        {c: (True if c in ("completed", "admissible") else float(i + j))
         for j, c in enumerate(bench.PARETO_COLUMNS)}
        for i in range(3)
    ]  # fmt: skip
    with pytest.MonkeyPatch.context() as m:
        done.stub(m)
        bench.write_pareto(str(base / "pareto"), rows, {"paper": (1.0, 40.0)})
    return done


@pytest.fixture(scope="session")
def script_earlier(tmp_path_factory: pytest.TempPathFactory, scripts: Scripts) -> Earlier:
    """Each script's fresh output folder, once per session (the "own" start states)."""
    base = tmp_path_factory.mktemp("script-earlier")
    folders = {}
    for key in SCRIPTS:
        folders[key] = base / key
        assert scripts.run(key, folders[key], force=False) == 0, key
    done = Earlier(scripts.csv.parent, folders, _dead_pid(), os.getppid())
    assert all(done.records.values()), done.records
    return done


@st.composite
def script_states(draw) -> State:
    ops = tuple(o for o in OPS if o != "pin" or PINNING is not None)
    command = draw(st.sampled_from(sorted(SCRIPTS)))
    return State(
        command=command,
        start=draw(st.sampled_from(STARTS)),
        start_of=draw(st.sampled_from([command, command, *sorted(SCRIPTS)])),
        force=draw(st.booleans()),
        ops=tuple(
            draw(
                st.lists(
                    st.tuples(
                        st.sampled_from(ops),
                        st.integers(0, 10**6),
                        st.sampled_from(SCRIPT_PLACES),
                    ),
                    max_size=5,
                )
            )
        ),
        kill=draw(st.none() | st.integers(0, 8)),
    )


def _check_script_whole(
    before: dict, after: dict, state: State, earlier: Earlier, real: Path, ex: Path, record0
) -> None:
    """A script's run that succeeded: each of its files whole and listed as its own, every
    other file as before."""
    _, files, writer, _ = SCRIPTS[state.command]
    record = _record(real)
    assert record, "no record"
    for rel, entry in record.items():
        assert _own(real, rel, entry), f"{rel} is not as its record says"
    for rel in files:
        assert record.get(rel, {}).get("writer") == writer, f"{rel} missing from the record"
        fresh = earlier.folders[state.command] / rel
        if rel.endswith((".csv", ".npy")):  # the same inputs give the same bytes
            assert (real / rel).read_bytes() == fresh.read_bytes(), rel
    _check_kept(before, after, state, earlier, real.relative_to(ex).as_posix(), record0)


def _run_script_state(state: State, ex: Path, earlier: Earlier, scripts: Scripts, capsys):
    out, pinned = _build(state, ex, earlier)
    script, _, _, option = SCRIPTS[state.command]
    try:
        real = Path(os.path.realpath(out))
        out_rel = real.relative_to(ex).as_posix()
        record0 = _record(real) if real.is_dir() else {}
        before = killed = _snapshot(ex)
        if state.kill is not None and not pinned and real.is_dir():

            def invoke() -> None:
                scripts.run(state.command, out, state.force)

            _kill_a_run(state, out, ex, earlier, invoke)
            before = _snapshot(ex)
            swap = any(r.endswith(f"/{_SWAP_JOURNAL}") for r in before)
            event("a killed run's swap left" if swap else "a killed run, no swap begun")
            _check_recovery(state, ex, out_rel, killed, before, earlier)
        capsys.readouterr()
        code = scripts.run(state.command, out, state.force)
        stdout, err = capsys.readouterr()
        after = _snapshot(ex)
        event(f"{state.command}: exit {code}")
        if code == 0:
            _check_script_whole(killed, after, state, earlier, real, ex, record0)
        else:
            _check_refusal(code, str(out), stdout, err, prog=Path(script).name, option=option)
            try:
                _check_unchanged(before, after, state, earlier, out_rel)
            except AssertionError:
                if killed is before:
                    raise
                _check_unchanged(killed, after, state, earlier, out_rel)
    finally:
        _unpin_all(pinned, ex)


@_SCRIPT_SETTINGS
@given(state=script_states())
def test_a_script_writes_whole_or_changes_nothing(
    tmp_path_factory, script_earlier, scripts, capsys, state
):
    """Issue 43, finding 1: any folder state under a script's output option: the script
    writes all its files (listed, the user's kept, nothing written through a link) or is
    refused in one line, exit 2, and leaves every byte as it was."""
    _run_script_state(state, tmp_path_factory.mktemp("script"), script_earlier, scripts, capsys)


def test_script_fuzzer_budget_is_fixed_in_ci():
    """The scripts' CI run is bounded as the commands' is."""
    if not _ON_DEMAND:
        assert _SCRIPT_SETTINGS.max_examples == _SCRIPT_EXAMPLES and _SCRIPT_SETTINGS.derandomize
