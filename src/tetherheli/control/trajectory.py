"""Reference trajectories for flight beyond hover, independent of the vehicle.

Every trajectory gives, at a time t [s] from the run's start, the position, velocity and
acceleration of the vehicle's reference point (the helicopter's HO) in the paper's frame N
(n3 up), **relative to the start's hover point** (the trim hover the run starts from; over a
moving base, relative to the base, in whose translating frame the engine flies), and a yaw
angle relative to the start's with its rate: ``at(t) -> TrajectoryPoint``. The controller
that flies them (``control.reference``) adds the start's hover point.

- ``Hold``: the start's hover point (the paper's station-keeping).
- ``Steps``: setpoint changes at given times, each optionally smoothed by a minimum-jerk
  transition of a stated duration (so the references stay flyable).
- ``Waypoints``: rest-to-rest segments from the start through each point, minimum-jerk
  (quintic, zero velocity and acceleration at both ends, peak speed 1.875 D / T) or
  minimum-snap (septic, zero velocity, acceleration and jerk, peak speed 2.1875 D / T); each
  segment's duration T from its length D and the peak speed asked.
- ``CsvTrajectory``: a recorded path t, x, y, z [, yaw], interpolated per axis by a cubic
  spline (as ``base.motion.FileBase``); ``read_trajectory_csv`` reads it safely.

The polynomials are the rest-to-rest minimum-jerk (Flash & Hogan 1985) and minimum-snap
(Mellinger & Kumar 2011) profiles on a straight segment.
"""

from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from ..base.motion import FILE_MAX_BYTES, FILE_MAX_ROWS
from ..errors import ParameterError

__all__ = [
    "CSV_COLUMNS",
    "PEAK_SPEED_FACTOR",
    "SMOOTHINGS",
    "Climb",
    "CsvTrajectory",
    "Hold",
    "Steps",
    "Trajectory",
    "TrajectoryPoint",
    "Waypoints",
    "read_trajectory_csv",
    "smooth_step",
]

#: The segment shapes of ``Waypoints``.
SMOOTHINGS: tuple[str, ...] = ("min_jerk", "min_snap")
#: Peak speed of a rest-to-rest segment of length D and duration T, in units of D / T:
#: max s'(tau) of the quintic (at tau = 1/2: 30/16) and of the septic (140/64).
PEAK_SPEED_FACTOR: dict[str, float] = {"min_jerk": 1.875, "min_snap": 2.1875}
#: The columns of a trajectory CSV file (yaw optional).
CSV_COLUMNS: tuple[str, ...] = ("t", "x", "y", "z", "yaw")
#: Bounds of a trajectory file's values: |t| [s], |x|, |y|, |z| [m], |yaw| [rad].
_CSV_BOUNDS = (1e8, 1e4, 1e4, 1e4, 100.0)
_CSV_MAX_LINE = 320
_CSV_MIN_STEP_S = 1e-4
#: Peak memory of a trajectory file per row while it is read and splined [bytes]: a row's
#: list of five Python floats (about 270), the array and the spline's coefficients (about
#: 200); margin kept.
_CSV_BYTES_PER_ROW = 640
_CELL = re.compile(rb"[ \t]*[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?[ \t]*")


class TrajectoryPoint(NamedTuple):
    """A trajectory at one time (module docstring: N, relative to the start's hover point).

    Parameters
    ----------
    position : numpy.ndarray, shape (3,)
        The reference point's position [m].
    velocity : numpy.ndarray, shape (3,)
        Its velocity [m/s].
    acceleration : numpy.ndarray, shape (3,)
        Its acceleration [m/s^2].
    yaw : float
        The yaw angle relative to the start's [rad].
    yaw_rate : float
        Its rate [rad/s].
    """

    position: np.ndarray  #: (3,) [m]
    velocity: np.ndarray  #: (3,) [m/s]
    acceleration: np.ndarray  #: (3,) [m/s^2]
    yaw: float  #: [rad]
    yaw_rate: float  #: [rad/s]


