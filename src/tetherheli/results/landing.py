"""A landing's figures of merit (``[maneuver] type = "tethered_landing"``): the touchdown's
time, speeds, offset, attitude and tension, how low the gear came and, when the run records
them, the gear's penetration and force and the settling. A descent is judged by these, not
by the hover's peak deviations from trim (``SimulationResult.peak_deviations``), which stay
in the machine tables only.

The recorded states and outputs are relative to the base (``results.files``), so the
speeds are relative to the deck and q3 is HO's height above the pad.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from .result import SimulationResult

__all__ = [
    "GEAR_FORCE",
    "GEAR_PENETRATION",
    "LANDING_MANEUVER",
    "SETTLED_TIME",
    "gear_columns",
    "is_landing",
    "landing_metrics",
    "landing_rows",
]

#: the ``[maneuver] type`` of a landing
LANDING_MANEUVER = "tethered_landing"
#: the extra columns of a run with landing-gear contact, by their names' start: the gear's
#: penetration into the deck [m] and its force [N] (one column each, or one per contact point)
GEAR_PENETRATION = "gear_penetration"
GEAR_FORCE = "gear_force"
#: the touchdown record's key of the time [s] the helicopter settled on the deck, when the
#: run goes on after the touchdown and records it
SETTLED_TIME = "settled_time"


def is_landing(configuration: dict[str, Any]) -> bool:
    """Whether a run's scenario flies a tethered landing.

    Parameters
    ----------
    configuration : dict
        The scenario as plain data (``SimulationResult.configuration``).

    Returns
    -------
    bool
        True for ``[maneuver] type = "tethered_landing"``.
    """
    maneuver = configuration.get("maneuver") or {}
    return isinstance(maneuver, dict) and maneuver.get("type") == LANDING_MANEUVER


def gear_columns(extra: dict[str, np.ndarray], kind: str) -> dict[str, np.ndarray]:
    """The recorded gear columns of one kind, by name.

    Parameters
    ----------
    extra : dict of str to numpy.ndarray
        A run's extra columns (``SimulationResult.extra``).
    kind : str
        ``GEAR_PENETRATION`` [m] or ``GEAR_FORCE`` [N].

    Returns
    -------
    dict of str to numpy.ndarray
        The columns whose names start with ``kind`` (empty when not recorded).
    """
    return {name: v for name, v in extra.items() if name.startswith(kind)}


def _at(time: np.ndarray, values: np.ndarray, t: float) -> float:
    """``values`` interpolated linearly at ``t`` [s] (held at the ends)."""
    return float(np.interp(t, time, values)) if time.size else math.nan


def landing_metrics(result: SimulationResult) -> dict[str, Any]:
    """A landing's figures of merit (empty for a run that is not a landing).

    Parameters
    ----------
    result : SimulationResult
        The run.

    Returns
    -------
    dict of str to Any
        ``touched_down`` (bool); at the touchdown (None without one): ``touchdown_time``
        [s], ``touchdown_vertical_speed`` [m/s, downward positive, relative to the deck],
        ``touchdown_horizontal_speed`` [m/s, relative to the deck], ``touchdown_offset``
        [m, HO from the pad], ``touchdown_attitude_deg`` [deg, the fuselage's tilt],
        ``touchdown_tension`` [N, at P], ``touchdown_reasons`` (the limits broken);
        ``lowest_gear_height`` [m]: the least height of the gear (``gear_height`` below
        HO) above the pad over the run; when recorded, ``max_gear_penetration`` [m],
        ``max_gear_force`` [N] and ``settled_time`` [s].
    """
    if not is_landing(result.configuration):
        return {}
    gear_height = float(result.configuration["maneuver"].get("gear_height", 0.0))
    td = result.touchdown
    out: dict[str, Any] = {"touched_down": td is not None}
    keys = ("time", "vertical_speed", "horizontal_speed", "offset", "attitude_deg", "tension")
    if td is None:
        out.update({f"touchdown_{k}": None for k in keys})
        out["touchdown_reasons"] = []
    else:
        t = float(td["time"])
        u1, u2 = (_at(result.time, result.states[:, i], t) for i in (6, 7))
        out.update({
            "touchdown_time": t,
            "touchdown_vertical_speed": float(td["vertical_speed"]),
            "touchdown_horizontal_speed": math.hypot(u1, u2),
            "touchdown_offset": float(td["offset"]),
            "touchdown_attitude_deg": math.degrees(float(td["attitude"])),
            "touchdown_tension": _at(result.time, result.tension, t),
            "touchdown_reasons": list(td.get("reasons", [])),
        })  # fmt: skip
    height = result.outputs[:, 2] - gear_height
    out["lowest_gear_height"] = float(np.min(height)) if height.size else None
    for key, kind in (("max_gear_penetration", GEAR_PENETRATION), ("max_gear_force", GEAR_FORCE)):
        columns = gear_columns(result.extra, kind)
        if columns:
            out[key] = max(float(np.max(np.abs(v))) if v.size else 0.0 for v in columns.values())
    if td is not None and td.get(SETTLED_TIME) is not None:
        out["settled_time"] = float(td[SETTLED_TIME])
    return out


def landing_rows(metrics: dict[str, Any]) -> list[tuple[str, str]]:
    """A landing's figures of merit as (label, text) rows: a result's ``repr``, a run's
    report.

    Parameters
    ----------
    metrics : dict of str to Any
        ``landing_metrics``'s.

    Returns
    -------
    list of tuple of (str, str)
        The rows, each value with its unit.
    """
    if not metrics.get("touched_down"):
        rows = [("touchdown", "none")]
    else:
        m = metrics
        rows = [
            ("touchdown", f"t = {m['touchdown_time']:.4g} s"),
            ("touchdown speed", f"vertical {m['touchdown_vertical_speed']:.4g} m/s, "
             f"horizontal {m['touchdown_horizontal_speed']:.4g} m/s (relative to the deck)"),
            ("touchdown offset", f"{m['touchdown_offset']:.4g} m from the pad"),
            ("touchdown attitude", f"tilt {m['touchdown_attitude_deg']:.4g} deg"),
            ("touchdown tension", f"{m['touchdown_tension']:.4g} N"),
        ]  # fmt: skip
    if metrics.get("lowest_gear_height") is not None:
        rows.append(("lowest gear height", f"{metrics['lowest_gear_height']:.4g} m above the pad"))
    if "max_gear_penetration" in metrics:
        rows.append(("max gear penetration", f"{metrics['max_gear_penetration']:.4g} m"))
    if "max_gear_force" in metrics:
        rows.append(("max gear force", f"{metrics['max_gear_force']:.4g} N"))
    if "settled_time" in metrics:
        rows.append(("settled", f"t = {metrics['settled_time']:.4g} s"))
    return rows
