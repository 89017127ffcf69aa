"""What the commands share: the parser class, the help formatter, the argument types, and
one parent parser per shared flag (``--out``, ``--force``, ``--quiet``, ``--debug``,
``--workers``, ``--seed``, ``--format``, ``--figure-format``), each with one help text.

Light by design: building the parser (``tetherheli --help``) imports neither the compiled
engine nor Matplotlib; a command's heavy imports sit inside its ``run``.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..scenario.core import Scenario

__all__ = [
    "Formatter",
    "Parser",
    "UsageError",
    "common",
    "count_arg",
    "data_format",
    "figure_format",
    "force",
    "metric",
    "number_arg",
    "out_directory",
    "plain",
    "positive_float",
    "report_failures",
    "result_runs",
    "run_selection",
    "runs",
    "scenario_inputs",
    "seconds_arg",
    "seed",
    "workers",
]

#: The shared flags' help texts, one each (``tests/test_cli_grammar.py`` holds every command
#: to them). The formatter appends the default (``Formatter``).
HELP = {
    "--out": "output directory (created with its parents if missing)",
    "--force": "write into an output directory that holds files tetherheli did not write "
    "(they are kept; only tetherheli's own files are ever replaced or removed)",
    "--quiet": "no progress on stderr (no bar on a terminal, no summary line in a log); "
    "warnings and errors are still printed",
    "--debug": "print the traceback of an internal error",
    "--workers": "threads running the simulations (default: all CPUs)",
    "--seed": "root seed of the random draws (default: the file's [montecarlo] seed)",
    "--runs": "Monte Carlo draws N (default: the file's [montecarlo] runs)",
    "--format": "file format of the tables (time series, results): csv, or parquet (needs "
    "pandas and pyarrow); a run's time series also mcap (needs mcap: the signals and a 3-D "
    "scene for Foxglove)",
    "--metric": "the metric reported and plotted: a peak or RMS deviation from the trim "
    "(peak_q1, rms_q1, ...: m; peak_q4_deg, peak_q5_deg: deg) or a tension (N)",
    "--figure-format": (
        "format of the figures: png (raster, {dpi} dpi or Matplotlib's savefig.dpi), or pdf "
        "or svg (vector)"
    ),
}


class UsageError(Exception):
    """A wrong command line: printed as one line, exit code 2."""


class Formatter(argparse.HelpFormatter):
    """argparse's help, with every option's default stated: " (default: X)" is appended to a
    help text that does not already say its default, " (required)" to a required option."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if not action.option_strings or "default" in text:
            return text
        if action.required:
            return f"{text} (required)"
        default = action.default
        if default is None or default is False or default is argparse.SUPPRESS:
            return text
        if isinstance(default, list | tuple):
            return (
                text
                + " (default: "
                + ",".join(f"{v:g}" if isinstance(v, float) else str(v) for v in default)
                + ")"
            )
        return f"{text} (default: %(default)s)"


class Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line and exit code 2, with ``Formatter``."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("formatter_class", Formatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{self.prog}: {message}")


def plain(text: str) -> str:
    """``text`` without reStructuredText markup (double backquotes), for ``--help``.

    Parameters
    ----------
    text : str
        A docstring's line.

    Returns
    -------
    str
    """
    return text.replace("``", "")


# --- argument types: a bad value is one line naming the flag, its value and what is allowed ---


def positive_float(name: str) -> Callable[[str], float]:
    """An argparse type: a finite number >= 0.

    Parameters
    ----------
    name : str
        The flag, for the message.

    Returns
    -------
    callable
        Text -> float, raising ``argparse.ArgumentTypeError``.
    """

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: allowed: a number") from None
        if not math.isfinite(value) or value < 0:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: allowed: a finite number >= 0")
        return value

    return parse


def number_arg(name: str, low: float, high: float) -> Callable[[str], float]:
    """An argparse type: a finite number in [low, high].

    Parameters
    ----------
    name : str
        The flag, for the message.
    low, high : float
        The allowed range, both ends included.

    Returns
    -------
    callable
        Text -> float, raising ``argparse.ArgumentTypeError``.
    """

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and low <= value <= high):
            raise argparse.ArgumentTypeError(
                f"{name} = {text!r}: allowed: a number in [{low:g}, {high:g}]"
            )
        return value

    return parse


def count_arg(name: str, low: int, high: int) -> Callable[[str], int]:
    """An argparse type: an integer in [low, high].

    Parameters
    ----------
    name : str
        The flag, for the message.
    low, high : int
        The allowed range, both ends included.

    Returns
    -------
    callable
        Text -> int, raising ``argparse.ArgumentTypeError``.
    """

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


def seconds_arg(what: str, high: float) -> Callable[[str], float]:
    """An argparse type: a time in (0, high] s.

    Parameters
    ----------
    what : str
        What the time is ("a sample time"), for the message.
    high : float
        The largest allowed value [s].

    Returns
    -------
    callable
        Text -> float, raising ``argparse.ArgumentTypeError``.
    """

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: allowed: a number [s]") from None
        if not (math.isfinite(value) and 0 < value <= high):
            raise argparse.ArgumentTypeError(f"{text!r}: allowed: {what} in (0, {high:g}] s")
        return value

    return parse


def scenario_inputs(paths: Sequence[str], scenarios: Iterable[Scenario]) -> tuple[str, ...]:
    """The inputs of a run that ``--out`` must not hold or lie in (``_io``'s output rules):
    the scenario files given and every file they name (``Scenario.input_files``, a base's
    track), all protected alike.

    Parameters
    ----------
    paths : sequence of str
        The scenario (or Monte Carlo) files on the command line.
    scenarios : iterable of Scenario
        The scenarios they hold.

    Returns
    -------
    tuple of str
        Each input once, the given files first.
    """
    named = [path for s in scenarios for path in s.input_files]
    return tuple(dict.fromkeys([*paths, *named]))


