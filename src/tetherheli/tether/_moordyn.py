"""The same cable in MoorDyn v2, to validate the chain: ``drive_moordyn`` flies a ``Cable`` with
MoorDyn-C's Python API (``pip install "tetherheli[validation]"``) between the same fixed
anchor and prescribed top motion as ``drive_cable``, and returns a ``CableRun`` to compare.

MoorDyn models a line in water; in air it is set up as (``moordyn_input``): fluid density
rho (the air's), added mass Ca = CaAx = 0, bending stiffness EI = 0, MoorDyn's BA the
segment dashpot times l0 (``LumpedTether.segment_dashpot``: the same axial damping force per
unit strain rate), the tangential drag coefficient CdAx = Ct (both on the wetted area
pi d l), the whole chain ``depth`` below MoorDyn's still surface and far above its seabed
(nodes above the surface would get no drag), a uniform steady current for the wind
(``Currents 1``, a ``current_profile.txt`` beside the input file), MoorDyn's stationary
solver for the initial shape. MoorDyn weighs the displaced fluid (buoyancy rho A g per unit
length, A = pi d^2 / 4); ours does not: ``buoyant_gravity`` is the g that gives our chain the
same net weight.

Differences by design (measured in ``docs/studies/moordyn.md``): a slack segment carries no
tension and no damping in ours, while MoorDyn's dashpot BA (dl/dt) / l0 acts slack or taut (it
can push); ours takes the drag per stretched length at the segment midpoints, MoorDyn per
unstretched length at the nodes (with the node tangent); both report the force at the top
without the top half-segment's inertia (MoorDyn gives that mass to the coupled point:
``moordyn.GetPointM``; the engine leaves it out).
"""

from __future__ import annotations

import contextlib
import itertools
import math
import os
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from .._validation import Key, check_number
from ..errors import ParameterError
from ._cable import (
    MAX_FLUID_DENSITY,
    MAX_GRAVITY,
    Cable,
    CableRun,
    _drive_arguments,
    _run_record,
    _top_at,
    _top_start,
)
from .lumped import chain_omega_max

__all__ = ["MOORDYN_DEPTH_M", "buoyant_gravity", "drive_moordyn", "import_moordyn",
           "moordyn_input"]  # fmt: skip

#: the length of the last MoorDyn step before each sample [s] (module docstring)
_EVAL_S = 1e-9
#: the largest MoorDyn step of the stationary solver [s] (at most 1 / omega_max of the chain)
_IC_DT_S = 1e-3
#: the longest relaxation of MoorDyn's stationary solver (its TmaxIC) [s]
_TMAX_IC_S = 2000.0
#: the most node steps (MoorDyn steps x nodes) one call into MoorDyn-C may take: its start
#: (Init: up to TmaxIC / its step) and each Step call run in C, where Ctrl-C cannot stop them
#: (about 10 s at the 1e8 node steps per second measured)
MOORDYN_MAX_NODE_STEPS = 1e9
#: the most MoorDyn steps of dt_moordyn in one Step call of dt / coupling (as the chain's
#: ``lumped.CHAIN_MAX_SUBSTEPS``): each call returns to Python, where Ctrl-C stops the run
MOORDYN_MAX_STEPS_PER_CALL = 4096
#: MoorDyn's RK4 is stable for dt_moordyn |lambda| up to 2.78 (a real eigenvalue) or 2.83
#: (an imaginary one), lambda the cable's fastest eigenvalue: dt_moordyn is at most this over it
MOORDYN_RK4_STABLE = 2.5
#: the shortest Step call dt / coupling [s]: each ends with the _EVAL_S step at the sample
_MIN_CALL_S = 1000 * _EVAL_S
#: ``drive_moordyn``'s MoorDyn Step calls per sample (bounded as the engine's RK4 substeps)
COUPLING = Key("MoorDyn Step calls per control sample", kind="integer", low=1, high=1000)
#: how far below MoorDyn's still water surface the anchor sits [m] (the seabed is 3x lower)
MOORDYN_DEPTH_M = 1000.0


