"""How a run ended: ``Status``, an enum that carries its message (importable without Numba).

The compiled engine returns the integer value; ``Status(code).message`` says what it means.
A tether released by the safety device is an event of a run, not a status: it is added to
the message by ``status_message`` so a released run never reads as a plain "completed".

A controller that solves an optimisation each sample (the MPC) can fail to solve it and fly
a fallback instead (``control.mpc``: the ``mpc_fallback`` column). ``solver_status`` turns
the fraction of such samples into the run's status: above ``DEGRADED_FALLBACK_FRACTION``
(1 %) of the samples the run is ``DEGRADED``, above ``FAILED_FALLBACK_FRACTION`` (10 %) it
``SOLVER_FAILED``. Only ``OK`` is a success: a degraded or failed run is never "completed",
counts as a failure in every table and tally, and makes the command's exit code 1.

One success rule: ``Status.is_success`` (a run's status) and ``is_success`` (any status or
array of statuses) are the only test of success; every result, batch, table, tally and exit
code asks them. A run that breaks a limit its scenario sets, or whose recorded values are not
finite, never has a success status (``finite_status``).
"""

from __future__ import annotations

import enum
import math
from typing import overload

import numpy as np

__all__ = [
    "DEGRADED_FALLBACK_FRACTION",
    "FAILED_FALLBACK_FRACTION",
    "FALLBACK_COLUMN",
    "SUCCESS_STATUSES",
    "Status",
    "finite_status",
    "is_success",
    "markdown_table",
    "ran_to_end",
    "release_sentence",
    "solver_status",
    "status_message",
    "stopped",
]

