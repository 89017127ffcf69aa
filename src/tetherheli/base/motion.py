"""The winch's base and its prescribed motion b(t) in frame N.

The paper's winch sits still at the origin of N. Here it may sit on a moving base: a vehicle
or a ship under way, a heaving deck, or a recorded track. Every motion gives the position,
velocity and acceleration of the winch point B at any time: the engine flies the helicopter
and the tether in the base's translating frame, where b'' acts as the inertial force -m b''
(``model.derive(moving_base=True)``), and reports positions in N as b(t) plus the relative
ones.

The contract is one method, ``state(t) -> (n, 3, 3)``: for each time, the rows position
[m], velocity [m/s] and acceleration [m/s^2], each with N components. Every motion is also
written in the engine's packed form (``base.compiled``): a constant offset and velocity, a sum
of sinusoids per axis, and cubic pieces, so one compiled evaluation serves them all.
"""

from __future__ import annotations

import functools
import hashlib
import math
import re
from array import array
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from .._validation import Key, trusted
from ..errors import ParameterError

__all__ = [
    "BASE_KEYS",
    "FILE_MAX_BYTES",
    "FILE_MAX_ROWS",
    "MOTIONS",
    "MOTION_KEYS",
    "TRACK_COLUMNS",
    "BaseMotion",
    "BaseParts",
    "FileBase",
    "FixedBase",
    "HarmonicBase",
    "SeaStateBase",
    "VelocityBase",
    "base_motion_from",
    "jonswap",
    "read_base_csv",
    "sea_components",
    "sea_phases",
]

#: The most rows a track file may hold after its header, blank lines included (counted while
#: it is streamed, refused before more is read).
FILE_MAX_ROWS = 1_000_000
#: The longest line of a track file [bytes]: four numbers of 17 significant digits with
#: their signs and exponents fit in a third of it.
TRACK_MAX_LINE = 256
#: The largest track file [bytes] (checked before it is opened for reading).
FILE_MAX_BYTES = 128_000_000
#: The most sinusoids of a sea state (the engine evaluates each at every step).
SEA_STATE_MAX_COMPONENTS = 1024

# The physical range of the base's inputs: one rule for the [base] keys and the track's columns
#: [m] the farthest the base may be from the origin of N on each axis (a ship's track of
#: 1000 km; a deck's heave is metres)
BASE_POSITION_MAX_M = 1e6
#: [m/s] the fastest a base may move on each axis (the fastest ships are ~25 m/s, vehicles ~
#: 100 m/s)
BASE_SPEED_MAX_M_S = 100.0
#: [m] the largest harmonic amplitude per axis (the highest ocean waves are ~30 m)
BASE_AMPLITUDE_MAX_M = 100.0
#: [m/s] the fastest ship (a fast patrol craft; the encounter frequency of following seas is
#: folded at any speed, ``base.ship``)
SHIP_SPEED_MAX_M_S = 25.0
#: [m] the farthest a pad may lie from the ship's centre of motion on each axis
SHIP_PAD_MAX_M = 200.0
#: [s] the track's times lie within +-this (3 years; a run has at most 1e9 samples)
TRACK_TIME_MAX_S = 1e8
#: [s] the shortest step between two rows of a track (10 kHz); with the bounds above every
#: spline coefficient stays finite
TRACK_MIN_STEP_S = 1e-4

