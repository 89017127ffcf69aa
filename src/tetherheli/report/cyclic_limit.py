"""The cyclic-limit search's output folder (``tetherheli sweep --find-min
actuators.cyclic_limit``): the study (``studies.cyclic_limit``) returns a ``LimitSearch``;
this writes its table, its figure (``viz.plots.figure_limit_search``) and its summary."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from .._io import atomic_write_text, output_directory
from .._version import __version__
from ..studies.cyclic_limit import LimitSearch
from ..viz.plots import check_figure_format, figure_limit_search, save_figure

__all__ = ["write_limit_search"]


def write_limit_search(
    result: LimitSearch,
    out_dir: str | Path,
    *,
    command: str,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    figure_format: str = "png",
) -> None:
    """Table (CSV: every run), plot (``sweep.<figure_format>``: png, pdf or svg) and
    summary.json of a search, written whole or not at all (``_io.output_directory``).

    Parameters
    ----------
    result : LimitSearch
        The search.
    out_dir : str or Path
        The output folder.
    command : str
        The command line, recorded in summary.json.
    inputs : tuple of str or Path, optional
        The input files, recorded with the folder's marker.
    force : bool, optional
        Replace this command's earlier output (default False).
    figure_format : str, optional
        "png" (default), "pdf" or "svg".

    Returns
    -------
    None
    """
    figure_format = check_figure_format(figure_format)
    fig = figure_limit_search(result)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(["cyclic_limit_Nm", "metric", "meets", "status"])
    for v, m, ok, s in zip(
        result.values.tolist(), result.metric.tolist(), result.meets, result.statuses, strict=True
    ):
        writer.writerow([repr(v), repr(m), int(ok), s])
    with output_directory(out_dir, writer="sweep", inputs=inputs, force=force) as tmp:
        save_figure(fig, tmp / f"sweep.{figure_format}")
        atomic_write_text(tmp / "sweep.csv", buf.getvalue())
        info = {**result.as_dict(), "tetherheli_version": __version__, "command": command}
        atomic_write_text(tmp / "summary.json", json.dumps(info, indent=2) + "\n")
