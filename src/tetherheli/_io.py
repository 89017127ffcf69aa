"""File input and safe output.

Input files (TOML) are read by ``read_toml``, whose every failure is one line naming the
path. Output files are written whole or not at all and are on disk (file and directory
fsync) when the call returns; an output directory never loses a file that tetherheli did not
write (``output_directory``)."""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import shutil
import tempfile
import tomllib
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import IO, Any

from ._version import __version__
from .errors import ParameterError, TetherheliError
from .resources import check_memory

__all__ = [
    "OUTPUT_RECORD",
    "OutputPathError",
    "atomic_open",
    "atomic_path",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_output_file",
    "check_output_location",
    "claim_output_directory",
    "dumps_toml",
    "foreign_files",
    "output_directory",
    "read_toml",
    "record_output_file",
    "record_outputs",
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


_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def _toml_key(key: str) -> str:
    return key if _BARE_KEY.fullmatch(key) else json.dumps(key, ensure_ascii=False)


def _toml_value(value: Any, where: str) -> str:
    """One TOML value (TOML 1.0): JSON's string escapes are TOML's; floats as ``repr``
    (exact round trip), with TOML's ``inf``/``nan``; lists and tables inline."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v, f"{where}[]") for v in value) + "]"
    if isinstance(value, dict):
        items = (f"{_toml_key(k)} = {_toml_value(v, f'{where}.{k}')}" for k, v in value.items())
        return "{" + ", ".join(items) + "}"
    raise ParameterError(where, value, "a string, number, boolean, list or table (TOML)")


def dumps_toml(data: dict[str, Any]) -> str:
    """``data`` (str keys; str, int, float, bool, list/tuple and dict values, no None) as a
    TOML document that ``tomllib.loads`` reads back equal (tuples come back as lists):
    plain keys first, then each nested table as a ``[section]``; tables inside lists are
    written inline."""
    lines: list[str] = []

    def table(prefix: tuple[str, ...], d: dict[str, Any]) -> None:
        subtables = {k: v for k, v in d.items() if isinstance(v, dict)}
        plain = [(k, v) for k, v in d.items() if k not in subtables]
        if prefix and (plain or not subtables):
            lines.append(("\n" if lines else "") + f"[{'.'.join(map(_toml_key, prefix))}]")
        for k, v in plain:
            lines.append(f"{_toml_key(k)} = {_toml_value(v, '.'.join((*prefix, k)))}")
        for k, v in subtables.items():
            table((*prefix, k), v)

    table((), data)
    return "\n".join(lines) + "\n"


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
    os.chmod(tmp, 0o666 & ~_umask())  # mkstemp creates 0600; give the usual permissions
    os.replace(tmp, path)
    _fsync_directory(path.parent)


def atomic_write_bytes(path: Path, data: bytes) -> None:
    """Write a file whole or not at all (temporary file in the same folder, fsync, rename)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
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
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        kw = {"encoding": "utf-8", "newline": ""} if mode == "w" else {}
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
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=path.suffix)
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


# --- output directories: never delete or overwrite what tetherheli did not write ------------

#: The record, inside every output directory tetherheli writes, of the files it wrote there:
#: relative path -> size, modification time and the command that wrote it. A file that is not
#: listed, or whose size or time changed since, is the user's and is never removed or replaced.
OUTPUT_RECORD = ".tetherheli-output.json"


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
    st = path.stat()
    return {"size": st.st_size, "mtime_ns": st.st_mtime_ns}


