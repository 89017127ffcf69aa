"""Input validation: one style for every entry point (parameters, scenarios, winds, sensors,
actuators, the Monte Carlo table, the environment, the animation).

A number is a Python or NumPy real scalar (``int``, ``float``, ``np.integer``, ``np.floating``),
never a bool; an integer is a Python or NumPy integer, never a bool or a float. Every failure
is one ``ParameterError`` line naming the field, the value and what is allowed, and the
allowed text is the same whichever check failed (type, finiteness or range).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .errors import ParameterError

__all__ = [
    "check_bool",
    "check_integer",
    "check_number",
    "check_vector",
    "describe",
    "is_integer",
    "is_real",
]


def is_real(value: object) -> bool:
    """True for a real scalar (Python or NumPy), False for bools and everything else."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )


def is_integer(value: object) -> bool:
    """True for an integer scalar (Python or NumPy), False for bools and floats."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def _range(
    low: float | None, high: float | None, low_open: bool, high_open: bool, unit: str
) -> str:
    if low is not None and high is not None:
        text = f" in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
    elif low is not None:
        text = f" {'>' if low_open else '>='} {low:g}"
    elif high is not None:
        text = f" {'<' if high_open else '<='} {high:g}"
    else:
        text = ""
    return text + (f" {unit}" if unit else "")


def describe(
    *,
    integer: bool = False,
    finite: bool = True,
    nonzero: bool = False,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    unit: str = "",
) -> str:
    """The allowed text of a check, e.g. ``"a finite number > 0"``, ``"an integer in [1, 10]"``,
    ``"a number > 0 (inf: none)"``."""
    if integer:
        kind = "an integer"
    else:
        kind = "a " + ("nonzero " if nonzero else "") + ("finite number" if finite else "number")
    text = kind + _range(low, high, low_open, high_open, unit)
    if not finite:
        text += " (inf: none)"
    return text


def _in_range(
    x: float, low: float | None, high: float | None, low_open: bool, high_open: bool
) -> bool:
    if low is not None and (x <= low if low_open else x < low):
        return False
    return high is None or (x < high if high_open else x <= high)


def check_number(
    field: str,
    value: Any,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    finite: bool = True,
    nonzero: bool = False,
    unit: str = "",
    allowed: str | None = None,
    source: str | None = None,
) -> float:
    """``value`` as a float: a real number, finite (``finite=False``: +-inf allowed, NaN never),
    nonzero if asked, within [low, high] (``low_open``/``high_open``: exclusive); else
    ParameterError naming ``field`` with ``allowed`` (default: ``describe`` of the check)."""
    x = float(value) if is_real(value) else math.nan
    ok = (
        not math.isnan(x)
        and (math.isfinite(x) or not finite)
        and not (nonzero and x == 0.0)
        and _in_range(x, low, high, low_open, high_open)
    )
    if not ok:
        if allowed is None:
            allowed = describe(
                finite=finite,
                nonzero=nonzero,
                low=low,
                high=high,
                low_open=low_open,
                high_open=high_open,
                unit=unit,
            )
        raise ParameterError(field, value, allowed, source=source)
    return x


def check_integer(
    field: str,
    value: Any,
    *,
    low: int | None = None,
    high: int | None = None,
    allowed: str | None = None,
    source: str | None = None,
) -> int:
    """``value`` as an int: an integer (Python or NumPy) within [low, high]; else
    ParameterError naming ``field``."""
    if not is_integer(value) or not _in_range(int(value), low, high, False, False):
        raise ParameterError(
            field, value, allowed or describe(integer=True, low=low, high=high), source=source
        )
    return int(value)


def check_vector(
    field: str,
    value: Any,
    n: int,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    finite: bool = True,
    nonzero: bool = False,
    unit: str = "",
    allowed: str | None = None,
    source: str | None = None,
) -> tuple[float, ...]:
    """``value`` (list, tuple or array of shape (n,)) as a tuple of n floats, each as for
    ``check_number`` (``nonzero``: the vector, not each entry); else ParameterError naming
    ``field`` with the whole value."""
    if allowed is None:
        numbers = "finite numbers" if finite else "numbers"
        allowed = (
            f"{'a nonzero vector of ' if nonzero else ''}{n} {numbers}"
            + _range(low, high, low_open, False, unit)
            + ("" if finite else " (inf allowed)")
        )
    items = value.tolist() if isinstance(value, np.ndarray) else value
    if not isinstance(items, (list, tuple)) or len(items) != n:
        raise ParameterError(field, value, allowed, source=source)
    try:
        out = tuple(
            check_number(field, v, low=low, high=high, low_open=low_open, finite=finite)
            for v in items
        )
    except ParameterError:
        raise ParameterError(field, value, allowed, source=source) from None
    if nonzero and not any(out):
        raise ParameterError(field, value, allowed, source=source)
    return out


def check_bool(field: str, value: Any, *, source: str | None = None) -> bool:
    """``value`` if it is a bool (Python or NumPy), else ParameterError naming ``field``."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(field, value, "true or false", source=source)
    return bool(value)