def import_moordyn():
    """The ``moordyn`` module (MoorDyn-C's Python API).

    Returns
    -------
    module
        ``moordyn``.

    Raises
    ------
    ImportError
        One line naming the package to install when it is missing.
    """
    try:
        import moordyn
    except ImportError:
        raise ImportError(
            "moordyn is needed for the MoorDyn comparison and is not installed: pip install "
            '"tetherheli[validation]" (or pip install moordyn)'
        ) from None
    return moordyn


def buoyant_gravity(cable: Cable, rho: float = 1.225, g: float = 9.81) -> float:
    """The gravity that gives our chain (no buoyancy) MoorDyn's net weight per unit length in a
    fluid of density rho: g (1 - rho A / mu), A = pi d^2 / 4.

    Parameters
    ----------
    cable : Cable
        The cable (diameter d, mass per length mu).
    rho : float
        Fluid density [kg/m^3], >= 0.
    g : float
        Gravity [m/s^2], >= 0.

    Returns
    -------
    float
        The buoyancy-corrected gravity [m/s^2].
    """
    rho = check_number("rho", rho, low=0.0, high=MAX_FLUID_DENSITY, unit="[kg/m^3]")
    g = check_number("g", g, low=0.0, high=MAX_GRAVITY, unit="[m/s^2]")
    area = math.pi * cable.diameter**2 / 4.0
    return g * (1.0 - rho * area / cable.mass_per_length)


def _f(x: float) -> str:
    return repr(float(x))


def moordyn_input(
    cable: Cable,
    anchor: np.ndarray,
    top: np.ndarray,
    *,
    rho: float,
    g: float,
    dt_moordyn: float,
    current: bool,
    drag_scale: float = 1.0,
    anchor_coupled: bool = False,
) -> str:
    """The text of a MoorDyn v2 input file for the cable between a fixed anchor and a coupled
    top point (module docstring: the set-up in air).

    Parameters
    ----------
    cable : Cable
        The cable.
    anchor, top : ndarray, shape (3,)
        The anchor and the top's start position in MoorDyn's frame [m] (z up, 0 at the surface).
    rho : float
        Fluid density [kg/m^3].
    g : float
        Gravity [m/s^2].
    dt_moordyn : float
        MoorDyn's step dtM [s] (RK4; ``drive_moordyn`` writes the stationary solver's and sets
        the run's after it).
    current : bool
        Whether MoorDyn reads a steady current (``Currents 1``: ``current_profile.txt`` beside
        the input file).
    drag_scale : float
        Factor on both drag coefficients (the per-length drag comparison of the study).
    anchor_coupled : bool
        Whether the anchor is a coupled point too (a moving base: its motion prescribed,
        its coupled degrees of freedom first).

    Returns
    -------
    str
        The input file's text.
    """
    lt = cable.lumped_tether(rho)
    ba = lt.segment_dashpot(cable.unstretched_length) * cable.unstretched_length / cable.segments
    cd = cable.drag_coefficient * drag_scale
    ct = cable.tangential_drag_coefficient * drag_scale
    a, b = anchor, top
    return f"""--------------------- MoorDyn Input File ------------------------------------
tetherheli: a cable in air (tetherheli.tether.moordyn_input)
---------------------- LINE TYPES -----------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
cable {_f(cable.diameter)} {_f(cable.mass_per_length)} {_f(cable.EA)} {_f(ba)} 0 {_f(cd)} 0 {_f(ct)} 0
---------------------- POINTS ---------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 {"Coupled" if anchor_coupled else "Fixed"} {_f(a[0])} {_f(a[1])} {_f(a[2])} 0 0 0 0
2 Coupled {_f(b[0])} {_f(b[1])} {_f(b[2])} 0 0 0 0
---------------------- LINES ----------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (#) (#) (m) (-) (-)
1 cable 1 2 {_f(cable.unstretched_length)} {cable.segments} -
---------------------- OPTIONS -----------------------------------------
0 writeLog
{_f(dt_moordyn)} dtM
RK4 tScheme
{_f(g)} g
{_f(rho)} rho
{_f(3.0 * MOORDYN_DEPTH_M)} WtrDpth
{1 if current else 0} Currents
1e-7 threshIC
{_f(_TMAX_IC_S)} TmaxIC
0 ICgenDynamic
1 disableOutput
1 disableOutTime
------------------------- need this line -------------------------------------
"""  # noqa: E501


