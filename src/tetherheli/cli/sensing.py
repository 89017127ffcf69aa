"""``tetherheli sensing``: the tether as a GPS-free position sensor (Sec. IV-F)."""

from __future__ import annotations

import argparse
import sys

from . import _common as c

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """Run the sensing job (``report.run_sensing``) and print its table.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code: 0, or 1 if a run failed.
    """
    from ..report.paper import run_sensing

    if args.scenario_option:  # the deprecated spelling: still flown, after the arguments
        print(
            "tetherheli: warning: sensing --scenario FILE is deprecated; give the scenario "
            "files as arguments (tetherheli sensing FILE ... --out DIR)",
            file=sys.stderr,
        )
    files = (*args.scenarios, *args.scenario_option)
    table = run_sensing(
        args.out,
        scenarios=files or None,
        force=args.force,
        figure_format=args.figure_format,
        data_format=args.data_format,
    )
    print(
        f"wrote {args.out}/ (sensing.{args.figure_format}, summary.json, time series as "
        f"{args.data_format})"
    )
    print("RMS q1/q2/q3 [m]: the controller's estimate error, the true deviation from trim,")
    print("and the Kalman filter's error fusing the IMU with each source (over the GNSS outage)")

    def triple(values: dict | None) -> str:
        return "/".join(f"{v:.4g}" for v in values.values()) if values else "n/a"

    for name, row in table.items():
        note = "" if row["completed"] else f"  (failed at t = {row['end_time']:g} s)"
        print(f"{name} (position from {row['position_source']}){note}")
        print(f"  controller estimate error {triple(row['estimate_error_rms'])}")
        print(f"  true deviation            {triple(row['true_deviation_rms'])}")
        outage = row["kalman_error_rms_outage"] or {}
        for fusion, values in row["kalman_error_rms"].items():
            during = f"  (outage {triple(outage.get(fusion))})" if outage else ""
            sigma = triple(row["kalman_final_std"][fusion])
            print(f"  Kalman IMU + {fusion:<12} {triple(values)}{during}  [final sigma {sigma}]")
    return c.report_failures(table, args.out)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``sensing`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "sensing",
        help="the tether as a GPS-free position sensor (Sec. IV-F)",
        parents=[
            c.out_directory("sensing_out"), c.data_format(), c.figure_format(), c.force(),
        ],
    )  # fmt: skip
    p.add_argument(
        "scenarios",
        nargs="*",
        metavar="SCENARIO",
        help="scenario TOML files with [sensors] (default: the shipped sensing_*.toml)",
    )
    # deprecated: the scenario files are arguments, as in every other command
    p.add_argument(
        "--scenario", action="append", default=[], dest="scenario_option", help=argparse.SUPPRESS
    )
    p.set_defaults(func=run)
