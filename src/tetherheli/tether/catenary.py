"""The static tether: Irvine's elastic catenary between two points (``elastic_catenary``,
Irvine, *Cable Structures*, MIT Press 1981, ch. 1 and 2), the chain's start shape on it
(``initial_chain``), and the tether as a sensor with sag: the static cable
from the winch to P in a steady wind (``static_cable``), the encoders' catenary estimate of P
(``catenary_position_estimate``) and Sec. IV-F's straight-tether estimates it corrects
(``straight_tether_estimates``). Conventions (n3 up, the drag coefficients) are those of the
chain, ``tether.lumped``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy import optimize

from .._validation import check_number, check_vector
from ..errors import InfeasibleError, ParameterError
from ..layout import (
    LUMPED_CDN,
    LUMPED_CDT,
)
from ..model.kinematics import (
    tether_angles,
    tether_direction,
    tether_length_from_altitude,
    tethered_HO_position,
)

if TYPE_CHECKING:
    from .chain import LumpedTether
__all__ = [
    "ElasticCatenary",
    "StaticCable",
    "catenary_position_estimate",
    "elastic_catenary",
    "initial_chain",
    "static_cable",
    "straight_tether_estimates",
]

# ----------------------------------------------------------------------------------------------
# the elastic catenary (Irvine, Cable Structures, MIT Press 1981, ch. 1 and 2)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ElasticCatenary:
    """An elastic catenary between A (lower, s = 0) and B (s = L0) in the vertical plane, with
    horizontal span a [m] and rise b [m] of B over A; H the horizontal and V the vertical force
    the cable pulls A with, negated (the cable's tension at A is (H, V) along s).

    Lagrangian coordinate s in [0, L0] (unstretched arc length), w = mu g [N/m] (Irvine
    eqs 1.25-1.26 with the origin at A):
    x(s) = H s / EA + (H / w) [asinh((V + w s) / H) - asinh(V / H)],
    z(s) = (V s + w s^2 / 2) / EA + (H / w) [sqrt(1 + ((V + w s) / H)^2) - sqrt(1 + (V / H)^2)];
    for a = 0 (hanging vertically, H = 0): x = 0, z(s) = s + (V s + w s^2 / 2) / EA.

    Parameters
    ----------
    span_m : float
        Horizontal span a of B from A [m].
    rise_m : float
        Rise b of B over A [m].
    weight_per_length_N_m : float
        w = mu g [N/m].
    EA_N : float
        Axial stiffness [N].
    unstretched_length_m : float
        L0 [m].
    H_N, V_N : float
        The horizontal and vertical tension components at A [N].
    """

    span_m: float
    rise_m: float
    weight_per_length_N_m: float
    EA_N: float
    unstretched_length_m: float
    H_N: float
    V_N: float

    def position(self, s: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """(x(s), z(s)) [m] at unstretched arc length s [m] from A.

        Parameters
        ----------
        s : float or ndarray
            Unstretched arc length from A [m], in [0, L0].

        Returns
        -------
        x, z : ndarray
            Horizontal and vertical position from A [m], shaped as ``s``.
        """
        return _catenary_xz(
            np.asarray(s, dtype=float), self.H_N, self.V_N, self.weight_per_length_N_m, self.EA_N
        )

    @property
    def tension_A_N(self) -> float:
        """Tension at A [N]: sqrt(H^2 + V^2)."""
        return math.hypot(self.H_N, self.V_N)

    @property
    def tension_B_N(self) -> float:
        """Tension at B [N]: sqrt(H^2 + (V + w L0)^2)."""
        return math.hypot(
            self.H_N, self.V_N + self.weight_per_length_N_m * self.unstretched_length_m
        )

    def sag_m(self) -> float:
        """Largest vertical distance of the cable below the chord AB [m].

        Returns
        -------
        float
            The sag [m], from 2001 points along the cable.
        """
        s = np.linspace(0.0, self.unstretched_length_m, 2001)
        x, z = self.position(s)
        chord = self.rise_m * x / self.span_m if self.span_m > 0.0 else z
        return float(np.max(chord - z))


def _catenary_xz(s, H, V, w, EA):
    if H == 0.0:
        return np.zeros_like(s), s + (V * s + 0.5 * w * s * s) / EA
    x = H * s / EA + (H / w) * (np.arcsinh((V + w * s) / H) - np.arcsinh(V / H))
    z = (V * s + 0.5 * w * s * s) / EA + (H / w) * (
        np.hypot(1.0, (V + w * s) / H) - np.hypot(1.0, V / H)
    )
    return x, z


def elastic_catenary(
    span_m: float,
    rise_m: float,
    weight_per_length_N_m: float,
    EA_N: float,
    *,
    unstretched_length_m: float | None = None,
    horizontal_tension_N: float | None = None,
) -> ElasticCatenary:
    """Solve Irvine's elastic catenary for given end points and either the unstretched length
    or the horizontal tension (exactly one).

    Parameters
    ----------
    span_m, rise_m : float
        Horizontal distance a >= 0 and height b of the upper end B over A [m].
    weight_per_length_N_m : float
        w = mu g [N/m], > 0.
    EA_N : float
        Axial stiffness [N], > 0.
    unstretched_length_m, horizontal_tension_N : float
        L0 [m] or H [N] (H needs a > 0).

    Returns
    -------
    ElasticCatenary
        The solved cable (H, V at A).
    """
    a = check_number("span_m", span_m, low=0.0)
    b = check_number("rise_m", rise_m)
    w = check_number("weight_per_length_N_m", weight_per_length_N_m, low=0.0, low_open=True)
    EA = check_number("EA_N", EA_N, low=0.0, low_open=True)
    if (unstretched_length_m is None) == (horizontal_tension_N is None):
        raise ParameterError(
            "elastic_catenary",
            (unstretched_length_m, horizontal_tension_N),
            "exactly one of unstretched_length_m and horizontal_tension_N",
        )
    chord = math.hypot(a, b)
    if unstretched_length_m is not None:
        L0 = check_number("unstretched_length_m", unstretched_length_m, low=0.0, low_open=True)
        if a == 0.0:
            V = (b - L0) * EA / L0 - 0.5 * w * L0
            if V <= 0.0:
                raise InfeasibleError(
                    "unstretched_length_m", L0, f"a length that hangs taut over a rise of {b:g} m"
                )
            return ElasticCatenary(a, b, w, EA, L0, 0.0, V)
        H0, V0 = _guess(a, b, w, EA, L0, chord)

        def residual(u):
            x, z = _catenary_xz(np.array([L0]), math.exp(u[0]), u[1], w, EA)
            return [(x[0] - a) / chord, (z[0] - b) / chord]

        sol = optimize.root(residual, [math.log(H0), V0], method="hybr", tol=1e-14)
        H, V = math.exp(sol.x[0]), float(sol.x[1])
    else:
        H = check_number("horizontal_tension_N", horizontal_tension_N, low=0.0, low_open=True)
        if a == 0.0:
            raise ParameterError("span_m", a, "> 0 m with a horizontal tension given")

        def residual(u):
            x, z = _catenary_xz(np.array([math.exp(u[0])]), H, u[1], w, EA)
            return [(x[0] - a) / chord, (z[0] - b) / chord]

        V0 = H * b / a - 0.5 * w * chord
        sol = optimize.root(residual, [math.log(chord), V0], method="hybr", tol=1e-14)
        L0, V = math.exp(sol.x[0]), float(sol.x[1])
    if max(abs(r) for r in residual(sol.x)) > 1e-11:  # (hybr may flag xtol at 1e-14)
        raise InfeasibleError("elastic_catenary", (a, b), "end points the catenary can reach")
    return ElasticCatenary(a, b, w, EA, L0, H, V)


def _guess(a, b, w, EA, L0, chord):
    """Start values (H, V) for the solve: a straight stretched cable when L0 is shorter than
    the chord, else the parabolic sag f with L0 = chord + 8 f^2 / (3 chord)."""
    if L0 < chord:
        T = EA * (chord / L0 - 1.0) + 0.5 * w * L0
        return T * a / chord, T * b / chord - 0.5 * w * L0
    f = math.sqrt(3.0 * chord * (L0 - chord) / 8.0) + 1e-3 * chord
    H = w * a * a / (8.0 * f)
    return H, H * b / a - 0.5 * w * L0


def initial_chain(
    r_winch: np.ndarray, r_P: np.ndarray, L0: float, tether: LumpedTether, g: float
) -> np.ndarray:
    """Node positions (N+1, 3) [m] on the elastic catenary between the winch and P (nodes at
    s = i L0 / N), the start shape of a run (``static_chain`` refines it to the chain's own
    equilibrium).

    Parameters
    ----------
    r_winch, r_P : array_like, shape (3,)
        The fixed ends [m].
    L0 : float
        Unstretched length [m].
    tether : LumpedTether
        The tether (N segments, mu, EA).
    g : float
        Gravity [m/s^2].

    Returns
    -------
    ndarray, shape (N+1, 3)
        The node positions [m], rows 0 and N exactly the winch and P.
    """
    r_winch = np.asarray(r_winch, dtype=float)
    r_P = np.asarray(r_P, dtype=float)
    d = r_P - r_winch
    a = math.hypot(d[0], d[1])
    cat = elastic_catenary(
        a, d[2], tether.mass_per_length_kg_m * g, tether.EA_N, unstretched_length_m=L0
    )
    s = np.linspace(0.0, L0, tether.segments + 1)
    xs, zs = cat.position(s)
    horiz = np.array([d[0] / a, d[1] / a, 0.0]) if a > 0.0 else np.zeros(3)
    x = r_winch + np.outer(xs, horiz)
    x[:, 2] += zs
    x[0], x[-1] = r_winch, r_P  # exact ends
    return x


# ----------------------------------------------------------------------------------------------
# the tether as a sensor with sag
# ----------------------------------------------------------------------------------------------


def _cable_end(T0, L0, tether, g, wind):
    """Integrate the static cable from the winch (s = 0, tension vector T0 [N] along the cable)
    over its unstretched length L0 [m] in a steady uniform wind (3,) [m/s]: dT/ds = mu g n3 -
    drag, dr/ds = (1 + |T| / EA) T / |T|, the drag per stretched length that of
    ``chain_forces`` on a still cable (CDN |W_n| W_n + CDT |W_t| W_t). Returns r(L0), T(L0)."""
    from scipy.integrate import solve_ivp

    p = tether.packed(g)
    mu_g = tether.mass_per_length_kg_m * g
    EA = tether.EA_N
    W = np.asarray(wind, dtype=float)

    def rhs(_, y):
        T = y[3:]
        t = math.sqrt(T @ T)
        e = T / t
        lam = 1.0 + t / EA
        Wt = (W @ e) * e
        Wn = W - Wt
        drag = lam * (
            p[LUMPED_CDN] * math.sqrt(Wn @ Wn) * Wn + p[LUMPED_CDT] * math.sqrt(Wt @ Wt) * Wt
        )
        dT = -drag
        dT[2] += mu_g
        return np.concatenate([lam * e, dT]) * L0

    y0 = np.concatenate([np.zeros(3), T0])
    sol = solve_ivp(rhs, (0.0, 1.0), y0, method="DOP853", rtol=1e-12, atol=1e-12 * max(L0, 1.0))
    return sol.y[:3, -1], sol.y[3:, -1]


@dataclass(frozen=True)
class StaticCable:
    """A static cable from the winch (origin) to P in steady wind (``static_cable``).

    Parameters
    ----------
    r_P : ndarray, shape (3,)
        P relative to the winch [m].
    unstretched_length_m : float
        L0 [m].
    ground_tension : ndarray, shape (3,)
        The tension vector at the winch along the cable [N] (its direction the winch
        tangent).
    top_tension : ndarray, shape (3,)
        The tension vector at P [N] (the force on P is its negative).
    wind : ndarray, shape (3,)
        The steady wind [m/s].
    """

    r_P: np.ndarray
    unstretched_length_m: float
    ground_tension: np.ndarray
    top_tension: np.ndarray
    wind: np.ndarray

    @property
    def encoder_angles(self) -> tuple[float, float]:
        """(q7, q8) [rad] the ground joint's encoders read: the winch tangent
        e = c3 = [s8, -s7 c8, c7 c8] (eq 27)."""
        q7, q8, _ = tether_angles(self.ground_tension)  # model.kinematics, eq 27
        return float(q7), float(q8)


def static_cable(
    r_P: object,
    ground_tension_N: float,
    tether: LumpedTether,
    g: float,
    wind: object = (0.0, 0.0, 0.0),
) -> StaticCable:
    """The static cable from the winch at the origin to P for a given winch tension, in a
    steady uniform wind with drag on the cable (``_cable_end``): shooting on the ground
    tension's horizontal components and the unstretched length L0 (the vertical component
    sqrt(T_g^2 - Tx^2 - Ty^2) > 0: the cable leaves the winch upwards). Without wind it is
    Irvine's elastic catenary (a test checks it).

    Parameters
    ----------
    r_P : array_like, shape (3,)
        P relative to the winch [m], above it.
    ground_tension_N : float
        Tension at the winch [N], > 0.
    tether : LumpedTether
        The tether (mu, EA, drag).
    g : float
        Gravity [m/s^2].
    wind : array_like, shape (3,), optional
        Steady wind [m/s] (default none).

    Returns
    -------
    StaticCable
        The cable's unstretched length and end tensions.

    Raises
    ------
    InfeasibleError
        When no such cable leaves the winch upwards (a cable too heavy for the tension: it
        would lie on the ground).
    """
    d = np.array(check_vector("r_P", r_P, 3), dtype=float)
    if d[2] <= 0.0:
        raise ParameterError("r_P", d.tolist(), "a point above the winch (r_P[2] > 0 m)")
    T_g = check_number("ground_tension_N", ground_tension_N, low=0.0, low_open=True, unit="[N]")
    W = np.array(check_vector("wind", wind, 3), dtype=float)
    chord = float(np.linalg.norm(d))

    def unpack(z):
        hx, hy = z[0] * T_g, z[1] * T_g
        vz2 = T_g * T_g - hx * hx - hy * hy
        return hx, hy, vz2, chord * math.exp(z[2])

    def residual(z):
        hx, hy, vz2, L0 = unpack(z)
        if vz2 <= 0.0:
            return np.full(3, 1e3)
        r, _ = _cable_end(np.array([hx, hy, math.sqrt(vz2)]), L0, tether, g, W)
        return (r - d) / chord

    # start: the windless catenary's ground tangent (a straight stretched chord if it fails)
    e = d / chord
    z0 = np.array([e[0], e[1], math.log(1.0 / (1.0 + T_g / tether.EA_N))])
    sol = optimize.root(residual, z0, method="hybr", tol=1e-13)
    hx, hy, vz2, L0 = unpack(sol.x)
    if vz2 <= 0.0 or np.max(np.abs(residual(sol.x))) > 1e-9:
        raise InfeasibleError(
            "ground_tension_N",
            T_g,
            f"a tension that lifts the cable off the ground all the way to P at {d.tolist()} m "
            f"(mu = {tether.mass_per_length_kg_m:g} kg/m, wind {W.tolist()} m/s)",
        )
    T0 = np.array([hx, hy, math.sqrt(vz2)])
    _, Ttop = _cable_end(T0, L0, tether, g, W)
    return StaticCable(r_P=d, unstretched_length_m=L0, ground_tension=T0, top_tension=Ttop, wind=W)


def catenary_position_estimate(
    q7: float,
    q8: float,
    ground_tension_N: float,
    unstretched_length_m: float,
    tether: LumpedTether,
    g: float,
    wind: object = None,
) -> np.ndarray:
    """P relative to the winch [m] from the ground joint's encoders (the winch tangent
    c3(q7, q8)), the load cell's tension and the paid-out unstretched length: the elastic
    catenary (Irvine) integrated from the winch, H = T_g |c3_h|, V = T_g c3,3; with
    ``wind`` (3,) [m/s] the static cable with drag (``_cable_end``) instead. It corrects the
    sag bias of Sec. IV-F's straight-tether estimate (``sensing.sensors.tether_position_estimate``).

    Parameters
    ----------
    q7, q8 : float
        Encoder angles [rad].
    ground_tension_N : float
        Tension at the winch [N], > 0.
    unstretched_length_m : float
        Paid-out unstretched length L0 [m], > 0.
    tether : LumpedTether
        The tether (mu, EA, drag).
    g : float
        Gravity [m/s^2].
    wind : array_like, shape (3,), optional
        A known steady wind [m/s]; None (default): the catenary without drag.

    Returns
    -------
    ndarray, shape (3,)
        The estimate of P relative to the winch [m], along n1, n2, n3.
    """
    q7 = check_number("q7", q7)
    q8 = check_number("q8", q8)
    T_g = check_number("ground_tension_N", ground_tension_N, low=0.0, low_open=True, unit="[N]")
    L0 = check_number("unstretched_length_m", unstretched_length_m, low=0.0, low_open=True)
    e = tether_direction(q7, q8)  # c3 (eq 27)
    if wind is not None:
        r, _ = _cable_end(T_g * e, L0, tether, g, wind)
        return r
    eh = math.hypot(e[0], e[1])
    x, z = _catenary_xz(
        np.array([L0]), T_g * eh, T_g * e[2], tether.mass_per_length_kg_m * g, tether.EA_N
    )
    horiz = np.array([e[0] / eh, e[1] / eh, 0.0]) if eh > 0.0 else np.zeros(3)
    r = x[0] * horiz
    r[2] = z[0]
    return r


def straight_tether_estimates(cable: StaticCable, EA_N: float) -> tuple[np.ndarray, np.ndarray]:
    """Sec. IV-F's straight-tether estimates of P [m] from the winch-tangent angles of
    ``cable``: (i) with the altimeter (eq 45: the length from the true height of P,
    ``sensing.sensors.tether_position_estimate`` at zero arm, the attitude terms
    cancelling) and (ii) with the paid-out length as eq 28's stretched length
    L0 (1 + T_g / EA).

    Parameters
    ----------
    cable : StaticCable
        The cable whose winch tangent the encoders read.
    EA_N : float
        Axial stiffness [N], for the stretched length of (ii).

    Returns
    -------
    by_altimeter : ndarray, shape (3,)
        Estimate (i) of P [m].
    by_length : ndarray, shape (3,)
        Estimate (ii) of P [m].
    """
    q7, q8 = cable.encoder_angles
    # eq 45 at zero arm and attitude, as ``sensing.sensors.tether_position_estimate``
    q7a, q8a, height = (np.atleast_1d(float(v)) for v in (q7, q8, cable.r_P[2]))
    zero = np.zeros(1)
    q9 = tether_length_from_altitude(height, zero, zero, q7a, q8a, 0.0)
    alt = tethered_HO_position(zero, zero, q7a, q8a, q9, 0.0)[0]
    length = cable.unstretched_length_m * (1.0 + np.linalg.norm(cable.ground_tension) / EA_N)
    by_length = np.asarray(tethered_HO_position(0.0, 0.0, q7, q8, length, 0.0), dtype=float)
    return alt, by_length.reshape(3)
