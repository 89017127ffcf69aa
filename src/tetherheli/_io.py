"""File input and safe output.

Input files (TOML) are read by ``read_toml``, whose every failure is one line naming the
path. Output files are written whole or not at all and are on disk (file and directory
fsync) when the call returns; an output directory never loses a file that tetherheli did not
write, is changed all or nothing, and is never written through a link inside it
(``output_directory``); temporary files carry a tag and the writer's process id so that the
next run recognises and removes what a killed one left (``recover_output_directory``).

Every JSON file is written by ``write_json`` (text by ``json_text``) and read by ``read_json``
(text by ``json_from_text``): strict JSON, a float that is not finite written as one of the
strings of ``NONFINITE_JSON`` and read back as that float."""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import shutil
import stat
import tempfile
import tomllib
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import IO, Any

from ._version import __version__
from .errors import ParameterError, TetherheliError
from .resources import check_memory

__all__ = [
    "NONFINITE_JSON",
    "OUTPUT_RECORD",
    "OutputPathError",
    "atomic_open",
    "atomic_path",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_output_file",
    "check_output_location",
    "check_output_names",
    "check_real_folders",
    "claim_output_directory",
    "foreign_files",
    "json_from_text",
    "json_text",
    "open_user_file",
    "output_directory",
    "read_json",
    "read_toml",
    "record_output_file",
    "record_outputs",
    "write_json",
]


#: Peak memory of reading a TOML input over its size: the text, tomllib's objects and the
#: validated scenario (measured 27 on a 200 MB file of [[wind]] tables); margin kept.
_TOML_PEAK_FACTOR = 32


