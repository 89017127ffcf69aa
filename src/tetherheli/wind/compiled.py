"""The built-in disturbances in the compiled engine's form: profile rows (``layout.WIND_*``),
a gust table and drag coefficients. A custom disturbance has no compiled form (None)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..layout import WIND_COLUMNS, WIND_CONSTANT, WIND_PULSE, WIND_SINE, WIND_STEP
from .profiles import ConstantForce, Disturbance, NoWind, Pulse, Sine, Step, WindSum
from .turbulence import SteadyWind, Turbulence

__all__ = ["CompiledWind", "compile_wind"]


@dataclass(frozen=True)
class CompiledWind:
    """A disturbance in the engine's form: profile rows, a gust table and drag coefficients.

    Parameters
    ----------
    program : numpy.ndarray, shape (k, WIND_COLUMNS)
        One row per built-in profile (``layout.WIND_*`` columns: kind, start [s], duration
        [s], magnitude [N], frequency [Hz], phase [rad], unit direction in N).
    gust : numpy.ndarray, shape (m, 3)
        Gust plus mean wind velocity in N on a time grid [m/s]; (0, 3) without turbulence.
    gust_dt : float
        Step of that grid [s] (0: no gust table).
    drag : numpy.ndarray, shape (3,)
        0.5 rho CdA per axis [kg/m].
    """

    program: np.ndarray  # (k, WIND_COLUMNS)
    gust: np.ndarray  # (m, 3) gust + mean wind velocity on a grid [m/s]
    gust_dt: float  # grid step [s] (0: none)
    drag: np.ndarray  # (3,) 0.5 rho CdA per axis [kg/m]

    def breakpoints(self, t_end: float) -> np.ndarray:
        """Times in (0, t_end) where a profile switches (pulse and step edges, sine starts).

        Parameters
        ----------
        t_end : float
            End of the run [s].

        Returns
        -------
        numpy.ndarray, shape (n,)
            The switch times [s], sorted, without duplicates.
        """
        pts = []
        for row in self.program:
            kind, start, duration = int(row[0]), row[1], row[2]
            if kind in (WIND_PULSE, WIND_STEP, WIND_SINE):
                pts.append(start)
            if kind == WIND_PULSE:
                pts.append(start + duration)
        arr = np.array(sorted(set(pts)), dtype=float)
        return arr[(arr > 0.0) & (arr < t_end)]


def compile_wind(wind: Disturbance) -> CompiledWind | None:
    """The engine form of built-in disturbances, or None for a custom one.

    Parameters
    ----------
    wind : Disturbance
        A built-in profile, turbulence, or a ``WindSum`` of them (at most one turbulence).

    Returns
    -------
    CompiledWind or None
        The engine form; None for a custom disturbance or more than one turbulence (the
        compiled engine cannot fly it).
    """
    rows: list[list[float]] = []
    gusts: list[Turbulence | SteadyWind] = []
    parts = wind.components if isinstance(wind, WindSum) else (wind,)
    for d in parts:
        if isinstance(d, NoWind):
            continue
        if isinstance(d, Pulse):
            rows.append([WIND_PULSE, d.start, d.duration, d.magnitude, 0, 0, *d.direction])
        elif isinstance(d, Step):
            rows.append([WIND_STEP, d.start, 0, d.magnitude, 0, 0, *d.direction])
        elif isinstance(d, Sine):
            rows.append([WIND_SINE, d.start, 0, d.amplitude, d.frequency, d.phase, *d.direction])
        elif isinstance(d, ConstantForce):
            rows.append([WIND_CONSTANT, 0, 0, 1.0, 0, 0, *d.vector])
        elif isinstance(d, (Turbulence, SteadyWind)):
            gusts.append(d)
        else:
            return None
    if len(gusts) > 1:
        return None
    program = np.array(rows, dtype=float).reshape(-1, WIND_COLUMNS)
    if gusts:
        g = gusts[0]
        drag = 0.5 * g.drag.rho * np.asarray(g.drag.cd_area_m2, dtype=float)
        if isinstance(g, SteadyWind):  # one row, held for every t >= 0 (``gust_velocity``)
            return CompiledWind(program, np.array([g.N_v_wind], dtype=float), 1.0, drag)
        table = np.ascontiguousarray(g.N_v_gust_grid + np.asarray(g.N_v_mean_wind))
        return CompiledWind(program, table, float(g.dt), drag)
    return CompiledWind(program, np.zeros((0, 3)), 0.0, np.zeros(3))
