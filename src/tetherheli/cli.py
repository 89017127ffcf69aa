"""The ``tetherheli`` command line (also ``python -m tetherheli``).

Exit codes: 0 success; 1 a run failed (reported, results written); 2 a user error (bad
parameter, scenario, argument or output path), printed as one line on stderr without a
traceback; 70 an internal error (a bug: one line, ``--debug`` prints the traceback);
130 interrupted.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

from ._version import __version__
from .errors import TetherheliError, named_source
from .params import Params

__all__ = ["main"]

EXIT_USAGE = 2
EXIT_INTERNAL = 70  # sysexits' EX_SOFTWARE
EXIT_INTERRUPTED = 130
#: ``montecarlo --max-chunks`` stopped before the job was finished (run it again to resume).
EXIT_STOPPED = 3


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(f"{self.prog}: {message}")


class _UsageError(Exception):
    pass


def _plain(text: str) -> str:
    """``text`` without reStructuredText markup (double backquotes), for ``--help``."""
    return text.replace("``", "")


def _load_params(path: str | None) -> Params:
    return Params.from_toml(path) if path else Params.paper()


# --- trim -----------------------------------------------------------------------------------

#: (name, unit, paper digits, converter from SI) of the rows of Tables IV and V.
_TRIM_ROWS: tuple[tuple[str, str, int, Callable[[float], float]], ...] = (
    ("q4", "deg", 2, math.degrees),
    ("q5", "deg", 2, math.degrees),
    ("q6", "deg", 2, math.degrees),
    ("q7", "deg", 2, math.degrees),
    ("q8", "deg", 2, math.degrees),
    ("q9", "m", 4, float),
    ("q1", "m", 4, float),
    ("q2", "m", 4, float),
    ("q3", "m", 4, float),
    ("fMR3", "N", 4, float),
    ("tMR1", "N m", 4, float),
    ("tMR2", "N m", 4, float),
    ("fTR2", "N", 4, float),
)


def _trim_values(args: argparse.Namespace) -> dict[str, float]:
    from .model import TetheredHelicopter

    model = TetheredHelicopter(_load_params(args.params))
    trim = model.trim(args.tension, args.q9)
    values = dict(zip(model.STATE, trim.x, strict=True))
    values.update(zip(model.OUTPUT, trim.y, strict=True))
    values.update(zip(model.INPUT, trim.u, strict=True))
    values["tMR1_total"] = trim.t_MR1_total
    values["LN"] = float(trim.x[12])
    values["TC"] = trim.tension
    return values


def _cmd_trim(args: argparse.Namespace) -> int:
    values = _trim_values(args)
    if args.json:
        si = {k: float(v) for k, v in values.items()}
        print(
            json.dumps(
                {
                    "tension": args.tension,
                    "q9": args.q9,
                    "trim": si,
                    "units": "SI (rad, m, N, N m)",
                    "version": __version__,
                },
                indent=2,
            )
        )
        return 0
    table = "Table IV" if args.tension == 0 else "Table V"
    print(
        f"Hover trim, TC = {args.tension:g} N, q9 = {args.q9:g} m "
        f"(paper: {table} for the paper's parameters)"
    )
    print(f"{'variable':<10} {'value':>12} {'full precision':>22}  units")
    for name, unit, digits, conv in _TRIM_ROWS:
        v = conv(float(values[name]))
        v = 0.0 if abs(v) < 0.5 * 10.0**-12 else v
        print(f"{name:<10} {v:>12.{digits}f} {v:>22.12g}  {unit}")
    print(f"{'LN':<10} {values['LN']:>12.4f} {values['LN']:>22.12g}  m   (winch natural length)")
    print(
        f"{'tMR1 total':<10} {values['tMR1_total']:>12.4f} {values['tMR1_total']:>22.12g}  "
        "N m (tMR1 the rotor produces: u0 minus the tether feed-forward C1, eq 54)"
    )
    return 0


# --- derive ---------------------------------------------------------------------------------


def _cmd_derive(args: argparse.Namespace) -> int:
    from ._io import atomic_write_text, check_output_file, record_output_file
    from .model.codegen import GENERATED_PATH, generate_source

    if args.output is not None:
        if args.out is not None:
            raise _UsageError("tetherheli derive: give --out only (--output is its old name)")
        print("tetherheli: warning: derive --output is deprecated; use --out", file=sys.stderr)
    out = args.out if args.out is not None else args.output
    target = Path(out) if out else GENERATED_PATH
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


# --- parser ---------------------------------------------------------------------------------


def _positive_float(name: str) -> Callable[[str], float]:
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: allowed: a number") from None
        if not math.isfinite(value) or value < 0:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: allowed: a finite number >= 0")
        return value

    return parse


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="tetherheli", description=_plain(__doc__.splitlines()[0]))
    parser.add_argument("--version", action="version", version=f"tetherheli {__version__}")
    common = _Parser(add_help=False)
    common.add_argument(
        "--debug", action="store_true", help="print the traceback of an internal error"
    )
    common.add_argument(
        "--quiet",
        action="store_true",
        help="no progress on stderr (no bar on a terminal, no summary line in a log); "
        "warnings and errors are still printed",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    sub.add_parser = functools.partial(sub.add_parser, parents=[common])  # type: ignore[method-assign]

    p = sub.add_parser("trim", help="hover trim (Tables IV and V)")
    p.add_argument(
        "--tension",
        type=_positive_float("--tension"),
        default=0.0,
        help="tether tension TC [N] (0: free configuration, Table IV)",
    )
    p.add_argument("--q9", type=_positive_float("--q9"), default=10.0, help="tether length [m]")
    p.add_argument("--params", help="TOML file overriding the paper's parameters")
    p.add_argument("--json", action="store_true", help="machine-readable output (SI units)")
    p.set_defaults(func=_cmd_trim)

    p = sub.add_parser("derive", help="regenerate the numeric model code from Kane's method")
    p.add_argument("--out", help="where to write (default: the package's _generated.py)")
    p.add_argument("--output", help=argparse.SUPPRESS)  # the old name of --out: warns
    p.add_argument(
        "--check",
        action="store_true",
        help="only compare the committed code with a fresh derivation",
    )
    p.set_defaults(func=_cmd_derive)

    for register in _EXTRA_COMMANDS:
        register(sub)
    return parser


#: Further sub-command registrations (simulation, analysis), appended by their modules.
_EXTRA_COMMANDS: list[Callable[[argparse._SubParsersAction], None]] = []


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _join_negative_values(argv: list[str]) -> list[str]:
    """``--values -0.2:-0.05:4`` as ``--values=-0.2:-0.05:4`` (argparse would take a value
    that starts with '-' for an option)."""
    out: list[str] = []
    it = iter(argv)
    for token in it:
        if token == "--values":
            value = next(it, None)
            out.append(token if value is None else f"--values={value}")
        else:
            out.append(token)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (see the module docstring).

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments after the program name (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit code: 0 success, 1 a run failed, ``EXIT_USAGE`` (2) a user error,
        ``EXIT_STOPPED`` (3) ``montecarlo --max-chunks`` stopped early, ``EXIT_INTERNAL``
        (70) a bug, ``EXIT_INTERRUPTED`` (130).
    """
    argv = _join_negative_values(list(sys.argv[1:] if argv is None else argv))
    debug = "--debug" in argv
    with warnings.catch_warnings():
        warnings.showwarning = _show_warning  # restored on return
        return _main(argv, debug)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one line on stderr: ``tetherheli: warning: ...`` for the package's own
    (``resources.SlowJobWarning``), Python's format for the others."""
    from .resources import SlowJobWarning

    if issubclass(category, SlowJobWarning):
        print(f"tetherheli: warning: {message}", file=sys.stderr)
    else:
        sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


