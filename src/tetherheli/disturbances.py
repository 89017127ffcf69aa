"""Kept for compatibility: the wind disturbances now live in the package ``tetherheli.wind``
(profiles, turbulence, drag, loader). ``from tetherheli.disturbances import Pulse`` and the
other public names keep working."""

from .wind import (
    ConstantForce,
    Disturbance,
    DragModel,
    DrydenGust,
    GustModel,
    HoverTurbulence,
    NoWind,
    Pulse,
    Sine,
    Step,
    Turbulence,
    WindSum,
    check_wind_covers,
    disturbance_from_dict,
    paper_wind,
)

__all__ = [
    "ConstantForce",
    "Disturbance",
    "DragModel",
    "DrydenGust",
    "GustModel",
    "HoverTurbulence",
    "NoWind",
    "Pulse",
    "Sine",
    "Step",
    "Turbulence",
    "WindSum",
    "check_wind_covers",
    "disturbance_from_dict",
    "paper_wind",
]
