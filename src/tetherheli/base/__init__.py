"""The winch's base: a still winch (the paper's), a vehicle under way, a heaving deck, a
recorded track, a ship in six degrees of freedom. ``motion`` defines the motions, ``ship``
the ship's, ``compiled`` their packed form for
the engine, ``loader`` the ``[base]`` table."""

from .compiled import CompiledBase, base_state, compile_base
from .motion import (
    BaseMotion,
    BaseParts,
    FileBase,
    FixedBase,
    HarmonicBase,
    SeaStateBase,
    VelocityBase,
    jonswap,
    read_base_csv,
)
from .ship import ShipBase, read_rao_csv

__all__ = [
    "BaseMotion",
    "BaseParts",
    "CompiledBase",
    "FileBase",
    "FixedBase",
    "HarmonicBase",
    "SeaStateBase",
    "ShipBase",
    "VelocityBase",
    "base_state",
    "compile_base",
    "jonswap",
    "read_base_csv",
    "read_rao_csv",
]
