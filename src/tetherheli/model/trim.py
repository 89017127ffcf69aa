"""Hover trim (paper Tables IV and V).

At hover q5 = q6 = q7 = q8 = 0 (tether vertical, docs/paper.md), all speeds are zero and the
winch's natural length is LN = q9 - TC / KC (eq 28). The unknowns [q4, q5, fMR3, tMR1, tMR2, fTR2]
solve u' = 0 (eqs 30-35) with the inputs of eq 54 at trim: the hover input u0|T plus minus the
feed-forward C_f-fwd (eq 55) that cancels the tether torque. Table V's inputs therefore exclude
the tether moment; the torque the rotor must actually produce about f1 is u0|T's tMR1 - C1.

In a steady wind force (``hover_trim(..., N_F_wind=F)``) the helicopter tilts and, tethered,
the tether leans: the outputs [q1, q2, q3, q6] are held where the windless trim puts them (the
controller's references, which its integral action restores), and q4, q5, q7, q8, q9 and the
four inputs solve the six dynamic equations and the three position equations.

The residuals evaluate the generated model code (``_generated``) as plain Python, not its
compiled kernels (``kernels``): a trim is a few dozen evaluations, and ``tetherheli trim``
then runs without importing Numba. The compiled kernels give the same values (they allow no
reassociation, see ``kernels``; a test compares the two routes' trims).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from .._validation import check_number, check_vector
from ..errors import InfeasibleError
from ..params import Params, check_tether_length
from . import _generated as gen
from .constants import model_constants

__all__ = ["TrimPoint", "check_trim_arguments", "hover_trim", "windless_trim"]


@dataclass(frozen=True)
class TrimPoint:
    """A hover equilibrium of the tethered model.

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        State q4..q9, u1..u6, LN (rad, m, m/s, rad/s, m).
    u : numpy.ndarray, shape (4,)
        Hover input u0 = (fMR3, tMR1, tMR2, fTR2) (N, N m, N m, N), excluding the tether
        torque (Tables IV, V).
    y : numpy.ndarray, shape (4,)
        Outputs q1, q2, q3, q6 (m, m, m, rad; eqs 43-45).
    tension : float
        TC at trim (N).
    feedforward : numpy.ndarray, shape (4,)
        C_f-fwd = (0, C1, C2, 0) at trim (N m, eq 55).
    """

    x: np.ndarray
    u: np.ndarray
    y: np.ndarray
    tension: float
    feedforward: np.ndarray

    @property
    def u_total(self) -> np.ndarray:
        """Inputs the rotors actually produce at trim, u0 - C_f-fwd (eq 54) (4,)."""
        return self.u - self.feedforward

    @property
    def t_MR1_total(self) -> float:
        """Total main-rotor torque about f1 at trim [N m]: u0|T's tMR1 minus C1."""
        return float(self.u_total[1])


def hover_trim(
    params: Params, tension: float, q9: float = 10.0, *, N_F_wind: object = None
) -> TrimPoint:
    """Hover trim with a given tether tension and length (Tables IV, V).

    With ``N_F_wind``, a constant wind force on HO, the trim in that wind: the outputs
    (q1, q2, q3, q6) equal the windless trim's (with the same ``tension``; ``q9`` is then the
    windless length, and the returned ``x`` holds the leaning tether's q7, q8, q9 and
    LN = q9 - tension / KC). None or a zero force gives the windless trim itself.

    Parameters
    ----------
    params : Params
        The parameter set.
    tension : float
        Tether tension TC at hover (N), >= 0; 0 gives Table IV's hover.
    q9 : float, optional
        Tether length (m); default 10 m.
    N_F_wind : array_like, shape (3,), optional
        Steady wind force on HO, N components (N).

    Returns
    -------
    TrimPoint

    Raises
    ------
    ParameterError
        A q9 outside ``params.TETHER_LENGTH_RANGE``.
    InfeasibleError
        A tension the tether cannot give at that length (``TetherParams.check_tension``) or
        a hover with no trim.
    """
    tension, q9 = check_trim_arguments(params, tension, q9)
    force = None if N_F_wind is None else np.array(check_vector("N_F_wind", N_F_wind, 3))
    return _hover_trim(params, tension, q9, force)


