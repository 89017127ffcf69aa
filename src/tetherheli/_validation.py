"""Input validation: one style for every entry point (parameters, scenarios, winds, sensors,
actuators, the Monte Carlo table, the environment, the animation).

A number is a Python or NumPy real scalar (``int``, ``float``, ``np.integer``, ``np.floating``),
never a bool; an integer is a Python or NumPy integer, never a bool or a float. Every failure
is one ``ParameterError`` line naming the field, the value and what is allowed, and the
allowed text is the same whichever check failed (type, finiteness or range).

Input is checked once, where it enters (a ``Scenario``, the arguments of a public function or
class); code that builds objects from numbers already checked trusts them: it calls a
function's private twin that skips the checks (``hover_trim`` checks, then calls
``_hover_trim``), and builds a checked dataclass with ``trusted``: a run's set-up repeats no
check.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, TypeGuard, TypeVar

import numpy as np

from ._io import NONFINITE_JSON
from .errors import ParameterError

__all__ = [
    "MAX_SAMPLES",
    "RK4_SUBSTEPS",
    "Key",
    "check_bool",
    "check_integer",
    "check_number",
    "check_samples",
    "check_vector",
    "describe",
    "is_integer",
    "is_real",
    "trusted",
]

_T = TypeVar("_T")


def is_real(value: object) -> bool:
    """True for a real scalar (Python or NumPy), False for bools and everything else."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )


def is_integer(value: object) -> TypeGuard[int | np.integer]:
    """True for an integer scalar (Python or NumPy), False for bools and floats."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def trusted(cls: type[_T], **values: Any) -> _T:
    """An instance of the frozen dataclass ``cls`` built from values already checked, without
    its ``__post_init__`` checks: the fields not given take their defaults, then the
    instance's ``_derive()``, if it has one, fills what follows from the fields (derived
    arrays, a default that depends on another field), as ``__post_init__`` does after its
    checks.

    The values must be those ``__post_init__`` would store (plain floats, ints, tuples), e.g.
    a ``Scenario``'s fields, which were checked when it was built.

    Parameters
    ----------
    cls : type
        A dataclass.
    **values
        Field name -> checked value.

    Returns
    -------
    object
        The instance of ``cls``.

    Raises
    ------
    TypeError
        A name that is not a field of ``cls``, or a field without a default left out.
    """
    obj = object.__new__(cls)
    for f in dataclasses.fields(cls):  # type: ignore[arg-type]
        if f.name in values:
            value = values.pop(f.name)
        elif f.default is not dataclasses.MISSING:
            value = f.default
        elif f.default_factory is not dataclasses.MISSING:
            value = f.default_factory()
        elif not f.init:  # set by _derive
            continue
        else:
            raise TypeError(f"{cls.__name__}: no value for the field {f.name!r}")
        object.__setattr__(obj, f.name, value)
    if values:
        raise TypeError(f"{cls.__name__}: no fields {sorted(values)}")
    derive = getattr(obj, "_derive", None)
    if derive is not None:
        derive()
    return obj


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
    try:
        x = float(value) if is_real(value) else math.nan
    except OverflowError:  # an int beyond the floats, e.g. 10**400
        x = math.nan
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


@dataclass(frozen=True)
class Key:
    """One configuration key described once: its documentation, unit and allowed values.

    The validation checks a value with ``check`` and the scenario reference
    (``docs/scenario_reference.md``, written by ``tetherheli.scenario.reference``) prints ``doc``,
    ``unit`` and ``allowed()``, so the documented range is the checked one.

    Parameters
    ----------
    doc : str
        What the key means (with the paper's equation or section where it has one).
    unit : str, optional
        The unit, e.g. ``"s"``, ``"N m"`` (empty: dimensionless or not a number).
    kind : {"number", "integer", "bool", "vector", "list", "points", "text"}, optional
        The value's type; ``"vector"`` is ``length`` numbers, ``"list"`` at most ``length``,
        ``"points"`` a list of 1 to ``length`` points of 3 numbers each.
    low, high : float, optional
        Bounds of a number, an integer or each entry of a vector (None: unbounded).
    low_open, high_open : bool, optional
        Whether the bounds are excluded.
    finite : bool, optional
        False: +-inf is allowed (NaN never).
    nonzero : bool, optional
        True: 0 is refused (a number).
    length : int, optional
        The number of entries of a vector.
    choices : tuple of str, optional
        The allowed values of a text key (empty: any string).
    note : str, optional
        A rule the range alone does not state (a bound set by another key), shown in the
        reference after the range.
    unset : str, optional
        When given, the key may be left unset (None; absent from a TOML file), and this says
        what then holds (a default that follows another key, e.g. ``"[T_ref/2, 1.5 T_ref]"``).
    """

    doc: str
    unit: str = ""
    kind: str = "number"
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    finite: bool = True
    nonzero: bool = False
    length: int = 0
    choices: tuple[str, ...] = ()
    note: str = ""
    unset: str = ""

    def _unit(self) -> str:
        return f"[{self.unit}]" if self.unit else ""

    def allowed(self) -> str:
        """The allowed values as the error messages state them, e.g. ``"a finite number
        > 0 [s]"``.

        Returns
        -------
        str
        """
        text = self._allowed()
        return f"{text} or unset ({self.unset})" if self.unset else text

    def _allowed(self) -> str:
        if self.kind == "bool":
            return "true or false"
        if self.kind == "text":
            if self.choices:
                return "one of " + ", ".join(map(repr, self.choices))
            return "a string other than " + ", ".join(map(repr, NONFINITE_JSON))
        if self.kind == "points":
            return f"a list of 1 to {self.length} points of 3 finite numbers" + _range(
                self.low, self.high, self.low_open, self.high_open, self._unit()
            )
        if self.kind in ("vector", "list"):
            numbers = "finite numbers" if self.finite else "numbers"
            return (
                ("a list of at most " if self.kind == "list" else "")
                + f"{self.length} {numbers}"
                + _range(self.low, self.high, self.low_open, self.high_open, self._unit())
                + ("" if self.finite else " (inf allowed)")
            )
        return describe(
            integer=self.kind == "integer",
            finite=self.finite,
            nonzero=self.nonzero,
            low=self.low,
            high=self.high,
            low_open=self.low_open,
            high_open=self.high_open,
            unit=self._unit(),
        )

    def check(self, field: str, value: Any, *, source: str | None = None, **bounds: Any) -> Any:
        """``value`` checked against this key (``check_number``, ``check_integer``,
        ``check_vector`` or ``check_bool`` by ``kind``).

        Parameters
        ----------
        field : str
            The key's dotted name, put in the error message.
        value : object
            The value to check.
        source : str, optional
            Where the value came from (a file name), put in front of the message.
        **bounds
            Overrides of ``low``, ``high``, ``low_open``, ``high_open`` for a bound that
            depends on another key (``note``).

        Returns
        -------
        float, int, bool, str, tuple of float or None
            The checked value as plain Python data (None: unset, where ``unset`` allows it).

        Raises
        ------
        ParameterError
            The value is of the wrong type or outside the allowed range.
        """
        low = bounds.get("low", self.low)
        high = bounds.get("high", self.high)
        low_open = bounds.get("low_open", self.low_open)
        high_open = bounds.get("high_open", self.high_open)
        if value is None and self.unset:
            return None
        allowed = self.allowed() if self.unset else None  # the message names "unset" too
        if self.kind == "bool":
            return check_bool(field, value, source=source)
        if self.kind == "text":
            if (
                not isinstance(value, str)
                or (self.choices and value not in self.choices)
                or value in NONFINITE_JSON  # JSON files write non-finite numbers so
            ):
                raise ParameterError(field, value, self.allowed(), source=source)
            return value
        if self.kind == "integer":
            return check_integer(field, value, low=low, high=high, source=source)
        if self.kind == "points":
            if not isinstance(value, (list, tuple)) or not 1 <= len(value) <= self.length:
                raise ParameterError(field, value, self.allowed(), source=source)
            return tuple(
                check_vector(f"{field}[{i}]", point, 3, low=low, high=high, low_open=low_open,
                             unit=self._unit(), source=source)
                for i, point in enumerate(value)
            )  # fmt: skip
        if self.kind == "list":
            items = value.tolist() if isinstance(value, np.ndarray) else value
            if not isinstance(items, (list, tuple)) or len(items) > self.length:
                raise ParameterError(field, value, self.allowed(), source=source)
            return check_vector(
                field, items, len(items), low=low, high=high, low_open=low_open,
                finite=self.finite, unit=self._unit(), allowed=self.allowed(), source=source,
            )  # fmt: skip
        if self.kind == "vector":
            return check_vector(
                field, value, self.length, low=low, high=high, low_open=low_open,
                finite=self.finite, unit=self._unit(), allowed=allowed, source=source,
            )  # fmt: skip
        return check_number(
            field, value, low=low, high=high, low_open=low_open, high_open=high_open,
            finite=self.finite, nonzero=self.nonzero, unit=self._unit(), allowed=allowed,
            source=source,
        )  # fmt: skip


#: The most control samples one run may have (about 12 days at dt = 1 ms, 115 days at 10 ms):
#: a scenario's duration / control.dt and ``tether.drive_cable``'s duration / dt alike.
MAX_SAMPLES = 1_000_000_000


def check_samples(
    duration: float, dt: float, *, dt_field: str = "dt", source: str | None = None
) -> int:
    """The number of sample intervals floor(duration / dt) of a run of checked ``duration``
    and ``dt`` (both > 0), refused above ``MAX_SAMPLES`` before anything is sized from it
    (a tiny dt makes it overflow an integer): ParameterError naming ``duration``.

    Parameters
    ----------
    duration : float
        The run's length [s], > 0.
    dt : float
        The sample time [s], > 0.
    dt_field : str, optional
        The sample time's name in the message (``"control.dt"`` in a scenario).
    source : str, optional
        Where the values came from (a file name), put in front of the message.

    Returns
    -------
    int
        floor(duration / dt) (to 1e-9 of a sample), at most ``MAX_SAMPLES``.

    Raises
    ------
    ParameterError
        More than ``MAX_SAMPLES`` samples.
    """
    ratio = duration / dt
    if not ratio <= MAX_SAMPLES:
        raise ParameterError(
            "duration",
            duration,
            f"at most {MAX_SAMPLES:.0e} control samples (duration / {dt_field}; dt = {dt} s)",
            source=source,
        )
    return math.floor(ratio + 1e-9)


#: The engine's RK4 steps per control sample (``[control] substeps``, ``tether.drive_cable``'s
#: ``substeps``): each step is a pass of the compiled loop, so their count is bounded.
RK4_SUBSTEPS = Key("RK4 steps per control sample", kind="integer", low=1, high=1000)