#: the motions a ``[base]`` table's ``motion`` names
MOTIONS: tuple[str, ...] = ("fixed", "velocity", "harmonic", "sea_state", "file", "ship")
#: the keys of a ``[base]`` table, each described once: the motions check their values with
#: them and the scenario reference prints them (``scenario.tables.BaseSettings``)
BASE_KEYS: dict[str, Key] = {
    "motion": Key("the winch's base: still (the paper's), under way at a constant velocity, "
                  "harmonic per axis, a JONSWAP sea state, a recorded track (CSV), or a ship "
                  "in six degrees of freedom (RAOs x a JONSWAP sea; tetherheli.base.ship)",
                  kind="text", choices=MOTIONS),
    "position": Key("the base's position at t = 0 (motion fixed or velocity)", "m",
                    kind="vector", length=3, low=-BASE_POSITION_MAX_M,
                    high=BASE_POSITION_MAX_M),
    "velocity": Key("the base's constant velocity (motion velocity)", "m/s", kind="vector",
                    length=3, low=-BASE_SPEED_MAX_M_S, high=BASE_SPEED_MAX_M_S),
    "amplitude": Key("amplitude of b_i = A_i sin(2 pi f_i t + p_i) per axis of N (motion "
                     "harmonic)", "m", kind="vector", length=3, low=0.0,
                     high=BASE_AMPLITUDE_MAX_M),
    "frequency": Key("frequency f_i per axis (motion harmonic)", "Hz", kind="vector", length=3,
                     low=0.0, high=100.0),
    "phase": Key("phase p_i per axis (motion harmonic)", "rad", kind="vector", length=3,
                 low=-2 * math.pi, high=2 * math.pi),
    "significant_wave_height": Key("Hs = 4 sqrt(m0) of the deck's heave (motion sea_state), "
                                   "of the waves (motion ship)",
                                   "m", low=0.0, low_open=True, high=20.0),
    "peak_period": Key("the JONSWAP spectrum's peak period Tp (motion sea_state, ship)",
                       "s", low=1.0, high=30.0),
    "peak_enhancement": Key("the JONSWAP peak enhancement gamma (motion sea_state, ship)",
                            low=1.0, high=7.0),
    "seed": Key("seed of the sea state's phases (motion sea_state, ship)", kind="integer",
                low=0),
    "sway_scale": Key("sway (n2) as this fraction of the heave spectrum, own phases (motion "
                      "sea_state)", low=0.0, high=1.0),
    "surge_scale": Key("surge (n1) as this fraction of the heave spectrum, own phases (motion "
                       "sea_state)", low=0.0, high=1.0),
    "components": Key("sinusoids of the sea state, evenly over [0.5, 4] wp (motion sea_state, "
                      "ship)",
                      kind="integer", low=1, high=SEA_STATE_MAX_COMPONENTS),
    "file": Key("CSV t,n1,n2,n3 [s, m, m, m] of the base's track, relative to the scenario "
                "file (motion file; see 'Track files' below)", kind="text"),
    "file_sha256": Key("the SHA-256 of the track's bytes (motion file): unset, it is taken "
                       "when the file is read; a result's saved scenario records it, and a "
                       "track whose bytes differ is refused", kind="text",
                       note="64 hexadecimal digits or empty"),
    "wave_heading": Key("where the waves come from, from the ship's bow toward port: 0 head "
                        "seas, 90 beam seas from port, 180 following (motion ship)", "deg",
                        low=0.0, high=180.0),
    "speed": Key("the ship's speed through the water along n1 (its heading; motion ship): the "
                 "base's constant velocity (speed, 0, 0), and the encounter frequency",
                 "m/s", low=0.0, high=SHIP_SPEED_MAX_M_S),
    "pad": Key("the winch's point (the pad) in the ship's axes (x forward = n1, y to port = "
               "n2, z up = n3) from its centre of motion (motion ship)", "m", kind="vector",
               length=3, low=-SHIP_PAD_MAX_M, high=SHIP_PAD_MAX_M),
    "rao_file": Key("CSV of the ship's response amplitude operators, relative to the scenario "
                    "file; empty: the default ship (motion ship; see 'RAO files' below)",
                    kind="text"),
    "rao_file_sha256": Key("the SHA-256 of the RAO file's bytes (motion ship), as file_sha256 "
                           "for a track", kind="text", note="64 hexadecimal digits or empty"),
}  # fmt: skip
#: the columns of a track file, each with its physical range (the same as the [base] keys')
TRACK_COLUMNS: dict[str, Key] = {
    "t": Key("time", "s", low=-TRACK_TIME_MAX_S, high=TRACK_TIME_MAX_S),
    "n1": Key("the base's position along n1", "m", low=-BASE_POSITION_MAX_M,
              high=BASE_POSITION_MAX_M),
    "n2": Key("the base's position along n2", "m", low=-BASE_POSITION_MAX_M,
              high=BASE_POSITION_MAX_M),
    "n3": Key("the base's position along n3", "m", low=-BASE_POSITION_MAX_M,
              high=BASE_POSITION_MAX_M),
}  # fmt: skip
#: the keys each motion reads besides ``motion`` (the others must keep their defaults)
MOTION_KEYS: dict[str, tuple[str, ...]] = {
    "fixed": ("position",),
    "velocity": ("velocity", "position"),
    "harmonic": ("amplitude", "frequency", "phase"),
    "sea_state": ("significant_wave_height", "peak_period", "peak_enhancement", "seed",
                  "sway_scale", "surge_scale", "components"),
    "file": ("file", "file_sha256"),
    "ship": ("significant_wave_height", "peak_period", "peak_enhancement", "seed", "components",
             "wave_heading", "speed", "pad", "rao_file", "rao_file_sha256"),
}  # fmt: skip


def _checked(motion: object, *names: str) -> None:
    """Check and store the named fields of a motion against their ``BASE_KEYS``."""
    for name in names:
        value = BASE_KEYS[name].check(f"base.{name}", getattr(motion, name))
        object.__setattr__(motion, name, value)


