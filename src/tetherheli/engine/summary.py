"""The on-line metrics of a run (``layout.SUMMARY_FIELDS``), accumulated by the engine's
sample step (``engine.loop.sample_record``) while it flies, and over a recorded run
(``summarize``, behind ``analysis.run_metrics``): one definition of every metric."""

from __future__ import annotations

import numpy as np

from .._compile import compiled
from ..layout import (
    HELD_LIMIT_TIME,
    HELD_LIMIT_WHICH,
    SUMMARY_N_SAMPLES,
    SUMMARY_PEAK_Q1,
    SUMMARY_PEAK_Q4,
    SUMMARY_PEAK_Q5,
    SUMMARY_RELEASE_TENSION,
    SUMMARY_RELEASE_TIME,
    SUMMARY_SUMSQ_Q1,
    SUMMARY_TENSION_MAX,
    SUMMARY_TENSION_MIN,
    SUMMARY_WINCH_LIMIT,
    SUMMARY_WINCH_LIMIT_TIME,
    X_Q4,
    X_Q5,
)

__all__ = [
    "accumulate", "finish_summary", "larger", "smaller", "start_summary", "summarize",
    "winch_limit_into",
]  # fmt: skip

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")


@_jit
def start_summary(summary):
    """Empty on-line metrics (``layout.SUMMARY_FIELDS``): no sample, no release.

    Parameters
    ----------
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        Receives the empty metrics (``layout.SUMMARY_*``).
    """
    summary[:] = 0.0
    summary[SUMMARY_TENSION_MIN] = np.inf
    summary[SUMMARY_TENSION_MAX] = -np.inf
    summary[SUMMARY_RELEASE_TIME] = np.nan
    summary[SUMMARY_RELEASE_TENSION] = np.nan
    summary[SUMMARY_WINCH_LIMIT_TIME] = np.nan
    summary[SUMMARY_WINCH_LIMIT] = np.nan


@_jit_inline
def winch_limit_into(held, summary):
    """The first stop of the reel at a payout limit (``held``'s ``HELD_LIMIT_*``, set by
    ``actuate``) into the summary's ``winch_limit_time`` [s] and ``winch_limit`` (-1
    min_length, +1 max_length); both NaN when no limit was reached.

    Parameters
    ----------
    held : numpy.ndarray, shape (HELD_SIZE,)
        What the actuators hold between samples (``layout.HELD_*``).
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        The on-line metrics (``layout.SUMMARY_*``), updated.
    """
    if held[HELD_LIMIT_WHICH] != 0.0:
        summary[SUMMARY_WINCH_LIMIT_TIME] = held[HELD_LIMIT_TIME]
        summary[SUMMARY_WINCH_LIMIT] = held[HELD_LIMIT_WHICH]
    else:
        summary[SUMMARY_WINCH_LIMIT_TIME] = np.nan
        summary[SUMMARY_WINCH_LIMIT] = np.nan


@_jit_inline
def accumulate(summary, x, x_ref, y, y_ref, tension):
    """One sample into the on-line metrics (``layout.SUMMARY_FIELDS``; their definitions:
    ``analysis``): peaks of |y - y_ref| (q1..q3) and |x - x_ref| (q4, q5), sums of squares of
    the position deviations, the tension range, the sample count.

    Parameters
    ----------
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        The on-line metrics (``layout.SUMMARY_*``), updated.
    x : numpy.ndarray, shape (13,)
        The true state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    x_ref : numpy.ndarray, shape (12,) or (13,)
        The trim state (``layout.LAW_X_REF``), q4 and q5 first [rad].
    y, y_ref : numpy.ndarray, shape (4,)
        The true outputs q1, q2, q3, q6 and their trim [m, m, m, rad].
    tension : float
        The true tension at P [N].
    """
    for a in range(3):
        dev = y[a] - y_ref[a]
        summary[SUMMARY_PEAK_Q1 + a] = larger(summary[SUMMARY_PEAK_Q1 + a], abs(dev))
        summary[SUMMARY_SUMSQ_Q1 + a] += dev * dev
    summary[SUMMARY_PEAK_Q4] = larger(summary[SUMMARY_PEAK_Q4], abs(x[X_Q4] - x_ref[X_Q4]))
    summary[SUMMARY_PEAK_Q5] = larger(summary[SUMMARY_PEAK_Q5], abs(x[X_Q5] - x_ref[X_Q5]))
    summary[SUMMARY_TENSION_MIN] = smaller(summary[SUMMARY_TENSION_MIN], tension)
    summary[SUMMARY_TENSION_MAX] = larger(summary[SUMMARY_TENSION_MAX], tension)
    summary[SUMMARY_N_SAMPLES] += 1.0


@_jit_inline
def larger(held, value):
    """A running maximum's update: ``value`` when it exceeds ``held`` (NaN never does).

    Parameters
    ----------
    held : float
        The running maximum.
    value : float
        The new value.

    Returns
    -------
    float
        The updated maximum.
    """
    return value if value > held else held


@_jit_inline
def smaller(held, value):
    """A running minimum's update: ``value`` when it is below ``held`` (NaN never is).

    Parameters
    ----------
    held : float
        The running minimum.
    value : float
        The new value.

    Returns
    -------
    float
        The updated minimum.
    """
    return value if value < held else held


@_jit
def summarize(x, x_ref, y, y_ref, tension, first, summary):
    """The on-line metrics (``accumulate``) of recorded samples first, first + 1, ... of x
    (n, 13), y (n, 4) and tension (n,) into ``summary`` (``start_summary`` first): a recorded
    or loaded run measured as the engine measures it while it flies.

    Parameters
    ----------
    x : numpy.ndarray, shape (n, 13)
        The recorded true states [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    x_ref : numpy.ndarray, shape (12,) or (13,)
        The trim state (``layout.LAW_X_REF``) [rad, m, rad/s, m/s].
    y : numpy.ndarray, shape (n, 4)
        The recorded true outputs q1, q2, q3, q6 [m, m, m, rad].
    y_ref : numpy.ndarray, shape (4,)
        The trim outputs [m, m, m, rad].
    tension : numpy.ndarray, shape (n,)
        The recorded true tension at P [N].
    first : int
        The first sample the metrics cover.
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        Receives the metrics (``layout.SUMMARY_*``).
    """
    start_summary(summary)
    for k in range(first, x.shape[0]):
        accumulate(summary, x[k], x_ref, y[k], y_ref, tension[k])


@_jit_inline
def finish_summary(summary, event, held):
    """The run's release event and first payout limit into its summary.

    Parameters
    ----------
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        The on-line metrics (``layout.SUMMARY_*``), updated.
    event : numpy.ndarray, shape (2,)
        The tether release: time [s], tension [N]; NaN without one.
    held : numpy.ndarray, shape (HELD_SIZE,)
        What the actuators hold between samples (``layout.HELD_*``).
    """
    summary[SUMMARY_RELEASE_TIME] = event[0]
    summary[SUMMARY_RELEASE_TENSION] = event[1]
    winch_limit_into(held, summary)
