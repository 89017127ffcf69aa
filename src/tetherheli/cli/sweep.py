"""``tetherheli sweep``: a metric against a parameter, or (``--find-min``) the smallest
cyclic limit whose runs keep the metric within a margin of the unlimited run's."""

from __future__ import annotations

import argparse
import math
import sys

from . import _common as c

__all__ = ["register", "run"]


def _values_arg(text: str) -> list[float]:
    """'a:b:n' (n points from a to b) or a comma-separated list."""
    try:
        if ":" in text:
            a, b, n = text.split(":")
            if int(n) < 1 or int(n) > 10000:
                raise ValueError
            import numpy as np

            return np.linspace(float(a), float(b), int(n)).tolist()
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: allowed: START:STOP:N (1 <= N <= 10000) or a comma-separated list"
        ) from None


def run(args: argparse.Namespace) -> int:
    """Run the sweep (``studies.sweep``) or the search (``studies.cyclic_limit``).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code: 0, or 1 if a point failed (sweep) or no grid value meets the
        criterion (``--find-min``).
    """
    from .._io import claim_output_directory
    from ..errors import named_source
    from ..results.result import check_result_format
    from ..scenario import load_scenario

    check_result_format(args.data_format)  # before the runs
    scenario = load_scenario(args.scenario)
    if args.controller is not None:  # every run under this controller
        from ..studies.controllers import with_controller

        scenario = with_controller(scenario, args.controller)
    inputs = c.scenario_inputs([args.scenario], [scenario])  # the track it names too
    command = "tetherheli sweep " + " ".join(sys.argv[2:])
    if args.find_min is not None:
        return _find_min(args, scenario, inputs, command)
    from ..report.sweep import write_sweep
    from ..studies.sweep import sweep

    metric = args.metric
    claim_output_directory(args.out, inputs=inputs, force=args.force)
    result = named_source(
        args.scenario,
        sweep,
        scenario,
        args.param,
        args.values,
        metric,
        cyclic_limit=args.cyclic_limit,
        progress=not args.quiet,
        workers=args.workers,
    )
    write_sweep(
        result,
        args.out,
        command=command,
        inputs=inputs,
        force=args.force,
        figure_format=args.figure_format,
        data_format=args.data_format,
    )
    moments = result.peak_tether_moment
    for i, (v, m, s) in enumerate(zip(result.values, result.metric, result.statuses, strict=True)):
        extra = ""
        if moments is not None and math.isfinite(moments[i]):
            extra = (
                f"  peak tether moment {moments[i]:.3f} N m "
                f"(eq 40 worst case {result.peak_worst_case_moment[i]:.3f}, "
                f"tether {result.peak_tether_angle_deg[i]:.1f} deg from the shaft)"
            )
        print(f"{args.param} = {v:<10.6g} {metric} = {m:.6g}  ({s}){extra}")
    if result.cyclic_limit is not None:
        print(f"cyclic authority: {result.cyclic_limit:.4g} N m, {result.limit_source}")
    if result.bound is not None:
        print(f"eq 40 tension bound (worst case): TC < {result.bound:.2f} N")
        print(f"best {args.param} within the bound: {result.best_within_bound}")
    print(f"best {args.param}: {result.best_value}")
    for i in result.failed:
        print(
            f"tetherheli: sweep point {args.param} = {result.values[i]:g}: {result.statuses[i]}",
            file=sys.stderr,
        )
    if result.failed:
        print(
            f"tetherheli: {len(result.failed)} of {len(result.values)} sweep points failed or "
            f"were invalid (statuses in {args.out}/summary.json)",
            file=sys.stderr,
        )
        return 1
    return 0


def _find_min(args: argparse.Namespace, scenario, inputs: tuple, command: str) -> int:
    """``sweep --find-min actuators.cyclic_limit``: ``studies.cyclic_limit``."""
    from .._io import claim_output_directory
    from ..report.cyclic_limit import write_limit_search
    from ..studies.cyclic_limit import minimum_cyclic_limit

    if args.cyclic_limit is not None:
        from ..errors import ParameterError

        raise ParameterError("--cyclic-limit", args.cyclic_limit, "not with --find-min")
    metric = args.metric
    claim_output_directory(args.out, inputs=inputs, force=args.force)
    result = minimum_cyclic_limit(
        scenario,
        args.values,
        within=args.within,
        metric=metric,
        tol=args.tol,
        progress=not args.quiet,
        workers=args.workers,
    )
    write_limit_search(
        result,
        args.out,
        command=command,
        inputs=inputs,
        force=args.force,
        figure_format=args.figure_format,
        data_format=args.data_format,
    )
    print(f"{scenario.name}: {metric} without cyclic limits = {result.reference:.6g}")
    rows = zip(result.values, result.metric, result.meets, result.statuses, strict=True)
    for v, m, ok, s in rows:
        print(f"cyclic limit = {v:<10.6g} {metric} = {m:.6g}  {'meets' if ok else '-'}  ({s})")
    print(
        f"smallest cyclic limit with {metric} <= {1 + result.within:g} x unlimited "
        f"({result.threshold:.4g}): {result.interval_text()}"
    )
    return 0 if result.hi is not None else 1


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``sweep`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "sweep",
        help="a metric against a parameter (e.g. Tref), or the smallest cyclic limit",
        description="A metric against a parameter (--param), or with --find-min "
        "actuators.cyclic_limit the smallest cyclic limit whose runs keep the metric "
        "within --within of the unlimited run's: a grid scan over --values, then "
        "bisection to --tol (exit 1 when none within the grid).",
        parents=[
            c.out_directory(), c.metric(), c.workers(), c.data_format(runs=False),
            c.figure_format(), c.force(),
        ],
    )  # fmt: skip
    p.add_argument("scenario", help="scenario TOML file")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument(
        "--find-min",
        choices=("actuators.cyclic_limit",),
        help="find the smallest value of this setting that meets the criterion (required, or "
        "--param)",
    )
    which.add_argument(
        "--param",
        help="section.field of the parameters (e.g. tension_control.T_ref, "
        "tether.K_C, helicopter.d_O_P3), q9, control.dt, or an actuator setting "
        "(actuators.cyclic_limit, .time_constant, .reel_rate_limit, "
        ".reel_acceleration_limit, .breaking_tension; required, or --find-min)",
    )
    p.add_argument(
        "--values",
        type=_values_arg,
        required=True,
        help="START:STOP:N or a,b,c (with --find-min: the grid)",
    )
    p.add_argument(
        "--cyclic-limit",
        type=c.positive_float("--cyclic-limit"),
        default=None,
        help="saturate tMR1, tMR2 of every run at +- this [N m] and size eq 40's bound with it "
        "(default: the scenario's [actuators] limits; without any, the paper's 20%% rule sizes "
        "the bound only and the runs are not saturated)",
    )
    p.add_argument(
        "--within",
        type=c.positive_float("--within"),
        default=0.10,
        help="--find-min: allowed relative increase of the metric over the unlimited run",
    )
    p.add_argument(
        "--tol",
        type=c.positive_float("--tol"),
        default=1e-3,
        help="--find-min: width of the reported interval [N m]",
    )
    p.add_argument(
        "--controller",
        default=None,
        help="fly every run under this controller ([control] controller, e.g. tether_lqi; "
        "default: the scenario's)",
    )
    p.set_defaults(func=run)