def _chord(motion: Callable[[float], tuple], ta: float, tb: float, last: bool) -> tuple:
    """A coupled point's MoorDyn step over [ta, tb]: (position at ta, velocity). MoorDyn moves
    it linearly from the position with the velocity: the chord between motion(ta) and
    motion(tb), or, for a sample's last sliver (``last``), its own velocity at tb."""
    rb, vb = motion(tb)
    rb, vb = np.asarray(rb, dtype=float), np.asarray(vb, dtype=float)
    if not last:
        vb = (rb - np.asarray(motion(ta)[0], dtype=float)) / (tb - ta)
    return rb - vb * (tb - ta), vb


@contextlib.contextmanager
def _quiet_stdout() -> Iterator[None]:
    """MoorDyn-C prints its banner on the process's standard output: send it to devnull."""
    sys.stdout.flush()
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):
        yield
        return
    saved = os.dup(fd)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), fd)
            yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, fd)
        os.close(saved)


def _check_moordyn_start(cable: Cable, omega: float, ic_dt: float) -> None:
    """Refuse a cable whose MoorDyn start (Init, one call into C) could take more than
    ``MOORDYN_MAX_NODE_STEPS``: (N + 1) nodes x TmaxIC / its step min(1 ms, 1 / omega_max)."""
    work = (cable.segments + 1) * _TMAX_IC_S / ic_dt
    if not work <= MOORDYN_MAX_NODE_STEPS:
        raise ParameterError(
            "cable",
            f"Cable(unstretched_length={cable.unstretched_length:g}, EA={cable.EA:g}, "
            f"segments={cable.segments}, mass_per_length={cable.mass_per_length:g})",
            f"a cable whose MoorDyn start takes at most {MOORDYN_MAX_NODE_STEPS:.0e} node steps "
            f"((N + 1) x TmaxIC / min(1 ms, 1 / omega_max), TmaxIC = {_TMAX_IC_S:g} s; here "
            f"{work:.2g}: N = {cable.segments}, omega_max = (2 N / L0) sqrt(EA / mu) = "
            f"{omega:.3g} rad/s): fewer segments or a softer or heavier cable",
        )


def _check_dt_moordyn(dt_moordyn: object, cable: Cable, rho: float, h: float,
                      omega: float) -> float:  # fmt: skip
    """``dt_moordyn`` checked: > 0, at least h / ``MOORDYN_MAX_STEPS_PER_CALL`` (h = dt /
    coupling, a Step call's length) and at most the stable step of MoorDyn's RK4 for the
    cable, ``MOORDYN_RK4_STABLE`` / |lambda|: lambda the fastest eigenvalue of the chain's
    highest axial mode, omega_max (zeta + sqrt(1 + zeta^2)), zeta = c omega_max / (2 k) its
    damping ratio (c the segment dashpot, k = EA / l0)."""
    n, L0 = cable.segments, cable.unstretched_length
    c = cable.lumped_tether(rho).segment_dashpot(L0)
    zeta = c * omega / (2.0 * cable.EA * n / L0)
    stable = MOORDYN_RK4_STABLE / (omega * (zeta + math.sqrt(1.0 + zeta * zeta)))
    least = h / MOORDYN_MAX_STEPS_PER_CALL
    allowed = (
        f"a finite number in [{least:.3g}, {stable:.3g}] [s] (at least dt / coupling / "
        f"{MOORDYN_MAX_STEPS_PER_CALL}: at most {MOORDYN_MAX_STEPS_PER_CALL} MoorDyn steps per "
        f"Step call; at most {MOORDYN_RK4_STABLE:g} / |lambda|, the stable step of MoorDyn's RK4 "
        f"for this cable, omega_max = {omega:.3g} rad/s with its damping ratio {zeta:.3g}"
        + (": none here, raise coupling or soften the cable)" if least > stable else ")")
    )
    return check_number("dt_moordyn", dt_moordyn, low=least, high=stable, allowed=allowed)


