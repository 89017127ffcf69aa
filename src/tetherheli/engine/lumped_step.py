"""The lumped-mass tether in the closed loop (``tether.lumped``): the chain's end
tensions before a sample (``chain_ends``) and the coupled step of helicopter and chain over a
sample (``lumped_interval``), which ``engine.loop``'s ``sample_sense`` and ``sample_advance``
call while a lumped tether is attached."""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled, inline_here, plain
from ..base.compiled import base_at
from ..layout import (
    BASE_MOVING,
    CFG_ARM,
    CFG_ATTACHED,
    CFG_DT,
    CFG_GUST_DT,
    CFG_N_SUB,
    CFG_TENSION_GROUND,
    CFG_TENSION_TOP,
    CHAIN_NODES,
    CHAIN_PARAMS,
    CHAIN_VELOCITIES,
    CHAIN_WORK,
    LUMPED_BASE_ACC,
    LUMPED_MU,
)
from ..model.kernels import (
    angle_trig,
    angle_trig_from,
    kinematics_P_motion_sc,
    tethered_rhs_sc,
)
from ..tether.coupling import force_at_P_loads_sc
from ..tether.lumped import chain_forces, chain_interval, coupling_substeps
from ..wind.evaluate import air_relative_to_base, base_frame_force, gust_velocity

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")

# --- the lumped-mass tether (``model.tether_lumped``) ------------------------------------------
# A lumped run carries its chain (``layout.CHAIN_*``: node positions and velocities, the
# packed tether, the ROS2 scratch) next to the helicopter's state x; x[12] is the chain's
# unstretched length L0 (the winch pays out by re-discretising it uniformly, as ``ros2_step``
# does), q7..q9 only locate P, and eq 28's tension is replaced by the chain's force at P.
# The wind on the nodes is the gust table's air (the helicopter's drag uses the same);
# force-only wind profiles act on the helicopter alone.

#: coupling of the helicopter's RK4 step and the chain's ROS2 step (``lumped_interval``)
COUPLING_STAGGERED = 0
COUPLING_CONDENSED = 1


def lumped_work(segments: int) -> tuple:
    """The scratch of ``chain_ends`` and ``lumped_interval`` for a chain of ``segments``
    segments (allocate once per run).

    Parameters
    ----------
    segments : int
        Number of segments N.

    Returns
    -------
    tuple of numpy.ndarray
        Node forces, segment tensions, the segment Jacobian blocks (K, C, D), the air at the
        nodes, the force at P, the stage loads and P's motion, the condensed K and C,
        the top interior node's velocity and acceleration.
    """
    return _lumped_work(segments)


@_jit
def _lumped_work(n):
    return (
        np.empty((n + 1, 3)),  # 0 F: node forces
        np.empty(n),  # 1 T: segment tensions
        np.empty((n, 3, 3)),  # 2 K
        np.empty((n, 3, 3)),  # 3 C
        np.empty((n, 3, 3)),  # 4 D
        np.zeros((n + 1, 3)),  # 5 air at the nodes
        np.zeros(3),  # 6 force on P at the step's start
        np.empty(4),  # 7 the stage's equivalent rotor inputs
        np.empty(3),  # 8 the stage's equivalent wind force
        np.empty(6),  # 9 P's position and velocity at a stage
        np.empty(3),  # 10 the stage's force on P
        np.empty(3),  # 11 the stage's wind force on HO
        np.empty(6),  # 12 P's position and velocity at the step's start
        np.zeros(9),  # 13 stiffness seen from P (3 x 3, row-major)
        np.zeros(9),  # 14 damping seen from P
        np.zeros(3),  # 15 the top interior node's velocity at the step's start
        np.zeros(3),  # 16 the top interior node's acceleration at the step's start
    )


@_jit_inline
def _node_air(gust, gust_dt, t, air):
    """The gust table's air velocity at t [m/s] on every node (uniform field)."""
    g1, g2, g3 = gust_velocity(gust, gust_dt, t)
    for i in range(air.shape[0]):
        air[i, 0] = g1
        air[i, 1] = g2
        air[i, 2] = g3


