"""``tetherheli derive``: regenerate the numeric model code from Kane's method."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """Write (or with ``--check`` compare) the generated model code.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``--out``, required: nothing is written into the installed
        package unless asked for by name; ``--check``).

    Returns
    -------
    int
        The exit code: 0, or 1 when ``--check`` finds a difference.
    """
    from .._io import atomic_write_text, check_output_file, record_output_file
    from ..model.codegen import GENERATED_PATH, generate_source

    target = Path(args.out)  # required: never the installed package's file by default
    generated = target.resolve() == GENERATED_PATH.resolve()
    if not (args.check or generated):  # a user's path: a new file, or one derive wrote
        check_output_file(target, option="--out")
    text = generate_source()
    if args.check:
        current = target.read_text() if target.exists() else ""
        if current != text:
            print(f"tetherheli derive: {target} differs from a fresh derivation", file=sys.stderr)
            return 1
        print(f"{target} matches a fresh derivation")
        return 0
    atomic_write_text(target, text)  # compiled callers recompile on the next import
    if not generated:
        record_output_file(target, writer="derive")
    print(f"wrote {target}")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``derive`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser("derive", help="regenerate the numeric model code from Kane's method")
    p.add_argument(
        "--out",
        metavar="FILE",
        required=True,
        help="the file to write, or with --check to compare (the package's own code is "
        "src/tetherheli/model/_generated.py in a source checkout)",
    )
    p.add_argument(
        "--check",
        action="store_true",
        help="only compare the --out file with a fresh derivation, writing nothing",
    )
    p.set_defaults(func=run)
