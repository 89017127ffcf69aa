"""Blank figures for the tests of output folders (``blank_figures``)."""

from __future__ import annotations

import pytest

#: the figures the commands under test draw (``viz.plots``); each is still saved
FIGURES = ("figure_outputs", "figure_inputs", "figure_montecarlo", "figure_paired")


def blank_figures(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every figure of ``FIGURES`` drawn blank, still saved by ``save_figure``: for tests of
    the folder rules (what is written, replaced, kept or refused), not of the plots, where a
    real figure costs a few tenths of a second. The plots are tested on their own
    (``tests/test_plots.py``) and through the commands elsewhere."""
    from matplotlib.figure import Figure

    import tetherheli.viz.plots as plots

    for name in FIGURES:
        monkeypatch.setattr(plots, name, lambda *a, **k: Figure(figsize=(0.5, 0.5)))