@_jit_inline
def chain_in_base_frame(base, t, air, p):
    """Over a moving base, the chain's air at time t relative to the base (air - b'(t),
    ``wind.evaluate.air_relative_to_base``: the still air's, -b'(t), added to every node's)
    and the base's acceleration b''(t) into p[LUMPED_BASE_ACC] (``tether.lumped``: the chain
    in the base's translating frame); a still base leaves both alone.

    Parameters
    ----------
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``layout.BASE_*``).
    t : float
        The time [s].
    air : numpy.ndarray, shape (N + 1, 3)
        The air's velocity at the nodes [m/s], made relative to the base in place.
    p : numpy.ndarray, shape (LUMPED_SIZE,)
        The chain's parameters (``layout.LUMPED_*``); receives the base's acceleration
        [m/s^2].
    """
    if base[0, BASE_MOVING] > 0.5:
        w1, w2, w3 = air_relative_to_base(base, t, 0.0, 0.0, 0.0)
        for i in range(air.shape[0]):
            air[i, 0] += w1
            air[i, 1] += w2
            air[i, 2] += w3
        _, _, _, _, _, _, a1, a2, a3 = base_at(base, t)
        p[LUMPED_BASE_ACC] = a1
        p[LUMPED_BASE_ACC + 1] = a2
        p[LUMPED_BASE_ACC + 2] = a3


@_jit
def chain_ends(x, t, cfg, gust, base, chain, cw):
    """The chain's top node put on P (``kinematics_P_motion_sc``), its forces at t in the gust
    table's air (``tether_lumped.chain_forces``, with the Jacobian blocks), and the ends'
    tensions into cfg: CFG_TENSION_TOP = |force on P|, CFG_TENSION_GROUND = |force on the winch|
    (each end force includes half an end segment's weight and drag, so the two differ by the
    cable's weight in a still hang). cw = ``lumped_work(N)``; cw[6] receives the force on P [N].
    Over a moving ``base`` the chain is in the base's frame at t (``chain_in_base_frame``).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The helicopter's state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    t : float
        The sample's time [s].
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``); receives the ends' tensions [N].
    gust : numpy.ndarray, shape (rows, 3)
        The gust table: the air's velocity [m/s] every cfg[CFG_GUST_DT] [s] (no rows: none).
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``layout.BASE_*``).
    chain : tuple of numpy.ndarray
        The lumped chain (``layout.CHAIN_*``); its top node is set on P.
    cw : tuple of numpy.ndarray
        The chain's scratch (``lumped_work(N)``); cw[6] receives the force on P [N].
    """
    nodes, vel, p = chain[CHAIN_NODES], chain[CHAIN_VELOCITIES], chain[CHAIN_PARAMS]
    F, T, K, C, D, air, force_P = cw[0], cw[1], cw[2], cw[3], cw[4], cw[5], cw[6]
    pm = cw[9]
    sc = np.empty(10)
    angle_trig(x, sc)
    kinematics_P_motion_sc(x, sc, cfg[CFG_ARM], pm)
    n = nodes.shape[0] - 1
    for j in range(3):
        nodes[n, j] = pm[j]
        vel[n, j] = pm[3 + j]
    _node_air(gust, cfg[CFG_GUST_DT], t, air)
    chain_in_base_frame(base, t, air, p)
    chain_forces(nodes, vel, air, x[12], p, F, T, (K, C, D), plain(True))
    for j in range(3):
        force_P[j] = F[n, j]
    cfg[CFG_TENSION_TOP] = math.sqrt(F[n, 0] ** 2 + F[n, 1] ** 2 + F[n, 2] ** 2)
    cfg[CFG_TENSION_GROUND] = math.sqrt(F[0, 0] ** 2 + F[0, 1] ** 2 + F[0, 2] ** 2)


