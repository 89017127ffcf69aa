"""Error types. Every user-facing error is a one-line message naming the field, the value and
what is allowed; the CLI prints it on stderr and exits with code 2 (``ClusterError``, a failure
while running rather than bad input, exits 1)."""

from __future__ import annotations


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
        super().__init__(f"{where}{field} = {value!r} is invalid; allowed: {allowed}")


class InfeasibleError(ParameterError):
    """A well-formed value that the physics cannot meet: a tension the tether cannot give at
    its length, a hover outside the actuator limits, a trim that does not exist. A sweep
    records such a point as invalid (with this message) instead of stopping.

    Parameters
    ----------
    field, value, allowed, source
        As for ``ParameterError``.
    """


class SingularConfigurationError(TetherheliError):
    """The state lies on a coordinate singularity (|q5| or |q8| = 90 deg, q9 <= 0)."""


class ClusterError(TetherheliError):
    """The Dask scheduler was lost during a run, or it had no worker for too long."""
