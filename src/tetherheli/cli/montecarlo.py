"""``tetherheli montecarlo``: a resumable Monte Carlo of a scenario, free against tethered."""

from __future__ import annotations

import argparse
import sys

from . import _common as c

__all__ = ["EXIT_STOPPED", "register", "run"]

#: ``montecarlo --max-chunks`` stopped before the job was finished (run it again to resume).
EXIT_STOPPED = 3


def run(args: argparse.Namespace) -> int:
    """Run (or resume) the Monte Carlo (``studies.montecarlo``), write its results folder
    (``report.montecarlo.run_montecarlo``) and print its statistics.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code: 0 finished; 1 a run failed with ``--strict`` or the cluster was lost;
        ``EXIT_STOPPED`` (3) stopped by ``--max-chunks``.
    """
    import dataclasses

    from .._validation import check_integer
    from ..errors import ClusterError, named_source
    from ..report.montecarlo import result_files, run_montecarlo
    from ..runs.batch import connect, disconnect
    from ..studies.montecarlo import CONFIGURATIONS, load_montecarlo
    from ..studies.montecarlo.config import MAX_RUNS
    from ..studies.montecarlo.runner import check_nominal_designs

    if args.runs is not None:
        check_integer("--runs", args.runs, low=1, high=MAX_RUNS)
    base, config = load_montecarlo(args.scenario)
    named_source(args.scenario, check_nominal_designs, base)
    if args.runs is not None:
        config = dataclasses.replace(config, runs=args.runs)
    if args.seed is not None:
        config = dataclasses.replace(config, seed=args.seed)
    client = connect(args.scheduler, args.connect_timeout) if args.scheduler else None
    try:
        summary = run_montecarlo(
            base,
            config,
            args.out,
            chunk_size=args.chunk_size,
            workers=args.workers,
            max_chunks=args.max_chunks,
            progress=not args.quiet,
            client=client,
            worker_timeout_s=args.worker_timeout,
            inputs=c.scenario_inputs([args.scenario], [base]),  # the track it names too
            force=args.force,
            table_format=args.data_format,
            metric=args.metric,
            figure_format=args.figure_format,
        )
    except ClusterError as exc:
        print(
            f"tetherheli: error: {exc}; the finished chunks are kept in {args.out}/partial, "
            "run the same command again to resume",
            file=sys.stderr,
        )
        return 1
    finally:
        if client is not None:
            disconnect(client)
    if summary is None:
        print(
            f"tetherheli: stopped after --max-chunks {args.max_chunks} before the job was "
            f"finished; run the same command again to resume ({args.out})",
            file=sys.stderr,
        )
        return EXIT_STOPPED
    figures = ", ".join(result_files(args.metric, args.figure_format, args.data_format)[2:])
    print(f"wrote {args.out}/ (results.{args.data_format}, summary.json, {figures})")
    failed = _print_statistics(summary, args.metric, CONFIGURATIONS)
    if failed:
        print(
            f"tetherheli: {failed} run{'s' if failed > 1 else ''} failed (status, message and "
            f"reason in {args.out}/results.{args.data_format}; in the percentiles a failed run "
            "counts as the worst value)",
            file=sys.stderr,
        )
    return 1 if failed and args.strict else 0


def _print_statistics(summary: dict, m: str, configurations: tuple[str, ...]) -> int:
    """Print each configuration's counts and percentiles of ``m`` and the paired reduction;
    returns the number of failed runs."""
    from ..names import METRIC_UNITS

    unit = METRIC_UNITS[m]

    def value(v: float | None, spec: str = ".4g") -> str:
        return f"{v:{spec}}" if v is not None else "(among the failed runs)"

    failed = 0
    for cfg in configurations:
        s = summary["statistics"][cfg]
        failed += s["failed"]
        if m not in s:  # no completed run: the counts say it all
            print(f"  {cfg:<9} completed {s['completed']}/{s['runs']}")
            continue
        p = s[m]
        print(
            f"  {cfg:<9} completed {s['completed']}/{s['runs']}, {m} median "
            f"{value(p['p50'])} {unit}, p95 {value(p['p95'])} {unit}"
        )
    r = summary["reduction_percent"].get(m)
    if r is not None and r["draws_with_reference"] == 0:
        print(
            f"  paired reduction of {m} by the tether: none (the free reference of every one "
            f"of the {r['draws']} draws failed)"
        )
    elif r is not None:
        lo, hi = r["ci95"]["p50"]
        print(
            f"  paired reduction of {m} by the tether per draw: median {value(r['p50'], '.1f')} "
            f"% (95% CI {value(lo, '.1f')} .. {value(hi, '.1f')}), "
            f"5th percentile {value(r['p5'], '.1f')} %"
        )
        if r["draws_with_reference"] < r["draws"]:
            print(
                f"  ({r['draws'] - r['draws_with_reference']} of {r['draws']} draws have no "
                "reduction: their free reference failed)"
            )
    return failed


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``montecarlo`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    from ..names import MONTECARLO_METRICS  # light: the help builds no engine

    p = sub.add_parser(
        "montecarlo",
        help="Monte Carlo of a scenario, free against tethered",
        description="Monte Carlo of a scenario, free against tethered. Exit codes: 0 finished "
        "(failed runs are rows of results.csv), 1 a run failed with --strict or the Dask "
        "cluster was lost (resumable), 2 bad input, 3 stopped by --max-chunks (resumable). "
        "The output directory is resumable: the same command continues an unfinished job.",
        parents=[
            c.out_directory(),
            c.runs(),
            c.seed(),
            c.metric(MONTECARLO_METRICS),
            c.workers(),
            c.data_format(runs=False),
            c.figure_format(),
            c.force(),
        ],
    )
    p.add_argument("scenario", help="scenario TOML file with a [montecarlo] table")
    p.add_argument(
        "--chunk-size",
        type=c.count_arg("--chunk-size", 1, 1_000_000),
        default=50,
        help="draws per resumable chunk file",
    )
    p.add_argument(
        "--max-chunks",
        type=c.count_arg("--max-chunks", 0, 10_000_000),
        help="compute at most this many new chunks, then stop with exit code 3 if the job is "
        "not finished (resume by running the same command again; default: no limit, run "
        "to the end)",
    )
    p.add_argument(
        "--strict",
        action="store_true",
        help="exit 1 if any run failed (by default failed runs are rows of the table, exit 0)",
    )
    p.add_argument(
        "--scheduler",
        help="run on a dask.distributed scheduler, e.g. tcp://host:8786 (default: none, "
        "in this process with --workers threads)",
    )
    p.add_argument(
        "--connect-timeout",
        type=c.positive_float("--connect-timeout"),
        default=10.0,
        help="seconds to wait for the scheduler, at the start and when it stops answering",
    )
    p.add_argument(
        "--worker-timeout",
        type=c.positive_float("--worker-timeout"),
        default=60.0,
        help="with --scheduler: give up (exit 1, resumable) when the cluster has had no worker "
        "for this many seconds",
    )
    p.set_defaults(func=run)
