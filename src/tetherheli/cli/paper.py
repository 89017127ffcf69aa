"""``tetherheli paper``: the paper's four wind simulations, Figs. 6-9 and a report."""

from __future__ import annotations

import argparse
import sys

from . import _common as c

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """Run the paper job (``report.run_paper``) and print the reductions.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code: 0, or 1 if a run failed.
    """
    from ..report import run_paper

    given = " ".join(sys.argv[2:]) if sys.argv[1:2] == ["paper"] else ""
    summary = run_paper(
        args.out,
        dt=args.dt,
        pulse_duration=args.pulse_duration,
        command=f"tetherheli paper {given}".strip(),
        force=args.force,
        data_format=args.data_format,
        figure_format=args.figure_format,
        progress=not args.quiet,
    )
    red = summary["reduction_percent"]
    fmt = args.figure_format.upper()
    print(f"wrote {args.out}/ (report.md, summary.json, fig6-fig9 {fmt}, time series)")
    print("reduction of the disturbance effect by the tether (100 (free - tethered) / free):")
    for k, v in red.items():
        print(f"  {k:<14} {v:6.1f} %" if v is not None else f"  {k:<14}    n/a (a run failed)")
    return c.report_failures(summary["statuses"], args.out)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``paper`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "paper",
        help="the paper's four wind simulations, Figs. 6-9, report",
        parents=[c.out_directory("paper_out"), c.data_format(), c.figure_format(), c.force()],
    )
    p.add_argument(
        "--dt",
        type=c.seconds_arg("a sample time", 1.0),
        default=0.01,
        help="controller sample time [s]",
    )
    p.add_argument(
        "--pulse-duration",
        type=c.seconds_arg("a duration", 20.0),
        default=1.0,
        help="duration of the 20 N pulse [s] (not stated in the paper)",
    )
    p.set_defaults(func=run)
