"""A tether with mass, sag and drag: the lumped-mass chain's compiled forces, its stiff-stable
step, the step-size rules and the coupling to the helicopter. The chain's parameters
(``LumpedTether``) and its static equilibrium (``static_chain``) are in ``tether.chain``, the
elastic catenary it converges to in ``tether.catenary``, the hover trim with such a tether in
``tether.lumped_trim``.

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
  compression, no pushing damper). The dashpot c is a property of the cable: from
  the internal damping BA [N s] (force per unit strain rate, MoorDyn's BA), c = BA / l0; from
  the damping ratio zeta of the cable's fundamental axial mode (both ends fixed),
  c = zeta sqrt(EA mu) / sin(pi / (2 N)). The chain's damping matrix is then (c / k) times
  its stiffness matrix, so mode j has the ratio c omega_j / (2 k), and the fundamental one,
  omega_1 = 2 sqrt(k / m) sin(pi / (2 N)), exactly zeta for every N and every length (the
  continuous cable: BA = 2 zeta L0 sqrt(EA mu) / pi). (Earlier versions took zeta as the ratio of
  one segment, c = 2 zeta sqrt(EA mu), so the cable's damping fell as N grew.)
- Drag on segment s from the air-relative velocity at its middle, u = (v[s] + v[s+1]) / 2 -
  (w[s] + w[s+1]) / 2 (w: the wind per node): normal part u_n = u - (u.e) e, tangential part
  u_t = (u.e) e; F = -0.5 rho d l Cd |u_n| u_n - 0.5 rho pi d l Ct |u_t| u_t (the normal drag
  on the projected area d l, the tangential on the wetted area pi d l; Hoerner's cross-flow
  principle), half of it on each end node.
- Gravity -g n3 (SPEC.md: n3 up).
- A moving winch (``base``): the chain is flown in the base's translating frame, positions
  and velocities relative to the winch, the air's velocity taken relative to the base, each
  free node feeling the inertial force -mu l0 b'' (``p[LUMPED_BASE_ACC]``); the ground below
  is then the base's deck, the plane z = 0 through the winch moving with it.
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
at HO plus the rotor torques of its moment about HO, with eq 28's tension set to zero; q7..q9
then only locate P (``tether.coupling``).
"""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled, plain
from ..layout import (
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
)

__all__ = [
    "CHAIN_OMEGA_H",
    "ROS2_GAMMA",
    "chain_forces",
    "chain_interval",
    "chain_omega_max",
    "chain_substeps",
    "coupling_substeps",
    "ground_force",
    "ground_jacobian",
    "ros2_step",
    "ros2_work",
    "ros2_work_size",
]

#: ROS2's gamma (Verwer et al. 1999): 1 + 1/sqrt(2), the L-stable choice
ROS2_GAMMA = 1.0 + 1.0 / math.sqrt(2.0)

_jit = compiled(fastmath={"nnan", "ninf"}, error_model="numpy")


# ----------------------------------------------------------------------------------------------
# compiled kernels: x, v (N+1, 3) node positions and velocities (rows 0 and N: winch and P)
# ----------------------------------------------------------------------------------------------


