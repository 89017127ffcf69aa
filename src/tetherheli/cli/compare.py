"""``tetherheli compare``: fly scenarios (and Monte Carlo files) under several controllers;
one table and one figure (``tetherheli.compare``)."""

from __future__ import annotations

import argparse
import sys

from . import _common as c

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """Check every input, fly the comparison, write the folder and print the table.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code: 0, or 1 if a single run failed (a Monte Carlo's failures are its
        results).
    """
    from .._io import claim_output_directory
    from .._validation import check_integer
    from ..compare import compare, markdown_reductions, markdown_table, write_compare
    from ..errors import ParameterError
    from ..scenario.core import CONTROLLERS, load_scenario

    names = tuple(n.strip() for n in args.controllers.split(",") if n.strip())
    if not names or any(n not in CONTROLLERS for n in names):
        raise ParameterError("--controllers", args.controllers, f"names from {CONTROLLERS}")
    mc_files = tuple(args.montecarlo or ())
    if not args.scenarios and not mc_files:
        raise ParameterError("scenarios", "none", "scenario files or --montecarlo FILE")
    from ..errors import named_source
    from ..results.result import check_result_format
    from ..studies.controllers import check_design, with_controller
    from ..studies.montecarlo import load_montecarlo
    from ..studies.montecarlo.config import MAX_RUNS
    from ..studies.montecarlo.draws import free_reference
    from ..studies.robust import check_comparison_memory, montecarlo_compare

    if args.runs is not None:
        check_integer("--runs", args.runs, low=1, high=MAX_RUNS)
    check_result_format(args.data_format)  # before the runs
    mc_inputs = []
    for path in mc_files:  # read them all before any run: a bad file fails fast
        mc_inputs.append(load_montecarlo(path))
        base = mc_inputs[-1][0]
        for name in ("paper", *names):  # the free reference's and each controller's design
            flown = (
                free_reference(base) if name == "paper" else base.replace(configuration="tethered")
            )
            named_source(path, check_design, with_controller(flown, name))
    for _, config in mc_inputs:  # and refuse what cannot fit, before the first run
        check_comparison_memory(config.runs if args.runs is None else args.runs, 1 + len(names))
    named = [load_scenario(path) for path in args.scenarios] + [b for b, _ in mc_inputs]
    inputs = c.scenario_inputs([*args.scenarios, *mc_files], named)  # the tracks they name too
    claim_output_directory(args.out, inputs=inputs, force=args.force)
    rows = compare(list(args.scenarios), names, eq40=args.eq40, workers=args.workers)
    montecarlo = []
    for base, config in mc_inputs:
        mc = montecarlo_compare(
            base, config, names, runs=args.runs, eq40=args.eq40, seed=args.seed,
            workers=args.workers,
        )  # fmt: skip
        montecarlo.append(mc)
        rows.extend(mc.rows())
    command = "tetherheli compare " + " ".join(sys.argv[2:])
    write_compare(
        rows, args.out, command=command, inputs=inputs, force=args.force,
        montecarlo=tuple(montecarlo), figure_format=args.figure_format,
        data_format=args.data_format,
    )  # fmt: skip
    print(markdown_table(rows), end="")
    if montecarlo:
        print(markdown_reductions(tuple(montecarlo)), end="")
    # a single run that failed fails the command; a Monte Carlo's failures are its results
    failed = [r for r in rows if r.get("runs", 1) == 1 and not r.get("completed")]
    for r in failed:
        print(f"tetherheli: {r['scenario']} / {r['controller']}: {r['status']}", file=sys.stderr)
    return 1 if failed else 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``compare`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "compare",
        help="fly scenarios under several controllers: table, figure",
        description="Fly scenarios (and a Monte Carlo's draws) under several controllers: "
        "one table, figures. The runs fly side by side on --workers threads; each run's "
        "compute time (us/sample) is taken with the others in flight, --workers 1 times "
        "each run alone.",
        parents=[
            c.out_directory(),
            c.runs(),
            c.seed(),
            c.workers(),
            c.data_format(runs=False),
            c.figure_format(),
            c.force(),
        ],
    )
    p.add_argument("scenarios", nargs="*", help="scenario TOML files")
    p.add_argument(
        "--controllers", default="paper,tether_lqi", help="comma-separated controller names"
    )
    p.add_argument(
        "--eq40", action="store_true", help="saturate tMR1, tMR2 at eq 40's cyclic limit"
    )
    p.add_argument(
        "--montecarlo",
        action="append",
        metavar="FILE",
        help="a Monte Carlo file ([montecarlo]): its draws under every controller, designed "
        "on the nominal plant; percentiles and paired reductions (repeatable; default: none)",
    )
    p.set_defaults(func=run)
