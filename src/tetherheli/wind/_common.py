"""Helpers shared by the wind modules: validation (field names are "Class.field"; the loader
re-prefixes them) and the plain ``to_dict`` table (``_plain_dict``, ``PlainTable``)."""

from __future__ import annotations

import math
from dataclasses import fields
from typing import Any, cast

import numpy as np

from .._validation import check_vector
from ..errors import ParameterError

Vec3 = tuple[float, float, float]


def _unit(where: str, value: object) -> Vec3:
    """Normalise a nonzero 3-vector; idempotent (a unit vector is returned unchanged)."""
    vec = check_vector(where, value, 3, nonzero=True)
    norm = math.sqrt(sum(v * v for v in vec))
    if abs(norm - 1.0) <= 4.0 * np.finfo(float).eps:
        return cast(Vec3, vec)  # check_vector(..., 3): three entries
    return tuple(v / norm for v in vec)  # type: ignore[return-value]


def _times(t: object) -> tuple[np.ndarray, bool]:
    """Validate times: returns a 1-D float array and whether the input was a scalar."""
    allowed = "a real number or a 1-D array of times [s]"
    if t is None or isinstance(t, (str, bytes)):
        raise ParameterError("t", t, allowed)
    try:
        arr = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("t", t, allowed) from None
    if arr.ndim > 1:
        raise ParameterError("t", t, allowed)
    if not np.all(np.isfinite(arr)):
        raise ParameterError("t", t, "finite times [s]")
    return np.atleast_1d(arr), arr.ndim == 0


def _velocities(N_v_HO: object, n: int) -> np.ndarray:
    """Validate velocities of HO: returns an (n, 3) float array."""
    try:
        v = np.asarray(N_v_HO, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("N_v_HO", N_v_HO, "an array of shape (3,) or (n, 3) [m/s]") from None
    if v.shape == (3,):
        v = np.broadcast_to(v, (n, 3))
    if v.shape != (n, 3):
        raise ParameterError(
            "N_v_HO", N_v_HO, f"an array of shape (3,) or ({n}, 3) matching the times [m/s]"
        )
    if not np.all(np.isfinite(v)):
        raise ParameterError("N_v_HO", N_v_HO, "finite velocities [m/s]")
    return v


def _set(obj: object, name: str, value: object) -> None:
    object.__setattr__(obj, name, value)


def _plain_dict(obj: Any) -> dict[str, Any]:
    """``{"type": ..., field: value}`` with tuples as lists (TOML arrays)."""
    out: dict[str, Any] = {"type": obj.type_name} if getattr(obj, "type_name", "") else {}
    for f in fields(obj):
        if not f.init:
            continue
        value = getattr(obj, f.name)
        out[f.name] = list(value) if isinstance(value, tuple) else value
    return out


class PlainTable:
    """Mixin of the frozen dataclasses whose table is their fields (``_plain_dict``): the
    profiles, the drag model and the gust models."""

    def to_dict(self) -> dict[str, Any]:
        """A TOML-friendly table that ``disturbance_from_dict`` maps back to an equal object.

        Returns
        -------
        dict of str to object
            ``type`` and the fields, as TOML writes them (tuples as lists).
        """
        return _plain_dict(self)
