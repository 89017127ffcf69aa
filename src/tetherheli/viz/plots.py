"""Figures in the style of the paper's Figs. 6-9: free and tethered overlaid.

These functions only read ``SimulationResult`` objects and return Matplotlib figures (the
Agg backend is used; nothing is shown on screen).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from .._io import atomic_write_bytes
from ..sim.result import SimulationResult

__all__ = ["figure_inputs", "figure_outputs", "save_figure"]

_STYLE = {
    "free": dict(color="tab:red", lw=1.1, label="free"),
    "tethered": dict(color="tab:blue", lw=1.1, label="tethered"),
}


def _style(result: SimulationResult) -> dict:
    return _STYLE.get(str(result.configuration.get("configuration")), dict(lw=1.1))


def _finish(fig: Figure, axes: np.ndarray, title: str) -> Figure:
    """Shared time axis label, legend, grid and title of the stacked time-series figures."""
    axes[-1].set_xlabel("t [s]")
    axes[0].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title)
    return fig


def figure_outputs(runs: list[SimulationResult], title: str = "") -> Figure:
    """Figs. 6 and 8: wind force, q1, q2, q3 [m] and q4, q5 [deg] against time."""
    fig, axes = plt.subplots(6, 1, figsize=(7.5, 10.5), sharex=True, layout="constrained")
    for r in runs:
        st = _style(r)
        wind_axis = int(np.argmax(np.abs(r.wind).max(axis=0))) if r.wind.size else 0
        axes[0].plot(r.time, r.wind[:, wind_axis], **st)
        axes[0].set_ylabel(f"Fw{wind_axis + 1} [N]")
        for i, ax in enumerate(axes[1:4]):
            ax.plot(r.time, r.outputs[:, i], **st)
            ax.set_ylabel(f"q{i + 1} [m]")
        axes[4].plot(r.time, np.degrees(r.states[:, 0]), **st)
        axes[4].set_ylabel("q4 [deg]")
        axes[5].plot(r.time, np.degrees(r.states[:, 1]), **st)
        axes[5].set_ylabel("q5 [deg]")
    return _finish(fig, axes, title)


def figure_inputs(runs: list[SimulationResult], title: str = "") -> Figure:
    """Figs. 7 and 9: tension TC and inputs fMR3, tMR1, tMR2 (with feed-forward)."""
    fig, axes = plt.subplots(4, 1, figsize=(7.5, 8.0), sharex=True, layout="constrained")
    for r in runs:
        st = _style(r)
        axes[0].plot(r.time, r.tension, **st)
        for i, (ax, name, unit) in enumerate(
            zip(axes[1:], ("fMR3", "tMR1", "tMR2"), ("N", "N m", "N m"), strict=True)
        ):
            ax.plot(r.time, r.inputs[:, i], **st)
            ax.set_ylabel(f"{name} [{unit}]")
    axes[0].set_ylabel("TC [N]")
    return _finish(fig, axes, title)


def save_figure(fig: Figure, path: str | Path, dpi: int = 110) -> Path:
    """Save as PNG atomically and close the figure."""
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    plt.close(fig)
    atomic_write_bytes(Path(path), buf.getvalue())
    return Path(path)