# --- the shared flags, one parent parser each ------------------------------------------------


def _parent() -> argparse.ArgumentParser:
    return Parser(add_help=False)


def common() -> argparse.ArgumentParser:
    """``--debug`` and ``--quiet``, which every command takes.

    Returns
    -------
    argparse.ArgumentParser
        A parent parser (``parents=[...]``).
    """
    p = _parent()
    p.add_argument("--debug", action="store_true", help=HELP["--debug"])
    p.add_argument("--quiet", action="store_true", help=HELP["--quiet"])
    return p


def out_directory(default: str | None = None) -> argparse.ArgumentParser:
    """``--out DIR``, the output directory; required when there is no ``default``.

    Parameters
    ----------
    default : str, optional
        The directory written without ``--out``; None: ``--out`` is required.

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    p = _parent()
    p.add_argument(
        "--out", metavar="DIR", default=default, required=default is None, help=HELP["--out"]
    )
    return p


def force() -> argparse.ArgumentParser:
    """``--force``: write into a directory that holds foreign files (they are kept).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    p = _parent()
    p.add_argument("--force", action="store_true", help=HELP["--force"])
    return p


def workers() -> argparse.ArgumentParser:
    """``--workers N``: the threads running the simulations (default all CPUs).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    p = _parent()
    p.add_argument("--workers", type=count_arg("--workers", 1, 1024), help=HELP["--workers"])
    return p


def seed() -> argparse.ArgumentParser:
    """``--seed N``: the root seed of a Monte Carlo's draws (overrides the file's).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    p = _parent()
    p.add_argument("--seed", type=count_arg("--seed", 0, 2**63 - 1), help=HELP["--seed"])
    return p


def result_runs() -> argparse.ArgumentParser:
    """``RESULT_DIR`` and ``--runs A,B``: the saved runs a picture draws (``animate``,
    ``view``; ``run_selection`` reads them).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    p = _parent()
    p.add_argument(
        "result_dir",
        help="folder written by 'tetherheli paper' or 'simulate' (one or several scenarios)",
    )
    p.add_argument("--runs", help="comma-separated run names (default: all in the folder)")
    return p


def run_selection(args: argparse.Namespace, default_name: str) -> tuple[list[str] | None, Path]:
    """The runs ``result_runs`` selects and the output file: the folder checked first (a
    missing one is reported as such, before the output), ``--runs`` split (None: all), and
    ``--out`` or ``RESULT_DIR/default_name``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``result_dir``, ``runs``, ``out``).
    default_name : str
        The output's file name in the result folder without ``--out``.

    Returns
    -------
    (list of str or None, pathlib.Path)
        The run names (None: every run of the folder) and the output file.
    """
    from ..viz.run_data import list_runs

    list_runs(args.result_dir)
    stems = args.runs.split(",") if args.runs else None
    output = Path(args.out) if args.out else Path(args.result_dir) / default_name
    return stems, output


def runs() -> argparse.ArgumentParser:
    """``--runs N``: the number of Monte Carlo draws (overrides the file's); the command
    checks it against ``studies.montecarlo.config.MAX_RUNS`` (which imports the engine).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    p = _parent()
    p.add_argument("--runs", type=int, help=HELP["--runs"])
    return p


def metric(choices: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """``--metric NAME``, the metric a command reports and plots; one default for every
    command (``names.DEFAULT_METRIC``).

    Parameters
    ----------
    choices : sequence of str, optional
        The metrics the command takes (None: the command checks the name).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    from ..names import DEFAULT_METRIC

    p = _parent()
    p.add_argument("--metric", choices=choices, default=DEFAULT_METRIC, help=HELP["--metric"])
    return p


def data_format(*, runs: bool = True) -> argparse.ArgumentParser:
    """``--format csv|parquet|mcap``, the time series' file format
    (``results.result.RESULT_FORMATS``), or ``--format csv|parquet`` for a table of many runs
    (``runs=False``: ``TABLE_FORMATS``).

    Parameters
    ----------
    runs : bool, optional
        The command writes runs (True), or one table of many runs' results (False).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    from ..results.result import RESULT_FORMATS, TABLE_FORMATS  # light: numpy only

    formats = RESULT_FORMATS if runs else TABLE_FORMATS
    p = _parent()
    p.add_argument(
        "--format",
        dest="data_format",
        choices=formats,
        default=formats[0],
        help=HELP["--format"],
    )
    return p


def figure_format() -> argparse.ArgumentParser:
    """``--figure-format png|pdf|svg`` (``viz.formats``, without Matplotlib).

    Returns
    -------
    argparse.ArgumentParser
        A parent parser.
    """
    from ..viz.formats import FIGURE_FORMATS, PRINT_DPI

    p = _parent()
    p.add_argument(
        "--figure-format",
        choices=FIGURE_FORMATS,
        default=FIGURE_FORMATS[0],
        help=HELP["--figure-format"].format(dpi=PRINT_DPI),
    )
    return p


def report_failures(statuses: dict, out: str) -> int:
    """One line on stderr per failed run of ``statuses`` (``report.run_status`` records).

    Parameters
    ----------
    statuses : dict
        Run name -> its status record (``completed``, ``end_time``, ``message``).
    out : str
        The output directory, named in the message.

    Returns
    -------
    int
        The exit code: 1 if any run failed, else 0.
    """
    failed = {k: st for k, st in statuses.items() if not st["completed"]}
    for k, st in failed.items():
        print(
            f"tetherheli: run {k} failed at t = {st['end_time']:g} s: {st['message']} "
            f"(partial results in {out})",
            file=sys.stderr,
        )
    return 1 if failed else 0
