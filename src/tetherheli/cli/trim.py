"""``tetherheli trim``: the hover trim of Tables IV and V, printed (or as JSON)."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

from ._common import positive_float

__all__ = ["register", "run"]

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
    # the trim alone (model.trim), not the model class: no compiled kernels, no Numba
    from ..model.trim import hover_trim
    from ..names import INPUT, OUTPUT, TETHERED_STATE
    from ..params import Params

    params = Params.from_toml(args.params) if args.params else Params.paper()
    trim = hover_trim(params, args.tension, args.q9)
    values = dict(zip(TETHERED_STATE, trim.x, strict=True))
    values.update(zip(OUTPUT, trim.y, strict=True))
    values.update(zip(INPUT, trim.u, strict=True))
    values["tMR1_total"] = trim.t_MR1_total
    values["LN"] = float(trim.x[12])
    values["TC"] = trim.tension
    return values


def run(args: argparse.Namespace) -> int:
    """Print the trim of ``args`` (Table IV for TC = 0, else Table V's layout).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``--tension``, ``--q9``, ``--params``, ``--json``).

    Returns
    -------
    int
        The exit code, 0.
    """
    from .._io import json_text
    from .._version import __version__

    values = _trim_values(args)
    if args.json:
        si = {k: float(v) for k, v in values.items()}
        document = {
            "tension": args.tension,
            "q9": args.q9,
            "trim": si,
            "units": "SI (rad, m, N, N m)",
            "version": __version__,
        }
        print(json_text(document))
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


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``trim`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser("trim", help="hover trim (Tables IV and V)")
    p.add_argument(
        "--tension",
        type=positive_float("--tension"),
        default=0.0,
        help="tether tension TC [N] (0: free configuration, Table IV)",
    )
    p.add_argument("--q9", type=positive_float("--q9"), default=10.0, help="tether length [m]")
    p.add_argument(
        "--params",
        help="TOML file overriding the paper's parameters (default: the paper's, Tables II-III)",
    )
    p.add_argument("--json", action="store_true", help="machine-readable output (SI units)")
    p.set_defaults(func=run)