def smooth_step(tau: float, smoothing: str = "min_jerk") -> tuple[float, float, float]:
    """The rest-to-rest profile s(tau) on tau in [0, 1] and its first two derivatives in tau:
    minimum-jerk s = 10 tau^3 - 15 tau^4 + 6 tau^5 (s', s'' zero at both ends), minimum-snap
    s = 35 tau^4 - 84 tau^5 + 70 tau^6 - 20 tau^7 (s', s'', s''' zero at both ends).

    Parameters
    ----------
    tau : float
        The normalised time, clipped to [0, 1].
    smoothing : {"min_jerk", "min_snap"}
        The profile.

    Returns
    -------
    s, ds, dds : float
        s(tau) [-] and its derivatives in tau.
    """
    t = min(max(float(tau), 0.0), 1.0)
    if smoothing == "min_jerk":
        s = t**3 * (10.0 - 15.0 * t + 6.0 * t * t)
        ds = 30.0 * t * t * (1.0 - t) ** 2
        dds = 60.0 * t * (1.0 - t) * (1.0 - 2.0 * t)
        return s, ds, dds
    if smoothing == "min_snap":
        s = t**4 * (35.0 - 84.0 * t + 70.0 * t * t - 20.0 * t**3)
        ds = 140.0 * t**3 * (1.0 - t) ** 3
        dds = 420.0 * t * t * (1.0 - t) ** 2 * (1.0 - 2.0 * t)
        return s, ds, dds
    raise ParameterError("smoothing", smoothing, f"one of {SMOOTHINGS}")


def _points(field_name: str, points: Any) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3 or p.shape[0] < 1 or not np.isfinite(p).all():
        raise ParameterError(field_name, f"shape {p.shape}", "n >= 1 finite points of 3 [m]")
    return p


def _yaws(field_name: str, yaws: Any, n: int) -> np.ndarray:
    if yaws is None:
        return np.zeros(n)
    y = np.asarray(yaws, dtype=float)
    if y.shape != (n,) or not np.isfinite(y).all():
        raise ParameterError(field_name, f"shape {y.shape}", f"{n} finite angles [rad]")
    return y


class Trajectory:
    """The contract: ``at(t) -> TrajectoryPoint`` (module docstring's frame), and ``end``, the
    time after which the reference no longer moves (or the last time a file covers)."""

    end: float = 0.0

    def at(self, t: float) -> TrajectoryPoint:
        """The trajectory at time t.

        Parameters
        ----------
        t : float
            Time from the run's start [s].

        Returns
        -------
        TrajectoryPoint
        """
        raise NotImplementedError

    @property
    def final_position(self) -> np.ndarray:
        """The position the reference ends at [m], shape (3,)."""
        return self.at(self.end).position


def _still(p: np.ndarray, yaw: float = 0.0) -> TrajectoryPoint:
    return TrajectoryPoint(p.copy(), np.zeros(3), np.zeros(3), float(yaw), 0.0)


@dataclass(frozen=True)
class Hold(Trajectory):
    """The start's hover point, held (the paper's station-keeping)."""

    def at(self, t: float) -> TrajectoryPoint:
        """Zero position, velocity, acceleration and yaw at every t.

        Parameters
        ----------
        t : float
            Time [s].

        Returns
        -------
        TrajectoryPoint
        """
        return _still(np.zeros(3))


@dataclass(frozen=True)
class Steps(Trajectory):
    """Setpoint changes: from ``times[i]`` the reference is ``points[i]`` (before
    ``times[0]``: the start's hover point); with ``transition`` > 0 each change is a
    minimum-jerk move of that duration starting at ``times[i]``.

    Parameters
    ----------
    times : array_like, shape (n,)
        When each setpoint starts [s], >= 0, increasing by at least ``transition``.
    points : array_like, shape (n, 3)
        The setpoints [m] (module docstring's frame).
    transition : float, optional
        The duration of each change's minimum-jerk move [s], >= 0 (0: a jump).
    yaws : array_like, shape (n,), optional
        The yaw of each setpoint [rad] (default 0).
    """

    times: Any
    points: Any
    transition: float = 0.0
    yaws: Any = None

    def __post_init__(self) -> None:
        p = _points("reference.points", self.points)
        t = np.asarray(self.times, dtype=float)
        if t.shape != (p.shape[0],) or not np.isfinite(t).all() or (t < 0).any():
            raise ParameterError("reference.times", f"shape {t.shape}",
                                 f"{p.shape[0]} finite times >= 0 [s], one per point")  # fmt: skip
        tr = float(self.transition)
        if not (np.isfinite(tr) and tr >= 0.0):
            raise ParameterError("reference.transition", tr, "a finite number >= 0 [s]")
        if (np.diff(t) < max(tr, 1e-9)).any():
            raise ParameterError("reference.times", t.tolist(), "increasing, each at least "
                                 "reference.transition after the one before")  # fmt: skip
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "transition", tr)
        object.__setattr__(self, "yaws", _yaws("reference.yaw", self.yaws, p.shape[0]))
        object.__setattr__(self, "end", float(t[-1] + tr))

    def at(self, t: float) -> TrajectoryPoint:
        """The setpoint at t, on its transition if one is under way.

        Parameters
        ----------
        t : float
            Time [s].

        Returns
        -------
        TrajectoryPoint
        """
        i = int(np.searchsorted(self.times, t, side="right")) - 1
        if i < 0:
            return _still(np.zeros(3))
        before = self.points[i - 1] if i > 0 else np.zeros(3)
        yaw0 = float(self.yaws[i - 1]) if i > 0 else 0.0
        T = self.transition
        if T <= 0.0 or t >= self.times[i] + T:
            return _still(self.points[i], self.yaws[i])
        s, ds, dds = smooth_step((t - self.times[i]) / T)
        d, dyaw = self.points[i] - before, float(self.yaws[i]) - yaw0
        return TrajectoryPoint(before + s * d, ds / T * d, dds / T**2 * d, yaw0 + s * dyaw,
                               ds / T * dyaw)  # fmt: skip


