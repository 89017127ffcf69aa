"""``Cable`` and ``drive_cable``: the lumped-mass chain of ``tether.lumped`` on its own,
bottom node fixed at an anchor, top node on a prescribed motion, advanced with the engine's
chain step (``tether.lumped.chain_interval``: ROS2 sub-steps chosen by the chain's step-size
rule inside each of the engine's RK4 steps)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._validation import RK4_SUBSTEPS, check_number, check_samples, check_vector
from ..base.motion import BaseMotion, FileBase
from ..errors import InfeasibleError, ParameterError
from ..layout import (
    GROUND_DAMPING_PA_S_M,
    GROUND_FRICTION,
    GROUND_FRICTION_SPEED_M_S,
    GROUND_STIFFNESS_PA_M,
    LUMPED_BASE_ACC,
)
from ..params import MAX_TETHER_STRAIN, check_tether_length
from ..resources import check_memory
from .chain import LumpedTether, static_chain
from .lumped import chain_forces, chain_interval, ros2_work

__all__ = ["Cable", "CableRun", "drive_cable"]

#: ``start`` values ``drive_cable`` takes besides an array of node positions
STARTS = ("static",)
#: the densest fluid the cable is flown in [kg/m^3] (ten times water's)
MAX_FLUID_DENSITY = 1e4
#: the strongest gravity [m/s^2] (ten times Jupiter's)
MAX_GRAVITY = 250.0
#: the fastest wind on the cable, per axis [m/s] (a category 5 hurricane's is 70 m/s)
MAX_WIND_SPEED = 100.0


@dataclass(frozen=True)
class Cable:
    """A lumped-mass cable: the keys of a scenario's ``[tether]`` table (``model`` and
    ``record_nodes`` aside) plus its unstretched length.

    Parameters
    ----------
    unstretched_length : float
        Unstretched length L0 [m], a tether length in [0.5, 1000] (``params.TETHER_LENGTH_RANGE``).
    EA : float
        Axial stiffness [N], > 0.
    segments : int
        Number of segments N in [2, 1000] (the ``[tether]`` table's range).
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
        # the length as a tether length (the scenario's q9 rule); LumpedTether checks the
        # others with the [tether] table's keys (CABLE_KEYS) and refuses both dampings
        L0 = check_tether_length(self.unstretched_length, "cable.unstretched_length")
        object.__setattr__(self, "unstretched_length", L0)
        chain = self.lumped_tether()
        for name, value in (
            ("segments", chain.segments),
            ("mass_per_length", chain.mass_per_length_kg_m),
            ("EA", chain.EA_N),
            ("diameter", chain.diameter_m),
        ):
            object.__setattr__(self, name, value)

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
    naming the argument): (anchor motion or None, anchor at t = 0 (3,), duration, dt, the
    number of sample intervals (``_validation.check_samples``: at most ``MAX_SAMPLES``, as a
    scenario's), wind (3,), rho, g)."""
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
    k_max = check_samples(duration, dt)
    w = np.array(check_vector("wind", wind, 3, low=-MAX_WIND_SPEED, high=MAX_WIND_SPEED,
                              unit="[m/s]"), dtype=float)  # fmt: skip
    rho = check_number("rho", rho, low=0.0, low_open=True, high=MAX_FLUID_DENSITY,
                       unit="[kg/m^3]")  # fmt: skip
    g = check_number("g", g, low=0.0, high=MAX_GRAVITY, unit="[m/s^2]")
    if not callable(top):
        raise ParameterError("top", top, "a function top(t) -> (position[3], velocity[3])")
    return motion, a, duration, dt, k_max, w, rho, g


def _run_record(cable: Cable, duration: float, dt: float, k_max: int) -> tuple:
    """The sample times t = 0, dt, ..., k_max dt (the last <= duration) and the empty arrays
    of a ``CableRun`` over them: (t, nodes, velocities, top_force, anchor_force). Their size is
    refused (``ResourceLimitError``) above the memory budget before it is allocated."""
    n = cable.segments
    check_memory(
        f"a cable run: duration = {duration:g} s at dt = {dt:g} s with {n} segments",
        (k_max + 1) * (2 * (n + 1) + 3) * 3 * 8,
        hint="shorten the duration, lengthen dt or use fewer segments",
    )
    nodes = np.empty((k_max + 1, n + 1, 3))
    return (np.arange(k_max + 1) * dt, nodes, np.empty_like(nodes), np.empty((k_max + 1, 3)),
            np.empty((k_max + 1, 3)))  # fmt: skip


def _static_start(a: np.ndarray, r0: np.ndarray, cable: Cable, tether: LumpedTether,
                  g: float) -> np.ndarray:  # fmt: skip
    """The chain's static shape between the anchor ``a`` and top(0) ``r0`` (``static_chain``),
    for ``start="static"``; a shape that does not exist or cannot be solved is refused naming
    what the caller wrote (``cable.unstretched_length``, ``start``), not the solver's own
    arguments."""
    if np.allclose(r0, a):
        raise ParameterError(
            "top", f"top(0) = {r0.tolist()}", "a start away from the anchor (start='static')"
        )
    if g == 0.0:
        raise ParameterError("g", g, "a finite number > 0 [m/s^2] with start='static' (a "
                             "weightless cable has no static shape of its own; or give start "
                             "as node positions)")  # fmt: skip
    try:
        x = static_chain(a, r0, cable.unstretched_length, tether, g)
    except ParameterError as exc:
        if exc.field == "unstretched_length_m":  # a slack cable straight above the anchor
            raise InfeasibleError(
                "cable.unstretched_length",
                cable.unstretched_length,
                f"{exc.allowed} (top(0) straight above the anchor, start='static'; or give "
                "start as node positions)",
            ) from None
        raise InfeasibleError(
            "start",
            "static",
            f"node positions ({cable.segments + 1}, 3): the static shape between the anchor "
            f"and top(0) = {r0.tolist()} has no solution here ({exc.allowed})",
        ) from None
    # the static shape ignores the ground: one that hangs through it (a long slack cable) would
    # start inside the ground's spring, far from rest
    if cable.ground_stiffness > 0.0 and x[1:-1, 2].min(initial=0.0) < min(a[2], 0.0) - 1e-9:
        raise InfeasibleError(
            "start",
            "static",
            f"node positions ({cable.segments + 1}, 3): the static shape between the anchor and "
            f"top(0) = {r0.tolist()} hangs through the ground (z = 0) to z = "
            f"{x[1:-1, 2].min():.3g} m (or cable.ground_stiffness = 0)",
        )
    return x


def _top_start(top: Callable, a: np.ndarray, cable: Cable) -> tuple[np.ndarray, np.ndarray]:
    """top(0) (position, velocity), refused (naming ``top``) farther from the anchor ``a`` than
    the cable reaches at ``params.MAX_TETHER_STRAIN`` (the strain rule of every tether)."""
    r0, v0 = _top_at(top, 0.0)
    reach = (1.0 + MAX_TETHER_STRAIN) * cable.unstretched_length
    if not np.linalg.norm(r0 - a) <= reach:
        raise ParameterError(
            "top",
            f"top(0) = {r0.tolist()}",
            f"a start within {reach:g} m of the anchor (cable.unstretched_length = "
            f"{cable.unstretched_length:g} m at a strain of at most {MAX_TETHER_STRAIN:g})",
        )
    return r0, v0


def _top_at(top, t):
    try:
        r, v = top(t)
        r = np.array(r, dtype=float).reshape(3)
        v = np.array(v, dtype=float).reshape(3)
    except (TypeError, ValueError, OverflowError) as err:
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
    motion, a, duration, dt, k_max, w, rho, g = _drive_arguments(
        cable, anchor, top, duration, dt, wind, rho, g
    )
    n_sub = RK4_SUBSTEPS.check("substeps", substeps)
    n = cable.segments
    if not (isinstance(start, str) or isinstance(start, (list, tuple, np.ndarray))):
        raise ParameterError("start", start, f"'static' or finite node positions ({n + 1}, 3)")
    t, nodes, vels, f_top, f_anchor = _run_record(cable, duration, dt, k_max)
    tether = cable.lumped_tether(rho)
    p = tether.packed(g)
    L0 = cable.unstretched_length
    r0, v0 = _top_start(top, a, cable)
    if isinstance(start, str):
        if start not in STARTS:
            raise ParameterError("start", start, f"one of {STARTS} or node positions (N+1, 3)")
        x = _static_start(a, r0, cable, tether, g)
    else:
        x = _start_nodes(start, n)
    x[0], x[n] = a, r0
    v = np.zeros_like(x)
    v[n] = v0
    work = ros2_work(n)
    if motion is not None:
        _drive_on_base(motion, top, x, v, w, L0, p, dt, n_sub, work, t, nodes, vels, f_top,
                       f_anchor)  # fmt: skip
        return CableRun(t=t, top_force=f_top, anchor_force=f_anchor, nodes=nodes,
                        velocities=vels, cable=cable, dt=dt, substeps=n_sub)  # fmt: skip
    air = np.tile(w, (n + 1, 1))
    h = dt / n_sub
    F = np.empty((n + 1, 3))
    T = np.empty(n)
    J = np.empty((n, 3, 3))
    for k in range(k_max + 1):
        chain_forces(x, v, air, L0, p, F, T, (J, J, J), False)
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


def _start_nodes(start: object, n: int) -> np.ndarray:
    """``drive_cable``'s ``start`` given as node positions: finite, of shape (n + 1, 3), checked
    before it is converted (a huge or ragged list is refused, never copied)."""
    allowed = f"'static' or finite node positions ({n + 1}, 3)"
    shape = np.shape(start) if isinstance(start, np.ndarray) else None
    if shape is None and (not isinstance(start, (list, tuple)) or len(start) != n + 1):
        raise ParameterError("start", start, allowed)
    try:
        x = np.array(start, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError("start", start, allowed) from None
    if x.shape != (n + 1, 3) or not np.all(np.isfinite(x)):
        raise ParameterError("start", start, allowed)
    return x


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
        chain_forces(x, v, air, L0, p, F, T, (J, J, J), False)
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
