"""How a run ended: ``Status``, an enum that carries its message (importable without Numba).

The compiled engine returns the integer value; ``Status(code).message`` says what it means.
A tether released by the safety device is an event of a run, not a status: it is added to
the message by ``status_message`` so a released run never reads as a plain "completed".
"""

from __future__ import annotations

import enum
import math

__all__ = ["Status", "release_sentence", "status_message"]


class Status(enum.IntEnum):
    """A run's end state; ``OK`` is the only success.

    The integer values are those the compiled engine returns and result files record;
    ``message`` gives each member's one-line explanation.

    Attributes
    ----------
    OK : int
        0: the run completed.
    NONFINITE : int
        1: the state became non-finite.
    GROUND : int
        2: the helicopter hit the ground (q3 < 0 or P at ground level).
    MAX_TENSION : int
        3: the tether tension exceeded ``limits.max_tension``.
    DIVERGED : int
        4: deviation or attitude beyond ``limits.max_deviation`` / ``limits.max_angle_deg``.
    SINGULAR : int
        5: a coordinate singularity (q9 <= 0 or |q5|, |q8| at 90 deg).
    SETUP : int
        6: the run could not be set up (never returned by the engine;
        ``run_batch(record_setup_failures=True)``).
    """

    OK = 0
    NONFINITE = 1
    GROUND = 2
    MAX_TENSION = 3
    DIVERGED = 4
    SINGULAR = 5
    SETUP = 6  # never returned by the engine: run_batch(record_setup_failures=True)

    @property
    def message(self) -> str:
        return _MESSAGES[self]


_MESSAGES = {
    Status.OK: "completed",
    Status.NONFINITE: "the state became non-finite",
    Status.GROUND: (
        "the helicopter hit the ground (q3 < 0 or the attachment point P at ground level)"
    ),
    Status.MAX_TENSION: "the tether tension exceeded the configured maximum",
    Status.DIVERGED: "the run diverged (deviation or attitude beyond the configured bounds)",
    Status.SINGULAR: (
        "the state reached a coordinate singularity (q9 <= 0 or |q5|, |q8| at 90 deg)"
    ),
    Status.SETUP: (
        "the run could not be set up (no hover trim within the parameters and actuator limits)"
    ),
}


def status_message(status: int, release_time: float | None = None) -> str:
    """The message of a run's status; a tether release (at ``release_time`` [s], None or NaN:
    none) is part of it, so a released run is never a plain "completed".

    Parameters
    ----------
    status : int
        A ``Status`` code.
    release_time : float, optional
        The tether release time [s]; None or NaN (default None): no release.

    Returns
    -------
    str
        The one-line message.
    """
    message = Status(int(status)).message
    if release_time is None or not math.isfinite(release_time):
        return message
    if status == Status.OK:
        return f"{message} (tether released at t = {release_time:g} s)"
    return f"{message} (after the tether was released at t = {release_time:g} s)"


def release_sentence(release_time: float, tension: float, breaking_tension: float) -> str:
    """One line describing a tether release, e.g. "tether released at t = 12.3 s (tension
    61.2034 N > breaking 60 N); continued free".

    Parameters
    ----------
    release_time : float
        Time of the release [s].
    tension : float
        The tension that broke the tether [N].
    breaking_tension : float
        The safety device's breaking tension [N].

    Returns
    -------
    str
        The sentence.
    """
    return (
        f"tether released at t = {release_time:g} s (tension {tension:.6g} N > breaking "
        f"{breaking_tension:g} N); continued free"
    )