def _main(argv: list[str], debug: bool) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        code = int(args.func(args) or 0)
        sys.stdout.flush()  # a closed pipe (``| head -1``) surfaces here, not at exit
        return code
    except BrokenPipeError:  # the reader of stdout has gone (``| head -1``): end quietly
        _drop_stdout()
        return 0
    except _UsageError as exc:
        print(str(exc), file=sys.stderr)
        return EXIT_USAGE
    except TetherheliError as exc:
        print(f"tetherheli: error: {_first_line(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        if exc.filename is None or debug:  # not about a user's path: a fault of ours
            return _internal_error(exc, debug)
        print(f"tetherheli: error: {exc.filename}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("tetherheli: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:
        return _internal_error(exc, debug)


def _drop_stdout() -> None:
    """Point stdout at the null device after its reader closed the pipe, so that the
    interpreter's final flush does not fail again ("Exception ignored ... BrokenPipeError")."""
    import contextlib
    import io

    with contextlib.suppress(OSError, ValueError, io.UnsupportedOperation):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def _internal_error(exc: BaseException, debug: bool) -> int:
    if debug:
        import traceback

        traceback.print_exception(exc)
    print(
        f"tetherheli: internal error ({type(exc).__name__}: "
        f"{_first_line(exc)}); this is a bug: please report it with the output of the same "
        "command with --debug",
        file=sys.stderr,
    )
    return EXIT_INTERNAL


# --- simulation commands --------------------------------------------------------------------


def _cmd_paper(args: argparse.Namespace) -> int:
    from .report import run_paper

    command = (
        "tetherheli paper " + " ".join(sys.argv[2:])
        if sys.argv[1:2] == ["paper"]
        else ("tetherheli paper")
    )
    summary = run_paper(
        args.out,
        dt=args.dt,
        pulse_duration=args.pulse_duration,
        command=command.strip(),
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
    return _report_failures(summary["statuses"], args.out)


def _report_failures(statuses: dict, out: str) -> int:
    """One line on stderr per failed run of ``statuses`` (``report.run_status`` records);
    the exit code: 1 if any failed, else 0."""
    failed = {k: st for k, st in statuses.items() if not st["completed"]}
    for k, st in failed.items():
        print(
            f"tetherheli: run {k} failed at t = {st['end_time']:g} s: {st['message']} "
            f"(partial results in {out})",
            file=sys.stderr,
        )
    return 1 if failed else 0


def _cmd_simulate(args: argparse.Namespace) -> int:
    from ._io import claim_output_directory
    from .report import write_comparison, write_run
    from .sim import load_scenario, simulate
    from .sim.closed_loop import check_run_memory
    from .sim.result import check_result_format
    from .sim.scenario import check_distinct_names
    from .status import ran_to_end

    check_result_format(args.data_format)  # before the runs
    scenarios = [load_scenario(path) for path in args.scenario]  # all validated first
    check_distinct_names(s.name for s in scenarios)  # one file or folder each
    for s in scenarios:  # refuse what cannot fit before the first run
        check_run_memory(s)
    inputs = tuple(args.scenario)
    claim_output_directory(args.out, inputs=inputs, force=args.force)
    command = "tetherheli simulate " + " ".join(args.scenario)
    results = [
        named_source(path, simulate, s, method=args.method)
        for path, s in zip(args.scenario, scenarios, strict=True)
    ]
    fmt = args.figure_format
    if len(results) == 1:
        write_run(
            results[0],
            args.out,
            command=command,
            inputs=inputs,
            force=args.force,
            data_format=args.data_format,
            figure_format=fmt,
        )
    else:
        write_comparison(
            results, args.out, command=command, inputs=inputs, force=args.force,
            data_format=args.data_format, figure_format=fmt,
        )  # fmt: skip
    for r in results:
        if r.released:
            print(f"tetherheli: run {r.name}: {r.release_note()}", file=sys.stderr)
    failed = [r for r in results if not r.ok]
    for r in failed:
        ended = "ended" if ran_to_end(r.status) else "stopped"
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


def _seconds_arg(what: str, high: float) -> Callable[[str], float]:
    """An argparse type: a time in (0, high] s, else one line naming ``what`` it must be."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: allowed: a number [s]") from None
        if not (math.isfinite(value) and 0 < value <= high):
            raise argparse.ArgumentTypeError(f"{text!r}: allowed: {what} in (0, {high:g}] s")
        return value

    return parse


_dt_arg = _seconds_arg("a sample time", 1.0)
_dt_arg_pulse = _seconds_arg("a duration", 20.0)


def _add_figure_format(p: argparse.ArgumentParser) -> None:
    from .viz.formats import FIGURE_FORMATS, PRINT_DPI

    p.add_argument(
        "--figure-format",
        choices=FIGURE_FORMATS,
        default="png",
        help=f"format of the figures: png ({PRINT_DPI} dpi, the default), or pdf or svg (vector)",
    )


def _add_force(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--force",
        action="store_true",
        help="write into an output directory that holds files tetherheli did not write "
        "(they are kept; only tetherheli's own files are ever replaced or removed)",
    )


def _add_format(p: argparse.ArgumentParser, what: str) -> None:
    """``--format csv|parquet`` of the time series (``sim.result.RESULT_FORMATS``)."""
    p.add_argument(
        "--format",
        dest="data_format",
        choices=("csv", "parquet"),
        default="csv",
        help=f"file format of {what}: csv (default) or parquet (needs pandas and pyarrow)",
    )


def _register_simulation(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("paper", help="the paper's four wind simulations, Figs. 6-9, report")
    p.add_argument("--out", default="paper_out", help="output directory (default paper_out)")
    p.add_argument("--dt", type=_dt_arg, default=0.01, help="controller sample time [s]")
    p.add_argument(
        "--pulse-duration",
        type=_dt_arg_pulse,
        default=1.0,
        help="duration of the 20 N pulse [s] (not stated in the paper; default 1)",
    )
    _add_format(p, "the time series <run>.csv")
    _add_figure_format(p)
    _add_force(p)
    p.set_defaults(func=_cmd_paper)

    p = sub.add_parser("simulate", help="run scenario TOML files (several: overlaid)")
    p.add_argument(
        "scenario",
        nargs="+",
        help="scenario TOML file(s) (see scenarios/); several runs go to OUT/<name>/ and are "
        "overlaid in OUT/outputs.png, OUT/inputs.png",
    )
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument(
        "--method",
        choices=("rk4", "adaptive"),
        default="rk4",
        help="integration: compiled fixed-step RK4 or the adaptive reference",
    )
    _add_format(p, "the time series <name>.csv")
    _add_figure_format(p)
    _add_force(p)
    p.set_defaults(func=_cmd_simulate)


def _cmd_animate(args: argparse.Namespace) -> int:
    from .viz.animation import animate, list_runs

    list_runs(args.result_dir)  # a missing folder is reported as such, before the output
    stems = args.runs.split(",") if args.runs else None
    output = Path(args.out) if args.out else Path(args.result_dir) / "animation.gif"
    path = animate(
        args.result_dir,
        output,
        stems=stems,
        fps=args.fps,
        speed=args.speed,
        max_frames=args.max_frames,
        progress=not args.quiet,
    )
    print(f"wrote {path}")
    return 0


def _cmd_sensing(args: argparse.Namespace) -> int:
    from .report import run_sensing

    table = run_sensing(
        args.out,
        scenarios=tuple(args.scenario) or None,
        force=args.force,
        figure_format=args.figure_format,
    )
    print(f"wrote {args.out}/ (sensing.{args.figure_format}, summary.json, time series)")
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
    return _report_failures(table, args.out)


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


def _cmd_sweep(args: argparse.Namespace) -> int:
    from ._io import claim_output_directory
    from .sim import load_scenario

    scenario = load_scenario(args.scenario)
    if args.controller is not None:  # every run under this controller (issue 14, item 3)
        from .studies.controllers import with_controller

        scenario = with_controller(scenario, args.controller)
    inputs = (args.scenario,)
    command = "tetherheli sweep " + " ".join(sys.argv[2:])
    if args.find_min is not None:
        return _find_min(args, scenario, inputs, command)
    from .studies.sweep import sweep, write_sweep

    metric = args.metric or "rms_q1"
    claim_output_directory(args.out, inputs=inputs, force=args.force)
    result = sweep(
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
    from ._io import claim_output_directory
    from .studies.cyclic_limit import minimum_cyclic_limit, write_limit_search

    if args.cyclic_limit is not None:
        from .errors import ParameterError

        raise ParameterError("--cyclic-limit", args.cyclic_limit, "not with --find-min")
    metric = args.metric or "peak_q1"
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


def _count_arg(name: str, low: int, high: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"{name} = {text!r}: allowed: an integer in [{low}, {high}]"
            )
        return value

    return parse


def _cmd_montecarlo(args: argparse.Namespace) -> int:
    import dataclasses

    from .errors import ClusterError
    from .sim.batch import connect, disconnect
    from .studies.montecarlo import CONFIGURATIONS, load_montecarlo, run_montecarlo
    from .studies.montecarlo.runner import check_nominal_designs, result_files

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
            inputs=(args.scenario,),
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

    from .viz.plots import metric_label

    m = args.metric
    unit = metric_label(m).rpartition("[")[2].rstrip("]")

    def value(v: float | None, spec: str = ".4g") -> str:
        return f"{v:{spec}}" if v is not None else "(among the failed runs)"

    failed = 0
    for cfg in CONFIGURATIONS:
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
    if m in summary["reduction_percent"]:
        r = summary["reduction_percent"][m]
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
    if failed:
        print(
            f"tetherheli: {failed} run{'s' if failed > 1 else ''} failed (status, message and "
            f"reason in {args.out}/results.{args.data_format}; in the percentiles a failed run "
            "counts as the worst value)",
            file=sys.stderr,
        )
    return 1 if failed and args.strict else 0


def _add_workers(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--workers",
        type=_count_arg("--workers", 1, 1024),
        help="threads running the simulations (default: all CPUs)",
    )


def _montecarlo_metrics() -> tuple[str, ...]:
    from .names import MONTECARLO_METRICS  # light: the command line's help builds no engine

    return MONTECARLO_METRICS


def _register_animate(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("animate", help="3-D animation (GIF/MP4) of the runs in a result folder")
    p.add_argument(
        "result_dir",
        help="folder written by 'tetherheli paper' or 'simulate' (one or several scenarios)",
    )
    p.add_argument("--out", help="output .gif or .mp4 (default RESULT_DIR/animation.gif)")
    p.add_argument("--runs", help="comma-separated run names (default: all in the folder)")
    p.add_argument(
        "--fps", type=_positive_float("--fps"), default=20.0, help="frames/s, at most 100"
    )
    p.add_argument(
        "--speed", type=_positive_float("--speed"), default=1.0, help="playback speed-up"
    )
    p.add_argument(
        "--max-frames",
        type=_count_arg("--max-frames", 1, 20_000),
        default=600,
        help="at most this many frames (a longer run is sampled more coarsely; default 600)",
    )
    p.set_defaults(func=_cmd_animate)

    p = sub.add_parser(
        "sweep",
        help="a metric against a parameter (e.g. Tref), or the smallest cyclic limit",
        description="A metric against a parameter (--param), or with --find-min "
        "actuators.cyclic_limit the smallest cyclic limit whose runs keep the metric (default "
        "peak_q1) within --within of the unlimited run's: a grid scan over --values, then "
        "bisection to --tol (exit 1 when none within the grid).",
    )
    p.add_argument("scenario", help="scenario TOML file")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument(
        "--find-min",
        choices=("actuators.cyclic_limit",),
        help="find the smallest value of this setting that meets the criterion",
    )
    which.add_argument(
        "--param",
        help="section.field of the parameters (e.g. tension_control.T_ref, "
        "tether.K_C, helicopter.d_O_P3), q9, control.dt, or an actuator setting "
        "(actuators.cyclic_limit, .time_constant, .reel_rate_limit, "
        ".reel_acceleration_limit, .breaking_tension)",
    )
    p.add_argument(
        "--values",
        type=_values_arg,
        required=True,
        help="START:STOP:N or a,b,c (with --find-min: the grid)",
    )
    p.add_argument(
        "--metric",
        default=None,
        help="rms_q1, peak_q1, ... (default rms_q1; with --find-min peak_q1)",
    )
    p.add_argument(
        "--cyclic-limit",
        type=_positive_float("--cyclic-limit"),
        default=None,
        help="saturate tMR1, tMR2 of every run at +- this [N m] and size eq 40's bound with it "
        "(default: the scenario's [actuators] limits; without any, the paper's 20%% rule sizes "
        "the bound only and the runs are not saturated)",
    )
    p.add_argument(
        "--within",
        type=_positive_float("--within"),
        default=0.10,
        help="--find-min: allowed relative increase of the metric over the unlimited run "
        "(default 0.10)",
    )
    p.add_argument(
        "--tol",
        type=_positive_float("--tol"),
        default=1e-3,
        help="--find-min: width of the reported interval [N m] (default 0.001)",
    )
    p.add_argument(
        "--controller",
        default=None,
        help="fly every run under this controller ([control] controller, e.g. tether_lqi; "
        "default: the scenario's)",
    )
    p.add_argument("--out", required=True, help="output directory")
    _add_workers(p)
    _add_figure_format(p)
    _add_force(p)
    p.set_defaults(func=_cmd_sweep)

    p = sub.add_parser(
        "montecarlo",
        help="Monte Carlo of a scenario, free against tethered",
        description="Monte Carlo of a scenario, free against tethered. Exit codes: 0 finished "
        "(failed runs are rows of results.csv), 1 a run failed with --strict or the Dask "
        "cluster was lost (resumable), 2 bad input, 3 stopped by --max-chunks (resumable).",
    )
    p.add_argument("scenario", help="scenario TOML file with a [montecarlo] table")
    p.add_argument("--out", required=True, help="output directory (resumable)")
    p.add_argument(
        "--runs", type=_count_arg("--runs", 1, 10_000_000), help="number of draws N (overrides)"
    )
    p.add_argument("--seed", type=_count_arg("--seed", 0, 2**63 - 1), help="root seed (overrides)")
    p.add_argument(
        "--chunk-size",
        type=_count_arg("--chunk-size", 1, 1_000_000),
        default=50,
        help="draws per resumable chunk file (default 50)",
    )
    _add_workers(p)
    p.add_argument(
        "--metric",
        choices=_montecarlo_metrics(),
        default="peak_q1",
        help="the metric of the figures (histogram, CDF, paired scatter; default peak_q1)",
    )
    p.add_argument(
        "--max-chunks",
        type=_count_arg("--max-chunks", 0, 10_000_000),
        help="compute at most this many new chunks, then stop with exit code 3 if the job is "
        "not finished (resume by running the same command again)",
    )
    p.add_argument(
        "--strict",
        action="store_true",
        help="exit 1 if any run failed (by default failed runs are rows of the table, exit 0)",
    )
    p.add_argument("--scheduler", help="run on a dask.distributed scheduler, e.g. tcp://host:8786")
    p.add_argument(
        "--connect-timeout",
        type=_positive_float("--connect-timeout"),
        default=10.0,
        help="seconds to wait for the scheduler, at the start and when it stops answering "
        "(default 10)",
    )
    p.add_argument(
        "--worker-timeout",
        type=_positive_float("--worker-timeout"),
        default=60.0,
        help="with --scheduler: give up (exit 1, resumable) when the cluster has had no worker "
        "for this many seconds (default 60)",
    )
    _add_format(p, "the results table results.csv")
    _add_figure_format(p)
    _add_force(p)
    p.set_defaults(func=_cmd_montecarlo)

    p = sub.add_parser("sensing", help="the tether as a GPS-free position sensor (Sec. IV-F)")
    p.add_argument("--out", default="sensing_out", help="output directory")
    p.add_argument(
        "--scenario",
        action="append",
        default=[],
        help="scenario with [sensors] (repeatable; default: the shipped sensing_*.toml)",
    )
    _add_figure_format(p)
    _add_force(p)
    p.set_defaults(func=_cmd_sensing)


_EXTRA_COMMANDS.append(_register_simulation)
_EXTRA_COMMANDS.append(_register_animate)


def _register_compare(sub: argparse._SubParsersAction) -> None:
    from .compare import register  # light: its heavy imports are inside the command

    register(sub)


_EXTRA_COMMANDS.append(_register_compare)


def _register_tether_study(sub: argparse._SubParsersAction) -> None:
    from .studies.tether_study import register  # light: its heavy imports are inside it

    register(sub)


_EXTRA_COMMANDS.append(_register_tether_study)


# --- shipped scenarios ------------------------------------------------------------------------


def _cmd_scenarios(args: argparse.Namespace) -> int:
    from .shipped import copy_scenario, shipped_scenarios

    if args.name is None:
        if args.out is not None:
            raise _UsageError("tetherheli scenarios: --out needs a scenario NAME")
        listing = shipped_scenarios()
        width = max(map(len, listing))
        for name, description in listing.items():
            print(f"{name:<{width}}  {description}")
        return 0
    if args.out is None:
        raise _UsageError(
            f"tetherheli scenarios: give --out PATH to copy {args.name} (e.g. "
            f"--out {args.name}.toml)"
        )
    path = copy_scenario(args.name, args.out)
    print(f"wrote {path}")
    return 0


def _register_scenarios(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "scenarios",
        help="list the shipped scenario files, or copy one out to edit",
        description="Without NAME: list the scenarios shipped with tetherheli. With NAME and "
        "--out: copy that scenario's TOML file to PATH (never over a file tetherheli did not "
        "write).",
    )
    p.add_argument("name", nargs="?", help="a shipped scenario's name (see the list)")
    p.add_argument("--out", help="file to write the scenario to (with NAME)")
    p.set_defaults(func=_cmd_scenarios)


_EXTRA_COMMANDS.append(_register_scenarios)
