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
from ..errors import ParameterError
from ..names import BASE_ACCELERATION, INPUT, OUTPUT, REEL_RATE, WIND
from ._generated import (  # the generated Python: 30 us a call, no compilation
    free_jacobian,
    free_output_jacobian,
    tethered_jacobian,
    tethered_output_jacobian,
)
from .dynamics import FreeHelicopter, TetheredHelicopter
from .trim import TrimPoint

__all__ = ["EXPORT_INPUTS", "LinearModel", "discretize_zoh", "linearize"]

#: The input names ``LinearModel.to_statespace(inputs=...)`` accepts: the four rotor inputs
#: (columns of B), the reel rate RC (``B_reel``, tethered model only), the wind force on HO
#: (columns of ``E_wind``) and a moving winch's acceleration b'' (columns of ``E_base``).
#: Unless chosen, the inputs are the controls (``LinearModel.control_inputs``).
EXPORT_INPUTS: tuple[str, ...] = (*INPUT, REEL_RATE, *WIND, *BASE_ACCELERATION)


@dataclass(frozen=True)
class LinearModel:
    """x' = A dx + B du + E dwind (+ E_base b''), dy = C dx, about ``trim`` (deviations from
    trim; over a moving winch the state and outputs are relative to the base).

    Parameters
    ----------
    A : numpy.ndarray, shape (n, n)
        State matrix (n = 13 tethered, 12 free).
    B : numpy.ndarray, shape (n, 4)
        Columns of the rotor inputs fMR3, tMR1, tMR2, fTR2.
    C : numpy.ndarray, shape (4, n)
        Output matrix of q1, q2, q3, q6 (eqs 43-45).
    E_wind : numpy.ndarray, shape (n, 3)
        Columns of the wind force on HO, N components.
    B_reel : numpy.ndarray, shape (n,)
        Column of the reel rate RC (tethered; zeros for the free model).
    state_names : tuple of str
        The names of the states, labelling the rows of A.
    trim : TrimPoint
        The hover the model is linearized about.
    mass : float
        The helicopter's mass m = mF + mMR [kg]: b'' enters as the force -m b'' at HO
        (``derive(moving_base=True)``), so ``E_base`` = -m ``E_wind``.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    E_wind: np.ndarray
    B_reel: np.ndarray
    state_names: tuple[str, ...]
    trim: TrimPoint
    mass: float = float("nan")

    @property
    def E_base(self) -> np.ndarray:
        """Columns of a moving winch's acceleration b'' [m/s^2], N components (n, 3)."""
        return -self.mass * self.E_wind

    def discretize(self, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """The zero-order-hold discretization of eq 46.

        Parameters
        ----------
        dt : float
            Sample time (s), > 0.

        Returns
        -------
        G, H : numpy.ndarray
            The discrete state and input matrices, shapes (n, n) and (n, 4).
        """
        return discretize_zoh(self.A, self.B, dt)

    def select(self, names: tuple[str, ...]) -> LinearModel:
        """The sub-model on the named states (rows and columns of A, rows of B, columns of C).

        Parameters
        ----------
        names : tuple of str
            States to keep, among ``state_names``, in the order wanted.

        Returns
        -------
        LinearModel
        """
        idx = [self.state_names.index(n) for n in names]
        return LinearModel(
            A=self.A[np.ix_(idx, idx)],
            B=self.B[idx],
            C=self.C[:, idx],
            E_wind=self.E_wind[idx],
            B_reel=self.B_reel[idx],
            state_names=tuple(names),
            trim=self.trim,
            mass=self.mass,
        )

    @property
    def tethered(self) -> bool:
        """True for the tethered model (its state ends with the tether's natural length LN)."""
        return "LN" in self.state_names

    @property
    def control_inputs(self) -> tuple[str, ...]:
        """The inputs a controller sets, the default of ``to_statespace``, ``input_matrix``
        and ``uncontrollable_modes``: the four rotor inputs, and the reel rate RC on a model
        whose state has LN (eq 37: only RC moves LN, so without it (A, B) is not
        stabilisable).

        Returns
        -------
        tuple of str
        """
        return (*INPUT, REEL_RATE) if self.tethered else INPUT

    def input_matrix(self, inputs: tuple[str, ...] | None = None) -> np.ndarray:
        """The continuous input columns of the named inputs.

        Parameters
        ----------
        inputs : tuple of str, optional
            Names among ``EXPORT_INPUTS``: rotor inputs (from B), ``"RC"`` (from ``B_reel``),
            ``"Fw1"``, ``"Fw2"``, ``"Fw3"`` (from ``E_wind``), ``"ab1"``, ``"ab2"``, ``"ab3"``
            (from ``E_base``); None (default): ``control_inputs``.

        Returns
        -------
        numpy.ndarray, shape (n, len(inputs))
        """
        inputs = self.control_inputs if inputs is None else tuple(inputs)
        if not inputs:
            raise ParameterError("inputs", inputs, f"one or more of {EXPORT_INPUTS}")
        cols = []
        for name in inputs:
            if name in INPUT:
                cols.append(self.B[:, INPUT.index(name)])
            elif name == REEL_RATE:
                if not self.tethered:
                    raise ParameterError(
                        "inputs", inputs, f"{REEL_RATE!r} only on a model whose state has LN"
                    )
                cols.append(self.B_reel)
            elif name in WIND:
                cols.append(self.E_wind[:, WIND.index(name)])
            elif name in BASE_ACCELERATION:
                cols.append(self.E_base[:, BASE_ACCELERATION.index(name)])
            else:
                raise ParameterError("inputs", inputs, f"names from {EXPORT_INPUTS}")
        if len(set(inputs)) != len(inputs):
            raise ParameterError("inputs", inputs, "each name at most once")
        return np.column_stack(cols)

    def uncontrollable_modes(
        self, inputs: tuple[str, ...] | None = None
    ) -> tuple[tuple[complex, str], ...]:
        """The modes that make (A, B[inputs]) not stabilisable (PBH test, Hautus 1969).

        Parameters
        ----------
        inputs : tuple of str, optional
            The inputs, as for ``input_matrix`` (default ``control_inputs``).

        Returns
        -------
        tuple of (complex, str)
            Each eigenvalue s of A with Re s >= 0 and rank [A - sI, B] < n, with the state
            that dominates its uncontrollable left eigenvector. Empty when the pair is
            stabilisable.
        """
        A = self.A
        B = self.input_matrix(inputs)
        n = A.shape[0]
        found: list[tuple[complex, str]] = []
        scale = max(1.0, float(np.linalg.norm(A, 2)), float(np.linalg.norm(B, 2)))
        tol = 1e-9 * scale
        distinct: list[complex] = []
        for s in np.linalg.eigvals(A):
            if s.real >= -tol and all(abs(s - d) > 1e-6 * scale for d in distinct):
                distinct.append(complex(s))
        for s in distinct:
            u, sv, _ = np.linalg.svd(np.hstack([A - s * np.eye(n), B]))
            # each singular value ~ 0 is one uncontrollable direction w (w' [A - sI, B] ~ 0)
            for k in np.flatnonzero(sv <= tol):
                found.append((s, self.state_names[int(np.argmax(np.abs(u[:, k])))]))
        return tuple(found)

    def to_statespace(
        self,
        dt: float | None = None,
        *,
        inputs: tuple[str, ...] | None = None,
        name: str | None = None,
        require_stabilisable: bool = False,
    ):
        """The system as a python-control ``StateSpace``, labelled with our names.

        States are ``state_names``, inputs the chosen ``inputs`` (from ``EXPORT_INPUTS``,
        default ``control_inputs``: the four rotor inputs and, tethered, the reel rate RC),
        outputs ``names.OUTPUT``; the units of every label are
        ``names.UNITS[label]`` (python-control labels carry no units). With ``dt`` [s] the
        system is ZOH-discretised by ``discretize`` (eq 46), so A, B equal our G, H exactly.

        Without ``"RC"`` (inputs chosen without it) the tethered model is not stabilisable:
        LN changes only through the reel rate (eq 37, dLN/dt = RC), so its row of A and B is
        zero and LN is an uncontrollable integrator at s = 0 (python-control's
        ``lqr``/``dlqr`` then fail on the full 13-state system); ``select`` the first 12
        states, as the paper's LQI design does, for a rotor-only pair. ``require_stabilisable``
        raises ``ParameterError`` naming the offending modes (see ``uncontrollable_modes``).

        Parameters
        ----------
        dt : float, optional
            Sample time (s) for a discrete system; None (default): continuous.
        inputs : tuple of str, optional
            The inputs, as for ``input_matrix`` (default ``control_inputs``).
        name : str, optional
            The system's name in python-control.
        require_stabilisable : bool, optional
            Raise instead of returning a system that is not stabilisable.

        Returns
        -------
        control.StateSpace
        """
        import control

        inputs = self.control_inputs if inputs is None else tuple(inputs)
        B = self.input_matrix(inputs)
        if require_stabilisable:
            bad = self.uncontrollable_modes(inputs)
            if bad:
                modes = ", ".join(f"s = {s.real:.4g}{s.imag:+.4g}j (mostly {st})" for s, st in bad)
                why = (
                    f"; LN changes only through the reel rate (eq 37): add {REEL_RATE!r}"
                    if any(st == "LN" for _, st in bad) and REEL_RATE not in inputs
                    else ""
                )
                raise ParameterError(
                    "inputs",
                    inputs,
                    f"inputs from which (A, B) is stabilisable; uncontrollable and not stable "
                    f"(PBH): {modes}{why}",
                )
        D = np.zeros((self.C.shape[0], B.shape[1]))
        labels = {
            "states": list(self.state_names),
            "inputs": list(inputs),
            "outputs": list(OUTPUT),
            "name": name or ("tethered" if self.tethered else "free"),
        }
        if dt is None:
            return control.ss(self.A, B, self.C, D, **labels)
        G, H = discretize_zoh(self.A, B, dt)
        return control.ss(G, H, self.C, D, dt, **labels)


def linearize(model: TetheredHelicopter | FreeHelicopter, trim: TrimPoint) -> LinearModel:
    """Analytic linearization of ``model`` at ``trim`` (eqs 41-46).

    Inputs are the total rotor inputs (u0 - C_f-fwd at trim); the tethered model's state
    includes LN, with the reel rate as a separate input column ``B_reel``.

    Parameters
    ----------
    model : TetheredHelicopter or FreeHelicopter
        The model.
    trim : TrimPoint
        The hover to linearize about (``model.trim(...)``).

    Returns
    -------
    LinearModel
    """
    if isinstance(model, TetheredHelicopter):  # its tension's check of the state
        model._check_state(trim.x)
    return _linearize(model, trim)


def _linearize(model: TetheredHelicopter | FreeHelicopter, trim: TrimPoint) -> LinearModel:
    """``linearize`` about a trim the set-up solved (``model.trim._hover_trim`` on checked
    parameters): its state is not checked again."""
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
        law = model.params.tether  # eq 28's or the rope's (``TetherParams``), as model.tension
        tension = law.tension(x0[5], x0[12])
        tethered_jacobian(x0, u0, wind, tension, p, A12, B, E, E_T)
        tethered_output_jacobian(x0, p, C12)
        n = 13
        A = np.zeros((n, n))
        A[:12, :12] = A12
        if tension > 0.0:  # taut: eq 28's dTC = KC (dq9 - dLN), or the rope's
            dT_dq9, dT_dLN = law.stiffness(x0[5], x0[12])
            A[:12, 5] += E_T * dT_dq9
            A[:12, 12] += E_T * dT_dLN
        B_full = np.vstack([B, np.zeros((1, 4))])
        E_full = np.vstack([E, np.zeros((1, 3))])
        C = np.hstack([C12, np.zeros((4, 1))])
        B_reel = np.zeros(n)
        B_reel[12] = 1.0
        return LinearModel(
            A, B_full, C, E_full, B_reel, model.STATE, trim, model.params.helicopter.m
        )
    if isinstance(model, FreeHelicopter):
        free_jacobian(x0, u0, wind, 0.0, p, A12, B, E, E_T)
        free_output_jacobian(x0, p, C12)
        return LinearModel(
            A12, B, C12, E, np.zeros(12), model.STATE, trim, model.params.helicopter.m
        )
    raise TypeError(f"model must be a TetheredHelicopter or FreeHelicopter, not {type(model)}")
