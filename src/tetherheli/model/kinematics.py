"""The helicopter's geometry, generated from the derivation: the rotation N -> F (Table I),
the points of eq 2, HO from the tethered coordinates (eqs 27, 43-45), the tether direction
c3 and its inverse (eq 27).

``derive.kinematics`` builds them with the frames and points of the Kane derivation;
``codegen`` writes them into ``_generated.py`` as functions that run on floats in Numba
(``kernels.kinematics_*``, used by the compiled sensors) and on arrays in NumPy (here, with
samples along the leading axes, used by the sensor analysis helpers and the animation).
Vector names carry their frame and points (``N_p_HO``: HO from NO in N components).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..params import HelicopterParams, Params
from . import _generated as gen

__all__ = [
    "HelicopterPoints",
    "direction_cosines",
    "helicopter_points",
    "tether_angles",
    "tether_direction",
    "tether_length_from_altitude",
    "tethered_HO_position",
]


def _samples_last(*arrays: ArrayLike) -> tuple[np.ndarray, tuple[int, ...]]:
    """Broadcast scalars or arrays of one shape S and stack them as rows, shape (k, *S)."""
    rows = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in arrays))
    return np.stack(rows), rows[0].shape


def direction_cosines(q4: ArrayLike, q5: ArrayLike, q6: ArrayLike) -> np.ndarray:
    """Direction cosine matrix N_R_F of the fuselage frame F in N (Table I, body-1-2-3).

    Parameters
    ----------
    q4, q5, q6 : float or array of shape (...,)
        Roll, pitch, yaw Euler angles [rad], broadcast together.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``R`` with column j holding f_j in N components, so that a vector with F components
        ``v_F`` has N components ``R @ v_F``.
    """
    q, shape = _samples_last(q4, q5, q6)
    R = np.empty((3, 3, *shape))
    gen.kinematics_dcm(q, R)
    return np.moveaxis(R, (0, 1), (-2, -1))


@dataclass(frozen=True, eq=False)
class HelicopterPoints:
    """Positions of the helicopter's named points from NO, in N components [m], each (..., 3).

    Parameters
    ----------
    N_p_HO : numpy.ndarray, shape (..., 3)
        Centre of mass of the whole helicopter (q1, q2, q3) [m].
    N_p_O : numpy.ndarray, shape (..., 3)
        Reference point of the fuselage (eq 2) [m].
    N_p_MRO : numpy.ndarray, shape (..., 3)
        Main-rotor centre [m].
    N_p_TRO : numpy.ndarray, shape (..., 3)
        Tail-rotor centre [m].
    N_p_P : numpy.ndarray, shape (..., 3)
        Tether attachment point [m].
    N_R_F : numpy.ndarray, shape (..., 3, 3)
        Direction cosine matrix of F in N (column j = f_j), Table I.
    """

    N_p_HO: np.ndarray
    N_p_O: np.ndarray
    N_p_MRO: np.ndarray
    N_p_TRO: np.ndarray
    N_p_P: np.ndarray
    N_R_F: np.ndarray


def helicopter_points(
    position: ArrayLike, angles: ArrayLike, helicopter: HelicopterParams | None = None
) -> HelicopterPoints:
    """Where O, MRO, TRO and P are for a helicopter whose centre of mass HO is at ``position``.

    Parameters
    ----------
    position : array_like, shape (..., 3)
        HO in N: (q1, q2, q3) [m] (eq 4; eqs 43-45 for the tethered coordinates).
    angles : array_like, shape (..., 3)
        Euler angles (q4, q5, q6) [rad] (Table I).
    helicopter : HelicopterParams, optional
        The f-axis offsets dO-FO,3, dO-MRO,3, dO-TRO,1, dO-P,3 and the masses (Table II,
        eqs 2-3). Default: the paper's values.

    Returns
    -------
    HelicopterPoints
        With P = HO + (dO-P,3 - dO-HO,3) f3, which equals q9 c3 for a tethered state (eq 45).
    """
    h = helicopter if helicopter is not None else Params.paper().helicopter
    pos = np.asarray(position, dtype=float)
    ang = np.asarray(angles, dtype=float)
    q, shape = _samples_last(*np.moveaxis(pos, -1, 0), *np.moveaxis(ang, -1, 0))
    out = np.empty((5, 3, *shape))
    gen.kinematics_points(q, h.as_array(), out)
    N_p = np.moveaxis(out, (0, 1), (-2, -1))  # (..., 5, 3): HO, O, MRO, TRO, P
    return HelicopterPoints(
        N_p_HO=N_p[..., 0, :],
        N_p_O=N_p[..., 1, :],
        N_p_MRO=N_p[..., 2, :],
        N_p_TRO=N_p[..., 3, :],
        N_p_P=N_p[..., 4, :],
        N_R_F=direction_cosines(q[3], q[4], q[5]),
    )


def tethered_HO_position(
    q4: ArrayLike, q5: ArrayLike, q7: ArrayLike, q8: ArrayLike, q9: ArrayLike, arm: float
) -> np.ndarray:
    """HO in N from the tethered coordinates: HO = q9 c3 - arm f3 (eqs 27, 43-45).

    Parameters
    ----------
    q4, q5 : float or array of shape (...,)
        Roll and pitch [rad].
    q7, q8, q9 : float or array of shape (...,)
        Tether angles [rad] and length [m].
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).

    Returns
    -------
    ndarray, shape (..., 3)
        [q1, q2, q3] of HO [m].
    """
    q, shape = _samples_last(q4, q5, 0.0, q7, q8, q9)
    out = np.empty((3, *shape))
    gen.kinematics_tethered_HO(q, float(arm), out)
    return np.moveaxis(out, 0, -1)


def tether_length_from_altitude(
    altitude: ArrayLike, q4: ArrayLike, q5: ArrayLike, q7: ArrayLike, q8: ArrayLike, arm: float
) -> Any:
    """q9 from eq 45 given the altitude q3 of HO: (q3 + arm c4 c5) / (c7 c8) [m] (Sec. IV-F).

    Arguments as for ``tethered_HO_position``, ``altitude`` [m] in place of q9.

    Parameters
    ----------
    altitude : float or array of shape (...,)
        Altitude q3 of HO [m].
    q4, q5 : float or array of shape (...,)
        Roll and pitch [rad].
    q7, q8 : float or array of shape (...,)
        Tether angles [rad].
    arm : float
        dO-P,3 - dO-HO,3 [m] (``HelicopterParams.tether_arm``).

    Returns
    -------
    numpy.ndarray, shape (...,)
        q9 [m], of the broadcast shape (a 0-d array for scalars).
    """
    q, _ = _samples_last(q4, q5, 0.0, q7, q8, altitude)  # q9's row holds the altitude
    return gen.kinematics_tether_length(q, q[5], float(arm))


def tether_direction(q7: ArrayLike, q8: ArrayLike) -> np.ndarray:
    """c3, the unit tether direction in N: [s8, -s7 c8, c7 c8] (eq 27).

    Parameters
    ----------
    q7, q8 : float or array of shape (...,)
        Tether angles [rad], broadcast together.

    Returns
    -------
    ndarray, shape (..., 3)
        c3 along n1, n2, n3.
    """
    q, shape = _samples_last(0.0, 0.0, 0.0, q7, q8, 0.0)
    out = np.empty((3, *shape))
    gen.kinematics_tether_direction(q, out)
    return np.moveaxis(out, 0, -1)


def tether_angles(P: ArrayLike) -> tuple[Any, Any, Any]:
    """(q7, q8, q9) of a point P = q9 c3 from the winch: the inverse of eq 27,
    q9 = |P|, q7 = atan2(-P2, P3), q8 = asin(P1 / q9), on the tethered hover's branch
    |q7|, |q8| < pi/2.

    Parameters
    ----------
    P : array_like, shape (..., 3)
        P (or any point along the tether's direction) from the winch in N [m].

    Returns
    -------
    q7, q8, q9 : float or numpy.ndarray of shape (...,)
        The tether angles [rad] and |P| [m].
    """
    rows = np.moveaxis(np.asarray(P, dtype=float), -1, 0)
    out = np.empty((3, *rows.shape[1:]))
    gen.kinematics_tether_angles(rows, out)
    return out[0][()], out[1][()], out[2][()]
