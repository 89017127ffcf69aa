"""Figures in the style of the paper's Figs. 6-9: free and tethered overlaid.

These functions only read ``SimulationResult`` objects and return Matplotlib figures (the
Agg backend is used; nothing is shown on screen). A failed run is drawn up to its last
recorded sample and says so in the legend; samples that cannot be drawn (non-finite, or beyond
``PLOT_LIMIT``) are left out as gaps, with a note on the figure.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from .._io import atomic_write_bytes
from ..names import INPUT, INPUT_UNITS
from ..sim.result import SimulationResult

__all__ = ["PLOT_LIMIT", "figure_inputs", "figure_outputs", "plottable", "save_figure"]

_STYLE = {
    "free": dict(color="tab:red", lw=1.1, label="free"),
    "tethered": dict(color="tab:blue", lw=1.1, label="tethered"),
}


#: samples beyond this magnitude (or non-finite) are not drawn: Matplotlib cannot place ticks
#: on such ranges, and no physical signal of the model reaches them
PLOT_LIMIT = 1e100


def _style(result: SimulationResult) -> dict:
    st = dict(_STYLE.get(str(result.configuration.get("configuration")), dict(lw=1.1)))
    label = st.get("label", result.name)
    if not result.ok:  # a failed run is drawn up to its last recorded sample
        label += f" (stopped at t = {result.end_time:g} s)"
    elif result.released:
        label += f" (tether released at t = {result.release_time:g} s)"
    st["label"] = label
    return st


def plottable(values: np.ndarray) -> tuple[np.ndarray, int]:
    """A copy of ``values`` with the samples that cannot be drawn (non-finite, or beyond
    ``PLOT_LIMIT``) set to NaN (gaps in the line), and how many there were."""
    a = np.array(values, dtype=float)
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(a) <= PLOT_LIMIT)
    a[bad] = np.nan
    return a, int(bad.sum())


class _Plotter:
    """``ax.plot`` of ``plottable`` samples, counting those left out for the figure's note."""

    def __init__(self) -> None:
        self.dropped = 0

    def __call__(self, ax, t: np.ndarray, y: np.ndarray, **style) -> None:
        clean, n = plottable(y)
        self.dropped += n
        ax.plot(t, clean, **style)


def _finish(fig: Figure, axes: np.ndarray, title: str, dropped: int = 0) -> Figure:
    """Shared time axis label, legend, grid and title of the stacked time-series figures;
    a note when samples could not be drawn."""
    axes[-1].set_xlabel("t [s]")
    axes[0].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    if dropped:
        fig.text(
            0.01,
            0.002,
            f"{dropped} sample{'s' if dropped != 1 else ''} not drawn (non-finite or "
            f"beyond {PLOT_LIMIT:g})",
            fontsize=7,
            color="tab:red",
        )
    if title:
        fig.suptitle(title)
    return fig


def figure_outputs(runs: list[SimulationResult], title: str = "") -> Figure:
    """Figs. 6 and 8: wind force, q1, q2, q3 [m] and q4, q5 [deg] against time."""
    fig, axes = plt.subplots(6, 1, figsize=(7.5, 10.5), sharex=True, layout="constrained")
    plot = _Plotter()
    for r in runs:
        st = _style(r)
        with np.errstate(invalid="ignore"):
            peak = np.nan_to_num(np.abs(r.wind), nan=0.0).max(axis=0) if r.wind.size else 0
        wind_axis = int(np.argmax(peak)) if r.wind.size else 0
        plot(axes[0], r.time, r.wind[:, wind_axis], **st)
        axes[0].set_ylabel(f"Fw{wind_axis + 1} [N]")
        for i, ax in enumerate(axes[1:4]):
            plot(ax, r.time, r.outputs[:, i], **st)
            ax.set_ylabel(f"q{i + 1} [m]")
        plot(axes[4], r.time, np.degrees(r.states[:, 0]), **st)
        axes[4].set_ylabel("q4 [deg]")
        plot(axes[5], r.time, np.degrees(r.states[:, 1]), **st)
        axes[5].set_ylabel("q5 [deg]")
    return _finish(fig, axes, title, plot.dropped)


def figure_inputs(runs: list[SimulationResult], title: str = "") -> Figure:
    """Figs. 7 and 9: tension TC and inputs fMR3, tMR1, tMR2 (with feed-forward)."""
    fig, axes = plt.subplots(4, 1, figsize=(7.5, 8.0), sharex=True, layout="constrained")
    plot = _Plotter()
    for r in runs:
        st = _style(r)
        plot(axes[0], r.time, r.tension, **st)
        for i, (ax, name, unit) in enumerate(
            zip(axes[1:], INPUT[:3], INPUT_UNITS[:3], strict=True)
        ):
            plot(ax, r.time, r.inputs[:, i], **st)
            ax.set_ylabel(f"{name} [{unit}]")
    axes[0].set_ylabel("TC [N]")
    return _finish(fig, axes, title, plot.dropped)


def save_figure(fig: Figure, path: str | Path, dpi: int = 110) -> Path:
    """Save as PNG atomically and close the figure."""
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    plt.close(fig)
    atomic_write_bytes(Path(path), buf.getvalue())
    return Path(path)
