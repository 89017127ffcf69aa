"""Kept for compatibility: parameter sweeps now live in ``tetherheli.studies.sweep``."""

from .studies.sweep import (
    METRICS,
    SweepResult,
    paper_cyclic_limit,
    sweep,
    tension_bound,
    write_sweep,
)

__all__ = ["METRICS", "SweepResult", "paper_cyclic_limit", "sweep", "tension_bound", "write_sweep"]