#: The result column (``SimulationResult.extra``) marking the samples a fallback flew.
FALLBACK_COLUMN = "mpc_fallback"
#: Above this fraction of control samples flown by a solver's fallback a run is DEGRADED.
DEGRADED_FALLBACK_FRACTION = 0.01
#: Above this fraction of control samples flown by a solver's fallback a run SOLVER_FAILED.
FAILED_FALLBACK_FRACTION = 0.10


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
    TETHER_LENGTH : int
        7: the tether's natural (unstretched) length reached zero (LN <= 0): no physical
        tether.
    DEGRADED : int
        8: the run reached its end, but the controller's solver failed (a fallback flew) on
        more than ``DEGRADED_FALLBACK_FRACTION`` of the samples (``solver_status``).
    SOLVER_FAILED : int
        9: the controller's solver failed on more than ``FAILED_FALLBACK_FRACTION`` of the
        samples (``solver_status``).
    LANDED : int
        10: a landing maneuver touched down within its limits (``[maneuver]``; a success,
        as OK: ``is_success``).
    HARD_TOUCHDOWN : int
        11: a landing touched down outside its limits (speed, offset or attitude; the
        reason follows in the message).
    NOT_LANDED : int
        12: a landing maneuver reached the run's end without touching down.
    NOT_SETTLED : int
        13: a landing on its gear touched down but did not settle (``[maneuver]
        after_touchdown``): a gear point off the deck at the end of the settling, a bounce,
        a tip-over or off the pad (the reason follows in the message).
    """

    OK = 0
    NONFINITE = 1
    GROUND = 2
    MAX_TENSION = 3
    DIVERGED = 4
    SINGULAR = 5
    SETUP = 6  # never returned by the engine: run_batch(record_setup_failures=True)
    TETHER_LENGTH = 7
    DEGRADED = 8  # never returned by the engine: solver_status of a controller's fallbacks
    SOLVER_FAILED = 9  # never returned by the engine: solver_status
    LANDED = 10  # a landing's statuses: set by the Python loop at touchdown (runs.landing)
    HARD_TOUCHDOWN = 11
    NOT_LANDED = 12
    NOT_SETTLED = 13

    @property
    def message(self) -> str:
        return _MESSAGES[self]

    @property
    def is_success(self) -> bool:
        """Whether a run of this status is a success: OK, or LANDED for a landing (the one
        success rule: ``SUCCESS_STATUSES``)."""
        return int(self) in SUCCESS_STATUSES


#: The statuses of a successful run: ``OK`` ("completed") and ``LANDED``; every other status
#: is a failure in every result, table, tally and exit code.
SUCCESS_STATUSES: tuple[int, ...] = (int(Status.OK), int(Status.LANDED))


@overload
def is_success(status: np.ndarray) -> np.ndarray: ...
@overload
def is_success(status: int) -> bool: ...
def is_success(status: int | np.ndarray) -> bool | np.ndarray:
    """Whether a run (or each run) of ``status`` succeeded (``Status.is_success``).

    Parameters
    ----------
    status : int or numpy.ndarray of int
        One status code, or an array of them.

    Returns
    -------
    bool or numpy.ndarray of bool
        True where the status is in ``SUCCESS_STATUSES``; an array of the input's shape for
        an array.
    """
    if isinstance(status, np.ndarray):
        return np.isin(status, SUCCESS_STATUSES)
    return int(status) in SUCCESS_STATUSES


def finite_status(status: int, *recorded: np.ndarray) -> int:
    """``status``, or ``NONFINITE`` for a successful run any of whose ``recorded`` values
    is not finite (an overflow in a recorded series, e.g. a base position beyond the float
    range): such a run is never completed.

    Parameters
    ----------
    status : int
        The run's status as its loop ended it.
    *recorded : numpy.ndarray
        The run's recorded series (float arrays).

    Returns
    -------
    int
        The run's status.
    """
    if not is_success(status):
        return int(status)
    for values in recorded:
        if values.dtype.kind == "f" and not np.isfinite(values).all():
            return int(Status.NONFINITE)
    return int(status)


_MESSAGES = {
    Status.OK: "completed",
    Status.NONFINITE: "the state or a recorded value became non-finite",
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
    Status.TETHER_LENGTH: (
        "the tether's natural length reached zero (LN <= 0: no physical tether is that short)"
    ),
    Status.DEGRADED: (
        f"degraded: the controller's solver failed on more than "
        f"{100 * DEGRADED_FALLBACK_FRACTION:g} % of the samples (a fallback flew them)"
    ),
    Status.SOLVER_FAILED: (
        f"failed: the controller's solver failed on more than "
        f"{100 * FAILED_FALLBACK_FRACTION:g} % of the samples (a fallback flew them)"
    ),
    Status.LANDED: "landed: touched down within the maneuver's limits",
    Status.HARD_TOUCHDOWN: "failed: touched down outside the maneuver's limits",
    Status.NOT_LANDED: "failed: the landing did not touch down before the run's end",
    Status.NOT_SETTLED: "failed: touched down, but did not settle on the landing gear",
}


#: the statuses of a run that reached its end with too many fallbacks, and their limits
_LIMITS = {
    Status.DEGRADED: DEGRADED_FALLBACK_FRACTION,
    Status.SOLVER_FAILED: FAILED_FALLBACK_FRACTION,
}


def markdown_table() -> str:
    """Every status as a Markdown table (code, name, success, message): the table of
    ``docs/tutorials/statuses.md`` (``python docs/regenerate_tables.py --only statuses``
    prints it; a test checks the page holds it).

    Returns
    -------
    str
        The table, one row per ``Status`` member, ending with a newline.
    """
    rows = ["| code | status | success | message |", "|---:|---|---|---|"]
    for member in Status:
        success = "yes" if member.is_success else "no"
        message = member.message.replace("|", "\\|")  # a cell's pipes escaped
        rows.append(f"| {int(member)} | `{member.name}` | {success} | {message} |")
    return "\n".join(rows) + "\n"


def ran_to_end(status: int) -> bool:
    """Whether a run of ``status`` was flown to the run's end (``OK``, ``DEGRADED``,
    ``SOLVER_FAILED``, and ``NOT_LANDED``: a landing that reached the end without touching
    down), rather than stopped at a failure or ended by a touchdown.

    Parameters
    ----------
    status : int
        A ``Status`` code.

    Returns
    -------
    bool
        True for a run that reached its last sample.
    """
    return int(status) in (Status.OK, Status.NOT_LANDED) or int(status) in _LIMITS


#: the engine's stop checks: a run of these statuses stopped at a sample whose state failed
#: the checks (that sample is not recorded)
_STOPS = (
    Status.NONFINITE,
    Status.GROUND,
    Status.MAX_TENSION,
    Status.DIVERGED,
    Status.SINGULAR,
    Status.TETHER_LENGTH,
)


def stopped(status: int) -> bool:
    """Whether a run of ``status`` was stopped by one of the engine's checks at a sample it
    did not record (so it ended one sample after its last recorded one); False for a run
    flown to its end (``ran_to_end``) or ended at a recorded touchdown.

    Parameters
    ----------
    status : int
        A ``Status`` code.

    Returns
    -------
    bool
        True for a run stopped by a check.
    """
    return int(status) in _STOPS


def solver_status(status: int, fallbacks) -> int:
    """The status of a run whose controller flew a fallback on the samples ``fallbacks``
    marks: ``status`` unless it is ``OK`` and the fallback fraction exceeds
    ``DEGRADED_FALLBACK_FRACTION`` (``DEGRADED``) or ``FAILED_FALLBACK_FRACTION``
    (``SOLVER_FAILED``). A run that stopped keeps its own status.

    Parameters
    ----------
    status : int
        The run's status as the loop ended it.
    fallbacks : sequence of float
        One value per control sample, 1 where the fallback flew, else 0 (may be empty).

    Returns
    -------
    int
        The run's status.
    """
    n = len(fallbacks)
    if status != Status.OK or n == 0:
        return int(status)
    fraction = float(sum(fallbacks)) / n
    if fraction > FAILED_FALLBACK_FRACTION:
        return int(Status.SOLVER_FAILED)
    if fraction > DEGRADED_FALLBACK_FRACTION:
        return int(Status.DEGRADED)
    return int(status)


def status_message(
    status: int,
    release_time: float | None = None,
    fallback_fraction: float | None = None,
    winch_limit: dict | None = None,
    touchdown: dict | None = None,
) -> str:
    """The message of a run's status; a tether release (at ``release_time`` [s], None or NaN:
    none) is part of it, so a released run is never a plain "completed", and so is the
    fraction of samples a solver's fallback flew when there were any, and the winch's stop at
    a payout limit (``winch_limit``).

    Parameters
    ----------
    status : int
        A ``Status`` code.
    release_time : float, optional
        The tether release time [s]; None or NaN (default None): no release.
    fallback_fraction : float, optional
        The fraction of control samples a solver's fallback flew (``solver_status``); None or
        0 (default None): none, nothing added.
    winch_limit : dict, optional
        The first stop of the reel at a payout limit, ``{"time", "limit", "length"}`` (s,
        "min_length" or "max_length", m, the length optional; ``SimulationResult.winch_limit``);
        None (default): none, nothing added.
    touchdown : dict, optional
        A landing's touchdown (``SimulationResult.touchdown``): its time and figures, and
        for a hard one the limits it broke (``"reasons"``); None (default): none.

    Returns
    -------
    str
        The one-line message.
    """
    status = Status(int(status))
    message = status.message
    if fallback_fraction is not None and fallback_fraction > 0.0:
        share = f"{100 * fallback_fraction:.3g} %"
        if status in _LIMITS:
            message = message.replace("more than", f"{share} (more than", 1).replace(
                "% of the samples", "%) of the samples", 1
            )
        else:
            message += f" (solver fallback on {share} of the samples)"
    if winch_limit is not None:
        length = winch_limit.get("length")
        value = "" if length is None else f" = {length:g} m"
        message += (
            f" (the winch stopped at [winch] {winch_limit['limit']}{value} at "
            f"t = {winch_limit['time']:g} s)"
        )
    if touchdown is not None:
        message += (
            f" (touchdown at t = {touchdown['time']:.4g} s, "
            f"{touchdown['vertical_speed']:.3g} m/s, {touchdown['offset']:.3g} m from the pad, "
            f"tilt {touchdown['attitude']:.3g} rad"
            + "".join(f"; {reason}" for reason in touchdown.get("reasons", ()))
            + ")"
        )
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