def drive_moordyn(
    cable: Cable,
    *,
    anchor: object,
    top: Callable[[float], tuple[object, object]],
    duration: float,
    dt: float,
    wind: object = (0.0, 0.0, 0.0),
    rho: float = 1.225,
    g: float = 9.81,
    dt_moordyn: float = 1e-4,
    coupling: int = 20,
    drag_scale: float = 1.0,
) -> CableRun:
    """Fly the cable in MoorDyn v2 between ``anchor`` and the prescribed ``top(t)``, sampled as
    ``drive_cable`` (t_k = k dt), from MoorDyn's static shape for top(0) (in the wind, if any).

    Each sample is ``coupling`` MoorDyn ``Step`` calls of h = dt / coupling, each in sub-steps
    of at most ``dt_moordyn`` (RK4; the stationary solver of the start relaxes with the
    larger min(1 ms, 1 / omega_max), omega_max the chain's highest axial frequency). MoorDyn
    moves a coupled point linearly over a call, from the position given at its start with
    the velocity given: the calls follow the chords
    between top(t) and top(t + h) (the top's velocity errs by O(h) about a zero mean, a second
    order error). MoorDyn's force at the top is that of its last RK4 stage, whose state is
    first order in the step, and the chord's velocity lags by h / 2: the last call of each
    sample is therefore split, its last 1e-9 s at the sample's own position and velocity
    top(t_k), top'(t_k), so the force read is the sample's state's.

    Parameters
    ----------
    cable, anchor, top
        As for ``drive_cable``.
    duration : float
        Run length [s], > 0.
    dt : float
        Sample time [s], > 0.
    wind : array_like, shape (3,)
        Uniform steady wind [m/s] (MoorDyn's current).
    rho : float
        Air density [kg/m^3], > 0 (MoorDyn's fluid density: drag and buoyancy).
    g : float
        Gravity [m/s^2], >= 0.
    dt_moordyn : float
        MoorDyn's largest step dtM [s], > 0.
    coupling : int
        MoorDyn ``Step`` calls per sample, >= 1.
    drag_scale : float
        Factor on MoorDyn's drag coefficients, in (0, 10] (1: the cable's).

    Returns
    -------
    CableRun
        Times, end forces (the top's from ``GetPointForce``, the anchor's the net force on
        the line's node 0), nodes and velocities at the samples; ``substeps`` = ``coupling``.

    Raises
    ------
    ParameterError
        Bad input (one line naming the argument).
    ImportError
        ``moordyn`` is not installed.
    RuntimeError
        MoorDyn failed (its error code).
    """
    motion, a, duration, dt, k_max, w, rho, g = _drive_arguments(
        cable, anchor, top, duration, dt, wind, rho, g
    )
    m = COUPLING.check("coupling", coupling)
    if dt / m < _MIN_CALL_S:
        raise ParameterError("dt", dt, f"a finite number >= {m * _MIN_CALL_S:g} [s] (each MoorDyn "
                             f"Step call of dt / coupling at least {_MIN_CALL_S:g} s)")  # fmt: skip
    drag_scale = check_number("drag_scale", drag_scale, low=0.0, low_open=True, high=10.0)
    n = cable.segments
    p = cable.lumped_tether(rho).packed(g)
    omega = chain_omega_max(p, cable.unstretched_length, n)
    ic_dt = min(_IC_DT_S, 1.0 / omega)
    _check_moordyn_start(cable, omega, ic_dt)
    dtm = _check_dt_moordyn(dt_moordyn, cable, rho, dt / m, omega)
    md = import_moordyn()
    off = np.array([0.0, 0.0, -MOORDYN_DEPTH_M]) - a  # ours -> MoorDyn's frame
    r0 = _top_start(top, a, cable)[0]
    if np.allclose(r0, a):
        raise ParameterError("top", f"top(0) = {r0.tolist()}", "a start away from the anchor")
    t, nodes, vels, f_top, f_anchor = _run_record(cable, duration, dt, k_max)
    h = dt / m
    with tempfile.TemporaryDirectory(prefix="tetherheli-moordyn-") as folder:
        path = Path(folder) / "cable.txt"
        current = bool(np.any(w != 0.0))
        if current:
            z = (-4.0 * MOORDYN_DEPTH_M, 0.0)
            rows = "".join(f"{_f(zi)} {_f(w[0])} {_f(w[1])} {_f(w[2])}\n" for zi in z)
            (Path(folder) / "current_profile.txt").write_text(
                "--- MoorDyn steady currents (tetherheli) ---\nuniform\nz ux uy uz\n" + rows
            )
        # the stationary solver relaxes with dtM: the file has min(_IC_DT_S, 1 / omega_max),
        # the run's dt_moordyn is set after it (SetDt)
        path.write_text(moordyn_input(cable, a + off, r0 + off, rho=rho, g=g, dt_moordyn=ic_dt,
                                      current=current, drag_scale=drag_scale,
                                      anchor_coupled=motion is not None))  # fmt: skip
        start = [*(a + off), *(r0 + off)] if motion is not None else list(r0 + off)
        with _quiet_stdout():
            system = md.Create(str(path))
            err = md.Init(system, start, [0.0] * len(start))
        if err != 0:
            md.Close(system)
            raise RuntimeError(f"moordyn.Init failed with error code {err}")
        md.SetDt(system, dtm)
    point = md.GetPoint(system, 2)
    line = md.GetLine(system, 1)
    try:
        for k in range(k_max + 1):
            for i in range(n + 1):
                nodes[k, i] = md.GetLineNodePos(line, i)
                vels[k, i] = md.GetLineNodeVel(line, i)
            f_top[k] = md.GetPointForce(point)
            f_anchor[k] = md.GetLineNodeForce(line, 0)
            if k == k_max:
                break
            # chords over [ta, tb]; the last call ends with a step of _EVAL_S at the sample's
            # velocity: its last RK4 stage, hence the force read, is the sample's state
            ends = [k * dt + j * h for j in range(m)] + [(k + 1) * dt - _EVAL_S, (k + 1) * dt]
            for ta, tb in itertools.pairwise(ends):
                last = tb == ends[-1]
                ra, vb = _chord(lambda s: _top_at(top, s), ta, tb, last)
                if motion is not None:
                    aa, va = _chord(lambda s: motion.state(s)[0, :2], ta, tb, last)
                    ra, vb = np.concatenate([aa, ra]), np.concatenate([va, vb])
                    md.Step(system, list(ra + np.tile(off, 2)), list(vb), ta, tb - ta)
                else:
                    md.Step(system, list(ra + off), list(vb), ta, tb - ta)
            if not (np.all(np.isfinite(nodes[k])) and np.all(np.isfinite(f_top[k]))):
                raise FloatingPointError(f"drive_moordyn: MoorDyn diverged at t = {t[k]:g} s")
    finally:
        with _quiet_stdout():
            md.Close(system)
    nodes -= off
    return CableRun(t=t, top_force=f_top, anchor_force=f_anchor, nodes=nodes,
                    velocities=vels, cable=cable, dt=dt, substeps=m)  # fmt: skip
