"""Error types. Every user-facing error is a one-line message naming the field, the value and
what is allowed; the CLI prints it on stderr and exits with code 2 (``ClusterError``, a failure
while running rather than bad input, exits 1)."""

from __future__ import annotations

import reprlib
from collections.abc import Callable
from typing import Any

#: The longest value a message shows whole; a longer one (or one nested too deep for
#: ``repr``) is shortened by ``reprlib`` to its first items and levels.
_MAX_VALUE_CHARS = 240


def shown_value(value: object) -> str:
    """``repr(value)`` for a message: whole up to ``_MAX_VALUE_CHARS``, else shortened (a
    value from input can be megabytes long or nested thousands of levels deep).

    Parameters
    ----------
    value : object
        The value refused.

    Returns
    -------
    str
        Its representation on one line.
    """
    try:
        text = repr(value)
    except RecursionError:
        text = None
    if text is None or len(text) > _MAX_VALUE_CHARS:
        short = reprlib.Repr()
        short.maxlevel = 3
        short.maxstring = short.maxother = 80
        short.maxlist = short.maxtuple = short.maxdict = short.maxset = 10
        text = short.repr(value)
    return text.replace("\n", " ")


class TetherheliError(ValueError):
    """Base of the package's user-facing errors (a ValueError, so callers may catch either)."""


class ParameterError(TetherheliError):
    """An invalid parameter, scenario value or configuration field.

    The message is one line, ``"[source: ]field = value is invalid; allowed: allowed"``.

    Parameters
    ----------
    field : str
        The field's dotted name, e.g. ``"control.dt"``.
    value : object
        The value refused.
    allowed : str
        What is allowed, e.g. ``"a finite number > 0 [s]"``.
    source : str, optional
        Where the value came from (a file name).
    """

    def __init__(self, field: str, value: object, allowed: str, *, source: str | None = None):
        self.field = field
        self.value = value
        self.allowed = allowed
        self.source = source
        where = f"{source}: " if source else ""
        super().__init__(f"{where}{field} = {shown_value(value)} is invalid; allowed: {allowed}")


class InfeasibleError(ParameterError):
    """A well-formed value that the physics cannot meet: a tension the tether cannot give at
    its length, a hover outside the actuator limits, a trim that does not exist. A sweep
    records such a point as invalid (with this message) instead of stopping.

    Parameters
    ----------
    field, value, allowed, source
        As for ``ParameterError``.
    """


class WeightsError(InfeasibleError):
    """Weights the user wrote whose controller design has no stabilising solution
    (``design_failure``). Unlike another ``InfeasibleError`` it does not depend on a draw's
    dispersed plant (every controller is designed on the nominal one), so the studies refuse
    it at set-up, naming the file, instead of recording every run as failed.

    Parameters
    ----------
    field, value, allowed, source
        As for ``ParameterError``.
    """


def named_source(path: str, run: Callable[..., Any], *args: object, **kwargs: object) -> Any:
    """``run(*args, **kwargs)``, with a ``ParameterError`` that has no source (a set-up's:
    weights with no stabilising design, limits the hover does not fit) named after ``path``,
    and one whose source is a part of the work (a sweep point) named after both.

    Parameters
    ----------
    path : str
        The input file the run's settings came from.
    run : callable
        The work.
    *args, **kwargs
        Its arguments.

    Returns
    -------
    object
        What ``run`` returns.
    """
    try:
        return run(*args, **kwargs)
    except ParameterError as exc:
        if exc.source is not None and exc.source.startswith(str(path)):
            raise
        # a source that is not the file (a sweep point) is named after it
        source = str(path) if exc.source is None else f"{path}, {exc.source}"
        raise type(exc)(exc.field, exc.value, exc.allowed, source=source) from None


class DesignError(TetherheliError):
    """A controller design with no stabilising solution (a Riccati equation that has none,
    or a closed loop that is not stable). The design functions raise it about their matrix
    arguments; a scenario's set-up turns it into an ``InfeasibleError`` naming the weights
    the user wrote (``runs.setup.design_error``)."""


class SingularConfigurationError(TetherheliError):
    """The state lies on a coordinate singularity (|q5| or |q8| = 90 deg, q9 <= 0)."""


class ClusterError(TetherheliError):
    """The Dask scheduler was lost during a run, or it had no worker for too long."""


def design_failure(field: str, value: object, exc: DesignError) -> WeightsError:
    """The ``WeightsError`` that names the weights a failed design (``exc``) was given.

    Parameters
    ----------
    field : str
        The weights' keys as the user wrote them, e.g. ``"control.Qy/Ru"``.
    value : object
        Their values.
    exc : DesignError
        The design's failure, whose first line is kept as the reason.

    Returns
    -------
    WeightsError
        To raise ``from None``.
    """
    reason = str(exc).splitlines()[0]
    return WeightsError(
        field,
        value,
        "weights whose design has a stabilising solution, e.g. every entry within about 1e10 "
        f"of the others (here: {reason})",
    )
