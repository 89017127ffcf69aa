"""The cases of the MoorDyn comparison and their figures, shared by
``tests/test_moordyn.py`` and ``benchmarks/moordyn_validation.py`` (the tables of
``docs/studies/moordyn.md``).

Each case flies one cable three times: MoorDyn v2 at a converged step (``drive_moordyn``, the
reference), ``drive_cable`` at the engine's default 10 ms sample, and ``drive_cable`` at a
converged sample (to split the difference into the model's and our step's). The figures are
relative RMS differences of the force at the top (``relative_rms``) after the motion's ramp and
the static force's relative difference at t = 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from tetherheli.base.motion import HarmonicBase
from tetherheli.tether._cable import Cable, CableRun, drive_cable
from tetherheli.tether._moordyn import buoyant_gravity, drive_moordyn

__all__ = ["HEAVY_CABLE", "MOORDYN_CASES", "MOVING_ANCHOR_CASES", "PAPER_CABLE", "CaseFigures",
           "MoorDynCase", "compare_case", "half_segment_inertia", "relative_rms", "shaking_top",
           "slack_push", "steady_state"]  # fmt: skip

#: the paper's cable: EA = K_C L0N = 40 N/m x 9.375 m (Table III), 20 g/m, 5 mm, N = 10
PAPER_CABLE = Cable(unstretched_length=9.375, EA=375.0, segments=10)
#: a heavy 50 m cable: 0.1 kg/m, 10 mm, EA 20 kN, N = 10
HEAVY_CABLE = Cable(unstretched_length=50.0, EA=20e3, segments=10, mass_per_length=0.1,
                    diameter=0.01)  # fmt: skip


def relative_rms(got: np.ndarray, ref: np.ndarray) -> float:
    """RMS of the difference over the reference's standard deviation, vectors summed:
    sqrt(mean |got - ref|^2) / sqrt(mean |ref - mean(ref)|^2).

    Parameters
    ----------
    got, ref : ndarray, shape (n, 3) or (n,)
        The compared samples and the reference's.

    Returns
    -------
    float
        The relative RMS difference (0: equal).
    """
    got = np.asarray(got, dtype=float)
    ref = np.asarray(ref, dtype=float)
    diff = np.sqrt(np.mean(np.sum((got - ref).reshape(len(ref), -1) ** 2, axis=1)))
    spread = np.sqrt(np.mean(np.sum((ref - ref.mean(axis=0)).reshape(len(ref), -1) ** 2, axis=1)))
    return float(diff / spread)


def _smoothstep(t: float, T: float) -> tuple[float, float]:
    if T <= 0.0 or t >= T:
        return 1.0, 0.0
    s = t / T
    return s * s * (3.0 - 2.0 * s), 6.0 * s * (1.0 - s) / T


def shaking_top(
    base: tuple[float, float, float],
    axis: int = 0,
    amplitude: float = 0.0,
    frequency: float = 1.0,
    ramp: float = 1.0,
) -> Callable[[float], tuple[np.ndarray, np.ndarray]]:
    """top(t): the top at ``base`` moving amplitude sin(2 pi f t) along ``axis``, the amplitude
    ramped in by a smoothstep over ``ramp`` seconds (no impulsive start).

    Parameters
    ----------
    base : tuple of float
        The top's mean position [m] (anchor at the origin, n3 up).
    axis : int
        0, 1 or 2: the direction of the motion.
    amplitude : float
        Amplitude [m] (0: a still top).
    frequency : float
        Frequency [Hz].
    ramp : float
        Ramp time [s].

    Returns
    -------
    callable
        top(t) -> (position (3,) [m], velocity (3,) [m/s]).
    """
    w = 2.0 * math.pi * frequency

    def top(t: float) -> tuple[np.ndarray, np.ndarray]:
        a, da = _smoothstep(t, ramp)
        r = np.array(base, dtype=float)
        v = np.zeros(3)
        r[axis] += amplitude * a * math.sin(w * t)
        v[axis] += amplitude * (da * math.sin(w * t) + a * w * math.cos(w * t))
        return r, v

    return top


@dataclass(frozen=True)
class MoorDynCase:
    """One comparison: a cable, its top's motion, the wind, the run's length.

    Parameters
    ----------
    name : str
        The case's name (the tables' row).
    cable : Cable
        The cable.
    base : tuple of float
        The top's mean position [m] (anchor at the origin).
    axis : int
        The motion's direction (0 sideways, 2 vertical).
    amplitude : float
        The motion's amplitude [m] (0: statics or a steady wind).
    frequency : float
        The motion's frequency [Hz].
    duration : float
        Run length [s].
    settle : float
        The figures use t >= settle [s] (after the ramp or the wind's transient).
    wind : tuple of float
        Steady wind [m/s].
    anchor_axis, anchor_amplitude, anchor_frequency : int, float, float
        The anchor on a moving base: amplitude [m] cos(2 pi f t) along that axis,
        starting at rest (0: the fixed anchor).
    """

    name: str
    cable: Cable
    base: tuple[float, float, float]
    axis: int = 0
    amplitude: float = 0.0
    frequency: float = 1.0
    duration: float = 3.0
    settle: float = 1.0
    wind: tuple[float, float, float] = field(default=(0.0, 0.0, 0.0))
    anchor_axis: int = 2
    anchor_amplitude: float = 0.0
    anchor_frequency: float = 1.0

    def anchor(self) -> object:
        """The anchor: the origin, or a moving base's motion.

        Returns
        -------
        tuple or HarmonicBase
            (0, 0, 0), or the ``HarmonicBase`` (phase pi/2: at rest at t = 0).
        """
        if self.anchor_amplitude == 0.0:
            return (0.0, 0.0, 0.0)
        amplitude = [0.0, 0.0, 0.0]
        frequency = [0.0, 0.0, 0.0]
        phase = [0.0, 0.0, 0.0]
        amplitude[self.anchor_axis] = self.anchor_amplitude
        frequency[self.anchor_axis] = self.anchor_frequency
        phase[self.anchor_axis] = 0.5 * math.pi
        return HarmonicBase(
            amplitude=(amplitude[0], amplitude[1], amplitude[2]),
            frequency=(frequency[0], frequency[1], frequency[2]),
            phase=(phase[0], phase[1], phase[2]),
        )

    def top(self) -> Callable[[float], tuple[np.ndarray, np.ndarray]]:
        """The top's motion (``shaking_top``).

        Returns
        -------
        callable
            top(t) -> (position, velocity).
        """
        return shaking_top(self.base, self.axis, self.amplitude, self.frequency)


def _case(name, cable=PAPER_CABLE, base=(0.0, 0.0, 10.0), **kw) -> tuple[str, MoorDynCase]:
    return name, MoorDynCase(name=name, cable=cable, base=base, **kw)


#: the cases of ``docs/studies/moordyn.md``: statics, the paper's cable 10 m up moving 0.5 m
#: sideways and vertically at 0.2, 1 and 3 Hz (0.25 m vertically at 3 Hz: 0.5 m slackens
#: it), the heavy 50 m cable, a steady 10 m/s wind, and a 1 m vertical motion that slackens
#: the cable
MOORDYN_CASES: dict[str, MoorDynCase] = dict(
    [
        _case("static inclined", base=(5.0, 0.0, 8.66), duration=0.5, settle=0.0),
        _case("sideways 0.2 Hz", amplitude=0.5, frequency=0.2, duration=6.0),
        _case("sideways 1 Hz", amplitude=0.5, frequency=1.0, duration=4.0),
        _case("sideways 3 Hz", amplitude=0.5, frequency=3.0, duration=3.0),
        _case("vertical 0.2 Hz", axis=2, amplitude=0.5, frequency=0.2, duration=6.0),
        _case("vertical 1 Hz", axis=2, amplitude=0.5, frequency=1.0, duration=4.0),
        _case("vertical 3 Hz (0.25 m)", axis=2, amplitude=0.25, frequency=3.0, duration=3.0),
        _case(
            "heavy 50 m, 0.2 Hz",
            HEAVY_CABLE,
            base=(30.0, 0.0, 38.0),
            amplitude=0.5,
            frequency=0.2,
            duration=7.0,
        ),
        _case("steady wind 10 m/s", wind=(10.0, 0.0, 0.0), duration=8.0, settle=6.0),
        _case("slack: vertical 1 m, 1 Hz", axis=2, amplitude=1.0, frequency=1.0, duration=4.0),
    ]
)


#: the anchor on a moving base (a heaving or swaying deck), the top held still 10 m up:
#: the engine's moving-winch frame (``drive_cable`` on a ``BaseMotion``) against MoorDyn's
#: coupled anchor point in N
MOVING_ANCHOR_CASES: dict[str, MoorDynCase] = dict(
    [
        _case("anchor heave 1 Hz (0.25 m)", anchor_amplitude=0.25, duration=4.0),
        _case(
            "anchor heave 3 Hz (0.1 m)", anchor_amplitude=0.1, anchor_frequency=3.0, duration=3.0
        ),
        _case("anchor sway 1 Hz (0.5 m)", anchor_axis=0, anchor_amplitude=0.5, duration=4.0),
    ]
)


@dataclass(frozen=True)
class CaseFigures:
    """A case's figures (``compare_case``).

    Parameters
    ----------
    case : MoorDynCase
        The case.
    static_error : float
        |F_ours(0) - F_MoorDyn(0)| / |F_MoorDyn(0)| at the engine's sample (both static).
    rms_default : float
        ``relative_rms`` of the top force, ours at dt (the engine's 10 ms) against MoorDyn.
    rms_converged : float
        The same with ours at a converged sample (dt / ``refine``): the models' difference.
    rms_step : float
        Ours at dt against ours converged: our step's error.
    force_std : float
        The reference's spread sqrt(mean |F - mean F|^2) [N] over t >= settle.
    mean_force_error : float
        |mean F_ours - mean F_MoorDyn| / |mean F_MoorDyn| over t >= settle (ours at dt).
    min_tension : float
        The least segment tension of ours at dt over the run [N] (0: some segment went
        slack).
    ours : CableRun
        Ours at dt.
    reference : CableRun
        MoorDyn's run.
    """

    case: MoorDynCase
    static_error: float
    rms_default: float
    rms_converged: float
    rms_step: float
    force_std: float
    mean_force_error: float
    min_tension: float
    ours: CableRun
    reference: CableRun


def _min_tension(run: CableRun) -> float:
    d = np.diff(run.nodes, axis=1)
    strain = np.linalg.norm(d, axis=2) / (run.cable.unstretched_length / run.cable.segments)
    return float(max(0.0, np.min(strain - 1.0)) * run.cable.EA)


def compare_case(
    case: MoorDynCase,
    *,
    dt: float = 0.01,
    refine: int | None = 64,
    dt_moordyn: float = 1e-4,
    coupling: int = 20,
    cable: Cable | None = None,
    drag_scale: float = 1.0,
) -> CaseFigures:
    """Fly a case in MoorDyn and twice in ours (at dt and at dt / refine) and take the
    figures (``CaseFigures``). Ours flies with ``buoyant_gravity`` (MoorDyn's net weight).

    Parameters
    ----------
    case : MoorDynCase
        The case.
    dt : float
        Our sample [s] (the engine's default 0.01).
    refine : int or None
        Our converged run's sample is dt / refine, >= 1 (None: no converged run, its
        figures NaN).
    dt_moordyn : float
        MoorDyn's step dtM [s].
    coupling : int
        MoorDyn ``Step`` calls per sample dt.
    cable : Cable or None
        A replacement for the case's cable (the slack study's undamped variant).
    drag_scale : float
        Factor on MoorDyn's drag coefficients (the drag-per-length study).

    Returns
    -------
    CaseFigures
        The figures and the two runs at dt.
    """
    if cable is not None:
        case = replace(case, cable=cable)
    top = case.top()
    g = buoyant_gravity(case.cable)
    kw: dict[str, Any]  # keyword arguments of both drivers
    kw = {"anchor": case.anchor(), "top": top, "duration": case.duration, "wind": case.wind}
    ref = drive_moordyn(case.cable, dt=dt, dt_moordyn=dt_moordyn, coupling=coupling,
                        drag_scale=drag_scale, **kw)  # fmt: skip
    ours = drive_cable(case.cable, dt=dt, g=g, **kw)
    nan = float("nan")
    if refine is None:
        f_fine = np.full_like(ref.top_force, nan)
    else:
        fine = drive_cable(case.cable, dt=dt / refine, g=g, **kw)
        f_fine = fine.top_force[::refine][: len(ref.t)]
    s = ref.t >= case.settle - 1e-9
    F_ref, F_ours = ref.top_force[s], ours.top_force[s]
    spread = float(np.sqrt(np.mean(np.sum((F_ref - F_ref.mean(axis=0)) ** 2, axis=1))))
    moving = case.amplitude > 0.0 or case.anchor_amplitude > 0.0
    return CaseFigures(
        case=case,
        static_error=float(
            np.linalg.norm(ours.top_force[0] - ref.top_force[0]) / np.linalg.norm(ref.top_force[0])
        ),
        rms_default=relative_rms(F_ours, F_ref) if moving else nan,
        rms_converged=relative_rms(f_fine[s], F_ref) if moving else nan,
        rms_step=relative_rms(F_ours, f_fine[s]) if moving else nan,
        force_std=spread,
        mean_force_error=float(
            np.linalg.norm(F_ours.mean(axis=0) - F_ref.mean(axis=0))
            / np.linalg.norm(F_ref.mean(axis=0))
        ),
        min_tension=_min_tension(ours),
        ours=ours,
        reference=ref,
    )


def slack_push(run: CableRun) -> tuple[np.ndarray, np.ndarray]:
    """Where a run's segments are slack and what MoorDyn's dashpot does there: its force
    BA (dl/dt) / l0 on a slack segment, positive when it pushes (ours: none, by design).

    Parameters
    ----------
    run : CableRun
        A run (MoorDyn's for the push to be real).

    Returns
    -------
    slack : ndarray of bool, shape (n, N)
        l < l0 per sample and segment.
    push : ndarray, shape (n, N)
        -BA (dl/dt) / l0 on the slack segments, 0 elsewhere [N].
    """
    cable = run.cable
    l0 = cable.unstretched_length / cable.segments
    ba = cable.lumped_tether().segment_dashpot(cable.unstretched_length) * l0
    d = np.diff(run.nodes, axis=1)
    length = np.linalg.norm(d, axis=2)
    ldot = np.sum(np.diff(run.velocities, axis=1) * d / length[..., None], axis=2)
    slack = length < l0
    return slack, np.where(slack, -ba * ldot / l0, 0.0)


def steady_state(run: CableRun, settle: float) -> tuple[np.ndarray, np.ndarray, float]:
    """A run's means over t >= settle: the force at the top, the middle node's position and
    the mean stretch l / l0 of the segments.

    Parameters
    ----------
    run : CableRun
        A run.
    settle : float
        Start of the averages [s].

    Returns
    -------
    force : ndarray, shape (3,)
        Mean force at the top [N].
    middle : ndarray, shape (3,)
        Mean position of node N // 2 [m].
    stretch : float
        Mean l / l0 over segments and samples.
    """
    s = run.t >= settle - 1e-9
    nodes = run.nodes[s]
    l0 = run.cable.unstretched_length / run.cable.segments
    stretch = float(np.mean(np.linalg.norm(np.diff(nodes, axis=1), axis=2)) / l0)
    return run.top_force[s].mean(axis=0), nodes[:, run.cable.segments // 2].mean(axis=0), stretch


def half_segment_inertia(case: MoorDynCase, force_std: float) -> float:
    """The top half-segment's inertial force, RMS over t >= settle, over the force's spread:
    (mu l0 / 2) RMS(a_top) / force_std (the force neither code includes).

    Parameters
    ----------
    case : MoorDynCase
        A moving case.
    force_std : float
        The reference force's spread [N] (``CaseFigures.force_std``).

    Returns
    -------
    float
        The ratio.
    """
    cable = case.cable
    half = 0.5 * cable.mass_per_length * cable.unstretched_length / cable.segments
    w = 2.0 * math.pi * case.frequency
    t = np.linspace(case.settle, case.duration, 4001)
    a_top = case.amplitude * w**2 * np.sin(w * t)
    return float(half * np.sqrt(np.mean(a_top**2)) / force_std)