def check_trim_arguments(params: Params, tension: object, q9: object) -> tuple[float, float]:
    """The checks of a hover trim's tension and tether length (``hover_trim``; the public
    designs on a trim, e.g. ``control.tether_lqi.tethered_design``, check theirs with it).

    Parameters
    ----------
    params : Params
        The parameter set (its tether gives the largest tension at q9).
    tension : object
        Tether tension TC at hover [N], >= 0.
    q9 : object
        Tether length [m], in ``params.TETHER_LENGTH_RANGE``.

    Returns
    -------
    tension, q9 : float

    Raises
    ------
    ParameterError
        A tension that is not a number >= 0, or a q9 outside ``TETHER_LENGTH_RANGE``.
    InfeasibleError
        A tension the tether cannot give at that length (``TetherParams.check_tension``).
    """
    tension = check_number("tension", tension, low=0.0, unit="[N]")
    q9 = check_tether_length(q9, "q9")
    params.tether.check_tension(tension, q9, "tension")  # the natural length LN stays sensible
    return tension, q9


def _hover_trim(
    params: Params, tension: float, q9: float, force: np.ndarray | None = None
) -> TrimPoint:
    """``hover_trim`` of arguments already checked (a run's set-up from its ``Scenario``,
    which checked T_ref and q9 against the tether when it was built): no checks of them here;
    the trim's own failure (no hover found) still raises.

    Parameters
    ----------
    params : Params
        The parameter set.
    tension : float
        Tether tension TC at hover [N], a feasible one (``TetherParams.check_tension``).
    q9 : float
        Tether length [m], in ``params.TETHER_LENGTH_RANGE``.
    force : numpy.ndarray, shape (3,), optional
        Steady wind force on HO [N]; None or zero: the windless trim.

    Returns
    -------
    TrimPoint
    """
    point = _windless(params, tension, q9, params.tether.natural_length(q9, tension))
    if force is None or not np.any(force):
        return point
    return _trim_in_wind(params, point, force, model_constants("tethered", params.helicopter))


def _windless(params: Params, tension: float, q9: float, natural_length: float) -> TrimPoint:
    """``windless_trim``, solved once per parameter set, tension and length (``_kept_trim``;
    every trim in wind starts from it, e.g. at each turbulent episode of the Gymnasium
    environments): a copy of the kept point, whose arrays the caller may change."""
    try:
        kept = _kept_trim(params, tension, q9, natural_length)
    except TypeError:  # a parameter set that cannot be hashed: solved anew
        return windless_trim(params, tension, q9, natural_length)
    return TrimPoint(
        x=kept.x.copy(),
        u=kept.u.copy(),
        y=kept.y.copy(),
        tension=kept.tension,
        feedforward=kept.feedforward.copy(),
    )


