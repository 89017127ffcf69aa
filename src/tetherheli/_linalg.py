"""Shared linear-algebra helpers: zero-order-hold discretization and array validation."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import expm

from ._validation import check_number
from .errors import TetherheliError

__all__ = ["check_dt", "discretize_zoh", "real_matrix", "solve_dare"]


def check_dt(dt: float) -> float:
    """A sample time argument ``dt`` as a float: a finite number > 0 [s], else a one-line
    ``ParameterError`` naming ``dt`` (``_validation.check_number``'s rule).

    Parameters
    ----------
    dt : float
        The sample time [s].

    Returns
    -------
    float
        ``dt``.
    """
    return check_number("dt", dt, low=0.0, low_open=True, unit="[s]")


def real_matrix(
    name: str, value: ArrayLike, shape: tuple[int | None, int | None]
) -> NDArray[np.float64]:
    """A finite float 2-D copy of ``value``; ``None`` in ``shape`` means any size."""
    try:
        arr = np.array(value, dtype=np.float64, ndmin=2)
    except (TypeError, ValueError) as exc:
        raise TetherheliError(f"{name} is not a real 2-D array ({exc})") from None
    expected = "(" + ", ".join("*" if s is None else str(s) for s in shape) + ")"
    if arr.ndim != 2 or any(
        s is not None and a != s for a, s in zip(arr.shape, shape, strict=True)
    ):
        raise TetherheliError(f"{name} has shape {arr.shape}; allowed: {expected}")
    if not np.all(np.isfinite(arr)):
        raise TetherheliError(f"{name} has non-finite entries; allowed: finite numbers")
    return arr


def discretize_zoh(A: ArrayLike, B: ArrayLike, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero-order-hold discretisation of x' = A x + B u (giving eq 46's G and H).

    G = e^{A dt} and H = int_0^dt e^{A s} ds B, both read from one block-matrix exponential
    expm([[A, B], [0, 0]] dt) = [[G, H], [0, I]].

    Parameters
    ----------
    A : array_like, shape (n, n)
        Continuous-time state matrix [1/s].
    B : array_like, shape (n, m)
        Continuous-time input matrix [state unit / (input unit s)].
    dt : float
        Sample time [s], finite and > 0.

    Returns
    -------
    G : ndarray, shape (n, n)
        Discrete state-transition matrix (dimensionless).
    H : ndarray, shape (n, m)
        Discrete input matrix [state unit / input unit].

    Raises
    ------
    ValueError
        If ``dt`` is not finite and positive, a matrix is not 2-D of matching size, or has
        non-finite entries (the message names the argument).
    """
    dt = check_dt(dt)
    A = real_matrix("A", A, (None, None))
    n = A.shape[0]
    if A.shape[1] != n:
        raise TetherheliError(f"A has shape {A.shape}; allowed: square (n, n)")
    return _discretize_zoh(A, real_matrix("B", B, (n, None)), dt)


def _discretize_zoh(A: np.ndarray, B: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """``discretize_zoh`` of arrays and a sample time already checked (finite float arrays of
    matching shapes, dt > 0): a run's set-up, whose model and scenario were checked."""
    n, m = B.shape
    block = np.zeros((n + m, n + m))
    block[:n, :n] = A * dt
    block[:n, n:] = B * dt
    phi = expm(block)
    return phi[:n, :n].copy(), phi[:n, n:].copy()


def solve_dare(A: np.ndarray, B: np.ndarray, Q: np.ndarray, R: np.ndarray) -> np.ndarray:
    """``scipy.linalg.solve_discrete_are(A, B, Q, R)`` without its floating-point warnings:
    weights far apart (e.g. 1e200 next to 1) overflow inside its balancing, which warns
    before it fails; the callers check the solution (finite, stabilising) and name the
    weights (``errors.DesignError``).

    Parameters
    ----------
    A, B, Q, R : ndarray
        As for ``scipy.linalg.solve_discrete_are``.

    Returns
    -------
    ndarray
        The solution P.

    Raises
    ------
    numpy.linalg.LinAlgError, ValueError
        As ``solve_discrete_are`` does.
    """
    import warnings

    from scipy.linalg import solve_discrete_are

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        return solve_discrete_are(A, B, Q, R)
