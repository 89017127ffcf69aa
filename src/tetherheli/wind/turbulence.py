"""Turbulence: ``Turbulence``, the disturbance that turns a gust series into a drag force on
HO, and the checks of a run's wind that depend on it (``check_wind_covers``,
``initial_wind_force``).

The gust models (``DrydenGust``, ``GaussMarkovTurbulence``: ``wind.gusts``) generate gust
*velocities*, calibrated from published models by ``wind.calibration``
(``CalibratedGaussMarkovTurbulence``, ``gust_calibration``); ``DragModel`` turns the
air-relative velocity into a force; ``Turbulence`` ties a gust model, a drag model, a seed and
a time grid into a ``Disturbance``. The gust models' names are re-exported here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .._validation import check_integer, check_number, check_vector
from ..errors import ParameterError
from ._common import Vec3, _plain_dict, _set, _times
from .calibration import (
    CALIBRATIONS,
    CalibratedGaussMarkovTurbulence,
    GustCalibration,
    gust_calibration,
)
from .drag import DragModel
from .gusts import DrydenGust, GaussMarkovTurbulence, GustModel, heading_axes
from .profiles import Disturbance, WindSum

__all__ = [
    "CALIBRATIONS",
    "CalibratedGaussMarkovTurbulence",
    "DrydenGust",
    "GaussMarkovTurbulence",
    "GustCalibration",
    "GustModel",
    "SteadyWind",
    "Turbulence",
    "check_gust_grid",
    "check_wind_covers",
    "gust_calibration",
    "heading_axes",
    "initial_wind_force",
]

_MAX_SAMPLES = 20_000_000


@dataclass(frozen=True)
class Turbulence(Disturbance):
    """Turbulence as a disturbance: a gust series drawn once from a seed, turned into a drag
    force on HO.

    On construction the gust model is sampled on the grid t_k = k dt, k = 0..n, with
    n = ceil(duration / dt) (the grid covers [0, duration]); between grid points the gust
    velocity is interpolated linearly. Equal parameters give identical series. ``force(t)``
    is the drag with HO at rest; ``force_at(t, N_v_HO)`` uses the air-relative velocity.

    Parameters
    ----------
    model : GustModel
        ``DrydenGust`` or ``GaussMarkovTurbulence`` (or a custom ``GustModel``).
    drag : DragModel
        Turns the air-relative velocity into a force.
    seed : int
        Seed of the ``numpy.random.SeedSequence`` (>= 0); recorded by ``to_dict``.
    duration : float
        Time span covered [s], > 0. Asking for the force outside [0, end of grid] is an error.
    dt : float
        Grid step [s], 0 < dt <= duration.
    spawn_key : tuple of int, optional
        Spawn key of the seed sequence (default ()): ``spawn_key=(i,)`` gives the same
        generator as ``SeedSequence(seed).spawn(n)[i]``, for batches of independent runs.
    N_v_mean_wind : sequence of 3 floats, optional
        Mean wind in N added to the gusts [m/s] (default zero).
    """

    type_name: ClassVar[str] = "turbulence"

    model: GustModel
    drag: DragModel
    seed: int
    duration: float
    dt: float
    spawn_key: tuple[int, ...] = ()
    N_v_mean_wind: Vec3 = (0.0, 0.0, 0.0)
    _gust: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.model, GustModel):
            raise ParameterError("Turbulence.model", self.model, "a GustModel")
        if not isinstance(self.drag, DragModel):
            raise ParameterError("Turbulence.drag", self.drag, "a DragModel")
        _set(self, "seed", check_integer("Turbulence.seed", self.seed, low=0))
        key = self.spawn_key
        allowed = "a tuple of integers >= 0"
        if not isinstance(key, (list, tuple)):
            raise ParameterError("Turbulence.spawn_key", key, allowed)
        _set(
            self,
            "spawn_key",
            tuple(check_integer("Turbulence.spawn_key", k, low=0, allowed=allowed) for k in key),
        )
        duration = check_number("Turbulence.duration", self.duration, low=0.0, low_open=True)
        dt = check_number("Turbulence.dt", self.dt, low=0.0, low_open=True, high=duration)
        check_gust_grid("Turbulence.dt", duration, dt)
        n = math.ceil(duration / dt - 1e-9)
        _set(self, "duration", duration)
        _set(self, "dt", dt)
        _set(self, "N_v_mean_wind", check_vector("Turbulence.N_v_mean_wind", self.N_v_mean_wind, 3))
        if isinstance(self.model, CalibratedGaussMarkovTurbulence):
            _check_calibrated_mean_wind(self.model, self.N_v_mean_wind)
        gust = self.model.sample(dt * np.arange(n + 1), self.rng())
        gust.setflags(write=False)
        _set(self, "_gust", gust)

    def rng(self) -> np.random.Generator:
        """A fresh generator in the state used to draw the gusts.

        Returns
        -------
        numpy.random.Generator
            Seeded from ``seed`` and ``spawn_key``.
        """
        return np.random.default_rng(np.random.SeedSequence(self.seed, spawn_key=self.spawn_key))

    @property
    def t_grid(self) -> np.ndarray:
        """Grid times, shape (n + 1,) [s]."""
        return self.dt * np.arange(self._gust.shape[0])

    @property
    def N_v_gust_grid(self) -> np.ndarray:
        """Gust velocity on the grid (without the mean wind), shape (n + 1, 3) [m/s]."""
        return self._gust

    def gust_velocity(self, t: float | np.ndarray) -> np.ndarray:
        """Gust velocity (without the mean wind), linearly interpolated.

        Parameters
        ----------
        t : float or ndarray, shape (n,)
            Time(s) [s] within the grid.

        Returns
        -------
        ndarray, shape (3,) for a scalar ``t``, else (n, 3)
            n1, n2, n3 components [m/s].
        """
        ts, scalar = _times(t)
        out = self._interp(ts)
        return out[0] if scalar else out

    @property
    def t_end(self) -> float:
        """The end of the gust grid [s] (>= ``duration``)."""
        return self.dt * (self._gust.shape[0] - 1)

    def covers(self, t: float | np.ndarray) -> bool | np.ndarray:
        """Whether time(s) ``t`` [s] lie within the gust grid [0, ``t_end``] (relative
        tolerance 1e-12 at the end).

        Parameters
        ----------
        t : float or ndarray
            Time(s) [s].

        Returns
        -------
        bool or ndarray of bool
            Shaped as ``t``.
        """
        return (t >= 0.0) & (t <= self.t_end * (1.0 + 1e-12))

    def _interp(self, t: np.ndarray) -> np.ndarray:
        end = self.t_end
        inside = self.covers(t)
        if not np.all(inside):
            bad = t[~inside][0]
            raise ParameterError(
                "t", float(bad), f"a time within the turbulence grid [0, {end:g}] s"
            )
        s = np.clip(t / self.dt, 0.0, self._gust.shape[0] - 1)
        k = np.minimum(np.floor(s).astype(np.intp), self._gust.shape[0] - 2)
        w = (s - k)[:, None]
        return (1.0 - w) * self._gust[k] + w * self._gust[k + 1]

    def _force(self, t: np.ndarray) -> np.ndarray:
        return self.drag.force(self._interp(t) + np.asarray(self.N_v_mean_wind))

    def _force_at(self, t: np.ndarray, N_v_HO: np.ndarray) -> np.ndarray:
        return self.drag.force(self._interp(t) + np.asarray(self.N_v_mean_wind), N_v_HO)

    @property
    def initial_force(self) -> np.ndarray:
        """Drag on HO at rest of the air at t = 0, the mean wind plus the gust drawn for
        t = 0, shape (3,) [N]: the force the run's initial trim balances
        (``initial_wind_force``)."""
        return self.initial_force_on((0.0, 0.0, 0.0))

    def initial_force_on(self, N_v_HO: Sequence[float] | np.ndarray) -> np.ndarray:
        """Drag at t = 0 on HO moving at ``N_v_HO`` in N (over a moving base, the base's
        velocity b'(0): the air relative to HO is the mean wind plus the gust at t = 0 less
        it), shape (3,) [N].

        Parameters
        ----------
        N_v_HO : array_like, shape (3,)
            HO's velocity in N at t = 0 [m/s].

        Returns
        -------
        ndarray, shape (3,)
            The force along n1, n2, n3 [N].
        """
        air = np.asarray(self.N_v_mean_wind, dtype=float) + self._gust[0]
        return self.drag.force(air, np.asarray(N_v_HO, dtype=float))

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``; the gusts themselves are regenerated from the seed.
        Returns
        -------
        dict of str to object
            ``type``, the fields, and the ``model`` and ``drag`` tables.
        """
        out = _plain_dict(self)
        out["model"] = self.model.to_dict()
        out["drag"] = self.drag.to_dict()
        return out