@_jit
def _lumped_stage(xs, sc, command, times, cfg, c, air_pack, cw, out):
    """dx/dt (13,) of the helicopter at a stage state xs (sin, cos sc) under command = (inp,
    reel_rate) at times = (t, tau [s] into the step, side), in ``air_pack`` (``layout.WindPack``),
    pulled at P by the chain: the step-start force cw[6] minus (condensed coupling)
    the top segment's stiffness cw[13] times its stretch since the step's start (P's motion
    less the top interior node's, moving on from its start velocity cw[15] at its start
    acceleration cw[16]) and its damping cw[14]
    times P's change of velocity (cw[12]: P at the step's start)."""
    # typed and lowered once for the four stages, inlined by LLVM (``inline_here``): Numba's
    # inlining of the four (``tethered_rhs_sc`` in each) took 10 s of the first compile
    inline_here()
    inp, reel_rate = command
    t, tau, side = times
    program, gust, drag, base = air_pack
    force_P, inp2, wind2, pm, fp, wind = cw[6], cw[7], cw[8], cw[9], cw[10], cw[11]
    pm0, kc, cc, v_top, a_top = cw[12], cw[13], cw[14], cw[15], cw[16]
    base_frame_force(program, gust, cfg[CFG_GUST_DT], drag, base, t, side, (xs[6], xs[7], xs[8]),
                     wind)  # fmt: skip
    kinematics_P_motion_sc(xs, sc, cfg[CFG_ARM], pm)
    for a in range(3):
        fp[a] = force_P[a]
        for b in range(3):
            stretch = pm[b] - pm0[b] - (v_top[b] + 0.5 * a_top[b] * tau) * tau
            fp[a] -= kc[3 * a + b] * stretch + cc[3 * a + b] * (pm[3 + b] - pm0[3 + b])
    force_at_P_loads_sc(sc, inp, wind, fp, cfg[CFG_ARM], inp2, wind2)
    tethered_rhs_sc(xs, sc, inp2, wind2, 0.0, c, out)
    out[12] = reel_rate


