"""``tetherheli simulate``: run scenario files (several: one folder each, overlaid figures)."""

from __future__ import annotations

import argparse
import sys

from . import _common as c

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """Validate every scenario, fly them, write the run (or the comparison) folder.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code: 0, or 1 if a run failed or stopped early.
    """
    from .._io import claim_output_directory
    from ..errors import named_source
    from ..report.paper import _write_comparison, _write_run
    from ..results.result import check_result_format
    from ..runs.closed_loop import _simulate, check_run_memory
    from ..scenario import load_scenario
    from ..scenario.core import check_distinct_names
    from ..status import stopped

    check_result_format(args.data_format)  # before the runs
    scenarios = [load_scenario(path) for path in args.scenario]  # all validated first
    check_distinct_names(s.name for s in scenarios)  # one file or folder each
    for s in scenarios:  # refuse what cannot fit before the first run
        check_run_memory(s)
    inputs = c.scenario_inputs(args.scenario, scenarios)  # the tracks they name too
    claim_output_directory(args.out, inputs=inputs, force=args.force)
    command = "tetherheli simulate " + " ".join(args.scenario)
    results = [
        named_source(path, _simulate, s, method=args.method)  # each checked above
        for path, s in zip(args.scenario, scenarios, strict=True)
    ]
    # the formats: --format checked above (its packages), --figure-format by its choices
    where = (args.out, command, inputs, args.force, args.data_format, args.figure_format)
    if len(results) == 1:
        _write_run(results[0], *where)
    else:  # distinct names, checked above
        _write_comparison(results, *where)
    for r in results:
        if r.released:
            print(f"tetherheli: run {r.name}: {r.release_note()}", file=sys.stderr)
    failed = [r for r in results if not r.ok]
    for r in failed:
        ended = "stopped" if stopped(r.status) else "ended"
        print(
            f"tetherheli: run {r.name} {ended} at t = {r.end_time:g} s: {r.message} "
            f"(partial results in {args.out})",
            file=sys.stderr,
        )
    if failed:
        return 1
    done = ", ".join(f"{r.name}: {r.message}" for r in results)
    print(f"wrote {args.out}/ ({done})")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``simulate`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "simulate",
        help="run scenario TOML files (several: overlaid)",
        parents=[c.out_directory(), c.data_format(), c.figure_format(), c.force()],
    )
    p.add_argument(
        "scenario",
        nargs="+",
        help="scenario TOML file(s) (see scenarios/); several runs go to OUT/<name>/ and are "
        "overlaid in OUT/outputs.png, OUT/inputs.png",
    )
    p.add_argument(
        "--method",
        choices=("rk4", "adaptive"),
        default="rk4",
        help="integration: compiled fixed-step RK4 or the adaptive reference",
    )
    p.set_defaults(func=run)
