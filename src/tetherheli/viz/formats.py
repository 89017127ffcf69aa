"""The figures' file formats, their check and resolution, importable without Matplotlib or
the engine (the command line's ``--figure-format`` reads them while building its parser; the
report layer checks a format before any run or figure, so a study's start stays light)."""

from __future__ import annotations

from ..errors import ParameterError

__all__ = [
    "FIGURE_FORMATS",
    "PRINT_DPI",
    "REPLAY_FPS",
    "REPLAY_MAX_FRAMES",
    "check_figure_format",
]

#: The formats ``viz.plots.save_figure`` writes (by the file's suffix).
FIGURE_FORMATS = ("png", "pdf", "svg")
#: Resolution of the saved raster figures [dots per inch]: print quality.
PRINT_DPI = 300
#: Frames per second of simulated time a 3-D replay keeps by default (``view --fps``,
#: ``viz.replay``), and at most this many frames.
REPLAY_FPS = 25.0
REPLAY_MAX_FRAMES = 50_000


def check_figure_format(figure_format: str) -> str:
    """``figure_format`` if it is one of ``FIGURE_FORMATS``, else ParameterError.

    Parameters
    ----------
    figure_format : str
        A format name, e.g. ``"png"``.

    Returns
    -------
    str
        ``figure_format`` unchanged.
    """
    if figure_format not in FIGURE_FORMATS:
        raise ParameterError("figure format", figure_format, f"one of {list(FIGURE_FORMATS)}")
    return figure_format