@dataclass(frozen=True)
class Waypoints(Trajectory):
    """Rest-to-rest straight segments from the start's hover point through each point, the
    first starting at ``start_time``; segment i lasts T_i = c D_i / v_i (D_i its length, v_i
    its peak speed, c = ``PEAK_SPEED_FACTOR[smoothing]``: 1.875 for minimum-jerk, 2.1875 for
    minimum-snap) and moves along s(tau) of ``smooth_step``.

    Parameters
    ----------
    points : array_like, shape (n, 3)
        The waypoints [m] (module docstring's frame), each apart from the one before.
    speeds : array_like, shape (n,)
        The peak speed of the segment to each point [m/s], > 0.
    smoothing : {"min_jerk", "min_snap"}, optional
        The segments' profile.
    start_time : float, optional
        When the first segment starts [s], >= 0.
    yaws : array_like, shape (n,), optional
        The yaw at each point [rad] (default 0), reached along the same profile.
    """

    points: Any
    speeds: Any
    smoothing: str = "min_jerk"
    start_time: float = 0.0
    yaws: Any = None
    _knots: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        p = _points("reference.points", self.points)
        v = np.asarray(self.speeds, dtype=float)
        if v.shape != (p.shape[0],) or not (np.isfinite(v).all() and (v > 0).all()):
            raise ParameterError("reference.speeds", f"shape {v.shape}" if v.shape !=
                                 (p.shape[0],) else v.tolist(), f"{p.shape[0]} finite speeds "
                                 "> 0 [m/s], one per point")  # fmt: skip
        if self.smoothing not in SMOOTHINGS:
            raise ParameterError("reference.smoothing", self.smoothing, f"one of {SMOOTHINGS}")
        t0 = float(self.start_time)
        if not (np.isfinite(t0) and t0 >= 0.0):
            raise ParameterError("reference.start_time", t0, "a finite number >= 0 [s]")
        D = np.linalg.norm(np.diff(np.vstack([np.zeros(3), p]), axis=0), axis=1)
        if (D <= 1e-9).any():
            i = int(np.flatnonzero(D <= 1e-9)[0])
            raise ParameterError(
                f"reference.points[{i}]",
                p[i].tolist(),
                "a point apart from the one before (the start: 0, 0, 0)",
            )
        knots = t0 + np.concatenate([[0.0], np.cumsum(PEAK_SPEED_FACTOR[self.smoothing] * D / v)])
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "speeds", v)
        object.__setattr__(self, "start_time", t0)
        object.__setattr__(self, "yaws", _yaws("reference.yaw", self.yaws, p.shape[0]))
        object.__setattr__(self, "_knots", knots)
        object.__setattr__(self, "end", float(knots[-1]))

    @property
    def knots(self) -> np.ndarray:
        """The segments' start and end times [s], shape (n + 1,)."""
        return self._knots.copy()

    def at(self, t: float) -> TrajectoryPoint:
        """The position on the segment under way at t (rest at the start before
        ``start_time``, at the last point after ``end``).

        Parameters
        ----------
        t : float
            Time [s].

        Returns
        -------
        TrajectoryPoint
        """
        if t <= self._knots[0]:
            return _still(np.zeros(3))
        if t >= self._knots[-1]:
            return _still(self.points[-1], self.yaws[-1])
        i = int(np.searchsorted(self._knots, t, side="right")) - 1
        a = self.points[i - 1] if i > 0 else np.zeros(3)
        yaw0 = float(self.yaws[i - 1]) if i > 0 else 0.0
        T = self._knots[i + 1] - self._knots[i]
        s, ds, dds = smooth_step((t - self._knots[i]) / T, self.smoothing)
        d, dyaw = self.points[i] - a, float(self.yaws[i]) - yaw0
        return TrajectoryPoint(a + s * d, ds / T * d, dds / T**2 * d, yaw0 + s * dyaw,
                               ds / T * dyaw)  # fmt: skip


