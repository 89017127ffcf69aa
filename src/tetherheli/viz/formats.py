"""The figures' file formats and resolution, importable without Matplotlib or the engine
(the command line's ``--figure-format`` reads them while building its parser)."""

from __future__ import annotations

__all__ = ["FIGURE_FORMATS", "PRINT_DPI"]

#: The formats ``viz.plots.save_figure`` writes (by the file's suffix).
FIGURE_FORMATS = ("png", "pdf", "svg")
#: Resolution of the saved raster figures [dots per inch]: print quality.
PRINT_DPI = 300
