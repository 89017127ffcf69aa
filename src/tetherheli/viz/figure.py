"""What every figure shares: ``InlineFigure`` (shown inline in Jupyter; with pyplot's
figure manager when the user's code imported pyplot, ``new_figure``), the configurations'
colours, the styles, the dropping of samples that cannot be drawn (``plottable``,
``PLOT_LIMIT``), the figure's assembly and ``save_figure``.

The figures themselves are ``viz.plots`` (the runs', Figs. 6-9) and ``viz.study_figures``
(sweep, Monte Carlo, sensing, trade-off); ``viz.plots`` re-exports every public name.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._io import atomic_write_bytes
from ..errors import ParameterError
from ..results.result import SimulationResult
from ..status import stopped
from .formats import FOR_FILES, PRINT_DPI, check_figure_format, figures_for_files

__all__ = [
    "CONFIGURATION_COLOURS",
    "PLOT_LIMIT",
    "InlineFigure",
    "figure_dpi",
    "figures_for_files",
    "metric_label",
    "new_figure",
    "plottable",
    "save_figure",
]

#: The colour of each configuration in every figure and the animation.
CONFIGURATION_COLOURS = {"free": "tab:red", "tethered": "tab:blue"}

_STYLE: dict[str, dict[str, Any]] = {
    cfg: dict(color=c, lw=1.1, label=cfg) for cfg, c in CONFIGURATION_COLOURS.items()
}


def metric_label(metric: str) -> str:
    """An axis label with the unit for a run metric (``runs.batch.METRIC_NAMES``, e.g.
    "peak_q1" -> "peak |q1 - q1 trim| [m]").

    Parameters
    ----------
    metric : str
        A metric name such as ``"peak_q1"``, ``"rms_q2"``, ``"tension_max"``.

    Returns
    -------
    str
        The label; an unknown name is returned unchanged.
    """
    kind, _, rest = metric.partition("_")
    if kind == "tension":
        return f"{rest}imum tether tension TC [N]"
    q, _, unit = rest.partition("_")
    if kind == "peak":
        return f"peak |{q} - {q} trim| [{unit or 'm'}]"
    if kind == "rms":
        return f"RMS of {q} - {q} trim [m]"
    return metric


#: samples beyond this magnitude (or non-finite) are not drawn: Matplotlib cannot place ticks
#: on such ranges, and no physical signal of the model reaches them
PLOT_LIMIT = 1e100


def _style(result: SimulationResult) -> dict:
    st = dict(_STYLE.get(str(result.configuration.get("configuration")), dict(lw=1.1)))
    label = st.get("label", result.name)
    if not result.ok:  # a failed run is drawn up to its last recorded sample
        ended = "stopped" if stopped(result.status) else "ended"
        label += f" ({ended} at t = {result.end_time:g} s)"
    elif result.released:
        label += f" (tether released at t = {result.release_time:g} s)"
    st["label"] = label
    return st


def plottable(values: np.ndarray) -> tuple[np.ndarray, int]:
    """A copy of ``values`` with the samples that cannot be drawn (non-finite, or beyond
    ``PLOT_LIMIT``) set to NaN (gaps in the line), and how many there were.

    Parameters
    ----------
    values : ndarray
        Samples of any shape and unit.

    Returns
    -------
    drawable : ndarray of float
        The copy, same shape, NaN where a sample cannot be drawn.
    dropped : int
        How many samples were set to NaN.
    """
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


class InlineFigure(Figure):
    """A Matplotlib ``Figure`` that shows itself in Jupyter: as a cell's last expression or
    through ``display(fig)`` it renders as a PNG (at the figure's own dpi) in any kernel and
    backend, where a plain ``Figure`` prints ``<Figure size ... with n Axes>``.

    ``new_figure`` makes one: with pyplot's figure manager when the user's code imported
    pyplot (so ``plt.show()`` and ``%matplotlib inline`` show it), else without pyplot;
    never changing the process's backend. Shown inline, a figure whose manager has no
    window (the inline backend's, Agg's) leaves pyplot's figures (``plt.close``), so the
    inline backend's end-of-cell flush does not show it a second time.

    Parameters
    ----------
    figsize, dpi, facecolor, edgecolor, linewidth, frameon : optional
        As for ``matplotlib.figure.Figure``: the size [inch], resolution [dots per inch],
        colours, frame line width [points] and whether the frame is drawn.
    subplotpars, tight_layout, constrained_layout, layout, **kwargs : optional
        As for ``matplotlib.figure.Figure``: the subplots' spacing and the layout engine.
    """

    def _repr_png_(self) -> bytes:
        """The figure as PNG bytes (IPython's display protocol), at the resolution
        Matplotlib's ``savefig`` would take (``figure_dpi`` with the figure's own as the
        default), drawn once (``_png_bytes``: ``savefig`` draws a constrained layout twice)."""
        return _png_bytes(self, figure_dpi(self.dpi))

    def _ipython_display_(self) -> None:
        """Show the PNG (``_repr_png_``) in IPython, ahead of the formatter the inline
        backend registers for every ``Figure``; then out of pyplot if its manager has no
        window (``_shown_inline``)."""
        from IPython.display import display

        display({"image/png": self._repr_png_(), "text/plain": repr(self)}, raw=True)
        self._shown_inline()

    def _shown_inline(self) -> None:
        from matplotlib.backend_bases import FigureManagerBase

        manager = getattr(self.canvas, "manager", None)
        pyplot = sys.modules.get("matplotlib.pyplot")
        if pyplot is not None and manager is not None and type(manager) is FigureManagerBase:
            pyplot.close(self)


def new_figure(**kwargs: Any) -> Figure:
    """A new ``InlineFigure``: made by ``pyplot.figure(FigureClass=InlineFigure, ...)``,
    Matplotlib's documented way to give a Figure subclass pyplot's figure manager, when
    ``matplotlib.pyplot`` is already imported (the user's code uses pyplot: ``plt.show()``,
    ``%matplotlib inline`` then show it), else without pyplot, which tetherheli never imports
    for a figure (the backend is left alone). Within ``figures_for_files``: never pyplot.

    Parameters
    ----------
    **kwargs
        ``Figure``'s arguments (``figsize`` [in], ``layout``, ...).

    Returns
    -------
    matplotlib.figure.Figure
        An ``InlineFigure``.
    """
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is None or FOR_FILES.get():
        return InlineFigure(**kwargs)
    return pyplot.figure(FigureClass=InlineFigure, **kwargs)


def _new_figure(fig: Figure | None, size: tuple[float, float]) -> Figure:
    """``fig`` (a caller's empty figure) or a new constrained-layout figure (``new_figure``)."""
    if fig is None:
        return new_figure(figsize=size, layout="constrained")
    if fig.axes:
        raise ParameterError("fig", "a figure with axes", "an empty figure")
    return fig


def _single_axes(ax: Any, size: tuple[float, float]) -> tuple[Figure, Any]:
    """``ax`` and its figure, or a new figure with one axes."""
    if ax is not None:
        return ax.get_figure(), ax
    fig = new_figure(figsize=size, layout="constrained")
    return fig, fig.add_subplot()


def _stacked(
    rows: int, size: tuple[float, float], fig: Figure | None = None
) -> tuple[Figure, np.ndarray]:
    """A figure of ``rows`` axes stacked over a shared time axis (``new_figure``)."""
    fig = _new_figure(fig, size)
    return fig, np.atleast_1d(fig.subplots(rows, 1, sharex=True))


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


def figure_dpi(default: float = PRINT_DPI) -> float:
    """The resolution of a saved PNG [dots per inch]: Matplotlib's ``savefig.dpi`` where it
    is a number (a user's matplotlibrc or ``matplotlib.rc_context``), else ``default``:
    ``PRINT_DPI`` for a saved figure (Matplotlib's default ``"figure"`` would be the
    screen's 100 dpi), the figure's own dpi for one shown inline.

    Parameters
    ----------
    default : float, optional
        The resolution [dots per inch] where ``savefig.dpi`` is ``"figure"`` (default
        ``PRINT_DPI``).

    Returns
    -------
    float
        The resolution [dots per inch].
    """
    import matplotlib as mpl

    value = mpl.rcParams["savefig.dpi"]
    return float(default) if value == "figure" else float(value)


def save_figure(fig: Figure, path: str | Path, dpi: float | None = None) -> Path:
    """Save ``fig`` atomically in the format of ``path``'s suffix (``FIGURE_FORMATS``: PNG
    at ``dpi``; PDF, SVG as vectors, without a creation date).

    A PNG holds Matplotlib's Agg pixels (``_png_bytes``): RGB where the figure is opaque.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to save.
    path : str or Path
        The file to write; its suffix (.png, .pdf, .svg) selects the format.
    dpi : float, optional
        Resolution of a PNG [dots per inch] (default ``figure_dpi()``: ``PRINT_DPI`` unless
        Matplotlib's ``savefig.dpi`` is set).

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    check_figure_format(path.suffix.lower().lstrip("."))
    return _save_figure(fig, path, dpi)


def _save_figure(fig: Figure, path: str | Path, dpi: float | None = None) -> Path:
    """``save_figure`` of a path whose suffix the caller checked (a writer that checked its
    ``figure_format`` argument once, at its entry)."""
    import io

    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    dpi = figure_dpi() if dpi is None else dpi
    if fmt == "png":
        atomic_write_bytes(path, _png_bytes(fig, dpi))
        return path
    metadata = {"pdf": {"CreationDate": None}, "svg": {"Date": None}}[fmt]
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, dpi=dpi, metadata=metadata)
    atomic_write_bytes(path, buf.getvalue())
    return path


def _png_bytes(fig: Figure, dpi: float) -> bytes:
    """``fig`` as a PNG at ``dpi``: the pixels Matplotlib's own PNG holds, with its
    "Software" text and resolution, but without the alpha channel where every pixel is
    opaque (a figure's usual white face).

    Three channels instead of four: on the 2250 x 3150 pixels of a run's outputs figure at
    300 dpi, Pillow encodes in about 0.75 of the time of Matplotlib's RGBA PNG and the file
    is about 0.9 of its size (``tests/test_plots.py`` checks pixels and size). The pixels
    come from one drawing (``_agg_pixels``); a figure that needs more of Matplotlib's
    ``savefig`` (``_drawn_once`` says which) is left to Matplotlib's own PNG.
    """
    import io

    import matplotlib as mpl
    from PIL import Image, PngImagePlugin

    pixels = _agg_pixels(fig, dpi) if _drawn_once(fig) else None
    if pixels is None:
        png = io.BytesIO()
        fig.savefig(png, format="png", dpi=dpi)
        return png.getvalue()
    opaque = bool((pixels[:, :, 3] == 255).all())
    image = Image.fromarray(np.ascontiguousarray(pixels[:, :, :3]) if opaque else pixels)
    info = PngImagePlugin.PngInfo()
    info.add_text("Software", f"Matplotlib version{mpl.__version__}, https://matplotlib.org/")
    out = io.BytesIO()
    image.save(out, format="png", pnginfo=info, dpi=(dpi, dpi))
    return out.getvalue()


def _drawn_once(fig: Figure) -> bool:
    """Whether ``_agg_pixels`` gives what ``fig.savefig`` would: Matplotlib's savefig
    settings at their defaults (not cropped, the figure's own face and edge colours, not
    transparent) and no GUI window that a change of dpi would resize (a figure pyplot
    manages on a non-interactive backend, Agg or Jupyter's inline, has none)."""
    import matplotlib as mpl

    rc = mpl.rcParams
    manager = getattr(fig.canvas, "manager", None)
    return (
        rc["savefig.bbox"] is None
        and rc["savefig.facecolor"] == "auto"
        and rc["savefig.edgecolor"] == "auto"
        and not rc["savefig.transparent"]
        and getattr(manager, "window", None) is None
    )


def _agg_pixels(fig: Figure, dpi: float) -> np.ndarray | None:
    """The RGBA pixels (height, width, 4) of ``fig`` at ``dpi``, drawn once by Agg.

    ``savefig`` draws a figure with a layout engine twice: once without rendering, to run
    the layout, then again to render. One ``FigureCanvasAgg.draw`` runs the layout and
    renders in one pass, to the same pixels (``tests/test_plots.py`` compares them with
    Matplotlib's PNG): 0.80-0.91 of ``savefig``'s CPU time for the PNG of a run's or a Monte
    Carlo's figure (``benchmarks/bench_figures.py``). The figure's canvas and dpi are
    restored afterwards. None when the rendered size is not the figure's size at ``dpi``.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas, figure_dpi_ = fig.canvas, fig.dpi
    agg = FigureCanvasAgg(fig)  # attaches itself to fig; its own, window-less canvas
    try:
        # as during savefig: animated artists are drawn too (a private flag, not in the stubs)
        agg._is_saving = True  # type: ignore[attr-defined]
        fig.dpi = dpi
        agg.draw()
        pixels = np.array(agg.buffer_rgba(), dtype=np.uint8)
    finally:
        fig.dpi = figure_dpi_
        fig.set_canvas(canvas)
    width, height = int(fig.get_figwidth() * dpi), int(fig.get_figheight() * dpi)
    return pixels if pixels.shape == (height, width, 4) else None