class BaseParts(NamedTuple):
    """A motion's parts, summed: b(t) = offset + velocity t + the waves + the spline
    (``BaseMotion.parts``; ``base.compiled.compile_base`` packs them).

    Attributes
    ----------
    offset : numpy.ndarray, shape (3,)
        The constant position [m], N components.
    velocity : numpy.ndarray, shape (3,)
        The constant velocity [m/s], N components.
    waves : numpy.ndarray, shape (k, 4)
        One sinusoid A sin(w t + p) per row: axis index (0, 1, 2 for n1, n2, n3), amplitude
        A [m], angular frequency w [rad/s], phase p [rad]; k may be 0.
    knots : numpy.ndarray of shape (n,), or None
        A cubic spline's knot times [s], strictly increasing; None: no spline.
    coefficients : numpy.ndarray of shape (n - 1, 4, 3), or None
        The spline's cubic coefficients on the interval starting at each knot, highest power
        first, per axis of N ([m/s^3], [m/s^2], [m/s], [m]); None with ``knots``.
    """

    offset: np.ndarray
    velocity: np.ndarray
    waves: np.ndarray
    knots: np.ndarray | None = None
    coefficients: np.ndarray | None = None


class BaseMotion:
    """A prescribed motion b(t) of the winch point in N.

    Subclasses give their ``parts`` (``BaseParts``): ``offset`` and ``velocity`` (constant
    parts), ``waves`` (rows axis, amplitude [m], angular frequency [rad/s], phase [rad]:
    A sin(w t + p) on that axis) and ``knots`` with ``coefficients`` (a cubic spline's
    breakpoints and per-axis coefficients); ``state`` sums them in the engine's packed form
    (``base.compiled``: one formula for every caller).
    """

    #: True when b is constant: the paper's still winch (the engine then skips the base).
    fixed: bool = False

    def parts(self) -> BaseParts:
        """The motion's parts (``BaseParts``: offset [m], velocity [m/s], waves, spline knots
        [s] and coefficients).

        Returns
        -------
        BaseParts
            The parts whose sum is b(t).
        """
        raise NotImplementedError

    def state(self, t: object) -> np.ndarray:
        """Position, velocity and acceleration of B at times ``t``.

        Parameters
        ----------
        t : float or array_like of shape (n,)
            Times [s].

        Returns
        -------
        numpy.ndarray, shape (n, 3, 3)
            ``out[i, 0]`` position [m], ``out[i, 1]`` velocity [m/s], ``out[i, 2]``
            acceleration [m/s^2] at ``t[i]``, N components.
        """
        from .compiled import base_state, compile_base  # (compiled imports this module)

        packed = self.__dict__.get("_compiled")
        if packed is None:  # packed once: the engine's form, evaluated by its one formula
            packed = self.__dict__["_compiled"] = compile_base(self)
        return base_state(packed, np.asarray(t, dtype=np.float64))

    def to_dict(self) -> dict:
        """The motion as the keys of a ``[base]`` table.

        Returns
        -------
        dict
            ``"motion"`` (one of ``MOTIONS``) and the keys the motion reads
            (``MOTION_KEYS``), in the units of ``BASE_KEYS``.
        """
        raise NotImplementedError


_NO_WAVES = np.zeros((0, 4))
_ZERO = np.zeros(3)


@dataclass(frozen=True)
class FixedBase(BaseMotion):
    """The paper's winch: still, at ``position`` [m] in N (default the origin).

    Parameters
    ----------
    position : tuple of 3 float, optional
        The winch point's position [m], N components (default the origin), within
        ``BASE_KEYS["position"]``'s range.
    """

    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    fixed = True

    def __post_init__(self) -> None:
        _checked(self, "position")

    def parts(self) -> BaseParts:
        """The still winch's parts.

        Returns
        -------
        BaseParts
            The offset ``position`` [m]; no velocity, waves or spline.
        """
        return BaseParts(offset=np.array(self.position), velocity=_ZERO, waves=_NO_WAVES)

    def to_dict(self) -> dict:
        """The motion as the keys of a ``[base]`` table.

        Returns
        -------
        dict
            ``{"motion": "fixed"}`` and ``"position"`` [m].
        """
        return {"motion": "fixed", "position": list(self.position)}


@dataclass(frozen=True)
class VelocityBase(BaseMotion):
    """A base under way at constant ``velocity`` [m/s] from ``position`` [m] at t = 0.

    Parameters
    ----------
    velocity : tuple of 3 float, optional
        The constant velocity [m/s], N components (default zero), within
        ``BASE_KEYS["velocity"]``'s range.
    position : tuple of 3 float, optional
        The position at t = 0 [m], N components (default the origin).
    """

    velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        _checked(self, "velocity", "position")

    def parts(self) -> BaseParts:
        """The parts of the motion under way.

        Returns
        -------
        BaseParts
            The offset ``position`` [m] and the ``velocity`` [m/s]; no waves or spline.
        """
        return BaseParts(
            offset=np.array(self.position), velocity=np.array(self.velocity), waves=_NO_WAVES
        )

    def to_dict(self) -> dict:
        """The motion as the keys of a ``[base]`` table.

        Returns
        -------
        dict
            ``{"motion": "velocity"}`` and ``"velocity"`` [m/s], ``"position"`` [m].
        """
        return {
            "motion": "velocity",
            "velocity": list(self.velocity),
            "position": list(self.position),
        }