@dataclass(frozen=True)
class SteadyWind(Disturbance):
    """A steady wind as a disturbance: air moving at ``N_v_wind`` in N, turned into a drag
    force on HO by the air-relative velocity (``DragModel``). Over a moving base the
    helicopter feels the apparent wind, the true wind less its own velocity in N: a ship
    under way at U through still air gives a head wind U (the engine's drag takes HO's
    velocity in N, the base's included). ``force(t)`` is the drag with HO at rest.

    Parameters
    ----------
    drag : DragModel
        Turns the air-relative velocity into a force.
    N_v_wind : sequence of 3 floats, optional
        The true wind's air velocity in N [m/s] (default: still air).
    """

    type_name: ClassVar[str] = "steady"

    drag: DragModel
    N_v_wind: Vec3 = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.drag, DragModel):
            raise ParameterError("SteadyWind.drag", self.drag, "a DragModel")
        _set(self, "N_v_wind", check_vector("SteadyWind.N_v_wind", self.N_v_wind, 3))

    def _force(self, t: np.ndarray) -> np.ndarray:
        return self.drag.force(np.broadcast_to(np.asarray(self.N_v_wind), (t.shape[0], 3)))

    def _force_at(self, t: np.ndarray, N_v_HO: np.ndarray) -> np.ndarray:
        air = np.broadcast_to(np.asarray(self.N_v_wind), (t.shape[0], 3))
        return self.drag.force(air, N_v_HO)

    def initial_force_on(self, N_v_HO: Sequence[float] | np.ndarray) -> np.ndarray:
        """Drag at t = 0 on HO moving at ``N_v_HO`` in N, shape (3,) [N].

        Parameters
        ----------
        N_v_HO : array_like, shape (3,)
            HO's velocity in N at t = 0 [m/s].

        Returns
        -------
        ndarray, shape (3,)
            The force along n1, n2, n3 [N].
        """
        return self.drag.force(np.asarray(self.N_v_wind, dtype=float), np.asarray(N_v_HO, float))

    def to_dict(self) -> dict[str, Any]:
        """See ``Disturbance.to_dict``.

        Returns
        -------
        dict of str to object
            ``type``, ``N_v_wind`` and the ``drag`` table.
        """
        out = _plain_dict(self)
        out["drag"] = self.drag.to_dict()
        return out


