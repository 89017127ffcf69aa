"""Wind disturbances: a force on the helicopter's centre of mass HO, in the inertial frame N.

``profiles``
    the ``Disturbance`` contract and the deterministic profiles (``Pulse``, ``Step``,
    ``Sine``, ``ConstantForce``, ``NoWind``, their sum ``WindSum``, ``paper_wind``);
``gusts``
    gust models (``DrydenGust``, ``GaussMarkovTurbulence``) and their axes (``heading_axes``);
``calibration``
    ``gust_calibration`` and ``CalibratedGaussMarkovTurbulence``: gusts from MIL-HDBK-1797 or
    IEC 61400-1;
``turbulence``
    ``Turbulence``, a gust series turned into a drag force, ``SteadyWind``, a steady wind's
    drag (the apparent wind over a moving base), and the checks of a run's wind;
``drag``
    ``DragModel``, the air-relative velocity turned into a force;
``compiled``
    ``compile_wind``: the built-in disturbances in the compiled engine's packed form;
``loader``
    ``disturbance_from_dict``, the strict loader of TOML-style tables.
"""

from .compiled import CompiledWind, compile_wind
from .drag import DragModel
from .loader import disturbance_from_dict
from .profiles import ConstantForce, Disturbance, NoWind, Pulse, Sine, Step, WindSum, paper_wind
from .turbulence import (
    CALIBRATIONS,
    CalibratedGaussMarkovTurbulence,
    DrydenGust,
    GaussMarkovTurbulence,
    GustCalibration,
    GustModel,
    SteadyWind,
    Turbulence,
    check_gust_grid,
    check_wind_covers,
    gust_calibration,
    initial_wind_force,
)

__all__ = [
    "CALIBRATIONS",
    "CalibratedGaussMarkovTurbulence",
    "CompiledWind",
    "ConstantForce",
    "Disturbance",
    "DragModel",
    "DrydenGust",
    "GaussMarkovTurbulence",
    "GustCalibration",
    "GustModel",
    "NoWind",
    "Pulse",
    "Sine",
    "SteadyWind",
    "Step",
    "Turbulence",
    "WindSum",
    "check_gust_grid",
    "check_wind_covers",
    "compile_wind",
    "disturbance_from_dict",
    "gust_calibration",
    "initial_wind_force",
    "paper_wind",
]
