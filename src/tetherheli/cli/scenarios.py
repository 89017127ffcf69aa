"""``tetherheli scenarios``: list the shipped scenario files, or copy one out to edit."""

from __future__ import annotations

import argparse

from ._common import UsageError

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """List the shipped scenarios, or copy ``args.name`` to ``args.out``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``name``, ``--out``).

    Returns
    -------
    int
        The exit code, 0.
    """
    from ..shipped import copy_scenario, shipped_scenarios

    if args.name is None:
        if args.out is not None:
            raise UsageError("tetherheli scenarios: --out needs a scenario NAME")
        listing = shipped_scenarios()
        width = max(map(len, listing))
        for name, description in listing.items():
            print(f"{name:<{width}}  {description}")
        return 0
    if args.out is None:
        raise UsageError(
            f"tetherheli scenarios: give --out PATH to copy {args.name} (e.g. "
            f"--out {args.name}.toml)"
        )
    path = copy_scenario(args.name, args.out)
    print(f"wrote {path}")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``scenarios`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "scenarios",
        help="list the shipped scenario files, or copy one out to edit",
        description="Without NAME: list the scenarios shipped with tetherheli. With NAME and "
        "--out: copy that scenario's TOML file to PATH (never over a file tetherheli did not "
        "write).",
    )
    p.add_argument("name", nargs="?", help="a shipped scenario's name (see the list)")
    p.add_argument(
        "--out", metavar="FILE", help="file to write the scenario to (required with NAME)"
    )
    p.set_defaults(func=run)
