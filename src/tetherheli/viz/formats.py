"""The figures' file formats, their check and resolution, importable without Matplotlib or
the engine (the command line's ``--figure-format`` reads them while building its parser; the
report layer checks a format before any run or figure, so a study's start stays light);
and ``figures_for_files``, which keeps the figures a writer draws for files out of pyplot."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from contextvars import ContextVar

from ..errors import ParameterError

__all__ = [
    "FIGURE_FORMATS",
    "PRINT_DPI",
    "REPLAY_FPS",
    "REPLAY_MAX_FRAMES",
    "check_figure_format",
    "figures_for_files",
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


#: True while figures are drawn for files (``figures_for_files``): ``viz.figure.new_figure``
#: then never gives them pyplot's figure manager
FOR_FILES: ContextVar[bool] = ContextVar("tetherheli_figures_for_files", default=False)


@contextlib.contextmanager
def figures_for_files() -> Iterator[None]:
    """Within (a ``with`` block, or the function it decorates), the figures drawn are files
    to write: ``viz.figure.new_figure`` does not register them with pyplot, where, with
    pyplot imported (a notebook, a script), they would pile up in its figure list and show
    at a notebook cell's end. Every writer of figures (``report``, ``compare``) runs in it.

    Returns
    -------
    contextlib.AbstractContextManager
        The context (``with figures_for_files(): ...``), also a decorator
        (``@figures_for_files()``).
    """
    token = FOR_FILES.set(True)
    try:
        yield
    finally:
        FOR_FILES.reset(token)
