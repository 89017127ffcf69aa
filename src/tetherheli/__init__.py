"""tetherheli: modelling, control and simulation of small helicopters, free and tethered.

Implements Sandino, Bejar, Kondak, Ollero, "On the use of tethered configurations for
augmenting hovering stability in small-size autonomous helicopters". See docs/notation.md for
the paper's symbols and their code names.
"""

from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version

from .errors import ParameterError, SingularConfigurationError, TetherheliError
from .model import FreeHelicopter, LinearModel, TetheredHelicopter, TrimPoint, linearize
from .params import HelicopterParams, Params, TensionControlParams, TetherParams

try:
    __version__ = _version("tetherheli")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

__all__ = [
    "FreeHelicopter",
    "HelicopterParams",
    "LinearModel",
    "ParameterError",
    "Params",
    "SingularConfigurationError",
    "TensionControlParams",
    "TetherParams",
    "TetheredHelicopter",
    "TetherheliError",
    "TrimPoint",
    "__version__",
    "linearize",
]
