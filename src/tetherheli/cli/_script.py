"""What the repository's scripts (``examples/``, ``benchmarks/``, ``docs/*.py``) share with
the commands: a script that writes is a command too (docs/cli.md, "Output directories").

- The command line: ``script_parser`` is the commands' ``Parser`` (a wrong argument is one
  line and exit 2) with ``--debug``; the arguments take the commands' types
  (``_common.count_arg``, ``_common.number_arg``), so every value is checked before anything
  runs.
- Errors: ``run_script`` runs the script's work as a command (``cli.guarded``): a refusal is
  one line ``SCRIPT: error: ...``, exit 2, never a traceback.
- Results go where the user says by the commands' rules: an output directory
  (``out_argument``: ``OUT_DIR`` or ``--out`` with ``--force``; ``claim`` it before any
  work, write it whole with ``_io.output_directory``; ``write_figures`` does both for a
  figure), or one file (``claim_file`` and ``write_file``: new, or one tetherheli wrote).
- The documentation's pages and figures (``docs/``) that scripts regenerate are the
  project's own files, replaced by one rule (``docs_file``, ``write_docs_file``): a file in
  an existing folder of the checkout's ``docs/``, reached through real folders (never a link
  on the way), itself a regular file or new (never written through a link), replaced whole
  (``_io.atomic_write_bytes``), and only once the study has something to report.
"""

from __future__ import annotations

import os
import stat
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from .._io import (
    OutputPathError,
    _temporary_prefix,
    atomic_write_bytes,
    check_output_file,
    check_output_names,
    check_real_folders,
    claim_output_directory,
    output_directory,
    record_output_file,
)
from ._common import Parser

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "claim",
    "claim_file",
    "docs_file",
    "figure_example",
    "out_argument",
    "run_script",
    "script_parser",
    "write_docs_file",
    "write_figures",
    "write_file",
]


def script_parser(script: str, doc: str | None) -> Parser:
    """The command line of the script ``script`` (its ``__file__``): the commands' parser,
    named after the script, described by the first line of ``doc``, with ``--debug``.

    Parameters
    ----------
    script : str
        The script's path (``__file__``).
    doc : str or None
        The script's docstring.

    Returns
    -------
    Parser
        A parser whose errors are one line (``UsageError``, exit 2 by ``run_script``).
    """
    from ._common import HELP

    description = (doc or "").strip().splitlines()[0] if (doc or "").strip() else None
    p = Parser(prog=Path(script).name, description=description)
    p.add_argument("--debug", action="store_true", help=HELP["--debug"])
    return p


def run_script(
    script: str, work: Callable[[list[str]], int | None], argv: list[str] | None = None
) -> int:
    """Run a script's ``work`` on its arguments as the commands run: the exit code, or a
    refusal as one line ``SCRIPT: error: ...`` on stderr and exit 2 (``cli.guarded``).

    Parameters
    ----------
    script : str
        The script's path (``__file__``): its name prefixes the messages.
    work : callable
        Takes the arguments (``argv``), parses them (``script_parser``) and does the work;
        returns the exit code (None: 0).
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit code (0 done, 2 refused, 70 an internal error; see ``tetherheli.cli``).
    """
    from . import guarded

    args = list(sys.argv[1:] if argv is None else argv)
    return guarded(lambda: work(args), debug="--debug" in args, prog=Path(script).name)


# --- results: the commands' output rules ------------------------------------------------------


def out_argument(parser: Parser, default: str, *, positional: bool = False) -> None:
    """Add the output directory (``OUT_DIR``, or ``--out DIR`` unless ``positional``; created
    with its parents if missing) and ``--force`` (the commands' help texts), as ``out``
    and ``force``.

    Parameters
    ----------
    parser : Parser
        The script's parser.
    default : str
        The directory written without the argument (a dedicated folder: the current
        directory is refused, as by the commands).
    positional : bool, optional
        An optional positional ``OUT_DIR`` rather than ``--out``.
    """
    from ._common import HELP

    if positional:
        parser.add_argument(
            "out", metavar="OUT_DIR", nargs="?", default=default,
            help=f"{HELP['--out']} (default: {default})",
        )  # fmt: skip
    else:
        parser.add_argument("--out", metavar="DIR", default=default, help=HELP["--out"])
    parser.add_argument("--force", action="store_true", help=HELP["--force"])


