"""tetherheli: modelling, control and simulation of small helicopters, free and tethered.

Implements Sandino, Bejar, Kondak, Ollero, "On the use of tethered configurations for
augmenting hovering stability in small-size autonomous helicopters". See docs/notation.md for
the paper's symbols and their code names.

The public names below are imported lazily (on first use), so that light commands such as
``tetherheli derive`` start fast and work even while the generated code is being rebuilt.
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import TYPE_CHECKING

from ._lazy import lazy_getattr
from ._version import __version__
from .errors import (
    InfeasibleError,
    ParameterError,
    SingularConfigurationError,
    TetherheliError,
)
from .params import HelicopterParams, Params, TensionControlParams, TetherParams

if TYPE_CHECKING:
    from .control.base import Command, Controller, Measurement
    from .control.se3 import SE3Controller
    from .model import FreeHelicopter, LinearModel, TetheredHelicopter, TrimPoint, linearize
    from .model.multirotor import Multirotor
    from .results import SimulationResult, load_result
    from .runs import simulate
    from .runs.batch import BatchResult, run_batch
    from .scenario import Scenario, load_scenario
    from .scenario.core import paper_scenario
    from .shipped import shipped_scenario, shipped_scenarios
    from .status import Status
    from .tether import Cable, drive_cable

_LAZY = {
    "FreeHelicopter": ".model",
    "LinearModel": ".model",
    "TetheredHelicopter": ".model",
    "TrimPoint": ".model",
    "linearize": ".model",
    "Multirotor": ".model.multirotor",
    "SE3Controller": ".control.se3",
    "Scenario": ".scenario",
    "SimulationResult": ".results",
    "load_result": ".results",
    "load_scenario": ".scenario",
    "simulate": ".runs",
    "paper_scenario": ".scenario",
    "run_batch": ".runs",
    "BatchResult": ".runs",
    "Controller": ".control.base",
    "Command": ".control.base",
    "Measurement": ".control.base",
    "Cable": ".tether",
    "drive_cable": ".tether",
    "shipped_scenario": ".shipped",
    "shipped_scenarios": ".shipped",
    "Status": ".status",
}

__all__ = [
    "BatchResult",
    "Cable",
    "Command",
    "Controller",
    "FreeHelicopter",
    "HelicopterParams",
    "InfeasibleError",
    "LinearModel",
    "Measurement",
    "Multirotor",
    "ParameterError",
    "Params",
    "SE3Controller",
    "Scenario",
    "SimulationResult",
    "SingularConfigurationError",
    "Status",
    "TensionControlParams",
    "TetherParams",
    "TetheredHelicopter",
    "TetherheliError",
    "TrimPoint",
    "__version__",
    "drive_cable",
    "linearize",
    "load_result",
    "load_scenario",
    "paper_scenario",
    "run_batch",
    "shipped_scenario",
    "shipped_scenarios",
    "simulate",
]


def _register_gymnasium_ids() -> None:
    """Register the Gymnasium ids (``_gym_registration``) when Gymnasium is installed; this
    imports Gymnasium alone, never the compiled stack."""
    if importlib.util.find_spec("gymnasium") is not None:
        from ._gym_registration import register_envs

        register_envs()


_register_gymnasium_ids()


__getattr__ = lazy_getattr(__name__, _LAZY)


def __dir__() -> list[str]:
    return sorted(__all__)