@_jit
def lumped_interval(x, inp, reel_rate, t0, cfg, c, wind, chain, scratch, coupling):
    """Advance the helicopter x and its lumped chain over one control sample [t0, t0 + dt]:
    per substep h = dt / n_sub (n_sub the scenario's substeps, or more by the coupled step's
    rule ``tether_lumped.coupling_substeps``: h omega_max <= 2.5), ``chain_ends`` (the force
    on P at the step's start), one RK4 step of the helicopter under that force, then the
    chain's step
    (``tether_lumped.chain_interval``: ROS2 sub-steps of the chain's step-size rule)
    with its top driven to P's new position and velocity and L0 = x[12] held at the step's
    start value.

    ``coupling`` COUPLING_STAGGERED holds the force on P over the RK4 step;
    COUPLING_CONDENSED corrects it within the stages by the top segment's stiffness and
    damping seen from P (its Jacobian blocks at the step's start, the interior nodes held),
    F_P = F_P0 - K_top (r_P - r_P0 - v_(N-1) tau - a_(N-1) tau^2 / 2) - (C_top + D_top / 4)
    (v_P - v_P0), tau the time into the step and v_(N-1), a_(N-1) = F_(N-1) / m the top
    interior node's velocity and acceleration at its start (the acceleration term
    halved the 20 kN cable's energy drift at 4 substeps, 0.84 % to 0.46 %): the force
    follows P's motion relative to the chain inside the step, and the helicopter's RK4 sees
    the top segment's stiffness (stable while h sqrt(EA / (l0 m)) stays within RK4's bound:
    0.2 for 20 kN, N = 10, h = 5 ms). Why: against SciPy's Radau on the joint helicopter +
    chain ODE (rtol 1e-9; 2 s open loop, 10 N on HO, dt = 10 ms, 2 substeps) the staggered
    step, first order in the force's change, is 5.3-5.8e-4 m off on P's position, the
    condensed one 4.8-5.3e-5 m, for EA = 375 N (N = 10, 20) and 20 kN (N = 10) alike; the
    nodes' 5.5-6.0e-4 m is ROS2's own error (``tests/test_engine_lumped.py``,
    ``benchmarks/bench_engine_lumped.py --coupling``). The full Schur complement of the
    chain's implicit step was not needed. The engine runs COUPLING_CONDENSED.

    Parameters
    ----------
    x : ndarray, shape (13,)
        The helicopter's state, x[12] the unstretched length L0 [m]; advanced in place.
    inp, reel_rate, t0, cfg, c, wind
        As ``rk4_interval``'s (over a moving base the chain's step takes the air relative to
        the base and b'' at the step's middle).
    chain : tuple
        ``layout.CHAIN_*``: the chain, advanced in place.
    scratch : tuple
        (work, cw): ``rk4_interval``'s work array and ``lumped_work(N)``.
    coupling : int
        COUPLING_STAGGERED or COUPLING_CONDENSED.

    Returns
    -------
    None
    """
    nodes, vel, p, rwork = (
        chain[CHAIN_NODES],
        chain[CHAIN_VELOCITIES],
        chain[CHAIN_PARAMS],
        chain[CHAIN_WORK],
    )
    work, cw = scratch
    gust, base = wind.gust, wind.base
    F, K, C, D, air = cw[0], cw[2], cw[3], cw[4], cw[5]
    pm, pm0, kc, cc = cw[9], cw[12], cw[13], cw[14]
    n = nodes.shape[0] - 1
    n_sub = coupling_substeps(p, x[12], n, cfg[CFG_DT], int(cfg[CFG_N_SUB]))
    h = cfg[CFG_DT] / n_sub
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    sc0, sc = work[6, :10], work[7, :10]
    rate = reel_rate if cfg[CFG_ATTACHED] > 0.5 else 0.0
    # the stages' constant arguments as plain values: ``_lumped_stage`` keeps one signature
    zero, after, before = plain(0.0), plain(1), plain(-1)
    for j in range(n_sub):
        ta = t0 + j * h
        tb = t0 + (j + 1) * h
        tm = ta + 0.5 * h
        L0 = x[12]
        chain_ends(x, ta, cfg, gust, base, chain, cw)  # also puts nodes[n] on P(x)
        v_top, a_top = cw[15], cw[16]
        m_node = p[LUMPED_MU] * L0 / n
        for a in range(3):
            pm0[a] = nodes[n, a]
            pm0[3 + a] = vel[n, a]
            v_top[a] = vel[n - 1, a]
            a_top[a] = F[n - 1, a] / m_node
            for b in range(3):
                if coupling == COUPLING_CONDENSED:
                    kc[3 * a + b] = K[n - 1, a, b]
                    cc[3 * a + b] = C[n - 1, a, b] + 0.25 * D[n - 1, a, b]
                else:
                    kc[3 * a + b] = 0.0
                    cc[3 * a + b] = 0.0
        angle_trig(x, sc0)
        _lumped_stage(x, sc0, (inp, rate), (ta, zero, after), cfg, c, wind, cw, k1)
        for i in range(13):
            tmp[i] = x[i] + 0.5 * h * k1[i]
        angle_trig_from(tmp, x, sc0, sc)
        _lumped_stage(tmp, sc, (inp, rate), (tm, 0.5 * h, after), cfg, c, wind, cw, k2)
        for i in range(13):
            tmp[i] = x[i] + 0.5 * h * k2[i]
        angle_trig_from(tmp, x, sc0, sc)
        _lumped_stage(tmp, sc, (inp, rate), (tm, 0.5 * h, after), cfg, c, wind, cw, k3)
        for i in range(13):
            tmp[i] = x[i] + h * k3[i]
        angle_trig_from(tmp, x, sc0, sc)
        _lumped_stage(tmp, sc, (inp, rate), (tb, h, before), cfg, c, wind, cw, k4)
        for i in range(13):
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        angle_trig(x, sc0)
        kinematics_P_motion_sc(x, sc0, cfg[CFG_ARM], pm)
        if base[0, BASE_MOVING] > 0.5:  # the chain's step in the base's frame at mid-step
            _node_air(gust, cfg[CFG_GUST_DT], ta, air)
            chain_in_base_frame(base, tm, air, p)
        chain_interval(nodes, vel, air, L0, p, h, pm[:3], pm[3:], rwork)