def read_toml(path: str | Path, what: str = "TOML file") -> dict[str, Any]:
    """The parsed TOML file ``path`` (a ``what``).

    Raises
    ------
    ParameterError
        One line naming the path: missing, unreadable (a directory, permissions), not UTF-8,
        not valid TOML, or nested deeper than the parser can follow.
    ResourceLimitError
        Reading it would need more than the memory budget (``tetherheli.resources``).
    """
    source = str(path)
    try:
        size = Path(path).stat().st_size
    except OSError:
        size = 0  # missing or unreadable: said so below
    check_memory(  # before reading: a 200 MB table of winds is gigabytes once parsed
        f"reading {source} ({size} bytes)",
        size * _TOML_PEAK_FACTOR,
        hint="write shorter tables (a wind file of many profiles: a gust table instead)",
    )
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ParameterError("file", source, f"an existing {what}") from None
    except (OSError, UnicodeDecodeError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ParameterError("file", source, f"a readable UTF-8 {what} ({reason})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError("file", source, f"valid TOML ({exc})") from None
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise ParameterError(
            "file", source, "valid TOML with arrays and tables nested a few levels deep"
        ) from None


#: The files a scenario names (a base's track) may be any regular file that the user running
#: tetherheli may read: tetherheli reads with the user's own rights, so a scenario cannot reach
#: a file its user could not read anyway, and it never shows a byte of what it reads (a
#: refusal names the row, the column and what is wrong). A relative path is taken from the
#: scenario file's folder; the run records the resolved path and the SHA-256 of the bytes read.
USER_FILE_RULE = (
    "a regular file you may read (not a folder, device or pipe); a relative path is taken "
    "from the scenario file's folder"
)


@contextlib.contextmanager
def open_user_file(
    path: str | Path, *, field: str, what: str, max_bytes: int, source: str | None = None
) -> Iterator[tuple[IO[bytes], Path, int]]:
    """Open a file that a user's input names (a scenario's track) for reading in binary: the one
    way tetherheli opens such files (``USER_FILE_RULE``).

    It is opened without blocking (a pipe is refused, never waited on), checked on the open
    descriptor to be a regular file of at most ``max_bytes`` bytes, then handed to the caller,
    who streams it. No message shows its contents.

    Parameters
    ----------
    path : str or pathlib.Path
        The file as the input names it.
    field : str
        The key that names it, e.g. ``"base.file"``, for the messages.
    what : str
        What the file should be, e.g. ``"a CSV track t,n1,n2,n3"``.
    max_bytes : int
        The largest size allowed.
    source : str, optional
        The input that names the file, put in front of a message.

    Yields
    ------
    (binary file, pathlib.Path, int)
        The open file, its resolved path and its size [bytes].

    Raises
    ------
    ParameterError
        Missing, not readable, not a regular file, or larger than ``max_bytes``: one line
        naming ``field`` and the path.
    """
    shown = str(path)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        resolved = Path(path).expanduser().resolve()
        fd = os.open(resolved, flags)
    except FileNotFoundError:
        raise ParameterError(field, shown, f"an existing file: {what}", source=source) from None
    except (OSError, ValueError, RuntimeError) as exc:  # ValueError: a NUL in the path
        reason = getattr(exc, "strerror", None) or type(exc).__name__
        raise ParameterError(
            field, shown, f"{USER_FILE_RULE}: {what} ({reason})", source=source
        ) from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise ParameterError(field, shown, f"{USER_FILE_RULE}: {what}", source=source)
        if st.st_size > max_bytes:
            raise ParameterError(
                field, f"{shown} ({st.st_size} bytes)", f"{what} of at most {max_bytes} bytes",
                source=source,
            )  # fmt: skip
        fh = os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
    with fh:
        yield fh, resolved, st.st_size


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _fsync_directory(path: Path) -> None:
    """Make a rename in ``path`` durable (a no-op where directories cannot be opened)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:  # pragma: no cover - not POSIX
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - file systems that refuse fsync on directories
        pass
    finally:
        os.close(fd)


# --- own temporary files: named so that the next run knows them ------------------------------

#: The tag in the name of every temporary file or folder tetherheli makes:
#: ``.<name>.tetherheli-<pid>-<random>.tmp`` beside a file being written (``.tmp.<suffix>``
#: for writers that pick a format by suffix) and ``.<folder>.tetherheli-<pid>-<random>.partial``
#: beside an output folder being built. No scenario name starts with '.', so no result is ever
#: named so; a killed run's temporaries are recognised by the name and removed by the next run
#: that writes there (``clean_own_temporaries``), once the process ``<pid>`` is gone.
TEMPORARY_TAG = "tetherheli"
_TEMPORARY = re.compile(
    rf"\.(?P<of>.+)\.{TEMPORARY_TAG}-(?P<pid>[0-9]+)-[a-z0-9_]+\.(?P<kind>tmp(?:\.[^.]+)?|partial)"
)


def _temporary_prefix(name: str) -> str:
    return f".{name}.{TEMPORARY_TAG}-{os.getpid()}-"


def is_own_temporary(name: str) -> bool:
    """True when the file name ``name`` is one tetherheli gives its temporary files and
    folders (``TEMPORARY_TAG``)."""
    return _TEMPORARY.fullmatch(name) is not None


def _writer_gone(name: str) -> bool:
    """True when the process that made the own temporary ``name`` no longer runs (this
    process's own temporaries are in use)."""
    pid = int(_TEMPORARY.fullmatch(name)["pid"])  # type: ignore[index]
    if pid == os.getpid():
        return False
    if os.name != "posix":  # pragma: no cover - no signal 0 to ask with
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except OSError:  # another user's live process
        return False
    return False


def clean_own_temporaries(directory: Path) -> list[str]:
    """Remove what killed runs left below ``directory`` (never following a link): temporary
    files, and the folders of output directories being built there, whose interrupted swap
    is undone first (``_recover_build``); returns their relative paths."""
    removed = []
    for root, dirs, files in os.walk(directory):
        for name in [*files, *dirs]:
            path = Path(root, name)
            if not is_own_temporary(name) or not _writer_gone(name):
                continue
            if name in dirs and not path.is_symlink():
                _recover_build(path)
            else:
                with contextlib.suppress(FileNotFoundError):
                    path.unlink()
            removed.append(path.relative_to(directory).as_posix())
        dirs[:] = [d for d in dirs if not (Path(root, d).is_symlink() or is_own_temporary(d))]
    return removed


def _name_target(exc: OSError, path: Path) -> OSError:
    """``exc`` about the temporary file, re-raised about ``path``, the file being written."""
    return type(exc)(exc.errno, exc.strerror, str(path))


def _mkstemp(path: Path, suffix: str) -> tuple[int, str]:
    try:
        return tempfile.mkstemp(dir=path.parent, prefix=_temporary_prefix(path.name), suffix=suffix)
    except OSError as exc:
        raise _name_target(exc, path) from None


def _commit(fh: IO, tmp: str, path: Path) -> None:
    """Flush and fsync the open temporary file ``fh``, close it, and rename it to ``path``;
    then fsync the folder, so that after a crash ``path`` is the old file or the whole new one."""
    fh.flush()
    os.fsync(fh.fileno())
    fh.close()
    _rename_into_place(tmp, path)


def _rename_into_place(tmp: str, path: Path) -> None:
    """Give the synced temporary file ``tmp`` the usual permissions, rename it to ``path`` and
    fsync the folder."""
    try:
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp creates 0600; give the usual permissions
        os.replace(tmp, path)
    except OSError as exc:
        raise _name_target(exc, path) from None
    _fsync_directory(path.parent)


def atomic_write_bytes(path: Path, data: bytes) -> None:
    """Write a file whole or not at all (temporary file in the same folder, fsync, rename).
    An OSError names ``path``, not the temporary file."""
    path = Path(path)
    fd, tmp = _mkstemp(path, ".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            try:
                fh.write(data)
            except OSError as exc:
                raise _name_target(exc, path) from None
            _commit(fh, tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_text(path: Path, text: str) -> None:
    """``atomic_write_bytes`` for UTF-8 text."""
    atomic_write_bytes(path, text.encode("utf-8"))


@contextlib.contextmanager
def atomic_open(path: str | Path, mode: str = "w") -> Iterator[IO]:
    """Open a temporary file beside ``path`` for streaming writes; it replaces ``path`` only
    when the block ends without an error (``mode`` "w" text, "wb" binary)."""
    if mode not in ("w", "wb"):
        raise ValueError(f"mode = {mode!r} is invalid; allowed: 'w' or 'wb'")
    path = Path(path)
    fd, tmp = _mkstemp(path, ".tmp")
    try:
        kw: dict[str, Any] = {"encoding": "utf-8", "newline": ""} if mode == "w" else {}
        with os.fdopen(fd, mode, **kw) as fh:
            yield fh
            _commit(fh, tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` (same suffix, so writers that pick a format by suffix
    work) for a writer that takes a file name; on success the file is fsynced and renamed to
    ``path`` as by ``atomic_write_bytes``; on any error it is removed and ``path`` is
    untouched."""
    path = Path(path)
    fd, tmp = _mkstemp(path, ".tmp" + path.suffix)
    os.close(fd)
    try:
        yield Path(tmp)
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        _rename_into_place(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


# --- JSON: strict, with the non-finite floats as strings ------------------------------------

#: How every JSON file tetherheli writes holds a float that is not finite (strict JSON, RFC
#: 8259, has no Infinity or NaN): as one of these strings, the spellings JavaScript's
#: ``Number()`` and Python's ``float()`` read; ``read_json`` reads them back as the floats.
#: Text keys refuse these three words (``_validation.Key``, ``check_name``), so no text is
#: ever read back as a number.
NONFINITE_JSON: dict[str, float] = {"Infinity": math.inf, "-Infinity": -math.inf, "NaN": math.nan}


def _encode_nonfinite(value: Any) -> Any:
    if isinstance(value, float):
        if math.isfinite(value):
            return value
        return "NaN" if math.isnan(value) else ("Infinity" if value > 0 else "-Infinity")
    if isinstance(value, dict):
        return {k: _encode_nonfinite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_encode_nonfinite(v) for v in value]
    return value


def _decode_nonfinite(value: Any) -> Any:
    if isinstance(value, str):
        return NONFINITE_JSON.get(value, value)
    if isinstance(value, dict):
        return {k: _decode_nonfinite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_decode_nonfinite(v) for v in value]
    return value


def json_text(data: Any, *, indent: int | None = 2) -> str:
    """``data`` as strict JSON text: each non-finite float as its string of
    ``NONFINITE_JSON``, nothing else changed (``allow_nan=False``: any other non-finite
    number raises ValueError)."""
    return json.dumps(_encode_nonfinite(data), indent=indent, allow_nan=False)


def json_from_text(text: str) -> Any:
    """Parsed JSON text of ``json_text`` (or of an older file with bare ``Infinity``/``NaN``):
    the strings of ``NONFINITE_JSON`` become their floats again.

    Raises
    ------
    ValueError
        Not JSON (``json.JSONDecodeError``).
    """
    return _decode_nonfinite(json.loads(text))


def write_json(path: str | Path, data: Any, *, indent: int | None = 2) -> None:
    """Write ``json_text(data)`` and a newline to ``path``, whole or not at all."""
    atomic_write_text(Path(path), json_text(data, indent=indent) + "\n")


def read_json(path: str | Path) -> Any:
    """The content of a JSON file (``json_from_text``).

    Raises
    ------
    OSError
        Unreadable.
    ValueError
        Not UTF-8 (``UnicodeDecodeError``) or not JSON (``json.JSONDecodeError``).
    """
    return json_from_text(Path(path).read_text(encoding="utf-8"))


# --- output directories: never delete or overwrite what tetherheli did not write ------------

#: The record, inside every output directory tetherheli writes, of the files it wrote there:
#: relative path -> size, modification time and the command that wrote it. A file that is not
#: listed, or whose size or time changed since, is the user's and is never removed or replaced.
OUTPUT_RECORD = ".tetherheli-output.json"
#: The stems of the files tetherheli writes where a run's name also names a file or a folder:
#: ``simulate``'s summary.json, report.md, outputs.<fmt> and inputs.<fmt> beside the runs'
#: ``<name>.csv``/``<name>.json`` or ``<name>/`` folders, ``animate``'s animation.gif and
#: ``view``'s replay.html. No
#: scenario may be named so (alone or followed by a suffix, in any letter case), and no name
#: starts with '.' as the record and the temporary files do (``scenario.core.check_name``): a
#: run's file or folder can never be one of tetherheli's own. (scenario.toml needs no guard:
#: no run writes a .toml file, and it lies inside each run's folder.)
OWN_FILE_STEMS = ("animation", "inputs", "outputs", "replay", "report", "summary")
#: Inside a folder being built (``output_directory``): the record to be put in place (its
#: rename is the commit), the journal of the swap and the files it replaces, until the end.
_SWAP = ".tetherheli-swap"


class OutputPathError(TetherheliError):
    """An output location that would put a user's files at risk (one-line message)."""


def _resolved(path: str | Path) -> Path:
    return Path(path).expanduser().resolve()


def check_output_location(
    path: str | Path, *, option: str = "--out", inputs: Iterable[str | Path] = ()
) -> Path:
    """The resolved ``path`` (symlinks followed), or OutputPathError when it is the filesystem
    root, the home directory, the current directory, an ancestor of either, or a directory
    that holds one of the ``inputs`` (input files or folders) or is inside an input folder."""
    target = _resolved(path)
    shown = f"{option} {path}" + (f" (= {target})" if str(target) != str(path) else "")
    guarded = {"the current directory": Path.cwd().resolve(), "the home directory": _home()}
    if target == Path(target.anchor):
        raise OutputPathError(f"{shown} is the filesystem root; allowed: a dedicated directory")
    for label, place in guarded.items():
        if place is not None and (target == place or target in place.parents):
            relation = "is" if target == place else "is an ancestor of"
            raise OutputPathError(
                f"{shown} {relation} {label}; allowed: a dedicated directory below it"
            )
    for item in inputs:
        source = _resolved(item)
        if target == source or target in source.parents:
            raise OutputPathError(
                f"{shown} holds the input {item}; allowed: a directory that holds no input"
            )
        if source.is_dir() and source in target.parents:
            raise OutputPathError(
                f"{shown} lies inside the input folder {item}; allowed: a directory outside it"
            )
    if target.exists() and not target.is_dir():
        raise OutputPathError(f"{shown} exists and is not a directory; allowed: a directory")
    return target


def _home() -> Path | None:
    try:
        return Path.home().resolve()
    except (KeyError, RuntimeError):  # no HOME and no passwd entry
        return None


def _stamp(path: Path) -> dict[str, int]:
    st = os.lstat(path)
    return {"size": st.st_size, "mtime_ns": st.st_mtime_ns}


def _read_record(directory: Path) -> dict[str, dict[str, Any]] | None:
    """The files of ``directory``'s record, None unless it holds a record (a regular file,
    not a link, of JSON with a ``files`` table)."""
    path = directory / OUTPUT_RECORD
    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return None
        data = read_json(path)
        files = data["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not isinstance(files, dict):
        return None
    return {k: v for k, v in files.items() if isinstance(v, dict) and _is_relative_name(k)}


def read_output_record(directory: Path) -> dict[str, dict[str, Any]]:
    """The files tetherheli wrote in ``directory`` (relative path -> stamp and writer); {} for a
    directory without a readable record."""
    return _read_record(directory) or {}


def _is_relative_name(rel: str) -> bool:
    parts = Path(rel).parts
    return bool(parts) and not Path(rel).is_absolute() and ".." not in parts


def _link_below(directory: Path, rel: str) -> str | None:
    """The first folder on the way from ``directory`` to ``rel`` that is a link or not a
    folder (relative to ``directory``); None when every existing one is a real folder."""
    path = directory
    for part in Path(rel).parts[:-1]:
        path = path / part
        try:
            mode = os.lstat(path).st_mode
        except FileNotFoundError:
            return None  # the rest is new
        if not stat.S_ISDIR(mode):
            return path.relative_to(directory).as_posix()
    return None


def check_real_folders(directory: Path, rel: str, *, shown: str) -> None:
    """Refuse, in one line starting with ``shown``, to write ``directory/rel`` when a folder
    on the way is a link or a file (``_link_below``): tetherheli never writes through a link
    inside an output folder."""
    link = _link_below(directory, rel)
    if link is not None:
        kind = "a link" if (directory / link).is_symlink() else "not a folder"
        raise OutputPathError(
            f"{shown}: {link} is {kind} (tetherheli never writes through a link, nor over a "
            "file, inside an output folder); allowed: remove it, or choose another directory"
        )


def is_own_file(directory: Path, rel: str, record: dict[str, dict[str, Any]]) -> bool:
    """True when ``directory/rel`` is listed in the record and unchanged since written: a
    regular file reached through real folders (no link on the way)."""
    entry = record.get(rel)
    if entry is None or _link_below(directory, rel) is not None:
        return False
    try:
        st = os.lstat(directory / rel)
    except OSError:
        return False
    return (
        stat.S_ISREG(st.st_mode)
        and st.st_size == entry.get("size")
        and st.st_mtime_ns == entry.get("mtime_ns")
    )


def _files_below(directory: Path) -> list[str]:
    """Relative paths of the files (and links) below ``directory``, but not its record nor
    tetherheli's temporary files and folders (``is_own_temporary``)."""
    found = []
    record = _read_record(directory) is not None
    for root, dirs, files in os.walk(directory):
        base = Path(root)
        links = [d for d in dirs if (base / d).is_symlink()]
        files = files + links  # a link to a folder is a foreign entry, not a folder to enter
        dirs[:] = [d for d in dirs if d not in links and not is_own_temporary(d)]
        for name in files:
            rel = (base / name).relative_to(directory).as_posix()
            if not is_own_temporary(name) and not (record and rel == OUTPUT_RECORD):
                found.append(rel)
    return sorted(found)


def foreign_files(directory: Path) -> list[str]:
    """Files below ``directory`` that tetherheli did not write (or that changed since)."""
    if not directory.is_dir():
        return []
    record = read_output_record(directory)
    return [rel for rel in _files_below(directory) if not is_own_file(directory, rel, record)]


def _refuse_foreign(shown: str, foreign: list[str]) -> None:
    more = f" and {len(foreign) - 1} more" if len(foreign) > 1 else ""
    raise OutputPathError(
        f"{shown} was not created by tetherheli and holds files ({foreign[0]}{more}); allowed: "
        "a new or empty directory, one tetherheli wrote, or --force to write beside them "
        "(they are kept)"
    )


def claim_output_directory(
    path: str | Path,
    *,
    option: str = "--out",
    inputs: Iterable[str | Path] = (),
    force: bool = False,
    own: Callable[[str], bool] = lambda rel: False,
) -> Path:
    """Check ``path`` as an output directory before any work: ``check_output_location``, then
    a directory that tetherheli did not create (no ``OUTPUT_RECORD``) must be empty unless
    ``force``; ``own`` marks further files as the caller's, e.g. a resumable job's partial
    results. In a directory tetherheli created, the user's added files are simply kept.

    What a killed run left is put right first (``recover_output_directory``): an interrupted
    swap is undone, and temporary files are removed. Returns the resolved directory."""
    target = check_output_location(path, option=option, inputs=inputs)
    recover_output_directory(target, option=option)
    if force or _read_record(target) is not None:
        return target
    foreign = [rel for rel in foreign_files(target) if not own(rel)]
    if foreign:
        _refuse_foreign(f"{option} {path}", foreign)
    return target


def check_output_names(path: str | Path, rels: Iterable[str], *, option: str = "--out") -> None:
    """Before any work, refuse what ``output_directory`` would refuse at the end for the files
    ``rels`` a command is going to write into the output directory ``path``: a link or a
    file on the way to one (``check_real_folders``), or a file in its place that tetherheli
    did not write (or that changed since), even with ``--force``."""
    target = _resolved(path)
    if not target.is_dir():
        return  # new: nothing in the way
    shown = f"{option} {path}"
    record = _read_record(target)
    if record is None and os.path.lexists(target / OUTPUT_RECORD):
        _refuse_clash(shown, OUTPUT_RECORD)
    for rel in rels:
        check_real_folders(target, rel, shown=shown)
        if os.path.lexists(target / rel) and not is_own_file(target, rel, record or {}):
            _refuse_clash(shown, rel)


def record_outputs(directory: Path, rels: Iterable[str], *, writer: str) -> None:
    """Add files just written in ``directory`` to its record, as written by ``writer``."""
    record = read_output_record(directory)
    record = {k: v for k, v in record.items() if (directory / k).exists()}
    for rel in rels:
        record[rel] = {**_stamp(directory / rel), "writer": writer}
    _write_record(directory, record)


def _write_record(directory: Path, record: dict[str, dict[str, Any]]) -> None:
    data = {"tetherheli_version": __version__, "files": dict(sorted(record.items()))}
    write_json(directory / OUTPUT_RECORD, data)


def _recording_folder(path: Path) -> Path | None:
    """The nearest folder above ``path`` that holds a record (``OUTPUT_RECORD``), if any."""
    for folder in path.parents:
        if _read_record(folder) is not None:
            return folder
    return None


def check_output_file(path: str | Path, *, option: str = "--out") -> Path:
    """An output file may be new, or one tetherheli wrote (listed, unchanged, in the record of
    the nearest output directory above it); anything else is refused. Returns the resolved
    path."""
    target = _resolved(path)
    if target.is_dir():
        raise OutputPathError(f"{option} {path} is a directory; allowed: a file name")
    if target.name == OUTPUT_RECORD or is_own_temporary(target.name):
        raise OutputPathError(
            f"{option} {path} is a name tetherheli keeps for its own bookkeeping; allowed: "
            "another file name"
        )
    if target.exists() or target.is_symlink():
        folder = _recording_folder(target)
        rel = target.relative_to(folder).as_posix() if folder else ""
        if folder is None or not is_own_file(folder, rel, read_output_record(folder)):
            raise OutputPathError(
                f"{option} {path} exists and was not written by tetherheli (or was changed "
                "since); allowed: a new file name (tetherheli never overwrites it)"
            )
    return target


def record_output_file(path: str | Path, *, writer: str) -> None:
    """List a file just written in the record of the nearest output directory above it, if
    any (so it may be replaced by the same command later, and is kept by the others)."""
    target = _resolved(path)
    folder = _recording_folder(target)
    if folder is not None:
        record_outputs(folder, [target.relative_to(folder).as_posix()], writer=writer)


@contextlib.contextmanager
def output_directory(
    path: str | Path,
    *,
    writer: str,
    option: str = "--out",
    inputs: Iterable[str | Path] = (),
    force: bool = False,
    own: Callable[[str], bool] = lambda rel: False,
    remove_earlier: bool = True,
) -> Iterator[Path]:
    """Build a command's output in a temporary sibling folder and put it in place on success.

    ``path`` is checked first (``claim_output_directory``: a dedicated location with no foreign
    files unless ``force``; ``own`` marks the caller's further files). A new directory is
    moved into place whole. In an existing one, each new file replaces its namesake, files
    that ``writer`` wrote on an earlier run and did not write now are removed (unless not
    ``remove_earlier``), and every other file (the user's, or another command's such as an
    animation) is kept; a foreign file where a new one would go, or a link on the way to one,
    is refused before anything is moved. The replaced files are moved aside into the
    temporary folder and the new record's rename is the commit: on any error, and after a
    killed run at the next claim, the swap is undone, so nothing in ``path`` changes. The
    record ``OUTPUT_RECORD`` lists what was written.
    """
    target = claim_output_directory(path, option=option, inputs=inputs, force=force, own=own)
    shown = f"{option} {path}"
    created = _make_folders(target.parent)
    try:
        build = Path(
            tempfile.mkdtemp(
                dir=target.parent, prefix=_temporary_prefix(target.name), suffix=".partial"
            )
        )
    except OSError as exc:  # e.g. a file where the parent folder should be
        raise _name_target(exc, target.parent) from None
    os.chmod(build, 0o777 & ~_umask())
    keep = False  # the temporary folder holds the only copy of replaced files
    try:
        try:
            yield build
        except OSError as exc:  # a write into the folder being built: name the file, not it
            where = Path(exc.filename) if isinstance(exc.filename, str) else None
            if where is None or build not in where.parents:
                raise
            rel = where.relative_to(build).as_posix()
            raise OutputPathError(
                f"{shown}: {rel} could not be written ({exc.strerror or exc}); nothing in "
                f"{path} changed"
            ) from None
        _install(build, target, writer=writer, shown=shown, remove_earlier=remove_earlier)
    except _UndoFailed:
        keep = True
        raise
    finally:
        if not keep:
            shutil.rmtree(build, ignore_errors=True)  # the temporary folder is ours alone
        if not target.exists():
            for folder in reversed(created):
                with contextlib.suppress(OSError):
                    folder.rmdir()


def _make_folders(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; the ones created, outermost first."""
    missing = []
    while not folder.exists() and folder != folder.parent:
        missing.append(folder)
        folder = folder.parent
    for f in reversed(missing):
        f.mkdir(exist_ok=True)
    return missing[::-1]


class _UndoFailed(OutputPathError):
    """An interrupted swap could not be undone: the temporary folder keeps the replaced files."""


def _install(build: Path, target: Path, *, writer: str, shown: str, remove_earlier: bool) -> None:
    """Put the files built in ``build`` into ``target`` (``output_directory``)."""
    new = _files_below(build)
    stamps = {rel: _stamp(build / rel) for rel in new}
    if not os.path.lexists(target):
        _write_record(build, {rel: {**stamps[rel], "writer": writer} for rel in new})
        try:
            os.replace(build, target)
        except OSError as exc:
            raise OutputPathError(
                f"{shown} could not be put in place ({exc.strerror or exc}); nothing was written"
            ) from None
        _fsync_directory(target.parent)
        return
    record = _read_record(target)
    if record is None and os.path.lexists(target / OUTPUT_RECORD):
        _refuse_clash(shown, OUTPUT_RECORD)
    record = record or {}
    for rel in new:
        check_real_folders(target, rel, shown=shown)
        if os.path.lexists(target / rel) and not is_own_file(target, rel, record):
            _refuse_clash(shown, rel)
    earlier = [
        rel
        for rel, entry in record.items()
        if remove_earlier
        and rel not in stamps
        and entry.get("writer") == writer
        and is_own_file(target, rel, record)
    ]
    kept = {
        rel: entry
        for rel, entry in record.items()
        if rel not in stamps and rel not in earlier and is_own_file(target, rel, record)
    }
    kept.update({rel: {**stamps[rel], "writer": writer} for rel in new})
    folders = sorted(
        {p for rel in new for p in Path(rel).parents if p.parts and not (target / p).exists()},
        key=lambda p: len(p.parts),
    )
    swap = build / _SWAP
    old = swap / "old"
    aside = [rel for rel in new if os.path.lexists(target / rel)] + earlier
    journal = {"new": stamps, "aside": aside, "folders": [p.as_posix() for p in folders]}
    try:
        swap.mkdir()
        _write_record(swap, kept)  # staged: its rename into target is the commit
        write_json(swap / "journal.json", journal, indent=None)  # then moves
        for p in folders:
            (target / p).mkdir()
        for rel in aside:
            (old / rel).parent.mkdir(parents=True, exist_ok=True)
            os.replace(target / rel, old / rel)
        for rel in new:
            os.replace(build / rel, target / rel)
        for folder in {(target / rel).parent for rel in new}:
            _fsync_directory(folder)
        _fsync_directory(old)
        os.replace(swap / OUTPUT_RECORD, target / OUTPUT_RECORD)  # the commit
        _fsync_directory(target)
    except BaseException as exc:
        _undo_swap(build, target, shown=shown)
        if isinstance(exc, OSError):
            where = exc.filename2 if isinstance(exc.filename2, str) else exc.filename
            rel = _relative(where, target, build)
            raise OutputPathError(
                f"{shown}: {rel} could not be replaced ({exc.strerror or exc}); nothing in it "
                "changed"
            ) from None
        raise
    for rel in earlier:
        _remove_empty_parents(target, rel)


def _relative(where: object, target: Path, build: Path) -> str:
    """``where`` (a path an OSError names) relative to the output folder, if it lies there."""
    if not isinstance(where, str):
        return "a file"
    path = Path(where)
    for base in (target, build / _SWAP / "old"):
        if base in path.parents:
            return path.relative_to(base).as_posix()
    if build / _SWAP in path.parents or path == build / _SWAP:
        return f"its record ({OUTPUT_RECORD})"
    if build in path.parents:
        return path.relative_to(build).as_posix()
    return str(path)


def _refuse_clash(shown: str, rel: str) -> None:
    raise OutputPathError(
        f"{shown}: {rel} was not written by tetherheli, or was changed since; allowed: move it "
        "away or choose another directory (tetherheli never overwrites it)"
    )


def _undo_swap(build: Path, target: Path, *, shown: str) -> None:
    """Undo what the journal in ``build`` says a swap into ``target`` may have done (in this
    process after an error, or after a killed run): new files put in place go, the files
    moved aside come back, the folders made for new files go if empty. Nothing to undo
    without a journal (no file was moved yet) or without the staged record (committed)."""
    swap = build / _SWAP
    try:
        journal = read_json(swap / "journal.json")
    except (OSError, ValueError):
        return
    if not (swap / OUTPUT_RECORD).is_file():
        return
    try:
        for rel, stamp in journal["new"].items():
            dest = target / rel
            if not os.path.lexists(build / rel) and os.path.lexists(dest):
                if _link_below(target, rel) is None and _stamp(dest) == stamp:
                    dest.unlink()
        for rel in journal["aside"]:
            if os.path.lexists(swap / "old" / rel):
                os.replace(swap / "old" / rel, target / rel)
        for p in reversed(journal["folders"]):
            with contextlib.suppress(OSError):
                (target / p).rmdir()
        _fsync_directory(target)
    except (OSError, KeyError, TypeError, AttributeError) as exc:
        raise _UndoFailed(
            f"{shown}: an interrupted write could not be undone ({exc}); the files it replaced "
            f"are in {swap / 'old'}"
        ) from None


def recover_output_directory(target: Path, *, option: str = "--out") -> None:
    """Put right what killed runs left at the output directory ``target``: an interrupted
    swap from a temporary folder beside it is undone (``_undo_swap``) and the folder
    removed, and the temporary files below it are removed (``clean_own_temporaries``). Only
    what a process that no longer runs left is touched."""
    parent = target.parent
    if parent.is_dir():
        for entry in sorted(os.listdir(parent)):
            found = _TEMPORARY.fullmatch(entry)
            if found is None or found["of"] != target.name or found["kind"] != "partial":
                continue
            if _writer_gone(entry):
                path = parent / entry
                if path.is_symlink() or not path.is_dir():
                    path.unlink()
                else:
                    _recover_build(path, option=option)
    if target.is_dir() and not target.is_symlink():
        clean_own_temporaries(target)


def _recover_build(build: Path, *, option: str = "--out") -> None:
    """Undo the interrupted swap of the temporary folder ``build`` of a killed run into the
    output directory it is named after, then remove it."""
    target = build.parent / _TEMPORARY.fullmatch(build.name)["of"]  # type: ignore[index]
    _undo_swap(build, target, shown=f"{option} {target}")
    shutil.rmtree(build, ignore_errors=True)


def _remove_empty_parents(directory: Path, rel: str) -> None:
    for parent in (directory / rel).parents:
        if parent == directory:
            break
        try:
            parent.rmdir()  # only an empty folder goes
        except OSError:
            break