@dataclass(frozen=True)
class CsvTrajectory(Trajectory):
    """A recorded path interpolated per axis by a cubic spline (SciPy ``CubicSpline``,
    not-a-knot ends, as ``base.motion.FileBase``): position, velocity and acceleration
    continuous. Outside [times[0], times[-1]] the end's position is held (a scenario refuses a
    file that does not cover its run).

    Parameters
    ----------
    times : array_like, shape (n,)
        Strictly increasing [s], n >= 4.
    positions : array_like, shape (n, 3)
        The path [m] (module docstring's frame).
    yaws : array_like, shape (n,), optional
        The yaw [rad] (default 0).
    source : str, optional
        The file's resolved path.
    sha256 : str, optional
        The SHA-256 of its bytes (``read_trajectory_csv``).
    """

    times: Any
    positions: Any
    yaws: Any = None
    source: str = ""
    sha256: str = ""
    _spline: Any = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        from scipy.interpolate import CubicSpline

        t = np.asarray(self.times, dtype=float)
        p = np.asarray(self.positions, dtype=float)
        src = self.source or None
        if t.ndim != 1 or t.size < 4 or p.shape != (t.size, 3):
            raise ParameterError("reference.file", f"{t.shape} times, {p.shape} positions",
                                 "n >= 4 times and n rows of 3 positions", source=src)  # fmt: skip
        if (
            not (np.isfinite(t).all() and np.isfinite(p).all())
            or (np.diff(t) < _CSV_MIN_STEP_S).any()
        ):
            raise ParameterError("reference.file", "times or positions",
                                 f"finite, times increasing by at least {_CSV_MIN_STEP_S:g} s",
                                 source=src)  # fmt: skip
        y = _yaws("reference.file yaw", self.yaws, t.size)
        values = np.column_stack([p, y])
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "positions", p)
        object.__setattr__(self, "yaws", y)
        object.__setattr__(self, "_spline", CubicSpline(t, values, bc_type="not-a-knot"))
        object.__setattr__(self, "end", float(t[-1]))

    @property
    def start(self) -> float:
        """The first time the file covers [s]."""
        return float(self.times[0])

    def at(self, t: float) -> TrajectoryPoint:
        """The spline at t (clamped to the file's times).

        Parameters
        ----------
        t : float
            Time [s].

        Returns
        -------
        TrajectoryPoint
        """
        tc = min(max(float(t), self.start), self.end)
        v = self._spline(tc)
        if tc != t:  # held outside the file
            return _still(v[:3], v[3])
        d1, d2 = self._spline(tc, 1), self._spline(tc, 2)
        return TrajectoryPoint(v[:3], d1[:3], d2[:3], float(v[3]), float(d1[3]))