@dataclass(frozen=True)
class HarmonicBase(BaseMotion):
    """b_i(t) = amplitude_i sin(2 pi frequency_i t + phase_i) on each axis i of N.

    Parameters
    ----------
    amplitude : 3 floats >= 0 [m]
    frequency : 3 floats >= 0 [Hz] (at most 100 Hz)
    phase : 3 floats [rad]
    """

    amplitude: tuple[float, float, float] = (0.0, 0.0, 0.0)
    frequency: tuple[float, float, float] = (0.0, 0.0, 0.0)
    phase: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        _checked(self, "amplitude", "frequency", "phase")

    def parts(self) -> BaseParts:
        """The sinusoids of the motion.

        Returns
        -------
        BaseParts
            One wave per axis of nonzero amplitude: (axis, amplitude [m], 2 pi frequency
            [rad/s], phase [rad]); no offset, velocity or spline.
        """
        waves = [
            (i, a, 2 * math.pi * f, p)
            for i, (a, f, p) in enumerate(
                zip(self.amplitude, self.frequency, self.phase, strict=True)
            )
            if a > 0.0
        ]
        return BaseParts(
            offset=_ZERO, velocity=_ZERO, waves=np.array(waves, dtype=np.float64).reshape(-1, 4)
        )

    def to_dict(self) -> dict:
        """The motion as the keys of a ``[base]`` table.

        Returns
        -------
        dict
            ``{"motion": "harmonic"}`` and ``"amplitude"`` [m], ``"frequency"`` [Hz],
            ``"phase"`` [rad].
        """
        return {
            "motion": "harmonic",
            "amplitude": list(self.amplitude),
            "frequency": list(self.frequency),
            "phase": list(self.phase),
        }


def jonswap(omega: np.ndarray, hs: float, tp: float, gamma: float = 3.3) -> np.ndarray:
    """The JONSWAP spectrum S(w) [m^2 s/rad] of wave elevation (DNV-RP-C205 eq 3.5.5).

    S(w) = A_g (5/16) Hs^2 wp^4 w^-5 exp(-5/4 (w/wp)^-4) gamma^exp(-(w - wp)^2 / (2 s^2 wp^2)),
    s = 0.07 (w <= wp) or 0.09, A_g = 1 - 0.287 ln(gamma), wp = 2 pi / Tp.

    Parameters
    ----------
    omega : numpy.ndarray
        The angular frequencies w [rad/s], > 0, any shape.
    hs : float
        The significant wave height Hs [m].
    tp : float
        The peak period Tp [s].
    gamma : float, optional
        The peak enhancement factor gamma [-] (default 3.3, the JONSWAP mean).

    Returns
    -------
    numpy.ndarray
        S(w) [m^2 s/rad], the shape of ``omega``.
    """
    wp = 2 * math.pi / tp
    sigma = np.where(omega <= wp, 0.07, 0.09)
    shape = np.exp(-0.5 * ((omega - wp) / (sigma * wp)) ** 2)
    pm = 5.0 / 16.0 * hs**2 * wp**4 * omega**-5.0 * np.exp(-1.25 * (omega / wp) ** -4)
    return (1 - 0.287 * math.log(gamma)) * pm * gamma**shape


def sea_components(
    hs: float, tp: float, gamma: float, components: int
) -> tuple[np.ndarray, np.ndarray]:
    """A JONSWAP sea as sinusoids: ``components`` frequencies evenly over [0.5, 4] w_p
    (w_p = 2 pi / Tp) with amplitudes a_k = sqrt(2 S(w_k) dw) (``jonswap``), scaled so that
    4 sqrt(m0) = Hs exactly, m0 = sum a_k^2 / 2 (the random-phase model, DNV-RP-C205 3.5.11).

    Parameters
    ----------
    hs : float
        The significant wave height Hs [m].
    tp : float
        The peak period Tp [s].
    gamma : float
        The peak enhancement gamma [-].
    components : int
        The number of sinusoids, >= 1.

    Returns
    -------
    omega : numpy.ndarray, shape (components,)
        The angular frequencies [rad/s].
    amplitude : numpy.ndarray, shape (components,)
        The amplitudes a_k [m].
    """
    wp = 2 * math.pi / tp
    omega = np.linspace(0.5 * wp, 4.0 * wp, components)
    dw = omega[1] - omega[0] if components > 1 else 3.5 * wp
    amp = np.sqrt(2 * jonswap(omega, 1.0, tp, gamma) * dw)
    amp *= hs / (4 * math.sqrt(0.5 * np.sum(amp**2)))
    return omega, amp


