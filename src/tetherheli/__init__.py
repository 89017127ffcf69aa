"""tetherheli: modelling, control and simulation of small helicopters, free and tethered.

Implements Sandino, Bejar, Kondak, Ollero, "On the use of tethered configurations for
augmenting hovering stability in small-size autonomous helicopters". See docs/notation.md for
the paper's symbols and their code names.
"""

from ._version import __version__
from .errors import ParameterError, SingularConfigurationError, TetherheliError
from .model import FreeHelicopter, LinearModel, TetheredHelicopter, TrimPoint, linearize
from .params import HelicopterParams, Params, TensionControlParams, TetherParams
from .sim import Scenario, SimulationResult, load_scenario, simulate

__all__ = [
    "FreeHelicopter",
    "HelicopterParams",
    "LinearModel",
    "ParameterError",
    "Params",
    "Scenario",
    "SimulationResult",
    "SingularConfigurationError",
    "TensionControlParams",
    "TetherParams",
    "TetheredHelicopter",
    "TetherheliError",
    "TrimPoint",
    "__version__",
    "linearize",
    "load_scenario",
    "simulate",
]
