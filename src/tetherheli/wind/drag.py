"""Bluff-body quadratic drag: the air-relative velocity at HO turned into a force."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_number, check_vector
from ..errors import ParameterError
from ._common import PlainTable, Vec3, _set

__all__ = ["DragModel"]


@dataclass(frozen=True)
class DragModel(PlainTable):
    """Bluff-body quadratic drag of the helicopter:
    F_i = 0.5 rho CdA_i |v_rel| v_rel,i, v_rel = air velocity - velocity of HO, with |v_rel|
    the norm of the whole relative velocity (the dynamic pressure 0.5 rho |v_rel|^2 acts on
    each axis's area along the flow's direction cosine v_rel,i / |v_rel|).

    In a mean wind U a small gust v gives, to first order, dF = 0.5 rho CdA (|U| v_perp +
    2 |U| v_par) (v_par along U, v_perp across it): a sideways or vertical gust in a mean wind
    acts linearly, not quadratically. The areas are along the N axes (not rotated with the
    fuselage, which is near level in hover).

    Parameters
    ----------
    cd_area_m2 : sequence of 3 floats
        Drag coefficient times reference area along n1, n2, n3 [m^2], >= 0. For a helicopter
        of the paper's size (12.7 kg) a few tenths of a square metre sideways; vertically the
        rotor disc dominates.
    rho : float, optional
        Air density [kg/m^3], > 0 (default 1.225, ISA sea level).
    """

    cd_area_m2: Vec3
    rho: float = 1.225

    def __post_init__(self) -> None:
        _set(self, "cd_area_m2", check_vector("DragModel.cd_area_m2", self.cd_area_m2, 3, low=0.0))
        _set(self, "rho", check_number("DragModel.rho", self.rho, low=0.0, low_open=True))

    def force(self, N_v_air: np.ndarray, N_v_HO: np.ndarray | None = None) -> np.ndarray:
        """Drag force on HO.

        Parameters
        ----------
        N_v_air : ndarray, shape (3,) or (n, 3)
            Air velocity at HO (mean wind plus gust) in N [m/s].
        N_v_HO : ndarray, shape (3,) or (n, 3), optional
            Velocity of HO in N [m/s] (default: at rest). Broadcasts against ``N_v_air``.

        Returns
        -------
        ndarray, shape of the broadcast inputs
            Force along n1, n2, n3 [N].
        """
        v_rel = np.asarray(N_v_air, dtype=float)
        if N_v_HO is not None:
            v_rel = v_rel - np.asarray(N_v_HO, dtype=float)
        if v_rel.shape[-1:] != (3,) or v_rel.ndim > 2:
            raise ParameterError("N_v_air", N_v_air, "an array of shape (3,) or (n, 3) [m/s]")
        speed = np.linalg.norm(v_rel, axis=-1, keepdims=True)
        return 0.5 * self.rho * np.asarray(self.cd_area_m2) * speed * v_rel
