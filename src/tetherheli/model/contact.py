"""Landing gear in contact with a deck plane: a compliant (Kelvin-Voigt) normal force and
regularised Coulomb friction at each gear point, summed into one force and one moment.

Each gear point g, fixed in the fuselage F at ``r_g`` from HO, is in contact when it lies
below the deck plane (point d, unit normal n pointing out of the deck, both in N):
penetration ``delta = (d - x_g) . n > 0``. Its load on the helicopter is

- normal: ``F_n = k delta + c delta_dot`` along n, ``delta_dot = -(v_g - v_deck) . n`` (the
  linear spring-damper of the contact literature: Hunt and Crossley 1975 call it Kelvin-Voigt;
  the force is applied while the point penetrates, so it may pull briefly before the point
  leaves the plane, which is what gives the restitution ``exp(-zeta pi / sqrt(1 - zeta^2))``,
  ``zeta = c / (2 sqrt(k m))``);
- friction: ``F_t = -mu max(F_n, 0) v_t / max(|v_t|, v_slip)`` against the slip velocity
  ``v_t`` (the relative velocity's part in the plane): Coulomb's law above ``v_slip``, a
  viscous law below it, so that a resting gear holds still without a stick state.

The deck's velocity at the contact point is ``v_d + w_d x (x_g - d)``; a deck that moves,
tilts or turns therefore acts through relative velocities only (Galilean invariance, a test
checks it). The packed arrays' slots are named in ``layout`` (``GEAR_LAW_*``, ``BODY_*``,
``DECK_*``, ``LOADS_*``).
"""

from __future__ import annotations

import math

import numpy as np

from .._compile import compiled
from ..layout import (
    BODY_OMEGA_F,
    BODY_POSITION,
    BODY_R_NF,
    BODY_SIZE,
    BODY_VELOCITY,
    DECK_NORMAL,
    DECK_OMEGA,
    DECK_POINT,
    DECK_SIZE,
    DECK_VELOCITY,
    GEAR_LAW_DAMPING,
    GEAR_LAW_FRICTION,
    GEAR_LAW_SIZE,
    GEAR_LAW_SLIP_SPEED,
    GEAR_LAW_STIFFNESS,
    GEAR_WORK_BODY,
    GEAR_WORK_DECK,
    GEAR_WORK_INPUTS,
    GEAR_WORK_LOADS,
    GEAR_WORK_LOCK_DAMPING,
    GEAR_WORK_LOCK_STIFFNESS,
    GEAR_WORK_OUTPUTS,
    GEAR_WORK_SIZE,
    GEAR_WORK_WIND,
    LOADS_FORCE_N,
    LOADS_MOMENT_F,
    LOADS_SIZE,
    LOCK_ANCHOR,
    LOCK_HELD,
    LOCK_SIZE,
    X_U1,
    X_U4,
    Gear,
)
from ..params import HelicopterParams
from .kernels import tethered_outputs_sc, tethered_rhs_sc, wrench_loads_sc

__all__ = [
    "BODY_SIZE",
    "DECK_SIZE",
    "GEAR_LAW_SIZE",
    "LOADS_SIZE",
    "body_array",
    "deck_array",
    "gear_contact",
    "gear_inputs_sc",
    "gear_law_array",
    "gear_record",
    "gear_rhs_sc",
    "lock_loads",
    "tail_lever",
]

