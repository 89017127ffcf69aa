"""``Cable`` and ``drive_cable``: the lumped-mass chain of ``tether.lumped`` on its own,
bottom node fixed at an anchor, top node on a prescribed motion, advanced with the engine's
chain step (``tether.lumped.chain_interval``: ROS2 sub-steps chosen by the chain's step-size
rule inside each of the engine's RK4 steps)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._validation import check_integer, check_number, check_vector
from ..base.motion import BaseMotion, FileBase
from ..errors import ParameterError
from ..layout import (
    GROUND_DAMPING_PA_S_M,
    GROUND_FRICTION,
    GROUND_FRICTION_SPEED_M_S,
    GROUND_STIFFNESS_PA_M,
    LUMPED_BASE_ACC,
)
from ..resources import check_memory
from .chain import LumpedTether, static_chain
from .lumped import chain_forces, chain_interval, ros2_work

__all__ = ["Cable", "CableRun", "drive_cable"]

#: ``start`` values ``drive_cable`` takes besides an array of node positions
STARTS = ("static",)


@dataclass(frozen=True)
class Cable:
    """A lumped-mass cable: the keys of a scenario's ``[tether]`` table (``model`` and
    ``record_nodes`` aside) plus its unstretched length.

    Parameters
    ----------
    unstretched_length : float
        Unstretched length L0 [m], > 0.
    EA : float
        Axial stiffness [N], > 0.
    segments : int
        Number of segments N >= 1.
    mass_per_length : float
        Mass per unstretched length mu [kg/m], > 0.
    damping_ratio : float or None
        Damping ratio of the cable's fundamental axial mode (fixed ends), >= 0, whatever N.
        None with ``internal_damping`` None: 0.1 (the ``[tether]`` default).
    internal_damping : float or None
        Internal (Kelvin-Voigt) damping BA [N s]: axial damping force per unit strain rate,
        as MoorDyn's BA, >= 0. Give this or ``damping_ratio``, not both.
    diameter : float
        Diameter d [m], > 0.
    drag_coefficient : float
        Normal drag coefficient Cd, > 0.
    tangential_drag_coefficient : float
        Tangential drag coefficient Ct on the wetted area, >= 0.
    ground_stiffness : float
        The ground's normal stiffness kbot [Pa/m] under the free nodes (the plane z = 0 of
        N; the anchor at z = 0 lies on it), >= 0 (``[tether] ground_stiffness``; 0: none).
    ground_damping : float
        The ground's normal damping cbot [Pa s/m], >= 0.
    ground_friction : float
        Coulomb friction coefficient on the ground, >= 0.
    ground_friction_speed : float
        The friction's regularisation speed [m/s], > 0.
    """

    unstretched_length: float
    EA: float
    segments: int = 10
    mass_per_length: float = 0.02
    damping_ratio: float | None = None
    internal_damping: float | None = None
    diameter: float = 0.005
    drag_coefficient: float = 1.1
    tangential_drag_coefficient: float = 0.0
    ground_stiffness: float = GROUND_STIFFNESS_PA_M
    ground_damping: float = GROUND_DAMPING_PA_S_M
    ground_friction: float = GROUND_FRICTION
    ground_friction_speed: float = GROUND_FRICTION_SPEED_M_S

    def __post_init__(self) -> None:
        s = "cable"
        check_number(f"{s}.unstretched_length", self.unstretched_length, low=0.0, low_open=True,
                     unit="[m]")  # fmt: skip
        # LumpedTether validates the others and refuses both dampings
        object.__setattr__(self, "segments", check_integer(f"{s}.segments", self.segments, low=1))
        self.lumped_tether()

    def lumped_tether(self, rho: float = 1.225) -> LumpedTether:
        """The chain's parameters (``tether.chain.LumpedTether``).

        Parameters
        ----------
        rho : float
            Air density [kg/m^3], > 0.

        Returns
        -------
        LumpedTether
            The same cable at air density ``rho``.
        """
        return LumpedTether(
            segments=self.segments,
            mass_per_length_kg_m=self.mass_per_length,
            EA_N=self.EA,
            damping_ratio=self.damping_ratio,
            internal_damping_Ns=self.internal_damping,
            diameter_m=self.diameter,
            drag_coefficient=self.drag_coefficient,
            tangential_drag_coefficient=self.tangential_drag_coefficient,
            air_density_kg_m3=rho,
            ground_stiffness_Pa_m=self.ground_stiffness,
            ground_damping_Pa_s_m=self.ground_damping,
            ground_friction=self.ground_friction,
            ground_friction_speed_m_s=self.ground_friction_speed,
            field_prefix="cable",
        )


@dataclass(frozen=True)
class CableRun:
    """``drive_cable``'s result, at the samples t_k = k dt (frame N).

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times [s].
    top_force : ndarray, shape (n, 3)
        The cable's force on the top point [N] (with half the top segment's weight and drag,
        the force the engine applies at P).
    anchor_force : ndarray, shape (n, 3)
        The cable's force on the anchor [N] (with half the bottom segment's weight and drag).
    nodes : ndarray, shape (n, N + 1, 3)
        Node positions [m], node 0 the anchor, node N the top.
    velocities : ndarray, shape (n, N + 1, 3)
        Node velocities [m/s].
    cable : Cable
        The cable flown.
    dt : float
        The sample time [s].
    substeps : int
        The engine's RK4 steps per sample (the chain's step covers dt / substeps).
    """

    t: np.ndarray
    top_force: np.ndarray
    anchor_force: np.ndarray
    nodes: np.ndarray
    velocities: np.ndarray
    cable: Cable
    dt: float
    substeps: int


def _drive_arguments(cable, anchor, top, duration, dt, wind, rho, g) -> tuple:
    """The arguments ``drive_cable`` and ``tether.drive_moordyn`` share, checked (one line
    naming the argument): (anchor motion or None, anchor at t = 0 (3,), duration, dt, wind (3,),
    rho, g)."""
    if not isinstance(cable, Cable):
        raise ParameterError("cable", cable, "a tetherheli.tether.Cable")
    motion = anchor if isinstance(anchor, BaseMotion) else None
    a = (motion.state(0.0)[0, 0] if motion is not None
         else np.array(check_vector("anchor", anchor, 3), dtype=float))  # fmt: skip
    duration = check_number("duration", duration, low=0.0, low_open=True, unit="[s]")
    if isinstance(motion, FileBase) and motion.end < duration:
        raise ParameterError(
            "anchor",
            f"a file ending at t = {motion.end:g} s",
            f"a base motion covering the run (duration = {duration:g} s)",
        )
    dt = check_number("dt", dt, low=0.0, low_open=True, unit="[s]")
    w = np.array(check_vector("wind", wind, 3), dtype=float)
    rho = check_number("rho", rho, low=0.0, low_open=True, unit="[kg/m^3]")
    g = check_number("g", g, low=0.0, unit="[m/s^2]")
    if not callable(top):
        raise ParameterError("top", top, "a function top(t) -> (position[3], velocity[3])")
    return motion, a, duration, dt, w, rho, g


def _run_record(cable: Cable, duration: float, dt: float) -> tuple:
    """The sample times t = 0, dt, ..., (the last <= duration) and the empty arrays of a
    ``CableRun`` over them: (t, nodes, velocities, top_force, anchor_force). Their size is
    refused (``ResourceLimitError``) above the memory budget before it is allocated."""
    k_max = math.floor(duration / dt + 1e-9)
    n = cable.segments
    check_memory(
        f"a cable run: duration = {duration:g} s at dt = {dt:g} s with {n} segments",
        (k_max + 1) * (2 * (n + 1) + 3) * 3 * 8,
        hint="shorten the duration, lengthen dt or use fewer segments",
    )
    nodes = np.empty((k_max + 1, n + 1, 3))
    return (np.arange(k_max + 1) * dt, nodes, np.empty_like(nodes), np.empty((k_max + 1, 3)),
            np.empty((k_max + 1, 3)))  # fmt: skip


def _top_at(top, t):
    try:
        r, v = top(t)
        r = np.array(r, dtype=float).reshape(3)
        v = np.array(v, dtype=float).reshape(3)
    except (TypeError, ValueError) as err:
        raise ParameterError(
            "top", top, "a function top(t) -> (position[3] [m], velocity[3] [m/s])"
        ) from err
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(v))):
        raise ParameterError("top", f"top({t:g}) = ({r.tolist()}, {v.tolist()})",
                             "finite positions [m] and velocities [m/s]")  # fmt: skip
    return r, v


def drive_cable(
    cable: Cable,
    *,
    anchor: object,
    top: Callable[[float], tuple[object, object]],
    duration: float,
    dt: float,
    wind: object = (0.0, 0.0, 0.0),
    rho: float = 1.225,
    start: object = "static",
    substeps: int = 2,
    g: float = 9.81,
) -> CableRun:
    """Fly the cable with its bottom node fixed at ``anchor`` and its top node on the
    prescribed motion ``top(t)``, with the engine's chain step at the sample time ``dt``:
    per sample ``substeps`` steps of dt / substeps (the engine's ``[simulation] substeps``),
    each ``tether.lumped.chain_interval`` (ROS2 sub-steps of the chain's step-size rule, the
    top on the cubic Hermite curve between its values at the step's ends).

    Parameters
    ----------
    cable : Cable
        The cable.
    anchor : array_like, shape (3,), or BaseMotion
        The fixed bottom node [m], frame N (n3 up), or a moving base's motion b(t)
        (``tetherheli.base``): the chain is then flown in the base's translating frame, as
        the engine flies it over a moving winch, and recorded in N.
    top : callable
        top(t [s]) -> (position (3,) [m], velocity (3,) [m/s]) of the top node in N.
    duration : float
        Run length [s], > 0 (samples t = 0, dt, ..., the last <= duration).
    dt : float
        Sample time [s], > 0 (the engine's control sample; its default 0.01 s).
    wind : array_like, shape (3,)
        Uniform steady wind [m/s].
    rho : float
        Air density [kg/m^3], > 0.
    start : "static" or array_like, shape (N + 1, 3)
        "static": at rest in the chain's static shape (``static_chain``) between the anchor
        and top(0); an array: those node positions at rest (rows 0 and N are replaced by the
        anchor and top(0)).
    substeps : int
        The engine's RK4 steps per sample, >= 1 (its default 2).
    g : float
        Gravity [m/s^2], >= 0 (the paper's 9.81).

    Returns
    -------
    CableRun
        Times, end forces, nodes and velocities at the samples.

    Raises
    ------
    ParameterError
        Bad input (one line naming the argument).
    """
    motion, a, duration, dt, w, rho, g = _drive_arguments(
        cable, anchor, top, duration, dt, wind, rho, g
    )
    n_sub = check_integer("substeps", substeps, low=1)
    tether = cable.lumped_tether(rho)
    p = tether.packed(g)
    n = cable.segments
    L0 = cable.unstretched_length
    r0, v0 = _top_at(top, 0.0)
    if isinstance(start, str):
        if start not in STARTS:
            raise ParameterError("start", start, f"one of {STARTS} or node positions (N+1, 3)")
        if np.allclose(r0, a):
            raise ParameterError(
                "top", f"top(0) = {r0.tolist()}", "a start away from the anchor (start='static')"
            )
        x = static_chain(a, r0, L0, tether, g)
    else:
        x = np.array(start, dtype=float)
        if x.shape != (n + 1, 3) or not np.all(np.isfinite(x)):
            raise ParameterError("start", start, f"'static' or finite node positions ({n + 1}, 3)")
    x[0], x[n] = a, r0
    v = np.zeros_like(x)
    v[n] = v0
    work = ros2_work(n)
    t, nodes, vels, f_top, f_anchor = _run_record(cable, duration, dt)
    if motion is not None:
        _drive_on_base(motion, top, x, v, w, L0, p, dt, n_sub, work, t, nodes, vels, f_top,
                       f_anchor)  # fmt: skip
        return CableRun(t=t, top_force=f_top, anchor_force=f_anchor, nodes=nodes,
                        velocities=vels, cable=cable, dt=dt, substeps=n_sub)  # fmt: skip
    air = np.tile(w, (n + 1, 1))
    k_max = t.size - 1
    h = dt / n_sub
    F = np.empty((n + 1, 3))
    T = np.empty(n)
    J = np.empty((n, 3, 3))
    for k in range(k_max + 1):
        chain_forces(x, v, air, L0, p, F, T, J, J, J, False)
        nodes[k], vels[k], f_top[k], f_anchor[k] = x, v, F[n], F[0]
        if k == k_max:
            break
        for j in range(n_sub):
            r1, v1 = _top_at(top, k * dt + (j + 1) * h)
            chain_interval(x, v, air, L0, p, h, r1, v1, work)
            if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
                raise FloatingPointError(f"drive_cable: the chain diverged at t = {t[k]:g} s")
    return CableRun(t=t, top_force=f_top, anchor_force=f_anchor, nodes=nodes,
                    velocities=vels, cable=cable, dt=dt, substeps=n_sub)  # fmt: skip


def _drive_on_base(motion, top, x, v, w, L0, p, dt, n_sub, work, t, nodes, vels, f_top, f_anchor):
    """``drive_cable`` with the anchor on a moving base: the chain flown in the base's
    translating frame (positions and velocities relative to the anchor, the air relative to
    the base, the inertial force -m b'' on the free nodes, all at each step's middle; the
    engine's rule over a moving winch), recorded in N."""
    n = x.shape[0] - 1
    h = dt / n_sub
    b0 = motion.state(0.0)[0]
    x -= b0[0]
    v[n] -= b0[1]  # the other nodes start at rest on the base (the static shape in its frame)
    F = np.empty((n + 1, 3))
    T = np.empty(n)
    J = np.empty((n, 3, 3))
    air = np.empty((n + 1, 3))
    k_max = t.size - 1
    for k in range(k_max + 1):
        bk = motion.state(t[k])[0]
        air[:] = w - bk[1]
        p[LUMPED_BASE_ACC : LUMPED_BASE_ACC + 3] = bk[2]
        chain_forces(x, v, air, L0, p, F, T, J, J, J, False)
        nodes[k], vels[k], f_top[k], f_anchor[k] = x + bk[0], v + bk[1], F[n], F[0]
        if k == k_max:
            break
        for j in range(n_sub):
            t0 = k * dt + j * h
            b_mid, b1 = motion.state([t0 + 0.5 * h, t0 + h])
            r1, v1 = _top_at(top, t0 + h)
            air[:] = w - b_mid[1]
            p[LUMPED_BASE_ACC : LUMPED_BASE_ACC + 3] = b_mid[2]
            chain_interval(x, v, air, L0, p, h, r1 - b1[0], v1 - b1[1], work)
            if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
                raise FloatingPointError(f"drive_cable: the chain diverged at t = {t0:g} s")