def windless_trim(params: Params, tension: float, q9: float, natural_length: float) -> TrimPoint:
    """The windless hover trim (q5 = q7 = q8 = 0) with a force ``tension`` [N] pulling P
    straight down towards the ground joint at height ``q9`` [m]; ``natural_length`` [m] is
    stored in x[12] only (eq 28's LN; a lumped tether's unstretched length). Arguments are
    not validated (``hover_trim`` does it).

    Parameters
    ----------
    params : Params
        The helicopter's parameters (``params.helicopter``).
    tension : float
        Tether tension TC at P [N].
    q9 : float
        Distance from the ground joint to P [m].
    natural_length : float
        Unstretched tether length LN [m], stored in x[12].

    Returns
    -------
    TrimPoint
        The trim state (13,), inputs and feedforward, as ``hover_trim``'s.
    """
    h = params.helicopter
    p = model_constants("tethered", h)
    x = np.zeros(13)
    x[5] = q9
    x[12] = natural_length
    wind = np.zeros(3)
    out = np.empty(13)
    torque = np.empty(2)

    def assemble(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        xs = x.copy()
        xs[0], xs[1] = z[0], z[1]
        gen.tethered_tether_torque(xs, float(tension), p, torque)
        u0 = np.array([z[2], z[3], z[4], z[5]])
        ffwd = np.array([0.0, torque[0], torque[1], 0.0])
        return xs, u0, ffwd

    def residual(z: np.ndarray) -> np.ndarray:
        xs, u0, ffwd = assemble(z)
        gen.tethered_rhs(xs, u0 - ffwd, wind, float(tension), p, out)
        return out[6:12] * np.array([h.m, h.m, h.m, h.K4p4, h.K5p5, h.K6p6])

    # Closed-form start: lift balances weight plus tension, tail rotor balances rotor drag.
    lift = h.m * h.g + tension
    ratio = -h.rotor_drag_arm / h.d_O_TRO1
    q4 = math.atan(ratio)
    z0 = np.array(
        [q4, 0.0, lift * math.cos(q4), -h.d_O_HO3 * lift * math.sin(q4), 0.0, lift * math.sin(q4)]
    )
    sol = root(residual, z0, method="hybr", options={"xtol": 1e-15})
    scale = h.m * h.g
    if not np.all(np.isfinite(sol.x)) or np.max(np.abs(residual(sol.x))) > 1e-9 * scale:
        raise InfeasibleError(
            "trim", f"tension={tension}, q9={q9}", "a hover the helicopter can hold (no trim found)"
        )
    xs, u0, ffwd = assemble(sol.x)
    y = np.empty(4)
    gen.tethered_outputs(xs, p, y)
    return TrimPoint(x=xs, u=u0, y=y, tension=float(tension), feedforward=ffwd)


def _trim_in_wind(params: Params, base: TrimPoint, force: np.ndarray, p: np.ndarray) -> TrimPoint:
    """The trim in the constant wind force ``force`` [N] with ``base``'s outputs and tension;
    unknowns [q4, q5, q7, q8, q9, fMR3, tMR1, tMR2, fTR2]."""
    h = params.helicopter
    tension = base.tension
    out = np.empty(13)
    torque = np.empty(2)
    y = np.empty(4)
    # dynamic residuals in N and N m; position residuals in m, weighted by the weight [N/m]
    scale = np.array([h.m, h.m, h.m, h.K4p4, h.K5p5, h.K6p6])
    weight = h.m * h.g

    def assemble(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        xs = base.x.copy()
        xs[0], xs[1], xs[3], xs[4], xs[5] = z[0], z[1], z[2], z[3], z[4]
        xs[12] = params.tether.natural_length(z[4], tension)
        gen.tethered_tether_torque(xs, tension, p, torque)
        return xs, z[5:9].copy(), np.array([0.0, torque[0], torque[1], 0.0])

    def residual(z: np.ndarray) -> np.ndarray:
        xs, u0, ffwd = assemble(z)
        gen.tethered_rhs(xs, u0 - ffwd, force, tension, p, out)
        gen.tethered_outputs(xs, p, y)
        return np.concatenate([out[6:12] * scale, weight * (y[:3] - base.y[:3])])

    x0 = base.x
    z0 = np.array([x0[0], x0[1], x0[3], x0[4], x0[5], *base.u])
    # the windless q5, q7, q8, tMR2 are zero up to the solver's dust (e.g. 1e-42): zero them,
    # else MINPACK's finite-difference step, relative to |z|, underflows to a zero column
    z0[np.abs(z0) < 1e-12] = 0.0

    def solved(z: np.ndarray) -> bool:
        return bool(np.all(np.isfinite(z)) and np.max(np.abs(residual(z))) <= 1e-9 * weight)

    sol = root(residual, z0, method="hybr", options={"xtol": 1e-15})
    if not solved(sol.x):  # Powell's hybrid method can stall at this start; Levenberg-Marquardt
        sol = root(residual, z0, method="lm", options={"xtol": 1e-15, "ftol": 1e-15})
    if not solved(sol.x):
        raise InfeasibleError(
            "N_F_wind",
            f"{force.tolist()}",
            "a steady wind force the helicopter can hover in (no trim found)",
        )
    xs, u0, ffwd = assemble(sol.x)
    gen.tethered_outputs(xs, p, y)
    return TrimPoint(x=xs, u=u0, y=y.copy(), tension=tension, feedforward=ffwd)


_kept_trim = functools.lru_cache(maxsize=32)(windless_trim)