def sea_phases(seed: int, count: int, components: int) -> np.ndarray:
    """The random phases of a seeded sea, uniform on [0, 2 pi): ``count`` sets of
    ``components``, drawn one set after the other from ``numpy.random.default_rng(seed)``
    (the random-phase model, DNV-RP-C205 3.5.11).

    Parameters
    ----------
    seed : int
        The seed, >= 0.
    count : int
        The number of sets.
    components : int
        The phases per set.

    Returns
    -------
    numpy.ndarray, shape (count, components)
        The phases [rad].
    """
    rng = np.random.default_rng(seed)
    return np.array([rng.uniform(0.0, 2 * math.pi, components) for _ in range(count)])


@dataclass(frozen=True)
class SeaStateBase(BaseMotion):
    """A deck in a seaway: heave as a seeded sum of sinusoids from a JONSWAP spectrum.

    ``components`` frequencies spaced evenly over [0.5, 4] w_p (w_p = 2 pi / peak_period),
    amplitudes a_k = sqrt(2 S(w_k) dw), phases uniform from ``seed``; the amplitudes are then
    scaled so that 4 sqrt(m0) equals ``significant_wave_height`` exactly (m0 = sum a_k^2 / 2).
    Sway (n2) and surge (n1) are the same spectrum times ``sway_scale`` and ``surge_scale``
    with phases of their own.

    Assumption: the deck follows the wave elevation with a unit response amplitude operator
    (a small vessel at wave periods long against its natural periods); no roll, pitch or yaw
    of the deck, and the winch at the deck's origin. A ship's own RAO would filter the
    spectrum; supply its motion as ``FileBase`` for that.

    Parameters
    ----------
    significant_wave_height : float, optional
        Hs = 4 sqrt(m0) of the heave [m] (default 1), in (0, 20].
    peak_period : float, optional
        The JONSWAP peak period Tp [s] (default 8), in [1, 30].
    peak_enhancement : float, optional
        The JONSWAP peak enhancement gamma [-] (default 3.3), in [1, 7].
    seed : int, optional
        The seed of the phases (default 0), >= 0.
    sway_scale : float, optional
        Sway (n2) as this fraction of the heave spectrum [-] (default 0: none), in [0, 1].
    surge_scale : float, optional
        Surge (n1) as this fraction of the heave spectrum [-] (default 0: none), in [0, 1].
    components : int, optional
        The number of sinusoids per axis (default 128), at most
        ``SEA_STATE_MAX_COMPONENTS``.
    """

    significant_wave_height: float = 1.0
    peak_period: float = 8.0
    peak_enhancement: float = 3.3
    seed: int = 0
    sway_scale: float = 0.0
    surge_scale: float = 0.0
    components: int = 128
    _waves: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _checked(self, *MOTION_KEYS["sea_state"])
        self._derive()

    def _derive(self) -> None:
        """The sinusoids of the checked fields (``_waves``); also run by
        ``_validation.trusted``."""
        omega, amp = sea_components(self.significant_wave_height, self.peak_period,
                                    self.peak_enhancement, self.components)  # fmt: skip
        phases = sea_phases(self.seed, 3, self.components)  # drawn for every axis
        rows = []
        for (axis, scale), phase in zip(
            ((2, 1.0), (1, self.sway_scale), (0, self.surge_scale)), phases, strict=True
        ):
            if scale > 0.0:
                rows.append(np.column_stack([np.full_like(omega, axis), scale * amp, omega, phase]))
        waves = np.concatenate(rows)
        waves.setflags(write=False)
        object.__setattr__(self, "_waves", waves)

    def parts(self) -> BaseParts:
        """The sinusoids of the sea state.

        Returns
        -------
        BaseParts
            The waves (axis, amplitude [m], angular frequency [rad/s], phase [rad]), heave
            first, then sway and surge when scaled; no offset, velocity or spline.
        """
        return BaseParts(offset=_ZERO, velocity=_ZERO, waves=self._waves)

    def to_dict(self) -> dict:
        """The motion as the keys of a ``[base]`` table.

        Returns
        -------
        dict
            ``{"motion": "sea_state"}`` and the seven keys of ``MOTION_KEYS["sea_state"]``.
        """
        return {
            "motion": "sea_state",
            "significant_wave_height": self.significant_wave_height,
            "peak_period": self.peak_period,
            "peak_enhancement": self.peak_enhancement,
            "seed": self.seed,
            "sway_scale": self.sway_scale,
            "surge_scale": self.surge_scale,
            "components": self.components,
        }


