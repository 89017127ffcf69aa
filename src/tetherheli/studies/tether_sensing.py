"""The tether as a position sensor with sag: how far Sec. IV-F's
straight-tether estimate of P is off when the cable has weight and wind drag, and what the
catenary estimator (``tether.catenary.catenary_position_estimate``) leaves.

The truth is the static cable from the winch to P (``tether.catenary.static_cable``: the
elastic catenary with steady drag). The encoders read its tangent at the winch (q7, q8), the
load cell its tension there, the winch its paid-out unstretched length L0, the altimeter and
the IMU give the height of P. The estimates compared (``ESTIMATES``):

- ``ivf``: Sec. IV-F (eq 45 with the altimeter's height: P = h / c3,3 c3), the paper's sensor;
- ``catenary_wind_known``: the cable with drag integrated up from the winch with the true
  wind (what is left is the solver's residual: the method is exact for a static cable);
- ``catenary_wind_ignored``: the windless elastic catenary from the winch;
- ``catenary_wind_1ms``: the cable with drag and the wind known to +-1 m/s along its true
  direction (the worse of the two);

Not offered: the wind's speed estimated from the altimeter (the one scalar the ground
sensors lack). The cable's end height depends too weakly on the wind: with P straight above
the winch the height error has two roots in the wind, and 0.5 m of altimeter error moved the
estimate of P by metres (measured while this module was written).

Errors are the horizontal distance |estimate - P| in n1, n2 [m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validation import check_number
from ..errors import InfeasibleError
from ..tether.catenary import catenary_position_estimate, static_cable, straight_tether_estimates
from ..tether.chain import LumpedTether

__all__ = [
    "ESTIMATES",
    "sensing_errors",
    "sensing_study",
]

#: The estimates ``sensing_errors`` compares (see the module docstring).
ESTIMATES: tuple[str, ...] = (
    "ivf",
    "catenary_wind_known",
    "catenary_wind_ignored",
    "catenary_wind_1ms",
)


def _horizontal(err: np.ndarray) -> float:
    return math.hypot(float(err[0]), float(err[1]))


def sensing_errors(
    tether: LumpedTether,
    length_m: float,
    wind_m_s: float,
    elevation_deg: float,
    ground_tension_N: float,
    g: float,
    wind_error_m_s: float = 1.0,
) -> dict[str, float]:
    """Horizontal position errors [m] of each of ``ESTIMATES`` for P at distance
    ``length_m`` from the winch and ``elevation_deg`` above the horizon in the n1-n3 plane,
    a steady wind along n1 and the given winch tension.

    Parameters
    ----------
    tether : LumpedTether
        The cable.
    length_m : float
        Distance of P from the winch [m], > 0.
    wind_m_s : float
        Wind speed along n1 [m/s] (negative: along -n1).
    elevation_deg : float
        Elevation of P seen from the winch [deg], in (0, 90].
    ground_tension_N : float
        Tension at the winch [N], > 0.
    g : float
        Gravity [m/s^2].
    wind_error_m_s : float, optional
        The wind speed error of ``catenary_wind_1ms`` [m/s], >= 0 (default 1).

    Returns
    -------
    dict of str to float
        Estimate name -> error [m]; also ``ground_angle_deg`` (the cable's angle at the
        winch from the line to P, the bias's cause)

    Raises
    ------
    InfeasibleError
        No static cable lifts off the winch at that tension (it would lie on the ground).
    """
    L = check_number("length_m", length_m, low=0.0, low_open=True, unit="[m]")
    W = check_number("wind_m_s", wind_m_s, unit="[m/s]")
    el = math.radians(
        check_number("elevation_deg", elevation_deg, low=0.0, high=90.0, low_open=True)
    )
    dW = check_number("wind_error_m_s", wind_error_m_s, low=0.0, unit="[m/s]")
    e = np.array([math.cos(el), 0.0, math.sin(el)])
    r_P = L * e
    n1 = np.array([1.0, 0.0, 0.0])
    cab = static_cable(r_P, ground_tension_N, tether, g, W * n1)
    q7, q8 = cab.encoder_angles
    T_g = float(np.linalg.norm(cab.ground_tension))
    args = (q7, q8, T_g, cab.unstretched_length_m, tether, g)
    ivf, _ = straight_tether_estimates(cab, tether.EA_N)

    out = {
        "ivf": _horizontal(ivf - r_P),
        "catenary_wind_known": _horizontal(catenary_position_estimate(*args, wind=W * n1) - r_P),
        "catenary_wind_ignored": _horizontal(catenary_position_estimate(*args) - r_P),
        "catenary_wind_1ms": max(
            _horizontal(catenary_position_estimate(*args, wind=(W + s * dW) * n1) - r_P)
            for s in (-1.0, 1.0)
        ),
    }
    tangent = cab.ground_tension / T_g
    out["ground_angle_deg"] = math.degrees(math.acos(min(1.0, float(tangent @ e))))
    return out


def sensing_study(
    cables: Sequence[Any],
    lengths_m: Sequence[float],
    winds_m_s: Sequence[float],
    elevations_deg: Sequence[float],
    ground_tension_N: float,
    g: float,
) -> list[dict[str, Any]]:
    """``sensing_errors`` over a grid: one row per (cable, elevation, length, wind).

    Parameters
    ----------
    cables : sequence of StudyCable
        The cables (``studies.tether_study.StudyCable``: ``key`` and ``tether``).
    lengths_m, winds_m_s, elevations_deg : sequence of float
        The grid [m, m/s, deg].
    ground_tension_N : float
        Tension at the winch [N].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    list of dict
        ``cable``, ``elevation_deg``, ``length_m``, ``wind_m_s``, ``status`` ("ok" or why no
        static cable exists) and the errors of ``sensing_errors`` (NaN when not ok).
    """
    rows = []
    for cable in cables:
        for el in elevations_deg:
            for L in lengths_m:
                for W in winds_m_s:
                    row: dict[str, Any] = {
                        "cable": cable.key,
                        "elevation_deg": float(el),
                        "length_m": float(L),
                        "wind_m_s": float(W),
                    }
                    try:
                        err = sensing_errors(cable.tether, L, W, el, ground_tension_N, g)
                        row["status"] = "ok"
                    except InfeasibleError as exc:
                        err = dict.fromkeys((*ESTIMATES, "ground_angle_deg"), math.nan)
                        row["status"] = str(exc).splitlines()[0]
                    row.update(err)
                    rows.append(row)
    return rows
