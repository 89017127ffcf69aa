"""The lumped-mass tether's parameters and its Python-level helpers: ``LumpedTether`` (the
cable: mass, stiffness, damping, drag, ground contact; packed for the compiled step of
``tether.lumped``), the end forces and energy of a chain state (``end_forces``,
``chain_energy``) and its exact static equilibrium (``static_chain``). The chain's conventions
(segments, masses, drag, ground, end forces) are ``tether.lumped``'s module docstring."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np
from scipy import optimize

from .._validation import Key, check_number
from ..errors import InfeasibleError, ParameterError
from ..layout import (
    GROUND_DAMPING_PA_S_M,
    GROUND_FRICTION,
    GROUND_FRICTION_SPEED_M_S,
    GROUND_STIFFNESS_PA_M,
    LUMPED_BA,
    LUMPED_BASE_ACC,
    LUMPED_CDN,
    LUMPED_CDT,
    LUMPED_DAMPING,
    LUMPED_EA,
    LUMPED_FRICTION,
    LUMPED_FRICTION_SPEED,
    LUMPED_G,
    LUMPED_GROUND_C,
    LUMPED_GROUND_K,
    LUMPED_MU,
    LUMPED_SIZE,
)
from .catenary import ElasticCatenary, elastic_catenary
from .lumped import chain_forces

__all__ = [
    "AIR_DENSITY_KG_M3",
    "CABLE_KEYS",
    "LumpedTether",
    "chain_energy",
    "end_forces",
    "static_chain",
]

#: ISA sea-level air density [kg/m^3] (the default of ``wind.drag.DragModel`` too)
AIR_DENSITY_KG_M3 = 1.225


#: The cable's parameters described once (``Key``: meaning, unit, allowed values): the keys of a
#: scenario's ``[tether]`` table (``scenario.tables.TetherSettings``; the scenario reference
#: prints them) and the fields of ``tether.Cable`` and ``LumpedTether``, checked by the same
#: ``Key.check`` with the same bounds and messages. The scenario's EA also takes 0
#: (the paper's stiffness; any other value is checked by this key); the others are the same
#: everywhere.
CABLE_KEYS: dict[str, Key] = {
    "segments": Key("segments N of the lumped chain (N - 1 free nodes)", kind="integer", low=2,
                    high=1000),
    "mass_per_length": Key("mass per unstretched length (from the massless limit to a 1 t/m "
                           "chain)", "kg/m", low=1e-12, high=1000.0),
    "EA": Key("axial stiffness (at least an elastic cord's)", "N", low=1.0),
    "damping_ratio": Key("damping ratio of the cable's fundamental axial mode (ends fixed), "
                         "whatever N; 0 with internal_damping > 0", low=0.0, high=10.0),
    "internal_damping": Key("internal damping BA: axial damping force per unit strain rate "
                            "(MoorDyn's BA); 0: damping_ratio gives the damping", "N s",
                            low=0.0, high=1e9),
    "diameter": Key("cable diameter", "m", low=1e-6, high=1.0),
    "drag_coefficient": Key("normal (cross-flow) drag coefficient of the cable", low=0.0,
                            low_open=True, high=10.0),
    "tangential_drag_coefficient": Key("tangential (skin-friction) drag coefficient on the "
                                       "wetted area", low=0.0, high=10.0),
    "ground_stiffness": Key("the ground's normal stiffness kbot under the chain's free nodes, "
                            "per contact area d l0 (MoorDyn's seabed default; a cable at rest "
                            "sinks in by mass_per_length g / (kbot diameter)); 0: no ground",
                            "Pa/m", low=0.0, high=1e12),
    "ground_damping": Key("the ground's normal damping cbot per contact area (the default: the "
                          "default cable's critically damped contact)", "Pa s/m", low=0.0,
                          high=1e12),
    "ground_friction": Key("Coulomb friction coefficient of the cable on the ground (0: none)",
                           low=0.0, high=10.0),
    "ground_friction_speed": Key("the friction's regularisation speed: viscous below it", "m/s",
                                 low=1e-6, high=100.0),
}  # fmt: skip

#: ``LumpedTether``'s fields -> their ``CABLE_KEYS`` (the cable's names without the units)
_KEY_OF: dict[str, str] = {
    "segments": "segments",
    "mass_per_length_kg_m": "mass_per_length",
    "EA_N": "EA",
    "damping_ratio": "damping_ratio",
    "internal_damping_Ns": "internal_damping",
    "diameter_m": "diameter",
    "drag_coefficient": "drag_coefficient",
    "tangential_drag_coefficient": "tangential_drag_coefficient",
    "ground_stiffness_Pa_m": "ground_stiffness",
    "ground_damping_Pa_s_m": "ground_damping",
    "ground_friction": "ground_friction",
    "ground_friction_speed_m_s": "ground_friction_speed",
}


@dataclass(frozen=True)
class LumpedTether:
    """A lumped-mass tether's parameters (see the module docstring for the model). The
    defaults are the paper's tether (EA = K_C L0N = 40 N/m x 9.375 m, Table III) as a 20 g/m,
    5 mm cable with 10 % damping.

    Parameters
    ----------
    segments : int
        Number of segments N in [2, 1000] (N - 1 free nodes).
    mass_per_length_kg_m : float
        Mass per unstretched length mu [kg/m], > 0.
    EA_N : float
        Axial stiffness EA [N], > 0. ``from_paper_stiffness`` derives it from the paper's
        K_C: EA = K_C L0N (the whole tether's spring constant at its trim natural length).
    damping_ratio : float or None
        Damping ratio of the cable's fundamental axial mode (both ends fixed), >= 0, the same
        for every N (module docstring). None with ``internal_damping_Ns`` None: 0.1.
    internal_damping_Ns : float or None
        Internal damping BA [N s], >= 0: axial damping force per unit strain rate (MoorDyn's
        BA). Give this or ``damping_ratio``, not both.
    diameter_m : float
        Cable diameter d [m], > 0.
    drag_coefficient : float
        Normal (cross-flow) drag coefficient Cd, > 0 (about 1.0-1.2 for a round cable).
    tangential_drag_coefficient : float
        Skin-friction coefficient Ct on the wetted area pi d l, >= 0 (0: no tangential drag).
    air_density_kg_m3 : float
        rho [kg/m^3], > 0.
    ground_stiffness_Pa_m : float
        The ground's normal stiffness kbot [Pa/m] per contact area d l0, >= 0 (module
        docstring; ``GROUND_STIFFNESS_PA_M``); 0: no ground (the chain passes through z = 0,
        the airborne cable of the tests of its mechanics).
    ground_damping_Pa_s_m : float
        The ground's normal damping cbot [Pa s/m], >= 0 (``GROUND_DAMPING_PA_S_M``).
    ground_friction : float
        Coulomb friction coefficient mu_f on the ground, >= 0 (``GROUND_FRICTION``).
    ground_friction_speed_m_s : float
        The friction's regularisation speed v_f [m/s], > 0 (``GROUND_FRICTION_SPEED_M_S``).
    field_prefix : str
        The object named in error messages: "tether", with these field names; ``tether.Cable``
        "cable", with its own (``CABLE_KEYS``). Every field is checked by its ``CABLE_KEYS``
        entry, the rule of the scenario's ``[tether]`` table.
    """

    segments: int = 10
    mass_per_length_kg_m: float = 0.02
    EA_N: float = 375.0
    damping_ratio: float | None = None
    diameter_m: float = 0.005
    drag_coefficient: float = 1.1
    tangential_drag_coefficient: float = 0.0
    air_density_kg_m3: float = AIR_DENSITY_KG_M3
    internal_damping_Ns: float | None = None
    ground_stiffness_Pa_m: float = GROUND_STIFFNESS_PA_M
    ground_damping_Pa_s_m: float = GROUND_DAMPING_PA_S_M
    ground_friction: float = GROUND_FRICTION
    ground_friction_speed_m_s: float = GROUND_FRICTION_SPEED_M_S
    field_prefix: str = "tether"

    def __post_init__(self) -> None:
        s = self.field_prefix
        # the message names the field the caller wrote: LumpedTether's own ("tether.EA_N"),
        # or the cable's for ``tether.Cable`` ("cable.EA")
        names = {f: (f if s == "tether" else k) for f, k in _KEY_OF.items()}
        if self.damping_ratio is not None and self.internal_damping_Ns is not None:
            raise ParameterError(
                f"{s}.{names['internal_damping_Ns']}",
                self.internal_damping_Ns,
                f"no value when {s}.{names['damping_ratio']} is given (one or the other)",
            )
        self._derive()
        for name, key in _KEY_OF.items():
            value = getattr(self, name)
            if value is None and name in ("damping_ratio", "internal_damping_Ns"):
                continue
            object.__setattr__(self, name, CABLE_KEYS[key].check(f"{s}.{names[name]}", value))
        value = check_number(f"{s}.air_density_kg_m3", self.air_density_kg_m3, low=0.0,
                             low_open=True, unit="[kg/m^3]")  # fmt: skip
        object.__setattr__(self, "air_density_kg_m3", value)

    def _derive(self) -> None:
        """The default damping (a ratio of 0.1 when neither damping is given); also run by
        ``_validation.trusted``."""
        if self.damping_ratio is None and self.internal_damping_Ns is None:
            object.__setattr__(self, "damping_ratio", 0.1)

    def segment_dashpot(self, unstretched_length_m: float) -> float:
        """A segment's axial dashpot c [N s/m] at the unstretched length L0 (module
        docstring): zeta sqrt(EA mu) / sin(pi / (2 N)) or BA N / L0.

        Parameters
        ----------
        unstretched_length_m : float
            L0 [m], > 0.

        Returns
        -------
        float
            c [N s/m].
        """
        p = self._packed(0.0)
        return p[LUMPED_DAMPING] + p[LUMPED_BA] * self.segments / unstretched_length_m

    @classmethod
    def from_paper_stiffness(cls, K_C: float, natural_length_m: float, **kw) -> LumpedTether:
        """The tether whose whole-length spring constant at natural length L0N is the paper's
        K_C (eq 28, Table III): EA = K_C L0N [N].

        Parameters
        ----------
        K_C : float
            The paper's tether spring constant [N/m], > 0 (Table III: 40).
        natural_length_m : float
            The natural length L0N at which K_C holds [m], > 0.
        **kw
            The other fields of ``LumpedTether``.

        Returns
        -------
        LumpedTether
            The tether with EA_N = K_C L0N.
        """
        K_C = check_number("tether.K_C", K_C, low=0.0, low_open=True)
        L = check_number("tether.L_N0", natural_length_m, low=0.0, low_open=True)
        return cls._from_paper_stiffness(K_C, L, cls, **kw)

    @classmethod
    def _from_paper_stiffness(
        cls, K_C: float, natural_length_m: float, build: Callable[..., LumpedTether], **kw
    ) -> LumpedTether:
        """EA = K_C L0N of checked K_C and L0N, the tether made by ``build``: the class (its
        fields checked) or ``functools.partial(_validation.trusted, LumpedTether)`` (a run's
        set-up: its fields the scenario's, checked)."""
        return build(EA_N=K_C * natural_length_m, **kw)

    def packed(self, g: float) -> np.ndarray:
        """The packed array (``layout.LUMPED_*``) the compiled kernels take.

        Parameters
        ----------
        g : float
            Gravity [m/s^2], >= 0.

        Returns
        -------
        ndarray, shape (LUMPED_SIZE,)
            mu [kg/m], EA [N], the damping ratio's segment dashpot
            zeta sqrt(EA mu) / sin(pi / (2 N)) [N s/m], the normal and tangential drag factors
            rho d Cd / 2 and rho pi d Ct / 2 [kg/m^2], g [m/s^2], the internal damping BA
            [N s] (one of the two dampings is zero), the ground's kbot d [N/m^2] and
            cbot d [N s/m^2], mu_f and v_f [m/s], and the base's acceleration (3,) [m/s^2]
            (zero here; the engine sets it over a moving base).
        """
        return self._packed(check_number("g", g, low=0.0))

    def _packed(self, g: float) -> np.ndarray:
        """``packed`` of a gravity already checked (a run's set-up: ``params.helicopter.g``)."""
        p = np.empty(LUMPED_SIZE)
        p[LUMPED_MU] = self.mass_per_length_kg_m
        p[LUMPED_EA] = self.EA_N
        zeta = self.damping_ratio or 0.0
        p[LUMPED_DAMPING] = (
            zeta
            * math.sqrt(self.EA_N * self.mass_per_length_kg_m)
            / math.sin(math.pi / (2.0 * self.segments))
        )
        p[LUMPED_BA] = self.internal_damping_Ns or 0.0
        p[LUMPED_CDN] = 0.5 * self.air_density_kg_m3 * self.diameter_m * self.drag_coefficient
        p[LUMPED_CDT] = (
            0.5 * self.air_density_kg_m3 * math.pi * self.diameter_m
        ) * self.tangential_drag_coefficient
        p[LUMPED_G] = g
        p[LUMPED_GROUND_K] = self.ground_stiffness_Pa_m * self.diameter_m
        p[LUMPED_GROUND_C] = self.ground_damping_Pa_s_m * self.diameter_m
        p[LUMPED_FRICTION] = self.ground_friction
        p[LUMPED_FRICTION_SPEED] = self.ground_friction_speed_m_s
        p[LUMPED_BASE_ACC : LUMPED_BASE_ACC + 3] = 0.0  # set per step over a moving base
        return p


# ----------------------------------------------------------------------------------------------
# Python-level helpers
# ----------------------------------------------------------------------------------------------


def _scratch(n: int) -> tuple[np.ndarray, ...]:
    return (
        np.empty((n + 1, 3)),
        np.empty(n),
        np.empty((n, 3, 3)),
        np.empty((n, 3, 3)),
        np.empty((n, 3, 3)),
    )


def end_forces(
    x: np.ndarray, v: np.ndarray, wind: np.ndarray, L0: float, p: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The forces the tether exerts on the winch and on P [N] (each with half an end segment's
    weight and drag) and the segment tensions (N,) [N].

    Parameters
    ----------
    x, v : ndarray (N+1, 3)
        Node positions [m] and velocities [m/s], row 0 the winch, row N the point P.
    wind : ndarray (N+1, 3)
        Wind at the nodes [m/s].
    L0 : float
        Unstretched length [m].
    p : ndarray
        ``LumpedTether.packed(g)``.

    Returns
    -------
    force_winch, force_P : ndarray, shape (3,)
        The forces on the winch and on P [N], along n1, n2, n3.
    tensions : ndarray, shape (N,)
        The segment tensions [N].
    """
    F, T, K, C, D = _scratch(x.shape[0] - 1)
    chain_forces(x, v, wind, L0, p, F, T, (K, C, D), False)
    return F[0].copy(), F[-1].copy(), T


def chain_energy(x: np.ndarray, v: np.ndarray, L0: float, p: np.ndarray) -> float:
    """Kinetic + gravitational + elastic energy [J] of the free nodes and the segments, with
    the ground's spring 1/2 kbot d l0 z^2 of every free node below z = 0 (the end nodes'
    half-segment masses are not counted: it is conserved with fixed ends, no damping, no
    drag and no ground contact; the ground's damping and friction only take energy out).

    Parameters
    ----------
    x, v : ndarray, shape (N+1, 3)
        Node positions [m] and velocities [m/s].
    L0 : float
        Unstretched length [m].
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.

    Returns
    -------
    float
        The energy [J].
    """
    n = x.shape[0] - 1
    l0 = L0 / n
    m = p[LUMPED_MU] * l0
    kinetic = 0.5 * m * float(np.sum(v[1:-1] ** 2))
    gravity = m * p[LUMPED_G] * float(np.sum(x[1:-1, 2]))
    stretch = np.maximum(np.linalg.norm(np.diff(x, axis=0), axis=1) - l0, 0.0)
    sunk = np.minimum(x[1:-1, 2], 0.0)  # the free nodes' penetration of the ground
    ground = 0.5 * p[LUMPED_GROUND_K] * l0 * float(np.sum(sunk**2))
    return kinetic + gravity + 0.5 * (p[LUMPED_EA] / l0) * float(np.sum(stretch**2)) + ground


def static_chain(
    r_winch: np.ndarray,
    r_P: np.ndarray,
    L0: float,
    tether: LumpedTether,
    g: float,
    *,
    ground_tension_N: float | None = None,
) -> np.ndarray:
    """The lumped chain's exact static equilibrium (no wind, at rest) between the winch and P:
    the discrete catenary. Every free node carries W = mu l0 g, so segment s pulls its lower
    node with the tension vector (H h, V + s W) (h the horizontal unit vector towards P) and
    its length is l0 (1 + |t_s| / EA); (H, V) solve sum_s d_s = r_P - r_winch (SciPy ``root``
    from the elastic catenary's values).

    Parameters
    ----------
    r_winch, r_P, L0, tether, g
        As for ``catenary.initial_chain``, its start.
    ground_tension_N : float, optional
        The tension at the winch of a vertical chain (P straight above the winch) when it is
        known (``hover_trim_lumped``): the start value of the solve instead of the elastic
        catenary's, which a stiff cable cannot give (its stretch is below rounding).

    Returns
    -------
    ndarray, shape (N+1, 3)
        The node positions [m] (``chain_forces`` vanishes there on the free nodes; a test
        checks it).
    """
    r_winch = np.asarray(r_winch, dtype=float)
    r_P = np.asarray(r_P, dtype=float)
    d = r_P - r_winch
    a = math.hypot(d[0], d[1])
    n = tether.segments
    l0 = L0 / n
    W = tether.mass_per_length_kg_m * l0 * g
    EA = tether.EA_N
    vertical_guess = a == 0.0 and ground_tension_N is not None
    cat = (
        ElasticCatenary(
            0.0, d[2], tether.mass_per_length_kg_m * g, EA, L0, 0.0, cast(float, ground_tension_N)
        )  # not None: vertical_guess
        if vertical_guess
        else elastic_catenary(a, d[2], tether.mass_per_length_kg_m * g, EA, unstretched_length_m=L0)
    )
    vert = np.arange(n) * W

    def segments(H, V):
        tz = V + vert
        t = np.hypot(H, tz)
        stretch = l0 * (1.0 / t + 1.0 / EA)  # segment length / |t_s|
        return H * stretch, tz * stretch

    scale = max(math.hypot(a, d[2]), 1e-9)
    if a == 0.0:

        def residual(u):
            return [(np.sum(segments(0.0, u[0])[1]) - d[2]) / scale]

        sol = optimize.root(residual, [cat.V_N + 0.5 * W], method="hybr", tol=1e-14)
        H, V = 0.0, float(sol.x[0])
    else:

        def residual(u):
            sx, sz = segments(u[0], u[1])
            return [(np.sum(sx) - a) / scale, (np.sum(sz) - d[2]) / scale]

        sol = optimize.root(residual, [cat.H_N, cat.V_N + 0.5 * W], method="hybr", tol=1e-14)
        H, V = (float(u) for u in sol.x)
    if max(abs(r) for r in residual(sol.x)) > 1e-11:
        raise InfeasibleError("static_chain", (a, d[2]), "end points the chain can reach")
    sx, sz = segments(H, V)
    horiz = np.array([d[0] / a, d[1] / a, 0.0]) if a > 0.0 else np.zeros(3)
    x = np.empty((n + 1, 3))
    x[0] = r_winch
    x[1:] = r_winch + np.outer(np.cumsum(sx), horiz)
    x[1:, 2] += np.cumsum(sz)
    x[-1] = r_P
    return x
