"""The winch's base and its prescribed motion b(t) in frame N (issue 26).

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
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._validation import Key, trusted
from ..errors import ParameterError

__all__ = [
    "BASE_KEYS",
    "FILE_MAX_ROWS",
    "MOTIONS",
    "MOTION_KEYS",
    "BaseMotion",
    "FileBase",
    "FixedBase",
    "HarmonicBase",
    "SeaStateBase",
    "VelocityBase",
    "base_motion_from",
    "jonswap",
    "read_base_csv",
]

#: The most rows a base motion file may hold (checked before reading it whole).
FILE_MAX_ROWS = 1_000_000
#: The most sinusoids of a sea state (the engine evaluates each at every step).
SEA_STATE_MAX_COMPONENTS = 1024

#: the motions a ``[base]`` table's ``motion`` names
MOTIONS: tuple[str, ...] = ("fixed", "velocity", "harmonic", "sea_state", "file")
#: the keys of a ``[base]`` table, each described once: the motions check their values with
#: them and the scenario reference prints them (``sim.scenario_tables.BaseSettings``)
BASE_KEYS: dict[str, Key] = {
    "motion": Key("the winch's base: still (the paper's), under way at a constant velocity, "
                  "harmonic per axis, a JONSWAP sea state, or a recorded track (CSV)",
                  kind="text", choices=MOTIONS),
    "position": Key("the base's position at t = 0 (motion fixed or velocity)", "m",
                    kind="vector", length=3),
    "velocity": Key("the base's constant velocity (motion velocity)", "m/s", kind="vector",
                    length=3),
    "amplitude": Key("amplitude of b_i = A_i sin(2 pi f_i t + p_i) per axis of N (motion "
                     "harmonic)", "m", kind="vector", length=3, low=0.0),
    "frequency": Key("frequency f_i per axis (motion harmonic)", "Hz", kind="vector", length=3,
                     low=0.0, high=100.0),
    "phase": Key("phase p_i per axis (motion harmonic)", "rad", kind="vector", length=3),
    "significant_wave_height": Key("Hs = 4 sqrt(m0) of the deck's heave (motion sea_state)",
                                   "m", low=0.0, low_open=True, high=20.0),
    "peak_period": Key("the JONSWAP spectrum's peak period Tp (motion sea_state)", "s",
                       low=1.0, high=30.0),
    "peak_enhancement": Key("the JONSWAP peak enhancement gamma (motion sea_state)", low=1.0,
                            high=7.0),
    "seed": Key("seed of the sea state's phases (motion sea_state)", kind="integer", low=0),
    "sway_scale": Key("sway (n2) as this fraction of the heave spectrum, own phases (motion "
                      "sea_state)", low=0.0, high=1.0),
    "surge_scale": Key("surge (n1) as this fraction of the heave spectrum, own phases (motion "
                       "sea_state)", low=0.0, high=1.0),
    "components": Key("sinusoids of the sea state, evenly over [0.5, 4] wp (motion sea_state)",
                      kind="integer", low=1, high=SEA_STATE_MAX_COMPONENTS),
    "file": Key("CSV t,n1,n2,n3 [s, m, m, m] of the base's track, relative to the scenario "
                "file (motion file)", kind="text"),
}  # fmt: skip
#: the keys each motion reads besides ``motion`` (the others must keep their defaults)
MOTION_KEYS: dict[str, tuple[str, ...]] = {
    "fixed": ("position",),
    "velocity": ("velocity", "position"),
    "harmonic": ("amplitude", "frequency", "phase"),
    "sea_state": ("significant_wave_height", "peak_period", "peak_enhancement", "seed",
                  "sway_scale", "surge_scale", "components"),
    "file": ("file",),
}  # fmt: skip


def _checked(motion: object, *names: str) -> None:
    """Check and store the named fields of a motion against their ``BASE_KEYS``."""
    for name in names:
        value = BASE_KEYS[name].check(f"base.{name}", getattr(motion, name))
        object.__setattr__(motion, name, value)


class BaseMotion:
    """A prescribed motion b(t) of the winch point in N.

    Subclasses give ``offset`` and ``velocity`` (constant parts), ``waves`` (rows axis,
    amplitude [m], angular frequency [rad/s], phase [rad]: A sin(w t + p) on that axis) and
    ``knots`` (a cubic spline's breakpoints and per-axis coefficients); ``state`` sums them
    in the engine's packed form (``base.compiled``: one formula for every caller).
    """

    #: True when b is constant: the paper's still winch (the engine then skips the base).
    fixed: bool = False

    def parts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None, np.ndarray]:
        """(offset (3,), velocity (3,), waves (k, 4), knot times (n,) or None, coefficients
        (n - 1, 4, 3)) of the motion."""
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
        """The motion as the keys of a ``[base]`` table."""
        raise NotImplementedError


_NO_WAVES = np.zeros((0, 4))
_ZERO = np.zeros(3)


@dataclass(frozen=True)
class FixedBase(BaseMotion):
    """The paper's winch: still, at ``position`` [m] in N (default the origin)."""

    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    fixed = True

    def __post_init__(self) -> None:
        _checked(self, "position")

    def parts(self):
        return np.array(self.position), _ZERO, _NO_WAVES, None, None

    def to_dict(self) -> dict:
        return {"motion": "fixed", "position": list(self.position)}


@dataclass(frozen=True)
class VelocityBase(BaseMotion):
    """A base under way at constant ``velocity`` [m/s] from ``position`` [m] at t = 0."""

    velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        _checked(self, "velocity", "position")

    def parts(self):
        return np.array(self.position), np.array(self.velocity), _NO_WAVES, None, None

    def to_dict(self) -> dict:
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

    def parts(self):
        waves = [
            (i, a, 2 * math.pi * f, p)
            for i, (a, f, p) in enumerate(
                zip(self.amplitude, self.frequency, self.phase, strict=True)
            )
            if a > 0.0
        ]
        return _ZERO, _ZERO, np.array(waves, dtype=np.float64).reshape(-1, 4), None, None

    def to_dict(self) -> dict:
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
    """
    wp = 2 * math.pi / tp
    sigma = np.where(omega <= wp, 0.07, 0.09)
    shape = np.exp(-0.5 * ((omega - wp) / (sigma * wp)) ** 2)
    pm = 5.0 / 16.0 * hs**2 * wp**4 * omega**-5.0 * np.exp(-1.25 * (omega / wp) ** -4)
    return (1 - 0.287 * math.log(gamma)) * pm * gamma**shape


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
        wp = 2 * math.pi / self.peak_period
        omega = np.linspace(0.5 * wp, 4.0 * wp, self.components)
        dw = omega[1] - omega[0] if self.components > 1 else 3.5 * wp
        amp = np.sqrt(2 * jonswap(omega, 1.0, self.peak_period, self.peak_enhancement) * dw)
        amp *= self.significant_wave_height / (4 * math.sqrt(0.5 * np.sum(amp**2)))
        rng = np.random.default_rng(self.seed)
        rows = []
        for axis, scale in ((2, 1.0), (1, self.sway_scale), (0, self.surge_scale)):
            phase = rng.uniform(0.0, 2 * math.pi, self.components)  # drawn for every axis
            if scale > 0.0:
                rows.append(np.column_stack([np.full_like(omega, axis), scale * amp, omega, phase]))
        waves = np.concatenate(rows)
        waves.setflags(write=False)
        object.__setattr__(self, "_waves", waves)

    def parts(self):
        return _ZERO, _ZERO, self._waves, None, None

    def to_dict(self) -> dict:
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
    times : (n,) strictly increasing [s], n >= 4, starting at or before 0, no gap longer
        than ten times the median step
    positions : (n, 3) [m], N components
    source : str, optional
        Where they came from (a file name), named in error messages.
    """

    times: np.ndarray
    positions: np.ndarray
    source: str = ""
    row_offset: int = 0

    def __post_init__(self) -> None:
        from scipy.interpolate import CubicSpline

        t = np.asarray(self.times, dtype=np.float64)
        b = np.asarray(self.positions, dtype=np.float64)
        src = self.source or None
        if t.ndim != 1 or b.shape != (t.size, 3):
            raise ParameterError("base.file", f"{t.shape} times, {b.shape} positions",
                                 "n times and n rows of 3 positions", source=src)  # fmt: skip
        if t.size < 4:
            raise ParameterError("base.file", f"{t.size} rows", "at least 4 rows", source=src)
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(b))):
            row = int(np.flatnonzero(~np.isfinite(np.column_stack([t, b])).all(axis=1))[0])
            raise ParameterError(f"base.file row {row + self.row_offset}", "not finite",
                                 "finite numbers", source=src)  # fmt: skip
        steps = np.diff(t)
        if np.any(steps <= 0):
            row = int(np.flatnonzero(steps <= 0)[0]) + 1
            raise ParameterError(f"base.file row {row + self.row_offset}", f"t = {t[row]:g}",
                                 "times strictly increasing", source=src)  # fmt: skip
        median = float(np.median(steps))
        if np.any(steps > 10 * median):
            row = int(np.flatnonzero(steps > 10 * median)[0]) + 1
            raise ParameterError(
                f"base.file row {row + self.row_offset}", f"a gap of {steps[row - 1]:g} s",
                f"steps at most 10x the median step ({10 * median:g} s)", source=src,
            )  # fmt: skip
        if t[0] > 0.0:
            raise ParameterError("base.file", f"starts at t = {t[0]:g}", "a first time <= 0",
                                 source=src)  # fmt: skip
        spline = CubicSpline(t, b, bc_type="not-a-knot")
        coef = np.ascontiguousarray(np.moveaxis(spline.c, 0, 1))  # (n - 1, 4, 3)
        for arr in (t, coef):
            arr.setflags(write=False)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "positions", b)
        object.__setattr__(self, "_coef", coef)

    @property
    def end(self) -> float:
        """The last time the file covers [s]."""
        return float(self.times[-1])

    def parts(self):
        return _ZERO, _ZERO, _NO_WAVES, self.times, self._coef

    def to_dict(self) -> dict:
        return {"motion": "file", "file": self.source}