def read_output_record(directory: Path) -> dict[str, dict[str, Any]]:
    """The files tetherheli wrote in ``directory`` (relative path -> stamp and writer); {} for a
    directory without a readable record."""
    try:
        data = json.loads((directory / OUTPUT_RECORD).read_text(encoding="utf-8"))
        files = data["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return {}
    if not isinstance(files, dict):
        return {}
    return {k: v for k, v in files.items() if isinstance(v, dict) and _is_relative_name(k)}


def _is_relative_name(rel: str) -> bool:
    parts = Path(rel).parts
    return bool(parts) and not Path(rel).is_absolute() and ".." not in parts


def is_own_file(directory: Path, rel: str, record: dict[str, dict[str, Any]]) -> bool:
    """True when ``directory/rel`` is listed in the record and unchanged since written."""
    entry = record.get(rel)
    path = directory / rel
    if entry is None or path.is_symlink() or not path.is_file():
        return False
    stamp = _stamp(path)
    return stamp["size"] == entry.get("size") and stamp["mtime_ns"] == entry.get("mtime_ns")


def _files_below(directory: Path) -> list[str]:
    """Relative paths of the files (and links) below ``directory``, the record excepted."""
    found = []
    for root, dirs, files in os.walk(directory):
        base = Path(root)
        links = [d for d in dirs if (base / d).is_symlink()]
        files = files + links  # a link to a folder is a foreign entry, not a folder to enter
        dirs[:] = [d for d in dirs if d not in links]
        for name in files:
            rel = (base / name).relative_to(directory).as_posix()
            if rel != OUTPUT_RECORD:
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
    Returns the resolved directory."""
    target = check_output_location(path, option=option, inputs=inputs)
    if force or (target / OUTPUT_RECORD).is_file():
        return target
    foreign = [rel for rel in foreign_files(target) if not own(rel)]
    if foreign:
        _refuse_foreign(f"{option} {path}", foreign)
    return target


def record_outputs(directory: Path, rels: Iterable[str], *, writer: str) -> None:
    """Add files just written in ``directory`` to its record, as written by ``writer``."""
    record = read_output_record(directory)
    record = {k: v for k, v in record.items() if (directory / k).exists()}
    for rel in rels:
        record[rel] = {**_stamp(directory / rel), "writer": writer}
    _write_record(directory, record)


def _write_record(directory: Path, record: dict[str, dict[str, Any]]) -> None:
    data = {"tetherheli_version": __version__, "files": dict(sorted(record.items()))}
    atomic_write_text(directory / OUTPUT_RECORD, json.dumps(data, indent=2) + "\n")


def _recording_folder(path: Path) -> Path | None:
    """The nearest folder above ``path`` that holds an ``OUTPUT_RECORD``, if any."""
    for folder in path.parents:
        if (folder / OUTPUT_RECORD).is_file():
            return folder
    return None


def check_output_file(path: str | Path, *, option: str = "--out") -> Path:
    """An output file may be new, or one tetherheli wrote (listed, unchanged, in the record of
    the nearest output directory above it); anything else is refused. Returns the resolved
    path."""
    target = _resolved(path)
    if target.is_dir():
        raise OutputPathError(f"{option} {path} is a directory; allowed: a file name")
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
) -> Iterator[Path]:
    """Build a command's output in a temporary sibling folder and put it in place on success.

    ``path`` is checked first (``claim_output_directory``: a dedicated location with no foreign
    files unless ``force``). A new directory is moved into place whole. In an existing one,
    each new file replaces its namesake, files that ``writer`` wrote on an earlier run and
    did not write now are removed, and every other file (the user's, or another command's
    such as an animation) is kept; a foreign file where a new one would go is refused. On
    any error nothing in ``path`` changes. The record ``OUTPUT_RECORD`` lists what was written.
    """
    target = claim_output_directory(path, option=option, inputs=inputs, force=force)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=target.parent, prefix=f".{target.name}.", suffix=".partial"))
    os.chmod(tmp, 0o777 & ~_umask())
    try:
        yield tmp
        new = _files_below(tmp)
        if not target.exists():
            _write_record(tmp, {rel: {**_stamp(tmp / rel), "writer": writer} for rel in new})
            os.replace(tmp, target)
            _fsync_directory(target.parent)
            return
        record = read_output_record(target)
        clash = [
            rel
            for rel in new
            if ((target / rel).exists() or (target / rel).is_symlink())
            and not is_own_file(target, rel, record)
        ]
        if clash:
            raise OutputPathError(
                f"{option} {path}: {clash[0]} was not written by tetherheli, or was changed "
                "since; allowed: move it away or choose another directory (tetherheli never "
                "overwrites it)"
            )
        for rel in new:
            (target / rel).parent.mkdir(parents=True, exist_ok=True)
            os.replace(tmp / rel, target / rel)
            _fsync_directory((target / rel).parent)
        kept = {}
        for rel, entry in record.items():
            if rel in new or not is_own_file(target, rel, record):
                continue
            if entry.get("writer") == writer:
                _remove_file_and_empty_parents(target, rel)
            else:
                kept[rel] = entry
        kept.update({rel: {**_stamp(target / rel), "writer": writer} for rel in new})
        _write_record(target, kept)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)  # the temporary folder is ours alone


def _remove_file_and_empty_parents(directory: Path, rel: str) -> None:
    path = directory / rel
    path.unlink()
    for parent in path.parents:
        if parent == directory:
            break
        try:
            parent.rmdir()  # only an empty folder goes
        except OSError:
            break