@_jit
def chain_forces(x, v, wind, L0, p, F, T, blocks, jac):
    """Node forces F (N+1, 3) [N] (rows 0 and N: the force on the winch and on P, with half an
    end segment's weight and drag), segment tensions T (N,) [N]; if ``jac``, the per-segment
    Jacobian blocks ``blocks`` = (K, Cax, D), each (N, 3, 3): K = d(T e)/d(d) (axial +
    geometric stiffness),
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
    blocks : tuple of ndarray
        (K, Cax, D), each (N, 3, 3): receive the Jacobian blocks [N/m, N s/m, N s/m] when
        ``jac``.
    jac : bool
        Whether to fill K, Cax, D.

    Returns
    -------
    None
    """
    K, Cax, D = blocks
    n = x.shape[0] - 1
    l0 = L0 / n
    mu = p[LUMPED_MU]
    k = p[LUMPED_EA] / l0
    c = p[LUMPED_DAMPING] + p[LUMPED_BA] / l0
    cdn = p[LUMPED_CDN]
    cdt = p[LUMPED_CDT]
    w_half = 0.5 * mu * l0 * p[LUMPED_G]
    # a moving winch: the chain is flown in the base's translating frame, where each free
    # node of mass mu l0 also feels the inertial force -mu l0 b'' (zero for the paper's winch)
    m_node = mu * l0
    ax = p[LUMPED_BASE_ACC]
    ay = p[LUMPED_BASE_ACC + 1]
    az = p[LUMPED_BASE_ACC + 2]
    for i in range(n + 1):
        inner = 0 < i < n
        F[i, 0] = 0.0 - m_node * ax if inner else 0.0
        F[i, 1] = 0.0 - m_node * ay if inner else 0.0
        F[i, 2] = -2.0 * w_half - m_node * az if inner else -w_half
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
    weight = p[LUMPED_MU] * l0 * (p[LUMPED_G] + p[LUMPED_BASE_ACC + 2])
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
def _factor(n_free, m_node, blocks, ground, coefficients, factors):
    """Factor the symmetric block-tridiagonal matrix A = cm M + cc C + ck Kn of the free nodes
    (Kn = dF/dx, C = dF/dv assembled from the segment blocks (K, Cax, D) and the ground's
    node blocks ground = (Gk, Gc) of ``ground_jacobian``; coefficients = (cm, cc, ck)) by
    block Thomas into factors = (Dinv, B, piv, db): Dinv (n_free, 3, 3) the inverted pivots,
    B (n_free, 3, 3) the super-diagonal blocks A[i, i+1]; piv, db (3, 3) scratch."""
    K, Cax, D = blocks
    Gk, Gc = ground
    cm, cc, ck = coefficients
    Dinv, B, piv, db = factors
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
    chain_forces(x, v, wind, L0, p, F, T, (K, Cax, Dd), plain(True))
    ground_jacobian(x, v, L0, p, h, Gk, Gc)
    # (M - g h C - g^2 h^2 Kn) kv = M b + g h Kn a, kr = a + g h kv  for (I - g h J) k = (a, b)
    _factor(nf, m_node, (K, Cax, Dd), (Gk, Gc), (1.0, -g * h, -g * g * h * h), (Dinv, B, piv, db))
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
    _stage(nf, m_node, K, Gk, g * h, (ra, rb), (Dinv, B), (k1r, k1v), rhs)
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
    chain_forces(x, v, wind, L0, p, F, T, (K, Cax, Dd), plain(False))
    for i in range(nf):
        for j in range(3):
            ra[i, j] = h * v[i + 1, j] - 2.0 * k1r[i, j]
            rb[i, j] = h * F[i + 1, j] / m_node - 2.0 * k1v[i, j]
    rb[nf - 1, 0] -= scale_t * ft0
    rb[nf - 1, 1] -= scale_t * ft1
    rb[nf - 1, 2] -= scale_t * ft2
    _stage(nf, m_node, K, Gk, g * h, (ra, rb), (Dinv, B), (k2r, k2v), rhs)
    for i in range(nf):
        for j in range(3):
            x[i + 1, j] = x0[i + 1, j] + 1.5 * k1r[i, j] + 0.5 * k2r[i, j]
            v[i + 1, j] = v0[i + 1, j] + 1.5 * k1v[i, j] + 0.5 * k2v[i, j]


#: the chain's step-size rule (``chain_substeps``): sub-steps of h_c <= CHAIN_OMEGA_H / omega_max,
#: omega_max = 2 sqrt(k / m) = (2 N / L0) sqrt(EA / mu) the highest axial frequency of the
#: chain (a fixed-fixed spring-mass chain's limit). ROS2 is L-stable, so a larger step stays
#: stable but damps the modes it cannot resolve; at 0.2 the paper's cable driven at 3 Hz is
#: within 3 % of a converged run (0.37: 7 %, 0.73: 16 %, at N = 10;
#: ``tests/test_tether_cable.py``, ``tests/test_engine_lumped.py``).
CHAIN_OMEGA_H = 0.2
#: at most this many chain sub-steps per helicopter step (a guard on absurd stiffness)
CHAIN_MAX_SUBSTEPS = 4096
#: the coupled step's rule (``coupling_substeps``): the helicopter's RK4 steps of a lumped run
#: are at most COUPLING_OMEGA_H / omega_max long, so that the condensed coupling's Taylor
#: model of the top interior node (``lumped_step.lumped_interval``) spans at most about half of
#: its axial period 2 pi / (omega_max / 2). Why: with drag, damping and the winch
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
    return _steps_for(h * chain_omega_max(p, L0, n), CHAIN_OMEGA_H, plain(1))


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
    (xP1, vP1) at t + h: the step the engine takes (``lumped_step.lumped_interval``) and
    ``tether.drive_cable`` too. Arguments as ``ros2_step``'s.

    Parameters
    ----------
    x, v, wind, L0, p, h, xP1, vP1, work
        As for ``ros2_step`` (row N of x, v: P at t).

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
def _stage(nf, m_node, K, Gk, gh, given, factors, out, rhs):
    """Solve (I - gh J) (kr, kv) = (ra, rb) for J = [[0, I], [Kn/m, C/m]] (given = (ra, rb),
    out = (kr, kv), factors = (Dinv, B)): the factored A = M - gh C - gh^2 Kn takes kv from
    M rb + gh Kn ra, then kr = ra + gh kv (rhs: scratch; Kn with the ground's normal
    stiffness Gk)."""
    ra, rb = given
    Dinv, B = factors
    kr, kv = out
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