def check_gust_grid(name: str, duration: float, dt: float) -> None:
    """Refuse a gust grid of step ``dt`` over ``duration`` with more than ``_MAX_SAMPLES``
    samples (the one rule: ``Turbulence`` applies it, the Gymnasium environment at its
    construction for the episodes' turbulence).

    Parameters
    ----------
    name : str
        The field the error names.
    duration : float
        The grid's time span [s], > 0.
    dt : float
        The grid's step [s], > 0.

    Returns
    -------
    None

    Raises
    ------
    ParameterError
        Naming ``name`` with ``dt``.
    """
    if math.ceil(duration / dt - 1e-9) + 1 > _MAX_SAMPLES:
        raise ParameterError(name, dt, f"a step giving at most {_MAX_SAMPLES} samples")


def _check_calibrated_mean_wind(model: CalibratedGaussMarkovTurbulence, N_v_mean: Vec3) -> None:
    """The calibration's convection speed and gust axis u must be the mean wind's."""
    v = np.asarray(N_v_mean, dtype=float)
    speed = float(np.linalg.norm(v))
    if abs(model.mean_wind_m_s - speed) > 1e-9 * max(speed, 1.0):
        raise ParameterError(
            "Turbulence.model.mean_wind_m_s",
            model.mean_wind_m_s,
            f"the speed of N_v_mean_wind ({speed:g} m/s), the calibration's convection speed",
        )
    if math.hypot(v[0], v[1]) > 1e-9 * speed:
        azimuth = math.atan2(v[1], v[0])
        off = math.remainder(model.heading_rad - azimuth, 2.0 * math.pi)
        if abs(off) > 1e-9:
            raise ParameterError(
                "Turbulence.model.heading_rad",
                model.heading_rad,
                f"the azimuth of N_v_mean_wind ({azimuth:.9g} rad): gust axis u along the wind",
            )