def read_trajectory_csv(path: str | Path, *, sha256: str = "") -> CsvTrajectory:
    """A ``CsvTrajectory`` from a CSV file with the header ``t,x,y,z`` or ``t,x,y,z,yaw``
    (s, m, m, m, rad), read as ``base.motion.read_base_csv`` reads a track: opened by
    ``_io.open_user_file`` (a regular file, its size checked first), at most
    ``FILE_MAX_ROWS`` rows counted while streamed, each cell a plain decimal number within
    its column's bounds, the bytes hashed (SHA-256).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    sha256 : str, optional
        The SHA-256 the file must have (a result's saved scenario records it); empty: any.

    Returns
    -------
    CsvTrajectory
        Its ``source`` the resolved path, its ``sha256`` the hash of the bytes.

    Raises
    ------
    ParameterError
        A missing, unreadable or oversized file, a wrong header, too many rows, a cell that is
        not a plain decimal number or out of bounds, times not increasing, or other bytes
        than ``sha256``: one line naming the file, the row and the column, never its contents.
    """
    from .._io import open_user_file
    from ..resources import check_memory

    src = str(path)
    digest = hashlib.sha256()
    rows: list[list[float]] = []
    ncol = 0

    def refuse(row: int, value: str, allowed: str, column: str = "") -> None:
        where = f"reference.file row {row}" + (f" column {column}" if column else "")
        raise ParameterError(where, value, allowed, source=src)

    with open_user_file(path, field="reference.file", what="a CSV trajectory t,x,y,z[,yaw]",
                        max_bytes=FILE_MAX_BYTES) as (fh, resolved, size):  # fmt: skip
        # the most rows its size allows (a row takes 8 bytes at least), held as Python lists
        # and splined: before anything is read
        most = min(FILE_MAX_ROWS, size // 8 + 1)
        check_memory(f"reading the trajectory {src} (up to {most} rows)",
                     most * _CSV_BYTES_PER_ROW, hint="a shorter file (fewer rows)")  # fmt: skip
        row = 0
        while True:
            line = fh.readline(_CSV_MAX_LINE + 1)
            if not line:
                break
            row += 1
            digest.update(line)
            if row > FILE_MAX_ROWS + 1:
                raise ParameterError("reference.file", f"more than {FILE_MAX_ROWS} rows",
                                     f"at most {FILE_MAX_ROWS} rows", source=src)  # fmt: skip
            if len(line) > _CSV_MAX_LINE:
                refuse(row, f"a line longer than {_CSV_MAX_LINE} bytes", "a shorter line")
            text = line.removeprefix(b"\xef\xbb\xbf").strip().replace(b" ", b"")
            if row == 1:
                if text not in (b"t,x,y,z", b"t,x,y,z,yaw"):
                    refuse(1, "not the header", "the header t,x,y,z or t,x,y,z,yaw")
                ncol = text.count(b",") + 1
                continue
            if not text:
                continue
            cells = line.strip().split(b",")
            if len(cells) != ncol:
                refuse(row, f"{len(cells)} cells", f"{ncol} numbers as the header names")
            values = []
            for name, cell, bound in zip(CSV_COLUMNS, cells, _CSV_BOUNDS, strict=False):
                if not _CELL.fullmatch(cell):
                    refuse(row, "not a plain decimal number", "a plain decimal number such as "
                           "-0.5, 12 or 1.25e-3 (no '_', inf or nan)", column=name)  # fmt: skip
                value = float(cell)
                if not abs(value) <= bound:
                    refuse(row, "out of its range", f"within +-{bound:g}", column=name)
                values.append(value)
            if rows and values[0] < rows[-1][0] + _CSV_MIN_STEP_S:
                refuse(
                    row,
                    "not a step above the previous row's",
                    f"times strictly increasing, by at least {_CSV_MIN_STEP_S:g} s a row",
                    column="t",
                )
            rows.append(values)
    if row == 0:
        refuse(1, "an empty file", "the header t,x,y,z[,yaw], then the path's rows")
    if len(rows) < 4:
        raise ParameterError("reference.file", f"{len(rows)} rows", "at least 4 rows",
                             source=src)  # fmt: skip
    hexdigest = digest.hexdigest()
    if sha256 and hexdigest != sha256:
        raise ParameterError("reference.file_sha256", sha256, f"the SHA-256 of {src}'s bytes "
                             "(the file changed since it was recorded)")  # fmt: skip
    table = np.array(rows)
    return CsvTrajectory(
        table[:, 0], table[:, 1:4], table[:, 4] if ncol == 5 else None,
        source=str(resolved), sha256=hexdigest,
    )  # fmt: skip


@dataclass(frozen=True)
class Climb(Trajectory):
    """A vertical climb at a constant rate (a tethered take-off, the landing's mirror): at
    rest until ``start_time``, then up along n3 at ``rate`` until ``height`` above the start.

    Parameters
    ----------
    start_time : float
        When the climb starts [s], >= 0.
    rate : float
        The climb rate [m/s], > 0.
    height : float
        How far the reference rises above the start's hover point [m], > 0.
    """

    start_time: float
    rate: float
    height: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.start_time) and self.start_time >= 0.0):
            raise ParameterError("reference.start_time", self.start_time, "a number >= 0 [s]")
        for name, value in (("climb_rate", self.rate), ("height", self.height)):
            if not (np.isfinite(value) and value > 0.0):
                raise ParameterError(f"reference.{name}", value, "a finite number > 0")
        object.__setattr__(self, "end", float(self.start_time + self.height / self.rate))

    def at(self, t: float) -> TrajectoryPoint:
        """The climb's reference at t (velocity ``rate`` along n3 while climbing).

        Parameters
        ----------
        t : float
            Time [s].

        Returns
        -------
        TrajectoryPoint
        """
        if t <= self.start_time:
            return _still(np.zeros(3))
        if t >= self.end:
            return _still(np.array([0.0, 0.0, self.height]))
        z = self.rate * (t - self.start_time)
        return TrajectoryPoint(np.array([0.0, 0.0, z]), np.array([0.0, 0.0, self.rate]),
                               np.zeros(3), 0.0, 0.0)  # fmt: skip
