"""Memory budget: estimate what a job will allocate and refuse what does not fit, before
allocating anything.

The budget is ``TETHERHELI_MEMORY_LIMIT`` from the environment (bytes, or with a suffix:
``512M``, ``8G``, ``1.5GiB``), else ``DEFAULT_MEMORY_LIMIT`` (4 GiB, sized for a laptop).
A refused job says what it needed, the budget, and how to raise it.
"""

from __future__ import annotations

import math
import os
import re
import warnings

from .errors import TetherheliError

__all__ = [
    "DEFAULT_MEMORY_LIMIT",
    "MEMORY_LIMIT_ENV",
    "SLOW_JOB_SECONDS",
    "ResourceLimitError",
    "SlowJobWarning",
    "check_memory",
    "format_bytes",
    "memory_limit",
    "warn_slow",
]

#: Environment variable that sets the budget.
MEMORY_LIMIT_ENV = "TETHERHELI_MEMORY_LIMIT"
#: The default budget [bytes]: 4 GiB.
DEFAULT_MEMORY_LIMIT = 4 * 2**30

_UNITS = {"": 1, "k": 10**3, "m": 10**6, "g": 10**9, "t": 10**12}
_BINARY = {"": 1, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}


class ResourceLimitError(TetherheliError):
    """A job that would need more memory than the budget allows (one-line message)."""


def memory_limit() -> int:
    """The budget in bytes (``TETHERHELI_MEMORY_LIMIT``, else ``DEFAULT_MEMORY_LIMIT``).

    Returns
    -------
    int
        The budget [bytes].

    Raises
    ------
    ResourceLimitError
        ``TETHERHELI_MEMORY_LIMIT`` is not a size such as 512M, 8G or 1.5GiB.
    """
    text = os.environ.get(MEMORY_LIMIT_ENV, "").strip()
    if not text:
        return DEFAULT_MEMORY_LIMIT
    match = re.fullmatch(r"(\d+(?:\.\d*)?)\s*([kKmMgGtT]?)(i?)[bB]?", text)
    value = float(match.group(1)) if match else math.nan
    if not (match and math.isfinite(value) and value > 0):
        raise ResourceLimitError(
            f"{MEMORY_LIMIT_ENV} = {text!r} is invalid; allowed: a size such as 512M, 8G or 1.5GiB"
        )
    unit = match.group(2).lower()
    scale = _BINARY[unit] if match.group(3) else _UNITS[unit]
    return int(value * scale)


def format_bytes(n: float) -> str:
    """``n`` bytes in binary units, e.g. '3.2 GiB'.

    Parameters
    ----------
    n : float
        A size [bytes].

    Returns
    -------
    str
        The size with one decimal in KiB, MiB, ... (whole bytes below 1 KiB).
    """
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024 or unit == "PiB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024
    raise AssertionError("unreachable")


def check_memory(what: str, needed_bytes: float, *, hint: str = "") -> None:
    """Refuse (ResourceLimitError) a job whose estimated allocation exceeds the budget.

    ``what`` names the job and the input that sizes it (e.g. "run paper_sim1: duration =
    1e+12 s at dt = 0.01 s"); ``hint`` says how to make it smaller.

    Parameters
    ----------
    what : str
        The job and the input that sizes it, for the message.
    needed_bytes : float
        The job's estimated allocation [bytes].
    hint : str
        How to make the job smaller, appended to the message.

    Raises
    ------
    ResourceLimitError
        ``needed_bytes`` exceeds ``memory_limit()``.
    """
    limit = memory_limit()
    if not needed_bytes <= limit:  # also refuses NaN
        more = f"; {hint}" if hint else ""
        raise ResourceLimitError(
            f"{what} needs about {format_bytes(needed_bytes)}, more than the memory budget of "
            f"{format_bytes(limit)}{more}, or raise the budget with {MEMORY_LIMIT_ENV} "
            "(e.g. 16G)"
        )


#: A job estimated to run longer than this [s] is announced (``warn_slow``) before it starts.
SLOW_JOB_SECONDS = 600.0


class SlowJobWarning(UserWarning):
    """A valid job whose estimated run time exceeds ``SLOW_JOB_SECONDS`` (one-line message)."""


def warn_slow(what: str, seconds: float, *, hint: str = "") -> None:
    """Warn (``SlowJobWarning``) before a job estimated to take more than
    ``SLOW_JOB_SECONDS``: what it is, the estimate and how to make it shorter.

    Parameters
    ----------
    what : str
        The job and the input that sizes it, for the message.
    seconds : float
        The job's estimated run time [s].
    hint : str
        How to make the job shorter, appended to the message.
    """
    if seconds > SLOW_JOB_SECONDS:
        more = f"; {hint}" if hint else ""
        minutes = seconds / 60.0
        took = f"{minutes:.0f} min" if minutes < 120 else f"{minutes / 60.0:.1f} h"
        warnings.warn(f"{what} will take about {took}{more}", SlowJobWarning, stacklevel=3)
