"""Linearization at a trim from the derivation's analytic Jacobians, ZOH discretization
(eq 46), and conversion to python-control.

For the tethered model with a taut tether the tension depends on the state through eq 28
(dTC/dq9 = KC, dTC/dLN = -KC); at TC = 0 the tether is at the slack boundary and the paper
linearizes with the tether removed (Sec. V-A), which is what ``linearize`` does there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._linalg import discretize_zoh
from .dynamics import FreeHelicopter, TetheredHelicopter
from .kernels import (
    free_jacobian,
    free_output_jacobian,
    tethered_jacobian,
    tethered_output_jacobian,
)
from .trim import TrimPoint

__all__ = ["LinearModel", "discretize_zoh", "linearize"]


@dataclass(frozen=True)
class LinearModel:
    """x' = A dx + B du + E dwind, dy = C dx, about ``trim`` (deviations from trim).

    ``state_names`` label the rows of A; ``B_reel`` (n,) is the reel-rate input column of the
    tethered model (zeros for the free one).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    E_wind: np.ndarray
    B_reel: np.ndarray
    state_names: tuple[str, ...]
    trim: TrimPoint

    def discretize(self, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """(G, H) of eq 46 for sample time dt [s] (zero-order hold)."""
        return discretize_zoh(self.A, self.B, dt)

    def select(self, names: tuple[str, ...]) -> LinearModel:
        """The sub-model on the named states (rows and columns of A, rows of B, columns of C)."""
        idx = [self.state_names.index(n) for n in names]
        return LinearModel(
            A=self.A[np.ix_(idx, idx)],
            B=self.B[idx],
            C=self.C[:, idx],
            E_wind=self.E_wind[idx],
            B_reel=self.B_reel[idx],
            state_names=tuple(names),
            trim=self.trim,
        )

    def to_statespace(self, dt: float | None = None):
        """The system as a python-control ``StateSpace`` (continuous, or ZOH-discrete with dt)."""
        import control

        sys = control.ss(self.A, self.B, self.C, np.zeros((self.C.shape[0], self.B.shape[1])))
        return sys if dt is None else control.c2d(sys, dt, method="zoh")


def linearize(model: TetheredHelicopter | FreeHelicopter, trim: TrimPoint) -> LinearModel:
    """Analytic linearization of ``model`` at ``trim`` (eqs 41-46).

    Inputs are the total rotor inputs (u0 - C_f-fwd at trim); the tethered model's state
    includes LN, with the reel rate as a separate input column ``B_reel``.
    """
    p = model.constants
    x0 = np.asarray(trim.x, dtype=float)
    u0 = trim.u_total
    wind = np.zeros(3)
    A12 = np.zeros((12, 12))
    B = np.zeros((12, 4))
    E = np.zeros((12, 3))
    E_T = np.zeros(12)
    C12 = np.zeros((4, 12))
    if isinstance(model, TetheredHelicopter):
        tension = model.tension(x0)
        tethered_jacobian(x0, u0, wind, tension, p, A12, B, E, E_T)
        tethered_output_jacobian(x0, p, C12)
        n = 13
        A = np.zeros((n, n))
        A[:12, :12] = A12
        if tension > 0.0:  # taut: TC = KC (q9 - LN), eq 28
            K_C = model.params.tether.K_C
            A[:12, 5] += E_T * K_C
            A[:12, 12] -= E_T * K_C
        B_full = np.vstack([B, np.zeros((1, 4))])
        E_full = np.vstack([E, np.zeros((1, 3))])
        C = np.hstack([C12, np.zeros((4, 1))])
        B_reel = np.zeros(n)
        B_reel[12] = 1.0
        return LinearModel(A, B_full, C, E_full, B_reel, model.STATE, trim)
    if isinstance(model, FreeHelicopter):
        free_jacobian(x0, u0, wind, 0.0, p, A12, B, E, E_T)
        free_output_jacobian(x0, p, C12)
        return LinearModel(A12, B, C12, E, np.zeros(12), model.STATE, trim)
    raise TypeError(f"model must be a TetheredHelicopter or FreeHelicopter, not {type(model)}")