def read_base_csv(path: str | Path) -> FileBase:
    """A ``FileBase`` from a CSV file with the header ``t,n1,n2,n3`` (s, m, m, m).

    Raises
    ------
    ParameterError
        A missing or unreadable file, a wrong header, more than ``FILE_MAX_ROWS`` rows, or a
        track ``FileBase`` refuses, in one line naming the file and the row.
    """
    path = Path(path)
    src = str(path)
    try:
        size = path.stat().st_size
        if not path.is_file():
            raise OSError("not a regular file")
        if size > FILE_MAX_ROWS * 120:
            raise ParameterError("base.file", f"{size} bytes",
                                 f"at most {FILE_MAX_ROWS} rows", source=src)  # fmt: skip
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ParameterError("base.file", src, f"a readable CSV file ({exc})") from None
    lines = text.splitlines()
    header = lines[0].replace(" ", "") if lines else ""
    if header != "t,n1,n2,n3":
        raise ParameterError("base.file row 1", lines[0] if lines else "", "the header t,n1,n2,n3",
                             source=src)  # fmt: skip
    rows = [ln for ln in lines[1:] if ln.strip()]
    if len(rows) > FILE_MAX_ROWS:
        raise ParameterError("base.file", f"{len(rows)} rows", f"at most {FILE_MAX_ROWS} rows",
                             source=src)  # fmt: skip
    data = np.empty((len(rows), 4))
    for i, line in enumerate(rows):
        cells = line.split(",")
        try:
            if len(cells) != 4:
                raise ValueError
            data[i] = [float(c) for c in cells]
        except ValueError:
            raise ParameterError(f"base.file row {i + 2}", line.strip(), "4 numbers t,n1,n2,n3",
                                 source=src) from None  # fmt: skip
    return FileBase(data[:, 0], data[:, 1:], source=src, row_offset=2)