def claim(
    out: str | Path,
    *,
    option: str = "--out",
    force: bool = False,
    names: Iterable[str] = (),
    inputs: Iterable[str | Path] = (),
) -> Path:
    """Check an output directory before any work, so that a long run is never refused at
    its end: ``_io.claim_output_directory`` (a dedicated location, no foreign files unless
    ``force``, what a killed run left put right), nothing in the way of the files ``names``
    (``_io.check_output_names``), and a place where the directory can be made
    (``_check_creatable``).

    Parameters
    ----------
    out : str or Path
        The directory (``out_argument``'s ``out``).
    option : str, optional
        The argument that names it, for a refusal (``OUT_DIR``, ``--out``).
    force : bool, optional
        ``--force``: write beside foreign files.
    names : iterable of str, optional
        The files the script writes there (relative paths).
    inputs : iterable of path, optional
        The script's input files, which the directory must not hold.

    Returns
    -------
    Path
        The resolved directory.

    Raises
    ------
    OutputPathError
        One line naming the argument.
    """
    target = claim_output_directory(out, option=option, force=force, inputs=inputs)
    check_output_names(out, names, option=option)
    _check_creatable(target, shown=f"{option} {out}")
    return target


def _check_creatable(target: Path, *, shown: str) -> None:
    """Refuse an output directory whose nearest existing folder above takes no new entry
    (read-only, not a folder, a pseudo file system): probed by making and removing one of
    tetherheli's temporary folders there (a killed run's is removed by the next one)."""
    import tempfile

    folder = target if target.is_dir() else target.parent
    while not os.path.lexists(folder) and folder != folder.parent:
        folder = folder.parent
    try:
        probe = tempfile.mkdtemp(
            dir=folder, prefix=_temporary_prefix(target.name), suffix=".partial"
        )
    except OSError as exc:
        raise OutputPathError(
            f"{shown}: nothing can be created in {folder} ({exc.strerror or exc}); allowed: "
            "a directory in a folder you can write"
        ) from None
    os.rmdir(probe)


def write_figures(
    out: str | Path,
    figures: Mapping[str, Figure],
    *,
    writer: str,
    option: str = "--out",
    force: bool = False,
    dpi: float | None = None,
) -> list[Path]:
    """Save ``figures`` (file name -> figure) into the output directory ``out`` whole or not
    at all (``_io.output_directory``; ``viz.figure.save_figure``), and print ``wrote PATH``
    for each.

    Parameters
    ----------
    out : str or Path
        The directory.
    figures : mapping
        File name (its suffix the format) -> Matplotlib figure.
    writer : str
        The script, recorded as the files' writer (a re-run replaces its own files and
        keeps the others').
    option : str, optional
        The argument that names the directory, for a refusal.
    force : bool, optional
        ``--force``: write beside foreign files.
    dpi : float, optional
        A PNG's resolution (default ``save_figure``'s).

    Returns
    -------
    list of Path
        The files written.
    """
    from ..viz.figure import save_figure

    with output_directory(out, writer=writer, option=option, force=force) as tmp:
        for name, fig in figures.items():
            save_figure(fig, tmp / name, dpi=dpi)
    written = [Path(out) / name for name in figures]
    for path in written:
        print(f"wrote {path}")
    return written


