"""``tetherheli tether-study``: does the tether's benefit survive at 10-100 m of real cable?
(``studies.tether_study``, written by ``report.tether_study``; imported by the command only:
the study loads the lumped chain.)"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable

from ..names import (
    TETHER_STUDY_CABLES,
    TETHER_STUDY_ELEVATIONS_DEG,
    TETHER_STUDY_LENGTHS_M,
    TETHER_STUDY_MODELS,
    TETHER_STUDY_THRUST_TO_WEIGHT,
    TETHER_STUDY_WINCH_GAINS,
    TETHER_STUDY_WINDS_M_S,
)
from . import _common as c

__all__ = ["register", "run"]


def _floats(name: str) -> Callable[[str], list[float]]:
    def parse(text: str) -> list[float]:
        try:
            return [float(v) for v in text.split(",") if v.strip()]
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} = {text!r}: allowed: comma-separated numbers"
            ) from None

    return parse


def run(args: argparse.Namespace) -> int:
    """Run the study and write its folder (``report.tether_study.run_tether_study``).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code: 0, or 1 if a dynamic run failed.
    """
    from ..report.tether_study import run_tether_study
    from ..studies.tether_study import DYNAMIC_CASES, select_cables

    cables = select_cables([k.strip() for k in args.cables.split(",") if k.strip()])
    summary = run_tether_study(
        args.out,
        cables=cables,
        lengths_m=args.lengths,
        model=args.model,
        winch_gain=args.winch_gain,
        winds_m_s=args.winds,
        elevations_deg=args.elevations,
        duration_s=args.duration,
        max_thrust_N=args.max_thrust,
        workers=args.workers,
        command="tetherheli tether-study " + " ".join(sys.argv[2:]),
        force=args.force,
        progress=not args.quiet,
        figure_format=args.figure_format,
        data_format=args.data_format,
    )
    failed = [r for r in summary["dynamic"] if not r["completed"]]
    tables = ", ".join(f"{t}.{args.data_format}" for t in ("static", "dynamic", "sensing"))
    print(f"wrote {args.out}/ (study.md, {tables}, figures)")
    for r in failed:
        print(
            f"tetherheli: {r['cable']} at {r['length_m']:g} m: a run failed "
            f"({'; '.join(r[f'{case}_status'] for case, _ in DYNAMIC_CASES)})",
            file=sys.stderr,
        )
    return 1 if failed else 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``tether-study`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "tether-study",
        help="does the tether's benefit survive at 10-100 m of real cable?",
        parents=[
            c.out_directory("tether_study_out"), c.workers(), c.data_format(runs=False),
            c.figure_format(), c.force(),
        ],
    )  # fmt: skip
    p.add_argument(
        "--cables",
        default=",".join(TETHER_STUDY_CABLES),
        help=f"comma-separated cables from {list(TETHER_STUDY_CABLES)}",
    )
    p.add_argument(
        "--lengths",
        type=_floats("--lengths"),
        default=list(TETHER_STUDY_LENGTHS_M),
        help="tether lengths q9 [m], comma-separated, ascending",
    )
    p.add_argument(
        "--winds",
        type=_floats("--winds"),
        default=list(TETHER_STUDY_WINDS_M_S),
        help="steady winds of the sensing half [m/s], comma-separated, ascending",
    )
    p.add_argument(
        "--elevations",
        type=_floats("--elevations"),
        default=list(TETHER_STUDY_ELEVATIONS_DEG),
        help="elevations of P seen from the winch, sensing half [deg], ascending",
    )
    p.add_argument(
        "--duration",
        type=float,
        default=None,
        help="shorten every dynamic run to this many seconds (default: 60 s, turbulence 120 s)",
    )
    p.add_argument(
        "--max-thrust",
        type=float,
        default=None,
        help=f"maximum fMR3 [N] (default {TETHER_STUDY_THRUST_TO_WEIGHT:g} x the free hover "
        "thrust)",
    )
    p.add_argument(
        "--model",
        choices=TETHER_STUDY_MODELS,
        default=TETHER_STUDY_MODELS[0],
        help="the dynamic runs' tether: the lumped chain or the massless stand-in",
    )
    p.add_argument(
        "--winch-gain",
        choices=TETHER_STUDY_WINCH_GAINS,
        default=TETHER_STUDY_WINCH_GAINS[0],
        help="eq 56's gains: the paper's, or scaled to the paper's tension loop gain",
    )
    p.set_defaults(func=run)