@dataclass(frozen=True, eq=False)
class FileBase(BaseMotion):
    """A recorded track, interpolated by a cubic spline (SciPy ``CubicSpline``, not-a-knot
    ends) per axis: position, velocity and acceleration continuous, the acceleration linear
    between samples. Interpolation error of a smooth motion sampled every h: O(h^4) in
    position, O(h^2) in acceleration (about h^2 max|b''''| / 12).

    Parameters
    ----------
    times : (n,) strictly increasing [s], n >= 4, starting at or before 0, steps of at least
        ``TRACK_MIN_STEP_S`` and no gap longer than ten times the median step, within
        ``TRACK_COLUMNS["t"]``'s range
    positions : (n, 3) [m], N components, within ``TRACK_COLUMNS``' ranges
    source : str, optional
        Where they came from (a file's resolved path), named in error messages.
    row_offset : int, optional
        The row number of ``times[0]`` in the messages.
    sha256 : str, optional
        The SHA-256 of the file's bytes (``read_base_csv``), recorded with the run.
    """

    times: np.ndarray
    positions: np.ndarray
    source: str = ""
    row_offset: int = 0
    sha256: str = ""
    _coef: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        t = np.asarray(self.times, dtype=np.float64)
        b = np.asarray(self.positions, dtype=np.float64)
        src = self.source or None
        if t.ndim != 1 or b.shape != (t.size, 3):
            raise ParameterError("base.file", f"{t.shape} times, {b.shape} positions",
                                 "n times and n rows of 3 positions", source=src)  # fmt: skip
        _check_track(t, b, np.arange(t.size) + self.row_offset, src)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "positions", b)
        self._derive()

    def _derive(self) -> None:
        """The spline of the checked track (``_coef``); also run by ``_validation.trusted``."""
        from scipy.interpolate import CubicSpline

        spline = CubicSpline(self.times, self.positions, bc_type="not-a-knot")
        coef = np.ascontiguousarray(np.moveaxis(spline.c, 0, 1))  # (n - 1, 4, 3)
        for arr in (self.times, self.positions, coef):
            arr.setflags(write=False)
        object.__setattr__(self, "_coef", coef)

    @property
    def end(self) -> float:
        """The last time the file covers [s]."""
        return float(self.times[-1])

    def parts(self) -> BaseParts:
        """The spline of the track.

        Returns
        -------
        BaseParts
            The knots ``times`` [s] and the cubic coefficients, (n - 1, 4, 3); no offset,
            velocity or waves.
        """
        return BaseParts(
            offset=_ZERO, velocity=_ZERO, waves=_NO_WAVES, knots=self.times,
            coefficients=self._coef,
        )  # fmt: skip

    def to_dict(self) -> dict:
        """The motion as the keys of a ``[base]`` table.

        Returns
        -------
        dict
            ``{"motion": "file"}`` and ``"file"`` (the track's ``source``),
            ``"file_sha256"`` (the hash of its bytes).
        """
        return {"motion": "file", "file": self.source, "file_sha256": self.sha256}


def _check_track(t: np.ndarray, b: np.ndarray, rows: np.ndarray, src: str | None) -> None:
    """Refuse a track (times ``t``, positions ``b``; ``rows`` their row numbers) outside the
    one rule: at least 4 rows, every value in its column's range (``TRACK_COLUMNS``), times
    increasing by ``TRACK_MIN_STEP_S`` at least and by at most ten times the median step,
    the first at or before 0. Each message names the row and the column, never a value."""
    if t.size < 4:
        raise ParameterError("base.file", f"{t.size} rows", "at least 4 rows", source=src)
    for j, (name, key) in enumerate(TRACK_COLUMNS.items()):
        x = t if j == 0 else b[:, j - 1]
        bad = ~(np.abs(x) <= key.high)  # NaN too
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ParameterError(f"base.file row {rows[i]} column {name}", "out of its range",
                                 key.allowed(), source=src)  # fmt: skip
    steps = np.diff(t)
    if np.any(steps < TRACK_MIN_STEP_S):
        i = int(np.flatnonzero(steps < TRACK_MIN_STEP_S)[0]) + 1
        raise ParameterError(
            f"base.file row {rows[i]} column t", "not a step above the previous row's",
            f"times strictly increasing, by at least {TRACK_MIN_STEP_S:g} s a row", source=src,
        )  # fmt: skip
    median = float(np.median(steps))
    if np.any(steps > 10 * median):
        i = int(np.flatnonzero(steps > 10 * median)[0]) + 1
        raise ParameterError(
            f"base.file row {rows[i]} column t", "a gap after the previous row",
            f"steps at most 10x the median step ({10 * median:g} s)", source=src,
        )  # fmt: skip
    if t[0] > 0.0:
        raise ParameterError(f"base.file row {rows[0]} column t", "a first time after 0",
                             "a first time <= 0 s (the track covers the run's start)",
                             source=src)  # fmt: skip


