"""The ``[reference]`` table: what the helicopter flies beyond its hover
(``control.trajectory``, flown by ``control.flight.ReferenceController``).

Positions are HO's relative to the start's trim hover point in the paper's frame N (n3 up;
over a moving base relative to the base), in metres; yaw relative to the start's, in radians.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validation import Key
from ..control.trajectory import (
    Climb,
    Hold,
    Steps,
    Trajectory,
    Waypoints,
    read_trajectory_csv,
)

__all__ = [
    "MAX_REFERENCE_POINTS",
    "REFERENCE_KEYS",
    "REFERENCE_TYPES",
    "ReferenceSettings",
    "build_trajectory",
]

#: The ``[reference]`` types.
REFERENCE_TYPES: tuple[str, ...] = ("hold", "steps", "waypoints", "csv", "takeoff")
#: The most setpoints or waypoints of a ``[reference]``.
MAX_REFERENCE_POINTS = 1000
#: The keys each type uses besides ``type`` (the others must stay at their defaults).
REFERENCE_KEYS: dict[str, tuple[str, ...]] = {
    "hold": (),
    "steps": ("times", "x", "y", "z", "yaw", "transition"),
    "waypoints": ("start_time", "x", "y", "z", "yaw", "speeds", "smoothing"),
    "csv": ("file", "file_sha256"),
    "takeoff": ("start_time", "climb_rate", "height", "top_tension"),
}

_POS = 1e4  # [m] the largest |coordinate| of a setpoint


def _key(default: Any, key: Key) -> Any:
    return field(default=default, metadata={"key": key})


def _points_key(axis: str) -> Key:
    return Key(f"the setpoints' or waypoints' {axis} coordinates relative to the start's "
               "hover point (N, n3 up)", "m", kind="list", length=MAX_REFERENCE_POINTS,
               low=-_POS, high=_POS, note="one per point; steps, waypoints")  # fmt: skip


@dataclass(frozen=True)
class ReferenceSettings:
    """What the run flies (``[reference]``): ``type = "hold"`` (default: the paper's
    station-keeping, the compiled loop as before), ``"steps"`` (setpoint changes at given
    times), ``"waypoints"`` (rest-to-rest minimum-jerk or minimum-snap segments at given peak
    speeds), ``"csv"`` (a recorded path t,x,y,z[,yaw] in a file) or ``"takeoff"`` (tethered:
    from the helicopter resting just above the winch on the scenario's short tether ``q9``,
    climb at ``climb_rate`` to ``height`` while the winch pays out under the tension
    schedule: the landing's mirror).

    Parameters
    ----------
    type, start_time, times, x, y, z, yaw, speeds, smoothing, transition, file, file_sha256,
    climb_rate, height, top_tension
        The keys of a scenario's ``[reference]`` table; each field's ``Key`` gives its
        meaning, unit, default and allowed range; ``REFERENCE_KEYS`` which type uses which.
    """

    type: str = _key(
        "hold", Key("what the run flies beyond its hover", kind="text", choices=REFERENCE_TYPES)
    )
    start_time: float = _key(
        0.0, Key("hover before the first waypoint's segment or the take-off's climb", "s",
                 low=0.0, note="waypoints; takeoff (below duration)"),
    )  # fmt: skip
    times: tuple[float, ...] = _key(
        (), Key("when each setpoint starts", "s", kind="list", length=MAX_REFERENCE_POINTS,
                low=0.0, note="increasing by at least transition, below duration; steps"),
    )  # fmt: skip
    x: tuple[float, ...] = _key((), _points_key("n1"))
    y: tuple[float, ...] = _key((), _points_key("n2"))
    z: tuple[float, ...] = _key((), _points_key("n3 (up)"))
    yaw: tuple[float, ...] = _key(
        (), Key("the yaw at each point relative to the start's (empty: 0)", "rad", kind="list",
                length=MAX_REFERENCE_POINTS, low=-6.3, high=6.3,
                note="empty or one per point; steps, waypoints"),
    )  # fmt: skip
    speeds: tuple[float, ...] = _key(
        (), Key("the peak speed of the segment to each waypoint (its duration: 1.875 D / v "
                "min-jerk, 2.1875 D / v min-snap)", "m/s", kind="list",
                length=MAX_REFERENCE_POINTS, low=0.0, low_open=True, high=20.0,
                note="one per point; waypoints"),
    )  # fmt: skip
    smoothing: str = _key(
        "min_jerk", Key("the waypoints' segments: minimum-jerk (quintic) or minimum-snap "
                        "(septic)", kind="text", choices=("min_jerk", "min_snap")),
    )  # fmt: skip
    transition: float = _key(
        0.0, Key("each step's minimum-jerk move (0: a jump)", "s", low=0.0, high=1e4,
                 note="steps"),
    )  # fmt: skip
    file: str = _key(
        "", Key("a CSV trajectory with the header t,x,y,z or t,x,y,z,yaw (s, m, rad), relative "
                "to the scenario file's folder, covering the run", kind="text", note="csv"),
    )  # fmt: skip
    file_sha256: str = _key(
        "", Key("the SHA-256 of file's bytes, recorded when read (set: the file must have it)",
                kind="text", note="csv"),
    )  # fmt: skip
    climb_rate: float = _key(
        0.3, Key("the take-off's climb rate relative to the base", "m/s", low=0.0,
                 low_open=True, high=2.0, note="takeoff"),
    )  # fmt: skip
    height: float = _key(
        5.0, Key("HO's height above the winch at the top of the take-off", "m", low=0.0,
                 low_open=True, high=1000.0, note="above the start's by 0.5 m at least; takeoff"),
    )  # fmt: skip
    top_tension: float | None = _key(
        None, Key("the tension reference at the top of the take-off; it goes linearly with the "
                  "height from params.tension_control.T_ref (the start's, on the short tether)",
                  "N", low=0.0, low_open=True, note="below limits.max_tension; takeoff",
                  unset="params.tension_control.T_ref"),
    )  # fmt: skip

    @property
    def moving(self) -> bool:
        """Whether the reference moves (any type but hold)."""
        return self.type != "hold"


def build_trajectory(r: ReferenceSettings, *, start_height: float = 0.0) -> Trajectory:
    """The ``control.trajectory`` object a checked ``[reference]`` describes.

    Parameters
    ----------
    r : ReferenceSettings
        The table (its keys checked).
    start_height : float, optional
        HO's height above the winch at the start [m] (a take-off climbs from it to
        ``r.height``).

    Returns
    -------
    Trajectory
        ``Hold``, ``Steps``, ``Waypoints``, ``CsvTrajectory`` (the file read) or ``Climb``.

    Raises
    ------
    ParameterError
        A table the trajectory refuses (one line naming the key).
    """
    points = np.column_stack([r.x, r.y, r.z]) if r.x else np.zeros((0, 3))
    yaws = r.yaw or None
    if r.type == "steps":
        return Steps(r.times, points, transition=r.transition, yaws=yaws)
    if r.type == "waypoints":
        return Waypoints(points, r.speeds, r.smoothing, r.start_time, yaws=yaws)
    if r.type == "csv":
        return read_trajectory_csv(r.file, sha256=r.file_sha256)
    if r.type == "takeoff":
        return Climb(r.start_time, r.climb_rate, r.height - start_height)
    return Hold()
