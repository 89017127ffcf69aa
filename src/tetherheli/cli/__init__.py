"""The ``tetherheli`` command line (also ``python -m tetherheli``).

Exit codes: 0 success; 1 a run failed (reported, results written); 2 a user error (bad
parameter, scenario, argument or output path), printed as one line on stderr without a
traceback; 3 ``montecarlo --max-chunks`` stopped before the job was finished; 70 an internal
error (a bug: one line, ``--debug`` prints the traceback); 130 interrupted. A reader that
closes the pipe early (``tetherheli scenarios | head -1``) ends the command quietly, exit 0.

One module per command (``trim``, ``derive``, ``paper``, ``simulate``, ``animate``,
``view``, ``sweep``, ``montecarlo``, ``sensing``, ``compare``, ``tether_study``,
``scenarios``), each with ``register(sub)`` and ``run(args)``; the shared flags are parent
parsers in ``_common``. Building the parser imports neither the compiled engine nor Matplotlib.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import warnings
from collections.abc import Callable, Sequence

from .._version import __version__
from ..errors import TetherheliError
from . import (
    animate,
    compare,
    derive,
    montecarlo,
    paper,
    scenarios,
    sensing,
    simulate,
    sweep,
    tether_study,
    trim,
    view,
)
from ._common import Parser, UsageError, common, plain
from .montecarlo import EXIT_STOPPED

__all__ = [
    "EXIT_INTERNAL",
    "EXIT_INTERRUPTED",
    "EXIT_STOPPED",
    "EXIT_USAGE",
    "guarded",
    "main",
]

EXIT_USAGE = 2
EXIT_INTERNAL = 70  # sysexits' EX_SOFTWARE
EXIT_INTERRUPTED = 130

#: The commands, in the order ``tetherheli --help`` lists them.
COMMANDS = (
    trim, derive, paper, simulate, animate, view, sweep, montecarlo, sensing, compare, tether_study,
    scenarios,
)  # fmt: skip


def build_parser() -> Parser:
    """The whole command line: every command of ``COMMANDS`` with its flags.

    Returns
    -------
    Parser
        The top-level parser (``parse_args`` gives ``func``, the command's ``run``).
    """
    parser = Parser(prog="tetherheli", description=plain(__doc__.splitlines()[0]))
    parser.add_argument("--version", action="version", version=f"tetherheli {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    shared = common()
    add_parser = sub.add_parser

    def add_with_common(name: str, **kwargs):
        kwargs["parents"] = [*kwargs.get("parents", ()), shared]
        return add_parser(name, **kwargs)

    sub.add_parser = add_with_common  # type: ignore[method-assign]
    for command in COMMANDS:
        command.register(sub)
    return parser


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
    from ..resources import SlowJobWarning

    if issubclass(category, SlowJobWarning):
        print(f"tetherheli: warning: {message}", file=sys.stderr)
    else:
        sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


def _main(argv: list[str], debug: bool) -> int:
    def command() -> int:
        try:
            args = build_parser().parse_args(argv)
        except SystemExit as exc:  # --help, --version: printed; flush while we can catch
            sys.stdout.flush()
            return exc.code if isinstance(exc.code, int) else 0
        return int(args.func(args) or 0)

    return guarded(command, debug=debug)


def guarded(
    call: Callable[[], int | None], *, debug: bool = False, prog: str = "tetherheli"
) -> int:
    """Run ``call`` as a command: its exit code, or the error turned into one line on stderr
    and its exit code (the module docstring's). The commands and the repository's scripts
    (``tetherheli._script``) refuse alike.

    Parameters
    ----------
    call : callable
        The command's work; returns its exit code (None: 0).
    debug : bool, optional
        Print the traceback of an internal error.
    prog : str, optional
        The name in front of the messages (``"tetherheli"``, or a script's).

    Returns
    -------
    int
        The exit code: ``call``'s, ``EXIT_USAGE`` (2) for a user error (``UsageError``,
        ``TetherheliError``, an OSError about a user's path), ``EXIT_INTERNAL`` (70) for
        anything else, ``EXIT_INTERRUPTED`` (130).
    """
    try:
        code = int(call() or 0)
        sys.stdout.flush()  # a closed pipe (``| head -1``) surfaces here, not at exit
        return code
    except BrokenPipeError:  # the reader of stdout has gone (``| head -1``): end quietly
        _drop_stdout()
        return 0
    except UsageError as exc:
        print(str(exc), file=sys.stderr)
        return EXIT_USAGE
    except TetherheliError as exc:
        print(f"{prog}: error: {_first_line(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        if exc.filename is None or debug:  # not about a user's path: a fault of ours
            return _internal_error(exc, debug, prog)
        print(f"{prog}: error: {exc.filename}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:
        return _internal_error(exc, debug, prog)


def _drop_stdout() -> None:
    """Point stdout at the null device after its reader closed the pipe, so that the
    interpreter's final flush does not fail again ("Exception ignored ... BrokenPipeError")."""
    with contextlib.suppress(OSError, ValueError, io.UnsupportedOperation):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def _internal_error(exc: BaseException, debug: bool, prog: str = "tetherheli") -> int:
    if debug:
        import traceback

        traceback.print_exception(exc)
    print(
        f"{prog}: internal error ({type(exc).__name__}: "
        f"{_first_line(exc)}); this is a bug: please report it with the output of the same "
        "command with --debug",
        file=sys.stderr,
    )
    return EXIT_INTERNAL