def initial_wind_force(
    wind: Disturbance, N_v_HO: Sequence[float] | np.ndarray = (0.0, 0.0, 0.0)
) -> np.ndarray:
    """The force of the air at t = 0 on HO moving at ``N_v_HO`` in N, shape (3,) [N]: the
    drag of the mean wind plus the gust at t = 0 of every ``Turbulence`` in ``wind``
    (``Turbulence.initial_force_on``) relative to HO; zero for the force profiles (pulse,
    step, sine, constant), which a run meets as they come. A run starts in the trim that
    balances it (``runs.start.start_point``); over a moving base HO starts at rest relative
    to the base, so ``N_v_HO`` is the base's velocity b'(0).

    Parameters
    ----------
    wind : Disturbance
        The run's wind (a sum is summed part by part).
    N_v_HO : array_like, shape (3,), optional
        HO's velocity in N at t = 0 [m/s] (default: at rest).

    Returns
    -------
    ndarray, shape (3,)
        The force along n1, n2, n3 [N].
    """
    if isinstance(wind, WindSum):
        parts = [initial_wind_force(part, N_v_HO) for part in wind.components]
        return np.sum(parts, axis=0) + np.zeros(3)
    if isinstance(wind, (Turbulence, SteadyWind)):
        return wind.initial_force_on(N_v_HO)
    return np.zeros(3)


def check_wind_covers(
    wind: Disturbance, duration: float, *, name: str = "wind", source: str | None = None
) -> None:
    """Refuse a turbulence whose gust grid ends before a run of ``duration`` [s] does.

    The one check for every path: the compiled engine would hold the last gust value for the
    rest of the run and the Python loop would stop with an error mid-run; ``Scenario``
    calls it on construction, the Gymnasium environment on every episode's wind.

    Parameters
    ----------
    wind : Disturbance
        The wind (a sum is checked part by part).
    duration : float
        The run's length [s].
    name : str, optional
        The field the error names (default ``"wind"``).
    source : str, optional
        Where the wind came from (a file), for the error message.

    Returns
    -------
    None

    Raises
    ------
    ParameterError
        Naming the turbulence's ``duration`` field (``wind.duration``, ``wind[i].duration``).
    """
    if isinstance(wind, WindSum):
        for i, part in enumerate(wind.components):
            check_wind_covers(part, duration, name=f"{name}[{i}]", source=source)
    elif isinstance(wind, Turbulence) and not wind.covers(duration):
        raise ParameterError(
            f"{name}.duration",
            wind.duration,
            f"a gust series covering the whole run: >= the run's duration ({duration:g} s; "
            f"the gust grid ends at {wind.t_end:g} s)",
            source=source,
        )