#: a cell of a track: a plain decimal number (digits, at most one '.', an optional exponent),
#: never Python's wider float() grammar ('1_0', 'inf', 'nan', non-ASCII digits)
_CELL = rb"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
_ROW = re.compile(
    rb"[ \t]*(" + _CELL + rb")[ \t]*,[ \t]*(" + _CELL + rb")[ \t]*,[ \t]*(" + _CELL
    + rb")[ \t]*,[ \t]*(" + _CELL + rb")[ \t]*\r?\n?"
)  # fmt: skip
_CELL_ALONE = re.compile(rb"[ \t]*" + _CELL + rb"[ \t]*\r?\n?")
_HEADER = b"t,n1,n2,n3"
#: Peak memory of a track per data row while it is read and splined [bytes]: the parsed
#: numbers, the arrays and SciPy's spline (measured 500 with tracemalloc); margin kept.
_TRACK_BYTES_PER_ROW = 768
#: The data rows read between two checks of the memory budget while a track is streamed.
_MEMORY_BLOCK_ROWS = 65_536
_SHA256 = re.compile(r"[0-9a-f]{64}")
_CELLS = "4 plain decimal numbers t,n1,n2,n3 (e.g. -0.5,1.25e-3,0,12)"
_HEADER_TEXT = "the header t,n1,n2,n3 (time [s], then the base's position along n1, n2, n3 [m])"


def read_base_csv(path: str | Path, *, sha256: str = "") -> FileBase:
    """A ``FileBase`` from a CSV file with the header ``t,n1,n2,n3`` (s, m, m, m).

    The file is opened by ``_io.open_user_file`` (any regular file the user may read; its size
    checked first) and streamed: every line counts as a row (blank ones too), refused past
    ``FILE_MAX_ROWS`` before more is read, and the memory its rows need (the spline's
    included) is checked against the budget before each block of rows is held. Each cell is
    a plain decimal number (``_CELL``). The bytes read are hashed (SHA-256), recorded with the
    run.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    sha256 : str, optional
        The SHA-256 the file must have (a result's saved scenario records it); empty: any.

    Returns
    -------
    FileBase
        Its ``source`` is the resolved path, its ``sha256`` the hash of the bytes.

    Raises
    ------
    ParameterError
        A missing, unreadable or oversized file, a wrong header, too many rows, a cell that is
        not a plain decimal number, a track ``FileBase`` refuses, or other bytes than
        ``sha256``: one line naming the file, the row and the column, never its contents.
    ResourceLimitError
        Its rows would need more than the memory budget (``tetherheli.resources``).
    """
    from .._io import open_user_file

    if sha256 and not (isinstance(sha256, str) and _SHA256.fullmatch(sha256)):
        raise ParameterError("base.file_sha256", sha256, "64 hexadecimal digits (lower case) or "
                             "empty")  # fmt: skip
    src = str(path)
    with open_user_file(path, field="base.file", what="a CSV track t,n1,n2,n3",
                        max_bytes=FILE_MAX_BYTES) as (fh, resolved, _):  # fmt: skip
        try:
            digest, data, rows = _stream_track(fh, src)
        except OSError as exc:
            reason = exc.strerror or "a read error"
            raise ParameterError("base.file", src, f"a readable CSV track ({reason})",
                                 source=None) from None  # fmt: skip
    if sha256 and digest != sha256:
        raise ParameterError(
            "base.file_sha256", sha256, f"the SHA-256 of {src}'s bytes (the file changed since "
            "it was recorded: restore it, or fly the scenario that named it first)",
        )  # fmt: skip
    table = np.frombuffer(data, dtype=np.float64).reshape(-1, 4)
    times, positions = table[:, 0].copy(), table[:, 1:].copy()
    _check_track(times, positions, np.frombuffer(rows, dtype=np.int64), src)
    return trusted(FileBase, times=times, positions=positions, source=str(resolved),
                   sha256=digest)  # fmt: skip


