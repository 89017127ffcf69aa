"""A tether with mass, sag and drag: a lumped-mass chain, its stiff-stable step and its static
equilibrium (``static_chain``; the elastic catenary it converges to is in ``tether.catenary``,
the hover trim with such a tether in ``tether.lumped_trim``).

The chain has N straight segments between N + 1 nodes: node 0 is the ground winch (fixed over a
step), node N is the attachment point P (driven: its position and velocity are given), nodes
1..N-1 are free point masses. Conventions:

- Unstretched length: **uniform re-discretisation**. All segments share the unstretched length
  l0 = L0 / N; a winch that pays out changes L0, hence l0 and the node masses, of every segment
  at once (no node is created or removed, so the state keeps its size; the arrays of a run are
  fixed). L0 is held constant over one step.
- Masses: a segment's mass mu l0 is split half to each of its end nodes. The interior nodes
  carry mu l0; the half segments at the ends act on the winch and on P as part of the end
  force (their weight), not as inertia of the chain.
- Axial force of segment s (nodes s, s+1; d = x[s+1] - x[s], l = |d|, e = d / l):
  T = k (l - l0) + c dl/dt with k = EA / l0 when l > l0 and T >= 0, else 0 (slack: no
  compression, no pushing damper). The dashpot c is a property of the cable (issue 23): from
  the internal damping BA [N s] (force per unit strain rate, MoorDyn's BA), c = BA / l0; from
  the damping ratio zeta of the cable's fundamental axial mode (both ends fixed),
  c = zeta sqrt(EA mu) / sin(pi / (2 N)). The chain's damping matrix is then (c / k) times
  its stiffness matrix, so mode j has the ratio c omega_j / (2 k), and the fundamental one,
  omega_1 = 2 sqrt(k / m) sin(pi / (2 N)), exactly zeta for every N and every length (the
  continuous cable: BA = 2 zeta L0 sqrt(EA mu) / pi). (Before issue 23 zeta was the ratio of
  one segment, c = 2 zeta sqrt(EA mu), so the cable's damping fell as N grew.)
- Drag on segment s from the air-relative velocity at its middle, u = (v[s] + v[s+1]) / 2 -
  (w[s] + w[s+1]) / 2 (w: the wind per node): normal part u_n = u - (u.e) e, tangential part
  u_t = (u.e) e; F = -0.5 rho d l Cd |u_n| u_n - 0.5 rho pi d l Ct |u_t| u_t (the normal drag
  on the projected area d l, the tangential on the wetted area pi d l; Hoerner's cross-flow
  principle), half of it on each end node.
- Gravity -g n3 (SPEC.md: n3 up).
- Ground: the plane z = 0 of N through the winch (node 0), under the free nodes 1..N-1 only
  (P is the helicopter's, whose ground contact is a failure status). As MoorDyn's seabed
  (Hall, MoorDyn v2 theory), a node below it rests on its contact patch A = d l0 with the
  normal force F_n = max(0, kbot A (-z) - cbot A v_z) (kbot [Pa/m], cbot [Pa s/m]) and the
  regularised Coulomb friction F_f = -mu_f F_n v_t / max(|v_t|, v_f) on its horizontal
  velocity v_t (viscous below the speed v_f; it never does work on the node, F_f . v_t <= 0).
  A cable lying still sinks in by its static penetration mu g / (kbot d) (a test checks
  it); the spring's energy 1/2 kbot A z^2 belongs to ``chain_energy``. kbot = 0: no ground.
- End forces: the force the tether exerts on P is -T e of the top segment plus half the top
  segment's weight and drag; on the winch, +T e of the bottom segment plus half the bottom
  segment's weight and drag. With this convention the static chain converges to the elastic
  catenary at order 2 in N (a test checks it; the raw end-segment tension converges at
  order 1 only).

The step is the two-stage Rosenbrock method ROS2 of Verwer, Spee, Blom and Hundsdorfer
(SIAM J. Sci. Comput. 20, 1999), gamma = 1 + 1/sqrt(2): L-stable, second order for any
approximation W of the Jacobian. W holds the axial and geometric stiffness
k e e^T + (T / l)(I - e e^T), the axial damping c e e^T and the drag's velocity derivative; the
non-autonomous term (P moves) enters through dF/dt = K_P v_P + C_P a_P of the last interior
node. A slack segment keeps the axial blocks of a just-taut one in W: a step that starts slack
and ends taut then stays implicit (with the exact, zero, blocks a stiff cable that snaps taut
blows up at the control sample; a test covers the case). Each stage solves one symmetric
block-tridiagonal system of 3 x 3 blocks (block Thomas, O(N)). The test module measures the
step against SciPy's Radau at tight tolerances.

Coupling: the force at P enters the tethered helicopter's generated equations as a wind force
at HO plus the rotor torques of its moment about HO (``force_at_P_as_loads``), with eq 28's
tension set to zero; q7..q9 then only locate P.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from .._compile import compiled
from .._validation import check_integer, check_number
from ..errors import InfeasibleError, ParameterError
from ..layout import (
    GROUND_DAMPING_PA_S_M,
    GROUND_FRICTION,
    GROUND_FRICTION_SPEED_M_S,
    GROUND_STIFFNESS_PA_M,
    LUMPED_BA,
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
from ..model import kernels
from .catenary import ElasticCatenary, elastic_catenary

__all__ = [
    "CHAIN_OMEGA_H",
    "ROS2_GAMMA",
    "LumpedTether",
    "chain_energy",
    "chain_forces",
    "chain_interval",
    "chain_omega_max",
    "chain_substeps",
    "coupling_substeps",
    "end_forces",
    "force_at_P_as_loads",
    "ground_force",
    "ground_jacobian",
    "ros2_step",
    "ros2_work",
    "ros2_work_size",
    "static_chain",
    "tethered_derivative_force_at_P",
]

#: ROS2's gamma (Verwer et al. 1999): 1 + 1/sqrt(2), the L-stable choice
ROS2_GAMMA = 1.0 + 1.0 / math.sqrt(2.0)
#: ISA sea-level air density [kg/m^3] (the default of ``wind.drag.DragModel`` too)
AIR_DENSITY_KG_M3 = 1.225

_jit = compiled(fastmath={"nnan", "ninf"}, error_model="numpy")


@dataclass(frozen=True)
class LumpedTether:
    """A lumped-mass tether's parameters (see the module docstring for the model). The
    defaults are the paper's tether (EA = K_C L0N = 40 N/m x 9.375 m, Table III) as a 20 g/m,
    5 mm cable with 10 % damping.

    Parameters
    ----------
    segments : int
        Number of segments N >= 1 (N - 1 free nodes).
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
        The table named in error messages ("tether"; ``tether.Cable``: "cable").
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
        names = {
            "damping_ratio": "damping_ratio",
            "internal_damping_Ns": "internal_damping",
            "ground_stiffness_Pa_m": "ground_stiffness",
            "ground_damping_Pa_s_m": "ground_damping",
            "ground_friction": "ground_friction",
            "ground_friction_speed_m_s": "ground_friction_speed",
        }
        if s == "tether":
            names = {k: k for k in names}
        if self.damping_ratio is not None and self.internal_damping_Ns is not None:
            raise ParameterError(
                f"{s}.{names['internal_damping_Ns']}",
                self.internal_damping_Ns,
                f"no value when {s}.{names['damping_ratio']} is given (one or the other)",
            )
        if self.damping_ratio is None and self.internal_damping_Ns is None:
            object.__setattr__(self, "damping_ratio", 0.1)
        for name in ("damping_ratio", "internal_damping_Ns"):
            if getattr(self, name) is not None:
                value = check_number(f"{s}.{names[name]}", getattr(self, name), low=0.0)
                object.__setattr__(self, name, value)
        check_integer(f"{s}.segments", self.segments, low=1)
        for name, low_open in (
            ("mass_per_length_kg_m", True),
            ("EA_N", True),
            ("diameter_m", True),
            ("drag_coefficient", True),
            ("tangential_drag_coefficient", False),
            ("air_density_kg_m3", True),
        ):
            value = check_number(f"{s}.{name}", getattr(self, name), low=0.0, low_open=low_open)
            object.__setattr__(self, name, value)
        object.__setattr__(self, "segments", int(self.segments))
        for name, low_open in (
            ("ground_stiffness_Pa_m", False),
            ("ground_damping_Pa_s_m", False),
            ("ground_friction", False),
            ("ground_friction_speed_m_s", True),
        ):
            value = check_number(f"{s}.{names[name]}", getattr(self, name), low=0.0,
                                 low_open=low_open)  # fmt: skip
            object.__setattr__(self, name, value)

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
        p = self.packed(0.0)
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
        return cls(EA_N=K_C * L, **kw)

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
            cbot d [N s/m^2], mu_f and v_f [m/s].
        """
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
        p[LUMPED_G] = check_number("g", g, low=0.0)
        p[LUMPED_GROUND_K] = self.ground_stiffness_Pa_m * self.diameter_m
        p[LUMPED_GROUND_C] = self.ground_damping_Pa_s_m * self.diameter_m
        p[LUMPED_FRICTION] = self.ground_friction
        p[LUMPED_FRICTION_SPEED] = self.ground_friction_speed_m_s
        return p


# ----------------------------------------------------------------------------------------------
# compiled kernels: x, v (N+1, 3) node positions and velocities (rows 0 and N: winch and P)
# ----------------------------------------------------------------------------------------------


@_jit
def chain_forces(x, v, wind, L0, p, F, T, K, Cax, D, jac):
    """Node forces F (N+1, 3) [N] (rows 0 and N: the force on the winch and on P, with half an
    end segment's weight and drag), segment tensions T (N,) [N]; if ``jac``, the per-segment
    Jacobian blocks (N, 3, 3): K = d(T e)/d(d) (axial + geometric stiffness),
    Cax = d(T e)/d(dv) (axial damping), D = -d(drag)/du (drag's velocity derivative); a slack
    segment gets the axial blocks of a just-taut one.

    Parameters
    ----------
    x, v : ndarray, shape (N+1, 3)
        Node positions [m] and velocities [m/s], row 0 the winch, row N the point P.
    wind : ndarray, shape (N+1, 3)
        Wind at the nodes [m/s].
    L0 : float
        Unstretched length [m].
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.
    F : ndarray, shape (N+1, 3)
        Receives the node forces [N].
    T : ndarray, shape (N,)
        Receives the segment tensions [N].
    K, Cax, D : ndarray, shape (N, 3, 3)
        Receive the Jacobian blocks [N/m, N s/m, N s/m] when ``jac``.
    jac : bool
        Whether to fill K, Cax, D.

    Returns
    -------
    None
    """
    n = x.shape[0] - 1
    l0 = L0 / n
    mu = p[LUMPED_MU]
    k = p[LUMPED_EA] / l0
    c = p[LUMPED_DAMPING] + p[LUMPED_BA] / l0
    cdn = p[LUMPED_CDN]
    cdt = p[LUMPED_CDT]
    w_half = 0.5 * mu * l0 * p[LUMPED_G]
    for i in range(n + 1):
        F[i, 0] = 0.0
        F[i, 1] = 0.0
        F[i, 2] = -2.0 * w_half if 0 < i < n else -w_half
    for s in range(n):
        ex = x[s + 1, 0] - x[s, 0]
        ey = x[s + 1, 1] - x[s, 1]
        ez = x[s + 1, 2] - x[s, 2]
        length = math.sqrt(ex * ex + ey * ey + ez * ez)
        ex /= length
        ey /= length
        ez /= length
        ldot = (
            ex * (v[s + 1, 0] - v[s, 0])
            + ey * (v[s + 1, 1] - v[s, 1])
            + ez * (v[s + 1, 2] - v[s, 2])
        )
        tension = k * (length - l0) + c * ldot if length > l0 else 0.0
        if tension < 0.0:
            tension = 0.0
        T[s] = tension
        ux = 0.5 * (v[s, 0] + v[s + 1, 0] - wind[s, 0] - wind[s + 1, 0])
        uy = 0.5 * (v[s, 1] + v[s + 1, 1] - wind[s, 1] - wind[s + 1, 1])
        uz = 0.5 * (v[s, 2] + v[s + 1, 2] - wind[s, 2] - wind[s + 1, 2])
        ue = ux * ex + uy * ey + uz * ez
        ux -= ue * ex
        uy -= ue * ey
        uz -= ue * ez
        speed_n = math.sqrt(ux * ux + uy * uy + uz * uz)
        an = cdn * length * speed_n  # normal drag = -an u_n
        at = cdt * length * abs(ue)  # tangential drag = -at (u.e) e
        fx = tension * ex - 0.5 * (an * ux + at * ue * ex)
        fy = tension * ey - 0.5 * (an * uy + at * ue * ey)
        fz = tension * ez - 0.5 * (an * uz + at * ue * ez)
        dx = 0.5 * (an * ux + at * ue * ex)
        dy = 0.5 * (an * uy + at * ue * ey)
        dz = 0.5 * (an * uz + at * ue * ez)
        F[s, 0] += fx
        F[s, 1] += fy
        F[s, 2] += fz
        F[s + 1, 0] += -tension * ex - dx
        F[s + 1, 1] += -tension * ey - dy
        F[s + 1, 2] += -tension * ez - dz
        if jac:
            # W keeps a slack segment's axial stiffness and damping (as if just taut): a step
            # that starts slack and ends taut stays implicit (no snap blow-up); ROS2 keeps its
            # order 2 for any W
            geo = tension / length
            e = (ex, ey, ez)
            un = (ux, uy, uz)
            inv_speed = 1.0 / speed_n if speed_n > 0.0 else 0.0
            for a in range(3):
                for b in range(3):
                    eab = e[a] * e[b]
                    proj = (1.0 if a == b else 0.0) - eab
                    K[s, a, b] = k * eab + geo * proj
                    Cax[s, a, b] = c * eab
                    D[s, a, b] = (
                        cdn * length * (speed_n * proj + un[a] * un[b] * inv_speed) + 2.0 * at * eab
                    )
    kg = p[LUMPED_GROUND_K] * l0
    cg = p[LUMPED_GROUND_C] * l0
    for i in range(1, n):
        if kg > 0.0 and x[i, 2] < 0.0:
            fx, fy, fz = ground_force(x[i, 2], v[i, 0], v[i, 1], v[i, 2], kg, cg, p)
            F[i, 0] += fx
            F[i, 1] += fy
            F[i, 2] += fz


@_jit
def ground_force(z, vx, vy, vz, kg, cg, p):
    """The ground's force (3,) [N] on a free node at height z < 0 [m] moving at (vx, vy, vz)
    [m/s] (module docstring): F_n = max(0, -kg z - cg vz) along n3 and the regularised
    Coulomb friction -mu_f F_n v_t / max(|v_t|, v_f) on the horizontal velocity v_t.

    Parameters
    ----------
    z : float
        The node's height [m], < 0 (in the ground).
    vx, vy, vz : float
        The node's velocity [m/s].
    kg, cg : float
        The node's contact stiffness kbot d l0 [N/m] and damping cbot d l0 [N s/m].
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)`` (mu_f, v_f).

    Returns
    -------
    tuple of float
        (F_x, F_y, F_z) [N].
    """
    fn = -kg * z - cg * vz
    if fn <= 0.0:
        return 0.0, 0.0, 0.0
    speed = math.sqrt(vx * vx + vy * vy)
    scale = p[LUMPED_FRICTION] * fn / max(speed, p[LUMPED_FRICTION_SPEED])
    return -scale * vx, -scale * vy, fn


@_jit
def ground_jacobian(x, v, L0, p, h, Gk, Gc):
    """The ground's blocks of the ROS2 matrix W for the free nodes, Gk (N+1,) [N/m] the
    normal stiffness -dF_z/dz and Gc (N+1, 3, 3) [N s/m] the damping -dF/dv (normal damping,
    and the friction as a horizontal viscous damper mu_f F_n / max(|v_t|, v_f) at the normal
    force max(F_n, the node's weight)),
    for every node in the ground or reaching it within 2 h at its velocity (so that a step
    that hits the ground stays implicit, as a slack segment's W does); zero elsewhere.

    Parameters
    ----------
    x, v : ndarray, shape (N+1, 3)
        Node positions [m] and velocities [m/s].
    L0 : float
        Unstretched length [m].
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.
    h : float
        The step [s].
    Gk : ndarray, shape (N+1,)
        Receives the normal stiffness [N/m].
    Gc : ndarray, shape (N+1, 3, 3)
        Receives the damping blocks [N s/m].

    Returns
    -------
    None
    """
    n = x.shape[0] - 1
    l0 = L0 / n
    kg = p[LUMPED_GROUND_K] * l0
    cg = p[LUMPED_GROUND_C] * l0
    weight = p[LUMPED_MU] * l0 * p[LUMPED_G]
    vf = p[LUMPED_FRICTION_SPEED]
    for i in range(n + 1):
        Gk[i] = 0.0
        for a in range(3):
            for b in range(3):
                Gc[i, a, b] = 0.0
        z = x[i, 2]
        if kg == 0.0 or i == 0 or i == n or z + 2.0 * h * min(v[i, 2], 0.0) >= 0.0:
            continue
        Gk[i] = kg
        Gc[i, 2, 2] = cg
        # the friction as the viscous damper it equals at this speed, mu_f F_n / max(|v_t|, v_f)
        # in both directions (a secant, not the tangent, whose along-motion part is zero: with
        # it a sliding node stalls at a speed where the stages' friction flips sign)
        fn = max(-kg * z - cg * v[i, 2], weight)
        speed = math.sqrt(v[i, 0] ** 2 + v[i, 1] ** 2)
        Gc[i, 0, 0] = Gc[i, 1, 1] = p[LUMPED_FRICTION] * fn / max(speed, vf)


@_jit
def _factor(n_free, m_node, K, Cax, D, Gk, Gc, cm, cc, ck, Dinv, B, piv, db):
    """Factor the symmetric block-tridiagonal matrix A = cm M + cc C + ck Kn of the free nodes
    (Kn = dF/dx, C = dF/dv assembled from the segment blocks and the ground's node blocks Gk,
    Gc of ``ground_jacobian``) by block Thomas: Dinv (n_free, 3, 3) the inverted pivots,
    B (n_free, 3, 3) the super-diagonal blocks A[i, i+1]; piv, db (3, 3) scratch."""
    for i in range(n_free):
        s_lo = i  # segment below free node i (nodes i, i+1 of the chain)
        s_hi = i + 1  # segment above
        for a in range(3):
            for b in range(3):
                # dF/dx diagonal: -(K_lo + K_hi); dF/dv diagonal: -(Cax + D/4) of both
                kd = -(K[s_lo, a, b] + K[s_hi, a, b])
                if a == 2 and b == 2:
                    kd -= Gk[i + 1]
                cd = -(Cax[s_lo, a, b] + Cax[s_hi, a, b]) - 0.25 * (D[s_lo, a, b] + D[s_hi, a, b])
                cd -= Gc[i + 1, a, b]
                piv[a, b] = cc * cd + ck * kd + (cm * m_node if a == b else 0.0)
                # off-diagonal (i, i+1) through segment s_hi: dF/dx = +K, dF/dv = Cax - D/4
                B[i, a, b] = ck * K[s_hi, a, b] + cc * (Cax[s_hi, a, b] - 0.25 * D[s_hi, a, b])
        if i > 0:  # piv -= B_{i-1}^T (Dinv_{i-1} B_{i-1})
            for q in range(3):
                for b in range(3):
                    db[q, b] = (
                        Dinv[i - 1, q, 0] * B[i - 1, 0, b]
                        + Dinv[i - 1, q, 1] * B[i - 1, 1, b]
                        + Dinv[i - 1, q, 2] * B[i - 1, 2, b]
                    )
            for a in range(3):
                for b in range(3):
                    piv[a, b] -= (
                        B[i - 1, 0, a] * db[0, b]
                        + B[i - 1, 1, a] * db[1, b]
                        + B[i - 1, 2, a] * db[2, b]
                    )
        _inv3(piv, Dinv[i])


@_jit
def _inv3(m, out):
    """out = m^-1 (3 x 3, by cofactors)."""
    c00 = m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]
    c01 = m[1, 2] * m[2, 0] - m[1, 0] * m[2, 2]
    c02 = m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]
    det = m[0, 0] * c00 + m[0, 1] * c01 + m[0, 2] * c02
    inv = 1.0 / det
    out[0, 0] = c00 * inv
    out[1, 0] = c01 * inv
    out[2, 0] = c02 * inv
    out[0, 1] = (m[0, 2] * m[2, 1] - m[0, 1] * m[2, 2]) * inv
    out[1, 1] = (m[0, 0] * m[2, 2] - m[0, 2] * m[2, 0]) * inv
    out[2, 1] = (m[0, 1] * m[2, 0] - m[0, 0] * m[2, 1]) * inv
    out[0, 2] = (m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]) * inv
    out[1, 2] = (m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]) * inv
    out[2, 2] = (m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]) * inv


@_jit
def _solve(Dinv, B, rhs, out):
    """Solve A out = rhs (n_free, 3) with the factors of ``_factor`` (forward into out, then
    back in place)."""
    n_free = rhs.shape[0]
    for i in range(n_free):
        for a in range(3):
            out[i, a] = rhs[i, a]
        if i > 0:  # y_i -= B_{i-1}^T Dinv_{i-1} y_{i-1}
            t0 = (
                Dinv[i - 1, 0, 0] * out[i - 1, 0]
                + Dinv[i - 1, 0, 1] * out[i - 1, 1]
                + Dinv[i - 1, 0, 2] * out[i - 1, 2]
            )
            t1 = (
                Dinv[i - 1, 1, 0] * out[i - 1, 0]
                + Dinv[i - 1, 1, 1] * out[i - 1, 1]
                + Dinv[i - 1, 1, 2] * out[i - 1, 2]
            )
            t2 = (
                Dinv[i - 1, 2, 0] * out[i - 1, 0]
                + Dinv[i - 1, 2, 1] * out[i - 1, 1]
                + Dinv[i - 1, 2, 2] * out[i - 1, 2]
            )
            for a in range(3):
                out[i, a] -= B[i - 1, 0, a] * t0 + B[i - 1, 1, a] * t1 + B[i - 1, 2, a] * t2
    for i in range(n_free - 1, -1, -1):
        z0 = out[i, 0]
        z1 = out[i, 1]
        z2 = out[i, 2]
        if i < n_free - 1:
            z0 -= (
                B[i, 0, 0] * out[i + 1, 0] + B[i, 0, 1] * out[i + 1, 1] + B[i, 0, 2] * out[i + 1, 2]
            )
            z1 -= (
                B[i, 1, 0] * out[i + 1, 0] + B[i, 1, 1] * out[i + 1, 1] + B[i, 1, 2] * out[i + 1, 2]
            )
            z2 -= (
                B[i, 2, 0] * out[i + 1, 0] + B[i, 2, 1] * out[i + 1, 1] + B[i, 2, 2] * out[i + 1, 2]
            )
        for a in range(3):
            out[i, a] = Dinv[i, a, 0] * z0 + Dinv[i, a, 1] * z1 + Dinv[i, a, 2] * z2


@_jit
def ros2_work_size(segments):
    """The length of the scratch array ``ros2_step`` needs for ``segments`` segments.

    Parameters
    ----------
    segments : int
        Number of segments N >= 1.

    Returns
    -------
    int
        The scratch length.
    """
    n = segments
    return 3 * (n + 1) + n + 27 * n + 18 * n + 24 * n + 6 * (n + 1) + 18 + 10 * (n + 1) + 6


def ros2_work(segments: int) -> np.ndarray:
    """The scratch array ``ros2_step`` needs for a chain of ``segments`` segments (allocate
    once per run).

    Parameters
    ----------
    segments : int
        Number of segments N >= 1.

    Returns
    -------
    ndarray, shape (ros2_work_size(segments),)
        Uninitialised scratch.
    """
    return np.empty(ros2_work_size(segments))


@_jit
def ros2_step(x, v, wind, L0, p, h, xP1, vP1, work):
    """Advance the free nodes of the chain over one step h [s] by ROS2 (module docstring).

    x, v (N+1, 3): positions, velocities at t (rows 0 and N: winch and P), updated in place to
    t + h (row N becomes xP1, vP1, P's position and velocity at t + h; the winch row is left
    as it is). wind (N+1, 3) the wind at the nodes [m/s], held over the step; L0 the
    unstretched length [m], held over the step; work: ``ros2_work(N)``.

    Parameters
    ----------
    x, v : ndarray, shape (N+1, 3)
        Node positions [m] and velocities [m/s] at t, updated in place to t + h.
    wind : ndarray, shape (N+1, 3)
        Wind at the nodes [m/s], held over the step.
    L0 : float
        Unstretched length [m], held over the step.
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.
    h : float
        Step [s].
    xP1, vP1 : ndarray, shape (3,)
        P's position [m] and velocity [m/s] at t + h.
    work : ndarray
        Scratch, ``ros2_work(N)``.

    Returns
    -------
    None
    """
    n = x.shape[0] - 1
    nf = n - 1
    if nf == 0:
        for j in range(3):
            x[n, j] = xP1[j]
            v[n, j] = vP1[j]
        return
    o = 0
    F = work[o : o + 3 * (n + 1)].reshape((n + 1, 3))
    o += 3 * (n + 1)
    T = work[o : o + n]
    o += n
    K = work[o : o + 9 * n].reshape((n, 3, 3))
    o += 9 * n
    Cax = work[o : o + 9 * n].reshape((n, 3, 3))
    o += 9 * n
    Dd = work[o : o + 9 * n].reshape((n, 3, 3))
    o += 9 * n
    Dinv = work[o : o + 9 * nf].reshape((nf, 3, 3))
    o += 9 * nf
    B = work[o : o + 9 * nf].reshape((nf, 3, 3))
    o += 9 * nf
    ra = work[o : o + 3 * nf].reshape((nf, 3))
    o += 3 * nf
    rb = work[o : o + 3 * nf].reshape((nf, 3))
    o += 3 * nf
    k1r = work[o : o + 3 * nf].reshape((nf, 3))
    o += 3 * nf
    k1v = work[o : o + 3 * nf].reshape((nf, 3))
    o += 3 * nf
    k2r = work[o : o + 3 * nf].reshape((nf, 3))
    o += 3 * nf
    k2v = work[o : o + 3 * nf].reshape((nf, 3))
    o += 3 * nf
    rhs = work[o : o + 3 * nf].reshape((nf, 3))
    o += 3 * nf
    x0 = work[o : o + 3 * (n + 1)].reshape((n + 1, 3))
    o += 3 * (n + 1)
    v0 = work[o : o + 3 * (n + 1)].reshape((n + 1, 3))
    o += 3 * (n + 1)
    piv = work[o : o + 9].reshape((3, 3))
    o += 9
    db = work[o : o + 9].reshape((3, 3))
    o += 9
    Gk = work[o : o + n + 1]
    o += n + 1
    Gc = work[o : o + 9 * (n + 1)].reshape((n + 1, 3, 3))
    g = ROS2_GAMMA
    m_node = p[LUMPED_MU] * L0 / n
    chain_forces(x, v, wind, L0, p, F, T, K, Cax, Dd, True)
    ground_jacobian(x, v, L0, p, h, Gk, Gc)
    # (M - g h C - g^2 h^2 Kn) kv = M b + g h Kn a, kr = a + g h kv  for (I - g h J) k = (a, b)
    _factor(nf, m_node, K, Cax, Dd, Gk, Gc, 1.0, -g * h, -g * g * h * h, Dinv, B, piv, db)
    # the driven top point: d(F_{N-1})/dt = K_top vP + C_top aP, with aP over the step
    top = n - 1
    ft0 = 0.0
    ft1 = 0.0
    ft2 = 0.0
    for b in range(3):
        aP = (vP1[b] - v[n, b]) / h
        ft0 += K[top, 0, b] * v[n, b] + (Cax[top, 0, b] - 0.25 * Dd[top, 0, b]) * aP
        ft1 += K[top, 1, b] * v[n, b] + (Cax[top, 1, b] - 0.25 * Dd[top, 1, b]) * aP
        ft2 += K[top, 2, b] * v[n, b] + (Cax[top, 2, b] - 0.25 * Dd[top, 2, b]) * aP
    scale_t = g * h * h / m_node
    # stage 1: (I - g h J) k1 = h f(y) + g h^2 f_t
    for i in range(nf):
        for j in range(3):
            ra[i, j] = h * v[i + 1, j]
            rb[i, j] = h * F[i + 1, j] / m_node
    rb[nf - 1, 0] += scale_t * ft0
    rb[nf - 1, 1] += scale_t * ft1
    rb[nf - 1, 2] += scale_t * ft2
    _stage(nf, m_node, K, Gk, g * h, ra, rb, Dinv, B, k1r, k1v, rhs)
    # stage 2 at t + h, y + k1 (Verwer's form: (I - g h J) k2 = h f(y + k1) - 2 k1 - g h^2 f_t)
    for i in range(n + 1):
        for j in range(3):
            x0[i, j] = x[i, j]
            v0[i, j] = v[i, j]
    for i in range(nf):
        for j in range(3):
            x[i + 1, j] = x0[i + 1, j] + k1r[i, j]
            v[i + 1, j] = v0[i + 1, j] + k1v[i, j]
    for j in range(3):
        x[n, j] = xP1[j]
        v[n, j] = vP1[j]
    chain_forces(x, v, wind, L0, p, F, T, K, Cax, Dd, False)
    for i in range(nf):
        for j in range(3):
            ra[i, j] = h * v[i + 1, j] - 2.0 * k1r[i, j]
            rb[i, j] = h * F[i + 1, j] / m_node - 2.0 * k1v[i, j]
    rb[nf - 1, 0] -= scale_t * ft0
    rb[nf - 1, 1] -= scale_t * ft1
    rb[nf - 1, 2] -= scale_t * ft2
    _stage(nf, m_node, K, Gk, g * h, ra, rb, Dinv, B, k2r, k2v, rhs)
    for i in range(nf):
        for j in range(3):
            x[i + 1, j] = x0[i + 1, j] + 1.5 * k1r[i, j] + 0.5 * k2r[i, j]
            v[i + 1, j] = v0[i + 1, j] + 1.5 * k1v[i, j] + 0.5 * k2v[i, j]


#: the chain's step-size rule (``chain_substeps``): sub-steps of h_c <= CHAIN_OMEGA_H / omega_max,
#: omega_max = 2 sqrt(k / m) = (2 N / L0) sqrt(EA / mu) the highest axial frequency of the
#: chain (a fixed-fixed spring-mass chain's limit). ROS2 is L-stable, so a larger step stays
#: stable but damps the modes it cannot resolve; at 0.2 the paper's cable driven at 3 Hz is
#: within 3 % of a converged run (0.37: 7 %, 0.73: 16 %, at N = 10) (issue 23;
#: ``tests/test_tether_cable.py``, ``tests/test_engine_lumped.py``).
CHAIN_OMEGA_H = 0.2
#: at most this many chain sub-steps per helicopter step (a guard on absurd stiffness)
CHAIN_MAX_SUBSTEPS = 4096
#: the coupled step's rule (``coupling_substeps``): the helicopter's RK4 steps of a lumped run
#: are at most COUPLING_OMEGA_H / omega_max long, so that the condensed coupling's Taylor
#: model of the top interior node (``engine.lumped_interval``) spans at most about half of
#: its axial period 2 pi / (omega_max / 2). Issue 23 item 2b: with drag, damping and the winch
#: off, the closed-loop engine's energy over 20 s at the default 10 ms, 2 substeps drifted by
#: 1.06 % of the push for a 20 kN cable (N = 10: h omega_max = 10.7 at h = 5 ms); this rule
#: takes it to 9 RK4 steps per sample (0.53 %). The paper's cable keeps its 2 steps at N <= 10
#: and takes 3 at N = 20, 5 at N = 40; the chain's own sub-steps shrink in step, so the
#: chain's work per sample barely changes (``tests/test_engine_lumped.py``; measured figures
#: in ``docs/studies/lumped_tether.md``).
COUPLING_OMEGA_H = 2.5


@_jit
def chain_omega_max(p, L0, n):
    """The chain's highest axial angular frequency [rad/s]: 2 sqrt(k / m) with k = EA / l0,
    m = mu l0 (l0 = L0 / n), i.e. (2 n / L0) sqrt(EA / mu).

    Parameters
    ----------
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.
    L0 : float
        Unstretched length [m], > 0.
    n : int
        Number of segments.

    Returns
    -------
    float
        omega_max [rad/s].
    """
    return 2.0 * n / L0 * math.sqrt(p[LUMPED_EA] / p[LUMPED_MU])


@_jit
def chain_substeps(p, L0, n, h):
    """The number of ROS2 sub-steps ``chain_interval`` takes over a step h [s]: the least m
    with (h / m) omega_max <= CHAIN_OMEGA_H (``chain_omega_max``), at least 1, at most
    CHAIN_MAX_SUBSTEPS.

    Parameters
    ----------
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.
    L0 : float
        Unstretched length [m], > 0.
    n : int
        Number of segments.
    h : float
        The step to cover [s].

    Returns
    -------
    int
        The sub-step count m.
    """
    return _steps_for(h * chain_omega_max(p, L0, n), CHAIN_OMEGA_H, 1)


@_jit
def _steps_for(h_omega, omega_h, least):
    # the least m with (h / m) omega_max <= omega_h (h_omega = h omega_max), within
    # [least, CHAIN_MAX_SUBSTEPS]: the step rule of the chain and of the coupling
    m = int(h_omega / omega_h - 1e-9) + 1  # the ceiling
    if m < least:
        return least
    if m > CHAIN_MAX_SUBSTEPS:
        return CHAIN_MAX_SUBSTEPS
    return m


@_jit
def coupling_substeps(p, L0, n, dt, n_sub):
    """The helicopter's RK4 steps per control sample of a lumped run: ``n_sub`` (the
    scenario's substeps) or more, the least m with (dt / m) omega_max <= COUPLING_OMEGA_H
    (``chain_omega_max``), at most CHAIN_MAX_SUBSTEPS.

    Parameters
    ----------
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.
    L0 : float
        Unstretched length [m], > 0.
    n : int
        Number of segments.
    dt : float
        The control sample [s].
    n_sub : int
        The scenario's RK4 steps per sample, >= 1.

    Returns
    -------
    int
        The RK4 steps per sample.
    """
    return _steps_for(dt * chain_omega_max(p, L0, n), COUPLING_OMEGA_H, n_sub)


@_jit
def chain_interval(x, v, wind, L0, p, h, xP1, vP1, work):
    """Advance the chain over h [s] as ``ros2_step`` does, in ``chain_substeps`` ROS2
    sub-steps, the top node on the cubic Hermite curve from its start (row N of x, v) to
    (xP1, vP1) at t + h: the step the engine takes (``engine.lumped_interval``) and
    ``tether.drive_cable`` too. Arguments as ``ros2_step``'s.

    Parameters
    ----------
    x, v : ndarray, shape (N+1, 3)
        Node positions [m] and velocities [m/s] at t (row N: P at t), updated in place.
    wind : ndarray, shape (N+1, 3)
        Wind at the nodes [m/s], held over the step.
    L0 : float
        Unstretched length [m], held over the step.
    p : ndarray, shape (LUMPED_SIZE,)
        ``LumpedTether.packed(g)``.
    h : float
        Step [s].
    xP1, vP1 : ndarray, shape (3,)
        P's position [m] and velocity [m/s] at t + h.
    work : ndarray
        Scratch, ``ros2_work(N)``.

    Returns
    -------
    None
    """
    n = x.shape[0] - 1
    m = chain_substeps(p, L0, n, h)
    if m == 1:
        ros2_step(x, v, wind, L0, p, h, xP1, vP1, work)
        return
    size = work.shape[0]
    top = work[size - 6 : size]
    p0x, p0y, p0z = x[n, 0], x[n, 1], x[n, 2]
    v0x, v0y, v0z = v[n, 0], v[n, 1], v[n, 2]
    hs = h / m
    for j in range(1, m + 1):
        s = j / m
        s2 = s * s
        s3 = s2 * s
        h00 = 2.0 * s3 - 3.0 * s2 + 1.0
        h10 = (s3 - 2.0 * s2 + s) * h
        h01 = -2.0 * s3 + 3.0 * s2
        h11 = (s3 - s2) * h
        d00 = (6.0 * s2 - 6.0 * s) / h
        d10 = 3.0 * s2 - 4.0 * s + 1.0
        d01 = (-6.0 * s2 + 6.0 * s) / h
        d11 = 3.0 * s2 - 2.0 * s
        if j == m:
            for a in range(3):
                top[a] = xP1[a]
                top[3 + a] = vP1[a]
        else:
            top[0] = h00 * p0x + h10 * v0x + h01 * xP1[0] + h11 * vP1[0]
            top[1] = h00 * p0y + h10 * v0y + h01 * xP1[1] + h11 * vP1[1]
            top[2] = h00 * p0z + h10 * v0z + h01 * xP1[2] + h11 * vP1[2]
            top[3] = d00 * p0x + d10 * v0x + d01 * xP1[0] + d11 * vP1[0]
            top[4] = d00 * p0y + d10 * v0y + d01 * xP1[1] + d11 * vP1[1]
            top[5] = d00 * p0z + d10 * v0z + d01 * xP1[2] + d11 * vP1[2]
        ros2_step(x, v, wind, L0, p, hs, top[0:3], top[3:6], work)


@_jit
def _stage(nf, m_node, K, Gk, gh, ra, rb, Dinv, B, kr, kv, rhs):
    """Solve (I - gh J) (kr, kv) = (ra, rb) for J = [[0, I], [Kn/m, C/m]]: the factored A =
    M - gh C - gh^2 Kn takes kv from M rb + gh Kn ra, then kr = ra + gh kv (rhs: scratch;
    Kn with the ground's normal stiffness Gk)."""
    for i in range(nf):
        s_lo = i
        s_hi = i + 1
        for a in range(3):
            acc = m_node * rb[i, a]
            for b in range(3):
                kn = -(K[s_lo, a, b] + K[s_hi, a, b]) * ra[i, b]
                if i > 0:
                    kn += K[s_lo, a, b] * ra[i - 1, b]
                if i < nf - 1:
                    kn += K[s_hi, a, b] * ra[i + 1, b]
                acc += gh * kn
            if a == 2:
                acc -= gh * Gk[i + 1] * ra[i, 2]
            rhs[i, a] = acc
    _solve(Dinv, B, rhs, kv)
    for i in range(nf):
        for a in range(3):
            kr[i, a] = ra[i, a] + gh * kv[i, a]


# ----------------------------------------------------------------------------------------------
# coupling: a general force at P in the tethered helicopter's equations
# ----------------------------------------------------------------------------------------------


@_jit
def force_at_P_as_loads(x, inp, wind, force_P, arm, inp_out, wind_out):
    """The inputs and wind force under which the generated tethered RHS at zero tension feels
    a force ``force_P`` [N, N components] at P.

    Kane's generalised speeds of the tethered model are those of the free one (eq 7: u1..u3
    the velocity of HO in N; eq 8: u4..u6 the body rates), so a force F at P = HO + arm f3
    has the partial velocities of a force at HO (generalised forces F . n1..n3, exactly where
    the wind force at HO enters) plus a torque arm f3 x F about HO, i.e.
    (-arm F.f2, arm F.f1, 0) in F, exactly where the rotor torques tMR1, tMR2 enter (the
    rotor's partial angular velocities for u4, u5 are f1, f2, as the fuselage's). Hence:
    wind_out = wind + F, inp_out = inp with tMR1 - arm F.f2 and tMR2 + arm F.f1; q7..q9 only
    locate P. (The radial force -TC c3 reproduces ``kernels.tethered_derivative``; a test
    checks it, and a non-radial one against the Newton-Euler route.)

    Parameters
    ----------
    x : ndarray, shape (13,)
        The tethered state (q4..q6 [rad] used).
    inp : ndarray, shape (4,)
        Rotor inputs fMR3 [N], tMR1, tMR2 [N m], fTR2 [N].
    wind : ndarray, shape (3,)
        Wind force on HO [N], along n1, n2, n3.
    force_P : ndarray, shape (3,)
        The force at P [N], along n1, n2, n3.
    arm : float
        ``HelicopterParams.tether_arm`` [m].
    inp_out : ndarray, shape (4,)
        Receives the equivalent inputs.
    wind_out : ndarray, shape (3,)
        Receives the equivalent wind force [N].

    Returns
    -------
    None
    """
    R = np.empty((3, 3))
    kernels.kinematics_dcm(x[0:3], R)  # column j: f_j in N
    f1 = force_P[0] * R[0, 0] + force_P[1] * R[1, 0] + force_P[2] * R[2, 0]
    f2 = force_P[0] * R[0, 1] + force_P[1] * R[1, 1] + force_P[2] * R[2, 1]
    for j in range(3):
        wind_out[j] = wind[j] + force_P[j]
    inp_out[0] = inp[0]
    inp_out[1] = inp[1] - arm * f2
    inp_out[2] = inp[2] + arm * f1
    inp_out[3] = inp[3]


@_jit
def tethered_derivative_force_at_P(x, inp, wind, force_P, reel_rate, c, arm, out):
    """out (13,) = dx/dt of the tethered helicopter with the force ``force_P`` [N, in N] at P
    in place of eq 28's tension (``force_at_P_as_loads``); out[12] = reel_rate.

    Parameters
    ----------
    x : ndarray, shape (13,)
        The tethered state [q4..q9, u1..u6, LN].
    inp : ndarray, shape (4,)
        Rotor inputs fMR3 [N], tMR1, tMR2 [N m], fTR2 [N].
    wind : ndarray, shape (3,)
        Wind force on HO [N].
    force_P : ndarray, shape (3,)
        The force at P [N], along n1, n2, n3.
    reel_rate : float
        dLN/dt [m/s] (eq 37).
    c : ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    arm : float
        ``HelicopterParams.tether_arm`` [m].
    out : ndarray, shape (13,)
        Receives dx/dt.

    Returns
    -------
    None
    """
    inp2 = np.empty(4)
    wind2 = np.empty(3)
    force_at_P_as_loads(x, inp, wind, force_P, arm, inp2, wind2)
    kernels.tethered_rhs(x, inp2, wind2, 0.0, c, out)
    out[12] = reel_rate


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
    chain_forces(x, v, wind, L0, p, F, T, K, C, D, False)
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
    r_winch, r_P : array_like (3,)
        The fixed ends [m].
    L0 : float
        Unstretched length [m].
    tether : LumpedTether
        The tether (N segments, mu, EA).
    g : float
        Gravity [m/s^2].
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
        ElasticCatenary(0.0, d[2], tether.mass_per_length_kg_m * g, EA, L0, 0.0, ground_tension_N)
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
