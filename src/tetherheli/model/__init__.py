"""The mechanical model: Kane derivation, generated numeric code, dynamics, trim, linearization."""

from .dynamics import INPUT, OUTPUT, FreeHelicopter, TetheredHelicopter, state_index
from .linearize import LinearModel, discretize_zoh, linearize
from .trim import TrimPoint, hover_trim

__all__ = [
    "INPUT",
    "OUTPUT",
    "FreeHelicopter",
    "LinearModel",
    "TetheredHelicopter",
    "TrimPoint",
    "discretize_zoh",
    "hover_trim",
    "linearize",
    "state_index",
]
