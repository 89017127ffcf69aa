"""The winch's base: a still winch (the paper's), a vehicle under way, a heaving deck, a
recorded track. ``motion`` defines the motions, ``compiled`` their packed form for
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

__all__ = [
    "BaseMotion",
    "BaseParts",
    "CompiledBase",
    "FileBase",
    "FixedBase",
    "HarmonicBase",
    "SeaStateBase",
    "VelocityBase",
    "base_state",
    "compile_base",
    "jonswap",
    "read_base_csv",
]