def figure_example(
    script: str,
    doc: str | None,
    figures: Callable[[], Mapping[str, Figure]],
    names: Iterable[str],
    argv: list[str] | None = None,
    *,
    default: str = "examples_out",
    dpi: float = 120,
) -> int:
    """The command line of an example that draws figures: ``[OUT_DIR] [--force]``, the
    folder claimed before ``figures()`` runs and the figures written whole after
    (``write_figures``, the script recorded as their writer).

    Parameters
    ----------
    script : str
        The example's path (``__file__``).
    doc : str or None
        Its docstring (the first line describes it in ``--help``).
    figures : callable
        The example's work: returns file name -> figure.
    names : iterable of str
        The figures' file names (checked before ``figures()`` runs).
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).
    default : str, optional
        ``OUT_DIR`` when not given.
    dpi : float, optional
        The PNGs' resolution.

    Returns
    -------
    int
        The exit code (``run_script``).
    """

    def work(arguments: list[str]) -> int:
        parser = script_parser(script, doc)
        out_argument(parser, default, positional=True)
        args = parser.parse_args(arguments)
        where = {"option": "OUT_DIR", "force": args.force}
        claim(args.out, names=names, **where)
        drawn = figures()
        if set(drawn) != set(names):  # the script's own constants disagree: a bug
            raise AssertionError(f"{sorted(drawn)} drawn, {sorted(names)} announced")
        write_figures(args.out, drawn, writer=Path(script).name, dpi=dpi, **where)
        return 0

    return run_script(script, work, argv)


def claim_file(path: str | Path, *, option: str) -> Path:
    """Check an output file before any work: new, or one tetherheli wrote
    (``_io.check_output_file``), in an existing folder.

    Parameters
    ----------
    path : str or Path
        The file.
    option : str
        The argument that names it, for a refusal.

    Returns
    -------
    Path
        The resolved path.

    Raises
    ------
    OutputPathError
        One line naming the argument.
    """
    target = check_output_file(path, option=option)
    if not target.parent.is_dir():
        raise OutputPathError(
            f"{option} {path}: the folder {target.parent} does not exist; allowed: a file in "
            "an existing folder"
        )
    return target


def write_file(path: str | Path, data: bytes, *, option: str, writer: str) -> Path:
    """Write ``data`` to the output file ``path`` whole (``_io.atomic_write_bytes``), after
    ``claim_file``, and list it in the record of the output directory it lies in, if any.

    Parameters
    ----------
    path : str or Path
        The file.
    data : bytes
        Its content.
    option : str
        The argument that names it, for a refusal.
    writer : str
        The script, recorded as the writer.

    Returns
    -------
    Path
        The file written.
    """
    target = claim_file(path, option=option)
    atomic_write_bytes(target, data)
    record_output_file(target, writer=writer)
    return target


# --- the project's own documentation ----------------------------------------------------------


def docs_file(root: Path, rel: str) -> Path:
    """Check the documentation file ``root/rel`` (``rel`` below ``docs/``) before any work:
    its folder exists, every folder on the way from ``root`` is a real one (no link, no
    file), and the file is new or a regular file (not a link, not a folder).

    Parameters
    ----------
    root : Path
        The repository's checkout (the script's ``parents[1]``).
    rel : str
        The file, relative to ``root`` (``docs/studies/deck.md``).

    Returns
    -------
    Path
        ``root / rel``.

    Raises
    ------
    OutputPathError
        One line naming ``rel``: a link or a file on the way, a missing folder, a link or a
        folder in the file's place.
    """
    if not Path(rel).parts or Path(rel).parts[0] != "docs" or ".." in Path(rel).parts:
        raise ValueError(f"{rel!r} is not a file below docs/")  # the script's constant
    check_real_folders(root, rel, shown=rel)
    path = root / rel
    if not path.parent.is_dir():
        raise OutputPathError(
            f"{rel}: the folder {Path(rel).parent} does not exist; allowed: a documentation "
            "file of the repository's checkout (run the script from a clone)"
        )
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return path
    if not stat.S_ISREG(mode):
        kind = "a link" if stat.S_ISLNK(mode) else "not a regular file"
        raise OutputPathError(
            f"{rel} is {kind} (a script replaces the project's own pages only, never through "
            "a link); allowed: a regular file (git checkout it, or remove it)"
        )
    return path


def write_docs_file(root: Path, rel: str, data: str | bytes) -> Path:
    """Replace the documentation file ``root/rel`` whole with ``data`` (``docs_file``, then
    ``_io.atomic_write_bytes``; text as UTF-8).

    Parameters
    ----------
    root : Path
        The repository's checkout.
    rel : str
        The file, relative to ``root``.
    data : str or bytes
        The new content.

    Returns
    -------
    Path
        The file written.
    """
    path = docs_file(root, rel)
    atomic_write_bytes(path, data.encode("utf-8") if isinstance(data, str) else data)
    return path