def base_motion_from(settings: Any) -> BaseMotion:
    """The motion a ``[base]`` table describes (``sim.scenario_tables.BaseSettings``, or any
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
    return _motion(kind, settings, _MOTION_CLASSES.get(kind))


def _base_motion_from(settings: object) -> BaseMotion:
    """``base_motion_from`` of a table whose every key is checked already (a ``Scenario``'s
    ``[base]``, ``sim.scenario_checks``): the motion built ``trusted``; a file still read and
    its track checked."""
    kind = settings.motion  # type: ignore[attr-defined]
    cls = _MOTION_CLASSES.get(kind)
    return _motion(kind, settings, None if cls is None else functools.partial(trusted, cls))


def _motion(kind: str, settings: object, build: Callable[..., BaseMotion] | None) -> BaseMotion:
    """The motion ``kind`` of ``settings``' keys, made by ``build`` (a file: read)."""
    kw = {name: getattr(settings, name) for name in MOTION_KEYS[kind]}
    if build is None:  # kind == "file"
        if not kw["file"]:
            raise ParameterError("base.file", kw["file"], "a CSV file t,n1,n2,n3 (motion file)")
        return read_base_csv(kw["file"])
    return build(**kw)


#: the class of every motion but ``file`` (read from its CSV)
_MOTION_CLASSES: dict[str, type[BaseMotion]] = {
    "fixed": FixedBase,
    "velocity": VelocityBase,
    "harmonic": HarmonicBase,
    "sea_state": SeaStateBase,
}