def _stream_track(fh: Any, src: str) -> tuple[str, array, array]:
    """Read the open track ``fh`` line by line: (SHA-256 of its bytes, its numbers by row,
    the row number of each data row); a bad line, a row past ``FILE_MAX_ROWS`` or a block of
    rows beyond the memory budget (``tetherheli.resources``) is refused as soon as it is
    read, before it is held."""
    from ..resources import check_memory

    digest = hashlib.sha256()
    data, rows = array("d"), array("q")

    def refuse(row: int, value: str, allowed: str, column: str = "") -> None:
        where = f"base.file row {row}" + (f" column {column}" if column else "")
        raise ParameterError(where, value, allowed, source=src)

    row = 0
    while True:
        line = fh.readline(TRACK_MAX_LINE + 1)
        if not line:
            break
        row += 1
        digest.update(line)
        if row > FILE_MAX_ROWS + 1:
            raise ParameterError("base.file", f"more than {FILE_MAX_ROWS} rows",
                                 f"at most {FILE_MAX_ROWS} rows after the header (blank lines "
                                 "count)", source=src)  # fmt: skip
        if len(line) > TRACK_MAX_LINE:
            refuse(row, f"a line longer than {TRACK_MAX_LINE} bytes", _HEADER_TEXT if row == 1
                   else _CELLS)  # fmt: skip
        if row == 1:
            if line.removeprefix(b"\xef\xbb\xbf").strip().replace(b" ", b"") != _HEADER:
                refuse(1, "not the header", _HEADER_TEXT)
            continue
        found = _ROW.fullmatch(line)
        if found is None:
            if not line.strip():
                continue  # a blank line: counted, no data
            cells = line.split(b",")
            if len(cells) != 4:
                refuse(row, f"{len(cells)} cells", _CELLS)
            for name, cell in zip(TRACK_COLUMNS, cells, strict=True):
                if not _CELL_ALONE.fullmatch(cell):
                    refuse(row, "not a plain decimal number", "a plain decimal number such as "
                           "-0.5, 12 or 1.25e-3 (no '_', inf or nan)", column=name)  # fmt: skip
            refuse(row, "not a row of 4 numbers", _CELLS)  # e.g. a carriage return inside
        if rows and len(rows) % _MEMORY_BLOCK_ROWS == 0:  # before the next block is held
            check_memory(
                f"reading the track {src} (more than {len(rows)} rows)",
                (len(rows) + _MEMORY_BLOCK_ROWS) * _TRACK_BYTES_PER_ROW,
                hint="a shorter track (fewer rows)",
            )
        data.extend(map(float, found.groups()))  # type: ignore[union-attr]
        rows.append(row)
    if row == 0:
        refuse(1, "an empty file", "the header t,n1,n2,n3, then the track's rows")
    check_memory(  # before the arrays and the spline
        f"reading the track {src} ({len(rows)} rows)", len(rows) * _TRACK_BYTES_PER_ROW,
        hint="a shorter track (fewer rows)",
    )  # fmt: skip
    return digest.hexdigest(), data, rows


def base_motion_from(settings: Any) -> BaseMotion:
    """The motion a ``[base]`` table describes (``scenario.tables.BaseSettings``, or any
    object with its attributes): the keys of ``MOTION_KEYS[settings.motion]`` passed on
    (checked by the motion's class); a ``file`` read (``read_base_csv``).

    Parameters
    ----------
    settings : BaseSettings
        The table.

    Returns
    -------
    BaseMotion
    """
    kind = BASE_KEYS["motion"].check("base.motion", settings.motion)
    return _motion(kind, settings, _motion_class(kind))


def _base_motion_from(settings: object) -> BaseMotion:
    """``base_motion_from`` of a table whose every key is checked already (a ``Scenario``'s
    ``[base]``, ``scenario.checks``): the motion built ``trusted``; a file still read and
    its track checked."""
    kind = settings.motion  # type: ignore[attr-defined]
    cls = _motion_class(kind)
    return _motion(kind, settings, None if cls is None else functools.partial(trusted, cls))


def _motion(kind: str, settings: object, build: Callable[..., BaseMotion] | None) -> BaseMotion:
    """The motion ``kind`` of ``settings``' keys, made by ``build`` (a file: read)."""
    kw = {name: getattr(settings, name) for name in MOTION_KEYS[kind]}
    if build is None:  # kind == "file"
        if not kw["file"]:
            raise ParameterError("base.file", kw["file"], "a CSV file t,n1,n2,n3 (motion file)")
        return read_base_csv(kw["file"], sha256=kw["file_sha256"])
    return build(**kw)


#: the class of every motion but ``file`` (read from its CSV) and ``ship`` (``_motion_class``)
_MOTION_CLASSES: dict[str, type[BaseMotion]] = {
    "fixed": FixedBase,
    "velocity": VelocityBase,
    "harmonic": HarmonicBase,
    "sea_state": SeaStateBase,
}


def _motion_class(kind: str) -> type[BaseMotion] | None:
    """The class of the motion ``kind`` (None for ``file``, read from its CSV); the ship's
    imported here (``base.ship`` imports this module)."""
    if kind == "ship":
        from .ship import ShipBase

        return ShipBase
    return _MOTION_CLASSES.get(kind)
