"""Every figure of the package: the paper's Figs. 6-9 (free and tethered overlaid), the
sweep, the Monte Carlo, the sensing, the controller trade-off and ``tetherheli compare``'s
figures.

These functions only read results and return Matplotlib figures (``InlineFigure``, which
shows itself inline in Jupyter as a cell's last expression or through ``display(fig)``).
They never import pyplot: when the caller's code has imported it, a figure gets pyplot's
figure manager (``new_figure``), so ``plt.show()`` and ``%matplotlib inline`` show it as
any pyplot figure; importing or calling them leaves the process's Matplotlib backend alone.
Each takes an optional ``fig`` (an empty figure to draw into, e.g. one from
``plt.figure()`` in a notebook) or, for the one-panel figures, ``ax`` (axes to draw on), and
returns the figure. ``save_figure`` writes one as PNG (at ``figure_dpi()``: ``PRINT_DPI``
unless Matplotlib's ``savefig.dpi`` is set), PDF or SVG by the file's suffix. Free runs are
drawn in red and tethered runs in blue everywhere (``CONFIGURATION_COLOURS``, also used by
the animation). A failed run is drawn up to its last
recorded sample and says so in the legend; samples that cannot be drawn (non-finite, or beyond
``PLOT_LIMIT``) are left out as gaps, with a note on the figure.

This module draws the runs (Figs. 6-9); ``viz.landing`` a landing's figure (in place of
Figs. 6-9 for a descent), ``viz.study_figures`` the studies' figures and ``viz.figure`` what
every figure shares. Their names are re-exported here, where callers
import them.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ..names import INPUT, INPUT_UNITS
from ..results.result import SimulationResult
from .figure import (
    CONFIGURATION_COLOURS,
    PLOT_LIMIT,
    InlineFigure,
    _finish,
    _Plotter,
    _stacked,
    _style,
    figure_dpi,
    figures_for_files,
    metric_label,
    new_figure,
    plottable,
    save_figure,
)
from .formats import FIGURE_FORMATS, PRINT_DPI
from .landing import LANDING_SERIES, figure_landing
from .study_figures import (
    ControllerSpread,
    figure_compare,
    figure_compare_spread,
    figure_limit_search,
    figure_montecarlo,
    figure_paired,
    figure_pareto,
    figure_release,
    figure_sensing,
    figure_sweep,
)

__all__ = [
    "CONFIGURATION_COLOURS",
    "FIGURE_FORMATS",
    "LANDING_SERIES",
    "PLOT_LIMIT",
    "PRINT_DPI",
    "ControllerSpread",
    "InlineFigure",
    "figure_compare",
    "figure_compare_spread",
    "figure_dpi",
    "figure_inputs",
    "figure_landing",
    "figure_limit_search",
    "figure_montecarlo",
    "figure_outputs",
    "figure_paired",
    "figure_pareto",
    "figure_release",
    "figure_sensing",
    "figure_sweep",
    "figures_for_files",
    "metric_label",
    "new_figure",
    "plottable",
    "save_figure",
]


def figure_outputs(
    runs: list[SimulationResult], title: str = "", *, fig: Figure | None = None
) -> Figure:
    """Figs. 6 and 8: wind force, q1, q2, q3 [m] and q4, q5 [deg] against time (into ``fig``
    if given).

    Parameters
    ----------
    runs : list of SimulationResult
        The runs to overlay (coloured by configuration, ``CONFIGURATION_COLOURS``).
    title : str, optional
        The figure's title (default none).
    fig : matplotlib.figure.Figure, optional
        The figure to draw into (cleared); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn.
    """
    fig, axes = _stacked(6, (7.5, 10.5), fig)
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


def figure_inputs(
    runs: list[SimulationResult], title: str = "", *, fig: Figure | None = None
) -> Figure:
    """Figs. 7 and 9: tension TC and inputs fMR3, tMR1, tMR2 (with feed-forward), into
    ``fig`` if given. The tension axis spans the taut tethers' samples (a free run's TC = 0
    would flatten their variation), and says so when a free run lies off it.

    Parameters
    ----------
    runs : list of SimulationResult
        The runs to overlay (coloured by configuration).
    title : str, optional
        The figure's title (default none).
    fig : matplotlib.figure.Figure, optional
        The figure to draw into (cleared); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn.
    """
    fig, axes = _stacked(4, (7.5, 8.0), fig)
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
    _scale_to_taut(axes[0], runs)
    return _finish(fig, axes, title, plot.dropped)


def _scale_to_taut(ax: Any, runs: list[SimulationResult]) -> None:
    """Limit the tension axis to the tethered runs' finite samples (with a 10% margin) when
    a free run (TC = 0) would otherwise squash them; the free runs are then named below."""
    taut = [
        plottable(r.tension)[0]
        for r in runs
        if r.configuration.get("configuration") == "tethered" and r.tension.size
    ]
    values = np.concatenate(taut) if taut else np.zeros(0)
    values = values[np.isfinite(values)]
    if not values.size:
        return
    lo, hi = float(values.min()), float(values.max())
    pad = 0.1 * (hi - lo) if hi > lo else max(0.05 * abs(hi), 1e-3)
    if lo - pad <= 0.0:
        return  # zero is in range: the free runs are drawn as they are
    ax.set_ylim(lo - pad, hi + pad)
    if len(taut) < len(runs):
        ax.text(
            0.01,
            0.04,
            "free: TC = 0 N (below the axis)",
            transform=ax.transAxes,
            fontsize=7,
            color=CONFIGURATION_COLOURS["free"],
        )
