"""Kept for compatibility: the wind disturbances now live in the package ``tetherheli.wind``
(profiles, turbulence, drag, loader). ``from tetherheli.disturbances import Pulse`` and the
other public names keep working."""

from .wind import (
    ConstantForce,
    Disturbance,
    DragModel,
    DrydenGust,
    GaussMarkovTurbulence,
    GustModel,
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
    "GaussMarkovTurbulence",
    "GustModel",
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


def __getattr__(name: str) -> object:
    if name == "HoverTurbulence":  # deprecated name, with its warning
        from .wind import turbulence

        return turbulence.HoverTurbulence
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
