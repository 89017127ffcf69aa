"""The ``tetherheli`` command line (also ``python -m tetherheli``).

Every user error (bad parameter, scenario or argument) is printed as one line on stderr and
exits with code 2, without a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from . import __version__
from .errors import TetherheliError
from .params import Params

__all__ = ["main"]

EXIT_USAGE = 2


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(f"{self.prog}: {message}")


class _UsageError(Exception):
    pass


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
    values.update(zip(("q1", "q2", "q3", "q6"), trim.y, strict=True))
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
    from .model.codegen import GENERATED_PATH, generate_source

    text = generate_source()
    target = Path(args.output) if args.output else GENERATED_PATH
    if args.check:
        current = target.read_text() if target.exists() else ""
        if current != text:
            print(f"tetherheli derive: {target} differs from a fresh derivation", file=sys.stderr)
            return 1
        print(f"{target} matches a fresh derivation")
        return 0
    tmp = target.with_suffix(target.suffix + ".tmp")
    tmp.write_text(text)
    tmp.replace(target)
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
    parser = _Parser(prog="tetherheli", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"tetherheli {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

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
    p.add_argument("--output", help="where to write (default: the package's _generated.py)")
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


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        return int(args.func(args) or 0)
    except _UsageError as exc:
        print(str(exc), file=sys.stderr)
        return EXIT_USAGE
    except (TetherheliError, ValueError, OSError) as exc:
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"tetherheli: error: {message}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("tetherheli: interrupted", file=sys.stderr)
        return 130
