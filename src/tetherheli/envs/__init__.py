"""Gymnasium environments: the tethered hover as one environment, as N copies stepped in one
compiled call, and as a Stable-Baselines3 VecEnv; their checks, kernels and rendering.

The names below load on first use (PEP 562); the ids are registered on ``import tetherheli``.
"""

from __future__ import annotations

from .._lazy import lazy_getattr

_HOMES = {
    "TetheredHoverEnv": ".env",
    "TetheredHoverVectorEnv": ".vector",
    "TetheredHoverSB3VecEnv": ".sb3",
}

__all__ = ["TetheredHoverEnv", "TetheredHoverSB3VecEnv", "TetheredHoverVectorEnv"]

__getattr__ = lazy_getattr(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