_jit = compiled(fastmath={"nnan", "ninf"}, error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")
#: a call, not inlined: the engine's derivative keeps only the branch to it
_jit_call = compiled(error_model="numpy")


@_jit
def gear_contact(gear, law, body, deck, loads, penetration):
    """The gear's contact loads on the helicopter: ``loads`` receives the total force [N] in N
    and its moment about HO [N m] in F; ``penetration`` receives each point's depth below the
    deck [m] (<= 0: no contact).

    Parameters
    ----------
    gear : numpy.ndarray, shape (n, 3)
        The gear points from HO in F [m].
    law : numpy.ndarray, shape (GEAR_LAW_SIZE,)
        Stiffness [N/m], damping [N s/m], friction coefficient [-] and slip speed [m/s] per
        point (``layout.GEAR_LAW_*``).
    body : numpy.ndarray, shape (BODY_SIZE,)
        HO's position [m] and velocity [m/s] in N, the rotation N_R_F (row-major, column j is
        f_j in N) and F's angular velocity in F [rad/s] (``layout.BODY_*``).
    deck : numpy.ndarray, shape (DECK_SIZE,)
        A point of the deck plane [m], its unit normal (out of the deck), that point's
        velocity [m/s] and the deck's angular velocity [rad/s], all in N (``layout.DECK_*``).
    loads : numpy.ndarray, shape (LOADS_SIZE,)
        Receives the force in N and the moment about HO in F (``layout.LOADS_*``).
    penetration : numpy.ndarray, shape (n,)
        Receives each gear point's penetration [m].

    Returns
    -------
    int
        The number of gear points in contact.
    """
    k = law[GEAR_LAW_STIFFNESS]
    c = law[GEAR_LAW_DAMPING]
    mu = law[GEAR_LAW_FRICTION]
    v_slip = law[GEAR_LAW_SLIP_SPEED]
    p0, v0, r0, w0 = BODY_POSITION, BODY_VELOCITY, BODY_R_NF, BODY_OMEGA_F
    n1, n2, n3 = deck[DECK_NORMAL], deck[DECK_NORMAL + 1], deck[DECK_NORMAL + 2]
    for j in range(LOADS_SIZE):
        loads[j] = 0.0
    mx = my = mz = 0.0  # the moment about HO in N
    in_contact = 0
    for i in range(gear.shape[0]):
        gx, gy, gz = gear[i, 0], gear[i, 1], gear[i, 2]
        # the point from HO in N: r = R g; its velocity v_HO + R (w x g)
        rx = body[r0] * gx + body[r0 + 1] * gy + body[r0 + 2] * gz
        ry = body[r0 + 3] * gx + body[r0 + 4] * gy + body[r0 + 5] * gz
        rz = body[r0 + 6] * gx + body[r0 + 7] * gy + body[r0 + 8] * gz
        px = body[p0] + rx
        py = body[p0 + 1] + ry
        pz = body[p0 + 2] + rz
        dx = px - deck[DECK_POINT]
        dy = py - deck[DECK_POINT + 1]
        dz = pz - deck[DECK_POINT + 2]
        depth = -(dx * n1 + dy * n2 + dz * n3)
        penetration[i] = depth
        if depth <= 0.0:
            continue
        in_contact += 1
        wx, wy, wz = body[w0], body[w0 + 1], body[w0 + 2]
        ux = wy * gz - wz * gy  # w x g in F
        uy = wz * gx - wx * gz
        uz = wx * gy - wy * gx
        vx = body[v0] + body[r0] * ux + body[r0 + 1] * uy + body[r0 + 2] * uz
        vy = body[v0 + 1] + body[r0 + 3] * ux + body[r0 + 4] * uy + body[r0 + 5] * uz
        vz = body[v0 + 2] + body[r0 + 6] * ux + body[r0 + 7] * uy + body[r0 + 8] * uz
        # the deck's velocity at the point: v_d + w_d x (x - d)
        ox, oy, oz = deck[DECK_OMEGA], deck[DECK_OMEGA + 1], deck[DECK_OMEGA + 2]
        vx -= deck[DECK_VELOCITY] + oy * dz - oz * dy
        vy -= deck[DECK_VELOCITY + 1] + oz * dx - ox * dz
        vz -= deck[DECK_VELOCITY + 2] + ox * dy - oy * dx
        vn = vx * n1 + vy * n2 + vz * n3
        normal = k * depth - c * vn
        tx, ty, tz = vx - vn * n1, vy - vn * n2, vz - vn * n3
        slip = math.sqrt(tx * tx + ty * ty + tz * tz)
        scale = -mu * max(normal, 0.0) / max(slip, v_slip)
        fx = normal * n1 + scale * tx
        fy = normal * n2 + scale * ty
        fz = normal * n3 + scale * tz
        loads[LOADS_FORCE_N] += fx
        loads[LOADS_FORCE_N + 1] += fy
        loads[LOADS_FORCE_N + 2] += fz
        mx += ry * fz - rz * fy
        my += rz * fx - rx * fz
        mz += rx * fy - ry * fx
    # the moment in F: R^T m
    for j in range(3):
        loads[LOADS_MOMENT_F + j] = (
            body[r0 + j] * mx + body[r0 + 3 + j] * my + body[r0 + 6 + j] * mz
        )
    return in_contact


@_jit_call
def gear_rhs_sc(x, sc, inp, force, tension, c, gear, out):
    """dx/dt (13,) of the tethered model (``kernels.tethered_rhs_sc``) with the gear's
    contact loads added (``gear_inputs_sc``): the engine's vehicle slot calls it when the
    run has gear (a call, so that runs without gear keep the slot's inlined code alone).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The tethered state relative to the base (``layout.X_*``) [rad, m, rad/s, m/s, m].
    sc : numpy.ndarray, shape (10,)
        sin and cos of the angles (``layout.SC_*``).
    inp : numpy.ndarray, shape (4,)
        The rotor inputs [N, N m, N m, N] (not modified).
    force : numpy.ndarray, shape (3,)
        The air's force on the helicopter [N] in N (not modified).
    tension : float
        The tether's tension [N] (0: removed).
    c : numpy.ndarray
        The tethered model's constants.
    gear : layout.Gear
        The gear.
    out : numpy.ndarray, shape (13,)
        Receives dx/dt (its LN entry is the caller's).
    """
    inputs, wind = gear_inputs_sc(x, sc, inp, force, c, gear)
    tethered_rhs_sc(x, sc, inputs, wind, tension, c, out)


@_jit_inline
def gear_inputs_sc(x, sc, inp, force, c, gear):
    """The rotor inputs and wind force that carry the gear's contact loads on the tethered
    helicopter at x into the generated model (``gear_contact`` on the body's pose and motion
    relative to the base against ``gear``'s deck, then ``kernels.wrench_loads_sc``): views
    of ``gear.work`` (``layout.GEAR_WORK_*``); ``inp`` and ``force`` are not modified.

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The tethered state relative to the base (``layout.X_*``) [rad, m, rad/s, m/s, m].
    sc : numpy.ndarray, shape (10,)
        sin and cos of the angles (``layout.SC_*``).
    inp : numpy.ndarray, shape (4,)
        The rotor inputs [N, N m, N m, N].
    force : numpy.ndarray, shape (3,)
        The air's force on the helicopter [N] in N.
    c : numpy.ndarray
        The tethered model's constants.
    gear : layout.Gear
        The gear (points, law, tail lever, scratch with the deck).

    Returns
    -------
    inputs : numpy.ndarray, shape (4,)
        The inputs with the gear's moment [N, N m, N m, N].
    wind : numpy.ndarray, shape (3,)
        The wind force with the gear's force [N].
    """
    work = gear.work
    y = work[GEAR_WORK_OUTPUTS : GEAR_WORK_OUTPUTS + 4]
    body = work[GEAR_WORK_BODY : GEAR_WORK_BODY + BODY_SIZE]
    tethered_outputs_sc(x, sc, c, y)
    s4, s5, s6 = sc[0], sc[1], sc[2]
    c4, c5, c6 = sc[5], sc[6], sc[7]
    r = BODY_R_NF  # N_R_F (Table I; ``kernels.kinematics_dcm``), row-major
    body[r], body[r + 1], body[r + 2] = c5 * c6, -c5 * s6, s5
    body[r + 3] = s5 * c6 * s4 + s6 * c4
    body[r + 4] = c6 * c4 - s5 * s6 * s4
    body[r + 5] = -c5 * s4
    body[r + 6] = -c6 * s5 * c4 + s6 * s4
    body[r + 7] = s5 * s6 * c4 + c6 * s4
    body[r + 8] = c5 * c4
    for j in range(3):
        body[BODY_POSITION + j] = y[j]
        body[BODY_VELOCITY + j] = x[X_U1 + j]
        body[BODY_OMEGA_F + j] = x[X_U4 + j]
    loads = work[GEAR_WORK_LOADS : GEAR_WORK_LOADS + LOADS_SIZE]
    gear_contact(gear.points, gear.law, body, work[GEAR_WORK_DECK : GEAR_WORK_DECK + DECK_SIZE],
                 loads, gear.penetration)  # fmt: skip
    if gear.lock.shape[0] > 0:
        lock_loads(gear.points, gear.lock, body, work[GEAR_WORK_LOCK_STIFFNESS],
                   work[GEAR_WORK_LOCK_DAMPING], loads)  # fmt: skip
    inputs = work[GEAR_WORK_INPUTS : GEAR_WORK_INPUTS + 4]
    wind = work[GEAR_WORK_WIND : GEAR_WORK_WIND + 3]
    force_N = loads[LOADS_FORCE_N : LOADS_FORCE_N + 3]
    moment_F = loads[LOADS_MOMENT_F : LOADS_MOMENT_F + 3]
    wrench_loads_sc(sc, inp, force, force_N, moment_F, gear.tail, inputs, wind)
    return inputs, wind


@_jit
def lock_loads(gear, lock, body, stiffness, damping, loads):
    """The deck lock's loads added to ``loads`` (``layout.LOADS_*``): each held gear point
    (``lock[i, LOCK_HELD]``) pulled to its anchor by a spring-damper, ``-k (x_g - a) - c
    v_g`` (the harpoon in its grid; the anchor is at rest relative to the base).

    Parameters
    ----------
    gear : numpy.ndarray, shape (n, 3)
        The gear points from HO in F [m].
    lock : numpy.ndarray, shape (n, LOCK_SIZE)
        Held flags and anchors from the base in N [m] (``layout.LOCK_*``).
    body : numpy.ndarray, shape (BODY_SIZE,)
        The body's pose and motion relative to the base (``layout.BODY_*``).
    stiffness : float
        The anchor's stiffness [N/m].
    damping : float
        The anchor's damping [N s/m].
    loads : numpy.ndarray, shape (LOADS_SIZE,)
        The force in N [N] and moment about HO in F [N m], added to.
    """
    p0, v0, r0, w0 = BODY_POSITION, BODY_VELOCITY, BODY_R_NF, BODY_OMEGA_F
    mx = my = mz = 0.0
    for i in range(gear.shape[0]):
        if lock[i, LOCK_HELD] < 0.5:
            continue
        gx, gy, gz = gear[i, 0], gear[i, 1], gear[i, 2]
        rx = body[r0] * gx + body[r0 + 1] * gy + body[r0 + 2] * gz
        ry = body[r0 + 3] * gx + body[r0 + 4] * gy + body[r0 + 5] * gz
        rz = body[r0 + 6] * gx + body[r0 + 7] * gy + body[r0 + 8] * gz
        wx, wy, wz = body[w0], body[w0 + 1], body[w0 + 2]
        ux, uy, uz = wy * gz - wz * gy, wz * gx - wx * gz, wx * gy - wy * gx
        vx = body[v0] + body[r0] * ux + body[r0 + 1] * uy + body[r0 + 2] * uz
        vy = body[v0 + 1] + body[r0 + 3] * ux + body[r0 + 4] * uy + body[r0 + 5] * uz
        vz = body[v0 + 2] + body[r0 + 6] * ux + body[r0 + 7] * uy + body[r0 + 8] * uz
        a = LOCK_ANCHOR
        fx = -stiffness * (body[p0] + rx - lock[i, a]) - damping * vx
        fy = -stiffness * (body[p0 + 1] + ry - lock[i, a + 1]) - damping * vy
        fz = -stiffness * (body[p0 + 2] + rz - lock[i, a + 2]) - damping * vz
        loads[LOADS_FORCE_N] += fx
        loads[LOADS_FORCE_N + 1] += fy
        loads[LOADS_FORCE_N + 2] += fz
        mx += ry * fz - rz * fy
        my += rz * fx - rx * fz
        mz += rx * fy - ry * fx
    for j in range(3):  # the moment in F: R^T m
        loads[LOADS_MOMENT_F + j] += (
            body[r0 + j] * mx + body[r0 + 3 + j] * my + body[r0 + 6 + j] * mz
        )


def gear_record(
    points: np.ndarray,
    law: np.ndarray,
    helicopter: HelicopterParams,
    lock_stiffness: float = 0.0,
    lock_damping: float = 0.0,
) -> Gear:
    """The engine's ``layout.Gear`` of a helicopter's landing gear over the level deck
    through the base (point 0, normal n3, at rest relative to the base), no point held.

    Parameters
    ----------
    points : array_like, shape (n, 3)
        The gear points from HO in F [m].
    law : numpy.ndarray, shape (GEAR_LAW_SIZE,)
        The contact law (``gear_law_array``).
    helicopter : HelicopterParams
        The helicopter (its tail lever).
    lock_stiffness : float, optional
        The deck lock's anchor stiffness per held point [N/m] (``lock_loads``).
    lock_damping : float, optional
        The deck lock's anchor damping per held point [N s/m].

    Returns
    -------
    layout.Gear
        The record, with its own scratch.
    """
    pts = np.ascontiguousarray(points, dtype=float).reshape(-1, 3)
    work = np.zeros(GEAR_WORK_SIZE)
    work[GEAR_WORK_DECK : GEAR_WORK_DECK + DECK_SIZE] = deck_array(
        np.zeros(3), np.array([0.0, 0.0, 1.0])
    )
    work[GEAR_WORK_LOCK_STIFFNESS] = lock_stiffness
    work[GEAR_WORK_LOCK_DAMPING] = lock_damping
    return Gear(pts, np.asarray(law, dtype=float).copy(), tail_lever(helicopter), work,
                np.zeros(pts.shape[0]), np.zeros((pts.shape[0], LOCK_SIZE)))  # fmt: skip


def tail_lever(helicopter: HelicopterParams) -> np.ndarray:
    """TRO from HO in F, its f1 and f3 offsets [m] (eq 2: TRO = O + dO-TRO,1 f1; eq 3: HO =
    O + dO-HO,3 f3), as ``kernels.wrench_loads_sc`` takes them.

    Parameters
    ----------
    helicopter : HelicopterParams
        The helicopter (Table II).

    Returns
    -------
    numpy.ndarray, shape (2,)
        (dO-TRO,1, -dO-HO,3) [m].
    """
    return np.array([helicopter.d_O_TRO1, -helicopter.d_O_HO3])


def gear_law_array(
    stiffness: float, damping: float, friction: float, slip_speed: float
) -> np.ndarray:
    """The contact law packed for ``gear_contact`` (``layout.GEAR_LAW_*``).

    Parameters
    ----------
    stiffness : float
        Normal stiffness per gear point [N/m], > 0.
    damping : float
        Normal damping per gear point [N s/m], >= 0.
    friction : float
        Coulomb friction coefficient [-], >= 0.
    slip_speed : float
        The slip speed below which friction is viscous [m/s], > 0.

    Returns
    -------
    numpy.ndarray, shape (GEAR_LAW_SIZE,)
        The packed law.
    """
    law = np.empty(GEAR_LAW_SIZE)
    law[GEAR_LAW_STIFFNESS] = stiffness
    law[GEAR_LAW_DAMPING] = damping
    law[GEAR_LAW_FRICTION] = friction
    law[GEAR_LAW_SLIP_SPEED] = slip_speed
    return law


def body_array(
    position: np.ndarray, velocity: np.ndarray, R_NF: np.ndarray, omega_F: np.ndarray
) -> np.ndarray:
    """A rigid body's pose and motion packed for ``gear_contact`` (``layout.BODY_*``).

    Parameters
    ----------
    position : array_like, shape (3,)
        HO from NO in N [m].
    velocity : array_like, shape (3,)
        HO's velocity in N [m/s].
    R_NF : array_like, shape (3, 3)
        The rotation N <- F (column j: f_j in N components).
    omega_F : array_like, shape (3,)
        F's angular velocity in N, in F components [rad/s].

    Returns
    -------
    numpy.ndarray, shape (BODY_SIZE,)
        The packed body.
    """
    body = np.empty(BODY_SIZE)
    body[BODY_POSITION : BODY_POSITION + 3] = position
    body[BODY_VELOCITY : BODY_VELOCITY + 3] = velocity
    body[BODY_R_NF : BODY_R_NF + 9] = np.asarray(R_NF, dtype=float).reshape(9)
    body[BODY_OMEGA_F : BODY_OMEGA_F + 3] = omega_F
    return body


def deck_array(
    point: np.ndarray,
    normal: np.ndarray,
    velocity: np.ndarray | None = None,
    omega: np.ndarray | None = None,
) -> np.ndarray:
    """A deck plane packed for ``gear_contact`` (``layout.DECK_*``); the normal is made unit.

    Parameters
    ----------
    point : array_like, shape (3,)
        A point of the plane in N [m].
    normal : array_like, shape (3,)
        The plane's normal out of the deck, in N (normalised here).
    velocity : array_like, shape (3,), optional
        That point's velocity in N [m/s] (default: at rest).
    omega : array_like, shape (3,), optional
        The deck's angular velocity in N [rad/s] (default: none).

    Returns
    -------
    numpy.ndarray, shape (DECK_SIZE,)
        The packed deck.
    """
    n = np.asarray(normal, dtype=float)
    deck = np.empty(DECK_SIZE)
    deck[DECK_POINT : DECK_POINT + 3] = point
    deck[DECK_NORMAL : DECK_NORMAL + 3] = n / np.linalg.norm(n)
    deck[DECK_VELOCITY : DECK_VELOCITY + 3] = 0.0 if velocity is None else velocity
    deck[DECK_OMEGA : DECK_OMEGA + 3] = 0.0 if omega is None else omega
    return deck
